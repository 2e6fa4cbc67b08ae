// Initialisation from the target and re-seeding of dead leaves (see fuzzycsg/fit/init.hpp).
#include "fuzzycsg/fit/init.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/nearest.hpp"

namespace fuzzycsg {

namespace {

double uniform01(Rng& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

std::size_t uniform_index(Rng& rng, std::size_t n) {
  return static_cast<std::size_t>(uniform01(rng) * static_cast<double>(n)) % n;
}

void set(std::span<double> params, ParamRef r, double v) { params[r.index] = v; }

}  // namespace

struct BoundaryDistance::Impl {
  std::vector<float> normals;
  std::optional<NearestPoints> points;
};

BoundaryDistance::BoundaryDistance(const Target& target, std::size_t samples, Rng& rng)
    : impl_(std::make_unique<Impl>()) {
  std::vector<float> points;
  target.sample_boundary(std::max<std::size_t>(samples, 1), rng, points, impl_->normals);
  impl_->points.emplace(std::move(points), target.dim());
}

BoundaryDistance::~BoundaryDistance() = default;

int BoundaryDistance::dim() const { return impl_->points->dim(); }

std::size_t BoundaryDistance::nearest(const float* point) const {
  return impl_->points->nearest(point).index;
}

const float* BoundaryDistance::point(std::size_t i) const { return impl_->points->point(i); }

const float* BoundaryDistance::normal(std::size_t i) const {
  return &impl_->normals[i * static_cast<std::size_t>(dim())];
}

double BoundaryDistance::operator()(const float* point) const {
  return std::sqrt(static_cast<double>(impl_->points->nearest(point).squared_distance));
}

std::vector<Ball> cover_with_balls(const Target& target, const BoundaryDistance& distance,
                                   int count, Rng& rng, std::size_t candidates) {
  const int dim = target.dim();
  const auto d = static_cast<std::size_t>(dim);
  // Interior candidates, drawn in batches until enough are found (or the shape is too thin
  // for this many draws to find them).
  std::vector<float> inside;
  constexpr std::size_t kBatch = 65536;
  constexpr int kMaxBatches = 64;
  std::vector<float> occ(kBatch);
  for (int b = 0; b < kMaxBatches && inside.size() < candidates * d; ++b) {
    const std::vector<float> pts = uniform_points(dim, kBatch, rng);
    target.occupancy(pts, occ);
    for (std::size_t i = 0; i < kBatch && inside.size() < candidates * d; ++i) {
      if (occ[i] > 0.5f)
        inside.insert(inside.end(), pts.begin() + i * d, pts.begin() + (i + 1) * d);
    }
  }
  const std::size_t m = inside.size() / d;
  std::vector<Ball> balls;
  if (m == 0 || count <= 0) return balls;
  std::vector<double> radius(m);
  for (std::size_t i = 0; i < m; ++i) radius[i] = distance(&inside[i * d]);

  // gap[i]: distance from candidate i to the nearest chosen ball's sphere, negative inside one.
  std::vector<double> gap(m, std::numeric_limits<double>::infinity());
  balls.reserve(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    std::size_t best = 0;
    bool uncovered = false;
    for (std::size_t i = 0; i < m; ++i) {
      if (gap[i] > 0) {
        if (!uncovered || radius[i] > radius[best]) best = i;
        uncovered = true;
      }
    }
    if (!uncovered) {  // all covered: fill in where coverage is thinnest
      best = static_cast<std::size_t>(std::max_element(gap.begin(), gap.end()) - gap.begin());
    }
    Ball ball;
    for (std::size_t a = 0; a < d; ++a) ball.center[a] = inside[best * d + a];
    ball.radius = radius[best];
    balls.push_back(ball);
    for (std::size_t i = 0; i < m; ++i) {
      double r2 = 0.0;
      for (std::size_t a = 0; a < d; ++a) {
        const double x = inside[i * d + a] - ball.center[a];
        r2 += x * x;
      }
      gap[i] = std::min(gap[i], std::sqrt(r2) - ball.radius);
    }
  }
  return balls;
}

void order_for_tree(std::vector<Ball>& balls, int dim) {
  const auto split = [dim](auto& self, std::vector<Ball>::iterator first,
                           std::vector<Ball>::iterator last) -> void {
    if (last - first <= 1) return;
    int axis = 0;
    double widest = -1.0;
    for (int a = 0; a < dim; ++a) {
      const auto [lo, hi] = std::minmax_element(
          first, last, [a](const Ball& x, const Ball& y) { return x.center[a] < y.center[a]; });
      if (hi->center[a] - lo->center[a] > widest) {
        widest = hi->center[a] - lo->center[a];
        axis = a;
      }
    }
    const auto mid = first + (last - first) / 2;
    std::nth_element(first, mid, last, [axis](const Ball& x, const Ball& y) {
      return x.center[axis] < y.center[axis];
    });
    self(self, first, mid);
    self(self, mid, last);
  };
  split(split, balls.begin(), balls.end());
}

bool set_leaf_to_ball(const Tree& tree, int node, const Ball& ball, bool inside, double slope,
                      std::span<double> params) {
  const Node& n = tree.node(node);
  if (n.kind != NodeKind::kPrimitive) return false;
  const double r = std::max(ball.radius, 1e-3);
  const double* c = ball.center.data();
  const PrimitiveType type = n.shape.type;
  const bool quadric = type == PrimitiveType::kQuadric3 || type == PrimitiveType::kQuadric2;
  if (!quadric && !inside) return false;
  const auto sharpness = [&](double s) {
    if (n.step.kind == StepKind::kSigmoid && n.step.param) set(params, *n.step.param, s);
  };
  const auto place = [&]() {
    if (n.placement.translate.size() != static_cast<std::size_t>(tree.dim)) return false;
    for (int a = 0; a < tree.dim; ++a) set(params, n.placement.translate[a], c[a]);
    for (ParamRef p : n.placement.rotate) set(params, p, 0.0);
    if (n.placement.scale) set(params, *n.placement.scale, 1.0);
    return true;
  };
  const double sign = inside ? 1.0 : -1.0;
  switch (type) {
    case PrimitiveType::kQuadric3: {
      // sign * (|x - c|^2 - r^2): the gradient on the sphere is 2r, so s = slope / 2r.
      const double q[10] = {sign,
                            sign,
                            sign,
                            0,
                            0,
                            0,
                            -2 * sign * c[0],
                            -2 * sign * c[1],
                            -2 * sign * c[2],
                            sign * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2] - r * r)};
      for (int i = 0; i < 10; ++i) set(params, n.intrinsic[static_cast<std::size_t>(i)], q[i]);
      sharpness(slope / (2 * r));
      return true;
    }
    case PrimitiveType::kQuadric2: {
      const double q[6] = {sign,
                           sign,
                           0,
                           -2 * sign * c[0],
                           -2 * sign * c[1],
                           sign * (c[0] * c[0] + c[1] * c[1] - r * r)};
      for (int i = 0; i < 6; ++i) set(params, n.intrinsic[static_cast<std::size_t>(i)], q[i]);
      sharpness(slope / (2 * r));
      return true;
    }
    case PrimitiveType::kSphere:
    case PrimitiveType::kCircle:
      if (!place()) return false;
      set(params, n.intrinsic[0], r);
      break;
    case PrimitiveType::kEllipsoid:
    case PrimitiveType::kEllipse:
      if (!place()) return false;
      for (ParamRef p : n.intrinsic) set(params, p, r);
      break;
    case PrimitiveType::kBox:  // the cube inscribed in the ball
      if (!place()) return false;
      for (ParamRef p : n.intrinsic) set(params, p, 2 * r / std::sqrt(3.0));
      break;
    case PrimitiveType::kRectangle:
      if (!place()) return false;
      for (ParamRef p : n.intrinsic) set(params, p, 2 * r / std::sqrt(2.0));
      break;
    case PrimitiveType::kCylinder:  // radius r/sqrt2 and height sqrt2 r fit in the ball
      if (!place()) return false;
      set(params, n.intrinsic[0], r / std::sqrt(2.0));
      set(params, n.intrinsic[1], r * std::sqrt(2.0));
      break;
    default:
      return false;
  }
  sharpness(slope);  // a signed distance: its gradient is 1
  return true;
}

