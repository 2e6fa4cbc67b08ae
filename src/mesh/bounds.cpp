#include "bounds.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "fuzzycsg/core/bspline.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/placement.hpp"
#include "fuzzycsg/core/primitives.hpp"
#include "fuzzycsg/core/steps.hpp"

namespace fuzzycsg {

// Types of BoundsProgram::Impl (named, not anonymous: a member's type must not have internal
// linkage).
namespace bounds_detail {

constexpr double kInf = std::numeric_limits<double>::infinity();

enum class LeafBound { kLipschitz, kQuadric, kNone };

// A node with its numbers resolved.
struct Item {
  int node = -1;
  std::vector<int> children;
  bool leaf = false;
  // leaves
  LeafBound bound = LeafBound::kNone;
  const PrimitiveShape* shape = nullptr;
  std::vector<double> theta;
  bool has_rotate = false;
  std::array<double, 9> rotation{};  // row-major R (2D: embedded in the top-left 2x2)
  std::array<double, 3> translate{};
  double scale = 1.0;
  StepKind step = StepKind::kSigmoid;
  int step_n = 0;
  double step_param = 1.0;
  // operators
  OpKind op = OpKind::kUnion;
  logic::Family family = logic::Family::kProduct;
  double p = 0.0;
  int n = 0;
  logic::Complement complement = logic::Complement::kStandard;
  double lambda = 0.0;
  std::array<double, 4> weights{};  // B_c's c
  // spline
  std::vector<int> cells;
  int degree = 0;
  std::array<double, 3> box_lo{}, box_scale{};
};

}  // namespace bounds_detail

using bounds_detail::Item;
using bounds_detail::kInf;
using bounds_detail::LeafBound;

struct BoundsProgram::Impl {
  int dim = 3;
  std::size_t nodes = 0;
  int root = 0;
  std::vector<Item> items;  // post-order

  double step(const Item& it, double f) const {
    switch (it.step) {
      case StepKind::kSigmoid:
        return 1.0 / (1.0 + std::exp(it.step_param * f));
      case StepKind::kCrisp:
        return f < 0 ? 1.0 : (f > 0 ? 0.0 : 0.5);
      case StepKind::kHn:
        return steps::hn(it.step_n, it.step_n * -f / it.step_param);
    }
    return 0.5;
  }

  // Bounds of f (world frame) over the box given by its centre and half-extents.
  Interval implicit(const Item& it, const std::array<double, 3>& centre,
                    const std::array<double, 3>& half) const {
    if (it.bound == LeafBound::kNone) return {-kInf, kInf};
    // The box in the leaf's frame (p_local = R^T (p - t) / s): its centre exactly, its
    // half-extents as those of the bounding box of the rotated box.
    std::array<double, 3> c{}, h = half;
    for (int i = 0; i < dim; ++i) c[i] = centre[i] - it.translate[i];
    if (it.has_rotate) {
      const std::array<double, 3> d = c;
      for (int i = 0; i < dim; ++i) {
        c[i] = 0.0;
        h[i] = 0.0;
        for (int j = 0; j < dim; ++j) {
          c[i] += it.rotation[3 * j + i] * d[j];
          h[i] += std::abs(it.rotation[3 * j + i]) * half[j];
        }
      }
    }
    for (int i = 0; i < dim; ++i) {
      c[i] /= it.scale;
      h[i] /= it.scale;
    }
    const double s = it.scale;
    if (it.bound == LeafBound::kLipschitz) {
      double r2 = 0.0;
      for (int i = 0; i < dim; ++i) r2 += half[i] * half[i];
      const double f = s * primitive_value<double>(*it.shape, it.theta, c.data());
      const double r = std::sqrt(r2);
      return {f - r, f + r};
    }
    // Quadric: f(c + d) = f(c) + grad . d + d^T A d (primitives.cpp's monomial order).
    const auto& q = it.theta;
    double f = 0.0, lin = 0.0, qlo = 0.0, qhi = 0.0;
    if (dim == 3) {
      const double x = c[0], y = c[1], z = c[2];
      f = q[0] * x * x + q[1] * y * y + q[2] * z * z + q[3] * x * y + q[4] * y * z + q[5] * z * x +
          q[6] * x + q[7] * y + q[8] * z + q[9];
      const double g0 = 2 * q[0] * x + q[3] * y + q[5] * z + q[6];
      const double g1 = 2 * q[1] * y + q[3] * x + q[4] * z + q[7];
      const double g2 = 2 * q[2] * z + q[4] * y + q[5] * x + q[8];
      lin = std::abs(g0) * h[0] + std::abs(g1) * h[1] + std::abs(g2) * h[2];
      const double off = std::abs(q[3]) * h[0] * h[1] + std::abs(q[4]) * h[1] * h[2] +
                         std::abs(q[5]) * h[2] * h[0];
      qlo = -off;
      qhi = off;
      for (int i = 0; i < 3; ++i) {
        const double t = q[static_cast<std::size_t>(i)] * h[i] * h[i];
        (t < 0 ? qlo : qhi) += t;
      }
    } else {
      const double x = c[0], y = c[1];
      f = q[0] * x * x + q[1] * y * y + q[2] * x * y + q[3] * x + q[4] * y + q[5];
      const double g0 = 2 * q[0] * x + q[2] * y + q[3];
      const double g1 = 2 * q[1] * y + q[2] * x + q[4];
      lin = std::abs(g0) * h[0] + std::abs(g1) * h[1];
      const double off = std::abs(q[2]) * h[0] * h[1];
      qlo = -off;
      qhi = off;
      for (int i = 0; i < 2; ++i) {
        const double t = q[static_cast<std::size_t>(i)] * h[i] * h[i];
        (t < 0 ? qlo : qhi) += t;
      }
    }
    return {s * (f - lin + qlo), s * (f + lin + qhi)};
  }