std::vector<int> leaves_in_order(const Tree& tree) {
  std::vector<int> out;
  const auto walk = [&](auto& self, int i) -> void {
    const Node& n = tree.node(i);
    if (n.kind == NodeKind::kPrimitive) {
      out.push_back(i);
      return;
    }
    for (int c : n.children) self(self, c);
  };
  if (tree.root >= 0) walk(walk, tree.root);
  return out;
}

int initialise_from_target(Tree& tree, const Target& target, const TargetInitOptions& o) {
  if (target.dim() != tree.dim) {
    throw InputError("initialise_from_target: the tree and the target differ in dimension");
  }
  Rng rng(o.seed ^ 0x5851f42d4c957f2dULL);
  const BoundaryDistance distance(target, o.boundary_samples, rng);
  const std::vector<int> leaves = leaves_in_order(tree);
  std::vector<Ball> balls =
      cover_with_balls(target, distance, static_cast<int>(leaves.size()), rng, o.candidates);
  if (balls.empty()) {
    throw OptionError("init", "target: found no point inside the target to start from");
  }
  order_for_tree(balls, tree.dim);

  std::vector<double> params = tree.params.values();
  int set_count = 0;
  for (std::size_t i = 0; i < leaves.size() && i < balls.size(); ++i) {
    set_count += set_leaf_to_ball(tree, leaves[i], balls[i], true, o.slope, params) ? 1 : 0;
  }
  // Operators lean to union: sin(omega * logit) is m for union and 0 for the others, where
  // exp(m t) / (exp(m t) + 3) = union_weight.
  const double w = std::clamp(o.union_weight, 0.25, 0.999);
  const double margin = std::min(1.0, std::log(3.0 * w / (1.0 - w)) / o.temperature);
  for (Node& n : tree.nodes) {
    if (n.kind != NodeKind::kOperator) continue;
    if (n.op == OpKind::kUnified) {
      if (n.unified.size() != 4) continue;
      if (n.unified_logits) {
        const double omega = n.omega ? params[n.omega->index] : 10.0;
        for (int k = 0; k < 4; ++k) set(params, n.unified[static_cast<std::size_t>(k)], 0.0);
        set(params, n.unified[1], std::asin(margin) / omega);
      } else {
        const double c[4] = {(1 - w) / 3, w, (1 - w) / 3, (1 - w) / 3};
        for (int k = 0; k < 4; ++k) set(params, n.unified[static_cast<std::size_t>(k)], c[k]);
      }
    } else if (n.op == OpKind::kIntersection || n.op == OpKind::kDifference) {
      n.op = OpKind::kUnion;  // fixed booleans: start as the union of the balls
    }
  }
  tree.params.set_values(params);
  return set_count;
}