  // F = sum_k B_k L_k with sum_k B_k = 1 at every point. Over the box each weight lies in
  // [w_lo, w_hi] (products of the axes' basis ranges; 0 for the children whose basis vanishes
  // there) and each L_k in its bounds, so F lies within the extremes of sum_k w_k L_k over
  // weights in those ranges summing to 1: a fractional knapsack, solved greedily (the weight
  // beyond the w_lo goes to the children with the largest hi for the upper bound, the smallest
  // lo for the lower). This is never wider than the hull of the children's bounds.
  Interval spline(const Item& it, const double* lo, const double* hi,
                  const std::vector<Interval>& v) const {
    // Per axis, the range of each basis function over the box.
    std::array<std::vector<std::array<double, 2>>, 3> ranges;
    for (std::size_t axis = 0; axis < static_cast<std::size_t>(dim); ++axis) {
      const int n = it.cells[axis];
      double a = 0.0, b = 0.0;
      bspline::parameter_interval(lo[axis], hi[axis], it.box_lo[axis], it.box_scale[axis],
                                  n - it.degree, a, b);
      ranges[axis].resize(static_cast<std::size_t>(n));
      for (int i = 0; i < n; ++i) {
        auto& r = ranges[axis][static_cast<std::size_t>(i)];
        bspline::basis_range(i, n, it.degree, a, b, r[0], r[1]);
      }
    }
    struct Term {
      double w_lo, w_hi;
      Interval value;
    };
    std::vector<Term> terms;
    double base = 0.0;  // sum of the w_lo
    for (std::size_t k = 0; k < it.children.size(); ++k) {
      double w_lo = 1.0, w_hi = 1.0;
      std::size_t rest = k;
      for (std::size_t axis = 0; axis < static_cast<std::size_t>(dim); ++axis) {
        const auto n = static_cast<std::size_t>(it.cells[axis]);
        const auto& r = ranges[axis][rest % n];
        rest /= n;
        w_lo *= r[0];
        w_hi *= r[1];
      }
      if (w_hi <= 0.0) continue;
      terms.push_back({w_lo, w_hi, v[static_cast<std::size_t>(it.children[k])]});
      base += w_lo;
    }
    if (terms.empty()) return {0.0, 1.0};
    Interval hull{kInf, -kInf};
    for (const Term& t : terms) {
      hull.lo = std::min(hull.lo, t.value.lo);
      hull.hi = std::max(hull.hi, t.value.hi);
    }
    const double spare = 1.0 - base;
    // Rounding could leave the ranges inconsistent with sum 1: then the hull.
    if (!(spare >= -1e-12)) return hull;
    const auto extreme = [&](bool upper) {
      std::sort(terms.begin(), terms.end(), [&](const Term& x, const Term& y) {
        return upper ? x.value.hi > y.value.hi : x.value.lo < y.value.lo;
      });
      double sum = 0.0, left = std::max(spare, 0.0);
      for (const Term& t : terms) {
        const double value = upper ? t.value.hi : t.value.lo;
        const double extra = std::min(left, t.w_hi - t.w_lo);
        sum += (t.w_lo + extra) * value;
        left -= extra;
      }
      // Weight the ranges could not place (only by rounding) goes to the extreme child.
      return sum + left * (upper ? hull.hi : hull.lo);
    };
    const Interval r{extreme(false), extreme(true)};
    return {std::max(r.lo, hull.lo), std::min(r.hi, hull.hi)};
  }