bool set_leaf_through_point(const Tree& tree, int node, const float* point, const float* normal,
                            double curvature, double slope, Rng& rng, std::span<double> params) {
  const Node& n = tree.node(node);
  if (n.kind != NodeKind::kPrimitive) return false;
  const auto u = [&] { return curvature * (2.0 * uniform01(rng) - 1.0); };
  if (n.shape.type == PrimitiveType::kQuadric3) {
    // f(x) = x^T A x + b.x + c with A random, b = n - 2 A p and c = -(p^T A p + b.p): then
    // f(p) = 0 and grad f(p) = n.
    const double a[6] = {u(), u(), u(), u(), u(), u()};  // xx yy zz xy yz zx coefficients
    const double px = point[0], py = point[1], pz = point[2];
    // grad of the quadratic part at p: (2 a0 x + a3 y + a5 z, 2 a1 y + a3 x + a4 z, ...)
    const double gx = 2 * a[0] * px + a[3] * py + a[5] * pz;
    const double gy = 2 * a[1] * py + a[3] * px + a[4] * pz;
    const double gz = 2 * a[2] * pz + a[4] * py + a[5] * px;
    const double b[3] = {normal[0] - gx, normal[1] - gy, normal[2] - gz};
    const double quad = a[0] * px * px + a[1] * py * py + a[2] * pz * pz + a[3] * px * py +
                        a[4] * py * pz + a[5] * pz * px;
    const double c = -(quad + b[0] * px + b[1] * py + b[2] * pz);
    const double q[10] = {a[0], a[1], a[2], a[3], a[4], a[5], b[0], b[1], b[2], c};
    for (int i = 0; i < 10; ++i) set(params, n.intrinsic[static_cast<std::size_t>(i)], q[i]);
  } else if (n.shape.type == PrimitiveType::kQuadric2) {
    const double a[3] = {u(), u(), u()};  // xx yy xy
    const double px = point[0], py = point[1];
    const double gx = 2 * a[0] * px + a[2] * py;
    const double gy = 2 * a[1] * py + a[2] * px;
    const double b[2] = {normal[0] - gx, normal[1] - gy};
    const double quad = a[0] * px * px + a[1] * py * py + a[2] * px * py;
    const double c = -(quad + b[0] * px + b[1] * py);
    const double q[6] = {a[0], a[1], a[2], b[0], b[1], c};
    for (int i = 0; i < 6; ++i) set(params, n.intrinsic[static_cast<std::size_t>(i)], q[i]);
  } else {
    return false;
  }
  if (n.step.kind == StepKind::kSigmoid && n.step.param) set(params, *n.step.param, slope);
  return true;
}

int initialise_on_surface(Tree& tree, const Target& target, const SurfaceInitOptions& o) {
  if (target.dim() != tree.dim) {
    throw InputError("initialise_on_surface: the tree and the target differ in dimension");
  }
  Rng rng(o.seed ^ 0x2545f4914f6cdd1dULL);
  const std::vector<int> leaves = leaves_in_order(tree);
  std::vector<float> points, normals;
  target.sample_boundary(leaves.size(), rng, points, normals);
  const auto d = static_cast<std::size_t>(tree.dim);
  std::vector<double> params = tree.params.values();
  int set_count = 0;
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    set_count += set_leaf_through_point(tree, leaves[i], &points[i * d], &normals[i * d],
                                        o.curvature, o.slope, rng, params)
                     ? 1
                     : 0;
  }
  tree.params.set_values(params);
  return set_count;
}

std::vector<std::size_t> leaf_parameters(const Node& n) {
  std::vector<std::size_t> out;
  for (ParamRef p : n.intrinsic) out.push_back(p.index);
  for (ParamRef p : n.placement.translate) out.push_back(p.index);
  for (ParamRef p : n.placement.rotate) out.push_back(p.index);
  if (n.placement.scale) out.push_back(n.placement.scale->index);
  if (n.step.param) out.push_back(n.step.param->index);
  return out;
}

void grow_ball(Ball& ball, const BoundaryDistance& distance, int steps) {
  const int dim = distance.dim();
  const auto d = static_cast<std::size_t>(dim);
  float c[3] = {0, 0, 0};
  for (std::size_t a = 0; a < d; ++a) c[a] = static_cast<float>(ball.center[a]);
  double r = distance(c);
  double step = 0.5 * r;
  for (int k = 0; k < steps && step > 1e-4; ++k) {
    const float* q = distance.point(distance.nearest(c));
    double len = 0.0;
    for (std::size_t a = 0; a < d; ++a) len += (c[a] - q[a]) * (c[a] - q[a]);
    len = std::sqrt(len);
    if (len <= 0.0) break;
    float t[3] = {0, 0, 0};
    for (std::size_t a = 0; a < d; ++a) {
      t[a] = static_cast<float>(std::clamp(c[a] + step * (c[a] - q[a]) / len, -1.0, 1.0));
    }
    const double rt = distance(t);
    if (rt > r) {
      std::copy(t, t + 3, c);
      r = rt;
    } else {
      step *= 0.5;
    }
  }
  for (std::size_t a = 0; a < d; ++a) ball.center[a] = c[a];
  ball.radius = r;
}