  Interval binary(const Item& it, Interval x, Interval y) const {
    // Li & Tian's hat-AND is not monotone (its corner term bends it): no bound but [0, 1].
    if (it.family == logic::Family::kLiTianHat && it.op != OpKind::kUnified) return {0.0, 1.0};
    switch (it.op) {
      case OpKind::kUnion:
        return {logic::tconorm(it.family, x.lo, y.lo, it.p, it.n),
                logic::tconorm(it.family, x.hi, y.hi, it.p, it.n)};
      case OpKind::kIntersection:
        return {logic::tnorm(it.family, x.lo, y.lo, it.p, it.n),
                logic::tnorm(it.family, x.hi, y.hi, it.p, it.n)};
      case OpKind::kDifference: {
        // The complement is non-increasing.
        const double cy_lo = logic::complement(it.complement, y.hi, it.lambda);
        const double cy_hi = logic::complement(it.complement, y.lo, it.lambda);
        return {logic::tnorm(it.family, x.lo, cy_lo, it.p, it.n),
                logic::tnorm(it.family, x.hi, cy_hi, it.p, it.n)};
      }
      case OpKind::kUnified: {
        // Bilinear: the extremes over the box lie at its corners.
        Interval r{kInf, -kInf};
        for (double a : {x.lo, x.hi}) {
          for (double b : {y.lo, y.hi}) {
            const double o = logic::unified(it.weights, a, b);
            r.lo = std::min(r.lo, o);
            r.hi = std::max(r.hi, o);
          }
        }
        return r;
      }
      case OpKind::kComplement:
      case OpKind::kSpline:
        break;
    }
    throw Error("BoundsProgram: not a binary operator");
  }
};

BoundsProgram::BoundsProgram(const Tree& tree, std::span<const double> params)
    : impl_(std::make_unique<Impl>()) {
  if (params.size() != tree.params.size()) {
    throw InputError("BoundsProgram: params has " + std::to_string(params.size()) +
                     " entries, expected " + std::to_string(tree.params.size()));
  }
  Impl& m = *impl_;
  m.dim = tree.dim;
  m.nodes = tree.nodes.size();
  m.root = tree.root;
  const auto get = [&](ParamRef r) { return params[r.index]; };
  const auto get_or = [&](const std::optional<ParamRef>& r, double v) {
    return r ? params[r->index] : v;
  };
  // Post-order by an explicit stack (trees can be deep).
  std::vector<std::pair<int, bool>> stack{{tree.root, false}};
  while (!stack.empty()) {
    auto [index, expanded] = stack.back();
    stack.pop_back();
    const Node& node = tree.node(index);
    if (!expanded && node.kind == NodeKind::kOperator) {
      stack.push_back({index, true});
      for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) {
        stack.push_back({*c, false});
      }
      continue;
    }
    Item it;
    it.node = index;
    it.children = node.children;
    if (node.kind == NodeKind::kPrimitive) {
      it.leaf = true;
      const PrimitiveInfo& info = primitive_info(node.shape.type);
      it.shape = &node.shape;
      it.bound = info.exact_distance ? LeafBound::kLipschitz
                 : (node.shape.type == PrimitiveType::kQuadric3 ||
                    node.shape.type == PrimitiveType::kQuadric2)
                     ? LeafBound::kQuadric
                     : LeafBound::kNone;
      for (ParamRef r : node.intrinsic) it.theta.push_back(get(r));
      const auto& pl = node.placement;
      for (std::size_t i = 0; i < pl.translate.size(); ++i) it.translate[i] = get(pl.translate[i]);
      if (!pl.rotate.empty()) {
        it.has_rotate = true;
        if (tree.dim == 3) {
          it.rotation =
              placement::rotation_3d(get(pl.rotate[0]), get(pl.rotate[1]), get(pl.rotate[2]));
        } else {
          const auto r2 = placement::rotation_2d(get(pl.rotate[0]));
          it.rotation = {r2[0], r2[1], 0, r2[2], r2[3], 0, 0, 0, 1};
        }
      }
      if (pl.scale) it.scale = get(*pl.scale);
      it.step = node.step.kind;
      it.step_n = node.step.n;
      it.step_param = get_or(node.step.param, 1.0);
    } else {
      it.op = node.op;
      it.family = node.logic.family;
      it.p = get_or(node.logic.p, 0.0);
      it.n = node.logic.n;
      it.complement = node.complement.kind;
      it.lambda = get_or(node.complement.lambda, 0.0);
      if (node.op == OpKind::kSpline) {
        it.cells = node.spline_cells;
        it.degree = node.spline_degree;
        const Domain box = tree.spline_box(node);
        for (std::size_t a = 0; a < static_cast<std::size_t>(tree.dim); ++a) {
          it.box_lo[a] = box.min[a];
          it.box_scale[a] = (node.spline_cells[a] - node.spline_degree) / (box.max[a] - box.min[a]);
        }
      }
      if (node.op == OpKind::kUnified) {
        std::array<double, 4> v{};
        for (int i = 0; i < 4; ++i) v[i] = get(node.unified[static_cast<std::size_t>(i)]);
        it.weights = node.unified_logits
                         ? logic::unified_weights(v, get_or(node.temperature, 1000.0),
                                                  get_or(node.omega, 10.0))
                         : v;
      }
    }
    m.items.push_back(std::move(it));
  }
}