bool set_leaf_constant(const Tree& tree, int node, bool full, std::span<double> params) {
  const Node& n = tree.node(node);
  if (n.kind != NodeKind::kPrimitive) return false;
  const PrimitiveType type = n.shape.type;
  if (type == PrimitiveType::kQuadric3 || type == PrimitiveType::kQuadric2) {
    // f = +-1 everywhere, with a sharpness that saturates the sigmoid.
    for (ParamRef p : n.intrinsic) set(params, p, 0.0);
    set(params, n.intrinsic.back(), full ? -1.0 : 1.0);
    if (n.step.kind == StepKind::kSigmoid && n.step.param) set(params, *n.step.param, 60.0);
    return true;
  }
  if (full || n.placement.translate.size() != static_cast<std::size_t>(tree.dim)) return false;
  for (ParamRef p : n.placement.translate) set(params, p, 1e3);  // far away: empty
  return true;
}

ReseedReport reseed_dead_leaves(const Tree& model, const Evaluator& evaluator, const Target& target,
                                const BoundaryDistance& distance, std::span<double> params,
                                std::span<double> adam_m, std::span<double> adam_v,
                                const ReseedOptions& o, Rng& rng) {
  ReseedReport report;
  const std::vector<int> leaves = leaves_in_order(model);
  if (leaves.empty()) return report;
  std::vector<std::vector<std::size_t>> owned(leaves.size());
  for (std::size_t i = 0; i < leaves.size(); ++i) owned[i] = leaf_parameters(model.node(leaves[i]));

  // Judged on points near the surface and uniform ones: points exactly on it cost about 1/4
  // whatever the model, and tell nothing.
  SamplingOptions judge;
  judge.surface = 0.0;
  judge.near = 0.5;
  judge.near_distance = o.near_distance;
  const SampleSet s = draw_samples(target, o.points, judge, rng);
  const std::size_t n = s.size();
  const auto d = static_cast<std::size_t>(model.dim);
  std::vector<float> occ(n), trial(n);
  const auto loss_of = [&](const std::vector<float>& v) {
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double e = static_cast<double>(v[i]) - s.occupancy[i];
      sum += e * e;
    }
    return sum / static_cast<double>(n);
  };
  const auto distance_of = [&](const std::vector<float>& a, const std::vector<float>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double e = static_cast<double>(a[i]) - b[i];
      sum += e * e;
    }
    return sum / static_cast<double>(n);
  };
  evaluator.forward(params, s.points, occ);
  double loss = loss_of(occ);
  report.loss_before = loss;

  // Dead: a leaf that can be replaced by a constant (empty, or full) with the tree's output
  // changing by less than the threshold, mean squared: what pruning would remove.
  std::vector<std::size_t> order(leaves.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  for (std::size_t i = order.size(); i > 1; --i)
    std::swap(order[i - 1], order[uniform_index(rng, i)]);
  if (order.size() > o.max_tested) order.resize(o.max_tested);
  std::vector<double> saved;
  const auto save = [&](std::size_t leaf) {
    saved.clear();
    for (std::size_t p : owned[leaf]) saved.push_back(params[p]);
  };
  const auto restore = [&](std::size_t leaf) {
    for (std::size_t j = 0; j < owned[leaf].size(); ++j) params[owned[leaf][j]] = saved[j];
  };
  // A dead leaf that neither emptying nor filling changes at all is masked by its ancestors
  // (under an intersection with nothing, say): no move of it can help, and it is not tried.
  // The others are tried in the random order of `order`.
  std::vector<std::size_t> dead;
  for (std::size_t leaf : order) {
    save(leaf);
    double least = std::numeric_limits<double>::infinity(), most = 0.0;
    bool both = true;
    for (bool full : {false, true}) {
      if (!set_leaf_constant(model, leaves[leaf], full, params)) {
        both = false;
        continue;
      }
      evaluator.forward(params, s.points, trial);
      const double change = distance_of(trial, occ);
      least = std::min(least, change);
      most = std::max(most, change);
      restore(leaf);
    }
    if (least >= o.threshold) continue;
    ++report.dead;
    if (both && most < o.masked) continue;
    dead.push_back(leaf);
  }
  if (dead.size() > static_cast<std::size_t>(o.max_leaves)) {
    dead.resize(static_cast<std::size_t>(o.max_leaves));
  }

  struct Move {
    enum Kind { kBall, kPatch } kind;
    Ball ball;
    bool inside;
    std::size_t boundary;  // kPatch: the boundary sample the quadric passes through
  };
  for (const std::size_t leaf : dead) {
    // Where the model is wrong now: missed inside (false negatives), covered outside (false
    // positives).
    std::vector<std::size_t> missed, spurious;
    for (std::size_t i = 0; i < n; ++i) {
      if (s.occupancy[i] > 0.5f && occ[i] < 0.5f) missed.push_back(i);
      if (s.occupancy[i] < 0.5f && occ[i] > 0.5f) spurious.push_back(i);
    }
    if (missed.empty() && spurious.empty()) break;
    // Of a few wrong points drawn at random, the one deepest in the wrong region (farthest
    // from the boundary): a ball there can fix the most.
    const auto pick = [&](const std::vector<std::size_t>& where) {
      std::size_t best = where[uniform_index(rng, where.size())];
      double depth = distance(&s.points[best * d]);
      for (int k = 1; k < o.candidates; ++k) {
        const std::size_t i = where[uniform_index(rng, where.size())];
        const double di = distance(&s.points[i * d]);
        if (di > depth) {
          best = i;
          depth = di;
        }
      }
      return best;
    };
    const auto ball_at = [&](std::size_t i) {
      Ball b;
      for (std::size_t a = 0; a < d; ++a) b.center[a] = s.points[i * d + a];
      b.radius = distance(&s.points[i * d]);
      grow_ball(b, distance);
      b.radius = std::clamp(b.radius, o.min_radius, o.max_radius);
      return b;
    };
    std::vector<Move> moves;
    if (!missed.empty()) {
      const std::size_t i = pick(missed);
      moves.push_back({Move::kBall, ball_at(i), true, 0});
      moves.push_back({Move::kPatch, {}, true, distance.nearest(&s.points[i * d])});
    }
    if (!spurious.empty()) {
      const std::size_t i = pick(spurious);
      moves.push_back({Move::kBall, ball_at(i), true, 0});  // a ball a difference takes away
      moves.push_back(
          {Move::kBall, ball_at(i), false, 0});  // all but the ball, for an intersection
      moves.push_back({Move::kPatch, {}, true, distance.nearest(&s.points[i * d])});
    }
    save(leaf);
    double best_loss = loss - o.min_gain;
    std::vector<double> best_params;
    std::vector<float> best_occ;
    for (const Move& mv : moves) {
      const bool ok =
          mv.kind == Move::kBall
              ? set_leaf_to_ball(model, leaves[leaf], mv.ball, mv.inside, o.slope, params)
              : set_leaf_through_point(model, leaves[leaf], distance.point(mv.boundary),
                                       distance.normal(mv.boundary), o.curvature, o.patch_slope,
                                       rng, params);
      if (!ok) continue;
      evaluator.forward(params, s.points, trial);
      const double l = loss_of(trial);
      if (l < best_loss) {
        best_loss = l;
        best_occ = trial;
        best_params.clear();
        for (std::size_t p : owned[leaf]) best_params.push_back(params[p]);
      }
      restore(leaf);
    }
    ++report.tried;
    if (best_params.empty()) continue;
    for (std::size_t j = 0; j < owned[leaf].size(); ++j) {
      params[owned[leaf][j]] = best_params[j];
      adam_m[owned[leaf][j]] = adam_v[owned[leaf][j]] = 0.0;
    }
    occ = std::move(best_occ);
    loss = best_loss;
    ++report.moved;
  }
  report.loss_after = loss;
  return report;
}

}  // namespace fuzzycsg