BoundsProgram::~BoundsProgram() = default;
BoundsProgram::BoundsProgram(BoundsProgram&&) noexcept = default;
BoundsProgram& BoundsProgram::operator=(BoundsProgram&&) noexcept = default;

Interval BoundsProgram::bound(const double* lo, const double* hi,
                              std::vector<Interval>* per_node) const {
  const Impl& m = *impl_;
  std::array<double, 3> centre{}, half{};
  for (int i = 0; i < m.dim; ++i) {
    centre[i] = 0.5 * (lo[i] + hi[i]);
    half[i] = 0.5 * (hi[i] - lo[i]);
  }
  std::vector<Interval> local;
  std::vector<Interval>& v = per_node ? *per_node : local;
  v.assign(m.nodes, Interval{});
  // Rounding in the operators can leave a bound a few ulps outside [0, 1] or reversed by as
  // much; widen by a little so that every bound stays conservative.
  constexpr double kSlack = 1e-9;
  const auto tidy = [](Interval r) {
    return Interval{std::max(0.0, std::min(r.lo, r.hi) - kSlack),
                    std::min(1.0, std::max(r.lo, r.hi) + kSlack)};
  };
  for (const Item& it : m.items) {
    Interval r;
    if (it.leaf) {
      const Interval f = m.implicit(it, centre, half);
      r = (f.lo > -kInf && f.hi < kInf) ? Interval{m.step(it, f.hi), m.step(it, f.lo)}
                                        : Interval{0.0, 1.0};
    } else if (it.op == OpKind::kComplement) {
      const Interval x = v[static_cast<std::size_t>(it.children[0])];
      r = {logic::complement(it.complement, x.hi, it.lambda),
           logic::complement(it.complement, x.lo, it.lambda)};
    } else if (it.op == OpKind::kSpline) {
      r = m.spline(it, lo, hi, v);
    } else {
      r = v[static_cast<std::size_t>(it.children[0])];
      for (std::size_t i = 1; i < it.children.size(); ++i) {
        r = m.binary(it, r, v[static_cast<std::size_t>(it.children[i])]);
      }
    }
    v[static_cast<std::size_t>(it.node)] = tidy(r);
  }
  return v[static_cast<std::size_t>(m.root)];
}

Interval occupancy_bounds(const Tree& tree, std::span<const double> params, const double* lo,
                          const double* hi) {
  return BoundsProgram(tree, params).bound(lo, hi);
}

}  // namespace fuzzycsg
