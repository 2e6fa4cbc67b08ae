#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "bounds.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/limits.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/mesh/mesh.hpp"
#include "reduce.hpp"

namespace fuzzycsg {

namespace {

// Boxes whose bounds are within this of the level are refined, not skipped: the bounds are
// computed in double, the grid in float, and the two must never disagree on a side.
constexpr double kMargin = 1e-4;
// A subtree becomes a constant in a brick when it cannot move the root by more than kTau there
// (reduce.hpp); a brick's simplified tree is then within (subtrees replaced) x kTau of the tree.
constexpr double kTau = 1e-5;
// Float evaluation of the simplified and the whole tree may differ by rounding too.
constexpr double kRoundingSlack = 1e-5;
// A simplified tree with more than this share of the leaves is not worth compiling.
constexpr double kSimplifyShare = 0.5;
// A vertex that would lie on a grid point (a value exactly at the level, or an interpolation
// that rounds onto an end of its edge) is put this fraction of its edge from that end instead.
constexpr double kVertexInset = 1e-3;

struct Grid {
  int dim = 3;
  std::array<int, 3> n{1, 1, 1};  // cells per axis
  std::array<double, 3> min{}, max{};
  double coordinate(int axis, int i) const {
    return min[axis] + (max[axis] - min[axis]) * static_cast<double>(i) / n[axis];
  }
  float fcoordinate(int axis, int i) const { return static_cast<float>(coordinate(axis, i)); }
  std::uint64_t id(int i, int j, int k) const {
    return (static_cast<std::uint64_t>(i) * static_cast<std::uint64_t>(n[1] + 1) +
            static_cast<std::uint64_t>(j)) *
               static_cast<std::uint64_t>(n[2] + 1) +
           static_cast<std::uint64_t>(k);
  }
  bool on_boundary(int axis, int i) const { return i == 0 || i == n[axis]; }
};

Grid make_grid(const Tree& tree, const MeshOptions& o) {
  if (o.resolution < 1 || o.resolution > kMaxMeshResolution) {
    throw InputError(
        fmt::format("resolution must be in [1, {}] (got {})", kMaxMeshResolution, o.resolution));
  }
  if (o.brick < 1 || o.brick > 64) {
    throw InputError(fmt::format("brick must be in [1, 64] (got {})", o.brick));
  }
  const Domain d = tree.domain_or_default();
  Grid g;
  g.dim = tree.dim;
  double longest = 0.0;
  for (int a = 0; a < g.dim; ++a) {
    if (!(d.max[a] > d.min[a]) || !std::isfinite(d.max[a] - d.min[a])) {
      throw InputError("the tree's domain is empty along an axis");
    }
    longest = std::max(longest, d.max[a] - d.min[a]);
  }
  for (int a = 0; a < g.dim; ++a) {
    g.min[a] = d.min[a];
    g.max[a] = d.max[a];
    g.n[a] =
        std::max(1, static_cast<int>(std::lround(o.resolution * (d.max[a] - d.min[a]) / longest)));
  }
  if (g.dim == 2) {
    g.n[2] = 0;  // one layer of points
    g.min[2] = g.max[2] = 0.0;
  }
  return g;
}

// A box of cells [lo, hi) per axis.
struct CellBox {
  std::array<int, 3> lo{}, hi{};
};

class Extractor {
 public:
  Extractor(const Tree& tree, std::span<const double> params, const MeshOptions& o)
      : params_(params),
        o_(o),
        grid_(make_grid(tree, o)),
        bounds_(tree, params),
        simplify_(o.simplify && o.prune && mesh_detail::reducible(tree)),
        reducer_(tree, params),
        evaluator_(tree, EvalOptions{o.threads}) {
    for (const Node& n : tree.nodes) leaves_ += n.kind == NodeKind::kPrimitive ? 1 : 0;
  }

  const Grid& grid() const { return grid_; }

  // The bricks that can hold the level, in a fixed order.
  std::vector<CellBox> active_bricks(MeshStats& stats) const {
    const int axes = grid_.dim;
    std::vector<CellBox> level{
        CellBox{{0, 0, 0}, {grid_.n[0], grid_.n[1], std::max(grid_.n[2], 0)}}};
    std::vector<CellBox> bricks;
    while (!level.empty()) {
      std::vector<int> keep(level.size());  // 0 skip, 1 brick, 2 split
      tbb::parallel_for(std::size_t{0}, level.size(), [&](std::size_t b) {
        const CellBox& box = level[b];
        bool small = true;
        for (int a = 0; a < axes; ++a) small = small && box.hi[a] - box.lo[a] <= o_.brick;
        keep[b] = (!o_.prune || may_hold_level(box)) ? (small ? 1 : 2) : 0;
      });
      if (o_.prune) stats.boxes_bounded += level.size();
      std::vector<CellBox> next;
      for (std::size_t b = 0; b < level.size(); ++b) {
        if (keep[b] == 1) bricks.push_back(level[b]);
        if (keep[b] != 2) continue;
        // Split every axis longer than a brick at a multiple of the brick size.
        std::array<std::array<int, 3>, 3> cuts{};  // per axis: lo, mid, hi (mid == hi: no cut)
        for (int a = 0; a < 3; ++a) {
          const int lo = level[b].lo[a], hi = level[b].hi[a];
          const int len = hi - lo;
          int mid = hi;
          if (a < axes && len > o_.brick) {
            mid = lo + o_.brick * ((len / o_.brick + 1) / 2);
            if (mid >= hi) mid = lo + o_.brick;
          }
          cuts[a] = {lo, mid, hi};
        }
        for (int i = 0; i < 2; ++i) {
          for (int j = 0; j < 2; ++j) {
            for (int k = 0; k < 2; ++k) {
              const std::array<int, 3> part{i, j, k};
              CellBox child;
              bool empty = false;
              for (int a = 0; a < 3; ++a) {
                child.lo[a] = cuts[a][part[a]];
                child.hi[a] = cuts[a][part[a] + 1];
                empty = empty || (child.hi[a] <= child.lo[a] && !(a >= axes && part[a] == 0));
              }
              if (!empty) next.push_back(child);
            }
          }
        }
      }
      level = std::move(next);
    }
    std::sort(bricks.begin(), bricks.end(),
              [](const CellBox& x, const CellBox& y) { return x.lo < y.lo; });
    return bricks;
  }

  // The points of `box` ((hi - lo + 1) per axis, x slowest).
  std::vector<float> brick_points(const CellBox& box) const {
    const int dim = grid_.dim;
    std::vector<float> points(point_count(box) * static_cast<std::size_t>(dim));
    float* p = points.data();
    for (int i = box.lo[0]; i <= box.hi[0]; ++i) {
      for (int j = box.lo[1]; j <= box.hi[1]; ++j) {
        for (int k = box.lo[2]; k <= box.hi[2]; ++k) {
          *p++ = grid_.fcoordinate(0, i);
          *p++ = grid_.fcoordinate(1, j);
          if (dim == 3) *p++ = grid_.fcoordinate(2, k);
        }
      }
    }
    return points;
  }

  // One brick's values from the tree simplified for it, when that is small enough; `recheck`
  // receives the points too near the level to trust it with. False: evaluate the whole tree.
  bool evaluate_simplified(const CellBox& box, std::vector<float>& values,
                           std::vector<std::uint32_t>& recheck, MeshStats& stats) const {
    if (!simplify_) return false;
    const int dim = grid_.dim;
    std::array<double, 3> lo{}, hi{};
    for (int a = 0; a < dim; ++a) {
      lo[a] = grid_.coordinate(a, box.lo[a]);
      hi[a] = grid_.coordinate(a, box.hi[a]);
    }
    std::vector<Interval> per_node;
    bounds_.bound(lo.data(), hi.data(), &per_node);
    const mesh_detail::Reduced r = reducer_.reduce(
        per_node, kTau, static_cast<int>(kSimplifyShare * static_cast<double>(leaves_)), lo.data(),
        hi.data());
    if (r.tree.root < 0) return false;
    const std::vector<float> points = brick_points(box);
    values.resize(point_count(box));
    const Evaluator simple(r.tree, EvalOptions{1});
    simple.forward(r.tree.params.values(), points, values);
    const double guard = r.error + kRoundingSlack;
    for (std::size_t v = 0; v < values.size(); ++v) {
      if (std::abs(values[v] - o_.level) <= guard) recheck.push_back(static_cast<std::uint32_t>(v));
    }
    stats.leaves_evaluated += static_cast<std::size_t>(r.leaves);
    stats.points_rechecked += recheck.size();
    return true;
  }

  // Every brick's values: simplified trees in parallel, then the whole tree on the rest and on
  // the points to recheck, in batches; the points on the domain's boundary are set to 0.
  std::vector<std::vector<float>> evaluate(std::span<const CellBox> bricks,
                                           MeshStats& stats) const {
    const int dim = grid_.dim;
    std::vector<std::vector<float>> values(bricks.size());
    std::vector<std::vector<std::uint32_t>> recheck(bricks.size());
    std::vector<char> whole(bricks.size(), 1);
    tbb::enumerable_thread_specific<MeshStats> counts;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, bricks.size(), 1), [&](const auto& range) {
      MeshStats& c = counts.local();
      for (std::size_t b = range.begin(); b != range.end(); ++b) {
        whole[b] = evaluate_simplified(bricks[b], values[b], recheck[b], c) ? 0 : 1;
      }
    });
    for (const MeshStats& c : counts) {
      stats.leaves_evaluated += c.leaves_evaluated;
      stats.points_rechecked += c.points_rechecked;
    }
    // The whole tree, in batches of about kBatchPoints points.
    constexpr std::size_t kBatchPoints = std::size_t{1} << 20;
    const std::vector<double> all(params_.begin(), params_.end());
    for (std::size_t first = 0; first < bricks.size();) {
      std::vector<float> points;
      std::size_t last = first;
      for (; last < bricks.size() && points.size() < kBatchPoints * dim; ++last) {
        if (whole[last]) {
          const std::vector<float> p = brick_points(bricks[last]);
          points.insert(points.end(), p.begin(), p.end());
          stats.leaves_evaluated += static_cast<std::size_t>(leaves_);
        } else if (!recheck[last].empty()) {
          const std::vector<float> p = brick_points(bricks[last]);
          for (std::uint32_t v : recheck[last]) {
            points.insert(points.end(), p.begin() + v * dim, p.begin() + (v + 1) * dim);
          }
        }
      }
      std::vector<float> out(points.size() / static_cast<std::size_t>(dim));
      if (!out.empty()) evaluator_.forward(all, points, out);
      std::size_t at = 0;
      for (std::size_t b = first; b < last; ++b) {
        if (whole[b]) {
          const std::size_t n = point_count(bricks[b]);
          values[b].assign(out.begin() + static_cast<std::ptrdiff_t>(at),
                           out.begin() + static_cast<std::ptrdiff_t>(at + n));
          at += n;
        } else {
          for (std::uint32_t v : recheck[b]) values[b][v] = out[at++];
        }
      }
      first = last;
    }
    for (std::size_t b = 0; b < bricks.size(); ++b) {
      stats.points_evaluated += values[b].size();
      const CellBox& box = bricks[b];
      float* v = values[b].data();
      for (int i = box.lo[0]; i <= box.hi[0]; ++i) {
        for (int j = box.lo[1]; j <= box.hi[1]; ++j) {
          for (int k = box.lo[2]; k <= box.hi[2]; ++k, ++v) {
            if (grid_.on_boundary(0, i) || grid_.on_boundary(1, j) ||
                (dim == 3 && grid_.on_boundary(2, k))) {
              *v = 0.0f;
            }
          }
        }
      }
    }
    return values;
  }

  static std::size_t point_count(const CellBox& b) {
    return static_cast<std::size_t>(b.hi[0] - b.lo[0] + 1) *
           static_cast<std::size_t>(b.hi[1] - b.lo[1] + 1) *
           static_cast<std::size_t>(b.hi[2] - b.lo[2] + 1);
  }

 private:
  bool may_hold_level(const CellBox& box) const {
    std::array<double, 3> lo{}, hi{};
    bool boundary = false;
    for (int a = 0; a < grid_.dim; ++a) {
      lo[a] = grid_.coordinate(a, box.lo[a]);
      hi[a] = grid_.coordinate(a, box.hi[a]);
      boundary = boundary || box.lo[a] == 0 || box.hi[a] == grid_.n[a];
    }
    const Interval r = bounds_.bound(lo.data(), hi.data());
    if (r.hi < o_.level - kMargin) return false;               // outside throughout
    if (r.lo > o_.level + kMargin && !boundary) return false;  // inside throughout
    return true;
  }

  std::span<const double> params_;
  MeshOptions o_;
  Grid grid_;
  BoundsProgram bounds_;
  bool simplify_;
  mesh_detail::Reducer reducer_;
  int leaves_ = 0;
  Evaluator evaluator_;
};

// The vertices a brick made, keyed by their grid edge, and its triangles (or segments) in
// indices into them.
template <int kDim>
struct Piece {
  std::vector<std::uint64_t> keys;
  std::vector<std::array<float, kDim>> positions;
  std::vector<std::array<int, kDim>> elements;
};

template <int kDim>
class PieceBuilder {
 public:
  PieceBuilder(const Grid& g, const CellBox& box, const float* values, float level)
      : g_(g), box_(box), values_(values), level_(level) {
    for (int a = 0; a < 3; ++a) extent_[a] = box.hi[a] - box.lo[a] + 1;
  }

  // Value and position of the brick point at grid indices (i, j, k).
  float value(const std::array<int, 3>& q) const {
    const int i = q[0] - box_.lo[0], j = q[1] - box_.lo[1], k = q[2] - box_.lo[2];
    return values_[(static_cast<std::size_t>(i) * extent_[1] + j) * extent_[2] + k];
  }
  std::array<double, 3> position(const std::array<int, 3>& q) const {
    return {g_.coordinate(0, q[0]), g_.coordinate(1, q[1]),
            kDim == 3 ? g_.coordinate(2, q[2]) : 0.0};
  }
  bool inside(const std::array<int, 3>& q) const { return value(q) >= level_; }

  // The vertex on the edge between grid points a and b (b - a in {0, 1}^3), created once.
  int vertex(const std::array<int, 3>& a, const std::array<int, 3>& b) {
    const bool forward = b[0] >= a[0] && b[1] >= a[1] && b[2] >= a[2];
    const std::array<int, 3>& lo = forward ? a : b;
    const std::array<int, 3>& hi = forward ? b : a;
    const int code = (hi[0] - lo[0]) | ((hi[1] - lo[1]) << 1) | ((hi[2] - lo[2]) << 2);
    const std::uint64_t key = g_.id(lo[0], lo[1], lo[2]) * 8 + static_cast<std::uint64_t>(code);
    auto [it, fresh] = local_.try_emplace(key, static_cast<int>(piece.keys.size()));
    if (fresh) {
      // Interpolated in logit(occupancy), which is linear in f across a sigmoid leaf's surface
      // (a sharp sigmoid's occupancy is not: linear interpolation would put the vertex near
      // the middle of the edge whatever the distance); clamped where the occupancy saturates.
      const auto logit = [](double o) {
        o = std::clamp(o, 1e-7, 1.0 - 1e-7);
        return std::log(o / (1.0 - o));
      };
      const double la = logit(value(lo)), lb = logit(value(hi)), lv = logit(level_);
      const double t = std::clamp((lv - la) / (lb - la), 0.0, 1.0);
      std::array<float, kDim> p{};
      if (!between(lo, hi, t, p)) between(lo, hi, std::clamp(t, kVertexInset, 1 - kVertexInset), p);
      piece.keys.push_back(key);
      piece.positions.push_back(p);
    }
    return it->second;
  }

  // The point a fraction t along the grid edge lo -> hi (hi - lo in {0, 1}^3), in `p`. True when
  // it lies strictly between the edge's ends along every axis the edge spans, as it must for
  // the surface to be a 2-manifold in its positions, not only in its indices: vertices on edges
  // that meet at a grid point would otherwise coincide there (a surface through grid points, as
  // for faces on grid planes, gives triangles with repeated or collinear corners). A vertex so
  // placed is at the same coordinates as its edge's ends across the axes the edge does not
  // span and strictly between them across the others, which names the edge: no two vertices
  // coincide. Where rounding still puts it on an end, the next float towards the other end is
  // taken (none is left only where the grid is finer than float resolves).
  bool between(const std::array<int, 3>& lo, const std::array<int, 3>& hi, double t,
               std::array<float, kDim>& p) const {
    const auto tf = static_cast<float>(t);
    bool strict = true;
    for (int c = 0; c < kDim; ++c) {
      const float pa = g_.fcoordinate(c, lo[c]), pb = g_.fcoordinate(c, hi[c]);
      p[c] = pa + tf * (pb - pa);
      if (lo[c] == hi[c]) continue;
      if (!(p[c] > pa)) {
        p[c] = std::nextafter(pa, pb);
        strict = false;
      }
      if (!(p[c] < pb)) {
        p[c] = std::nextafter(pb, pa);
        strict = false;
      }
    }
    return strict;
  }

  Piece<kDim> piece;

 private:
  const Grid& g_;
  CellBox box_;
  const float* values_;
  float level_;
  std::array<std::size_t, 3> extent_{};
  std::unordered_map<std::uint64_t, int> local_;
};

using Point3 = std::array<int, 3>;

std::array<double, 3> midpoint(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
}
std::array<double, 3> sub(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
std::array<double, 3> cross(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Triangles of one tetrahedron, wound so that their normals point from inside to outside. The
// winding is decided on the edge midpoints, which never form a degenerate triangle.
void tetrahedron(PieceBuilder<3>& pb, const std::array<Point3, 4>& t) {
  std::array<int, 4> in{}, out{};
  int ni = 0, no = 0;
  for (int v = 0; v < 4; ++v) {
    if (pb.inside(t[v])) {
      in[ni++] = v;
    } else {
      out[no++] = v;
    }
  }
  if (ni == 0 || no == 0) return;
  std::array<std::array<double, 3>, 4> x{};
  for (int v = 0; v < 4; ++v) x[v] = pb.position(t[v]);
  std::array<double, 3> ci{}, co{};
  for (int v = 0; v < ni; ++v) {
    for (int c = 0; c < 3; ++c) ci[c] += x[in[v]][c] / ni;
  }
  for (int v = 0; v < no; ++v) {
    for (int c = 0; c < 3; ++c) co[c] += x[out[v]][c] / no;
  }
  const std::array<double, 3> outward = sub(co, ci);
  // Polygon on the cut edges, as (inside, outside) corner pairs in cyclic order.
  std::array<std::array<int, 2>, 4> poly{};
  int corners = 0;
  if (ni == 1 || no == 1) {
    const bool lone_inside = ni == 1;
    const int u = lone_inside ? in[0] : out[0];
    const std::array<int, 4>& others = lone_inside ? out : in;
    for (int k = 0; k < 3; ++k) poly[corners++] = {u, others[k]};
  } else {
    poly = {{{in[0], out[0]}, {in[0], out[1]}, {in[1], out[1]}, {in[1], out[0]}}};
    corners = 4;
  }
  const auto mid = [&](int k) { return midpoint(x[poly[k][0]], x[poly[k][1]]); };
  const bool flip = dot(cross(sub(mid(1), mid(0)), sub(mid(2), mid(0))), outward) < 0;
  std::array<int, 4> ids{};
  for (int k = 0; k < corners; ++k) ids[k] = pb.vertex(t[poly[k][0]], t[poly[k][1]]);
  const auto emit = [&](int a, int b, int c) {
    pb.piece.elements.push_back(flip ? std::array<int, 3>{ids[a], ids[c], ids[b]}
                                     : std::array<int, 3>{ids[a], ids[b], ids[c]});
  };
  emit(0, 1, 2);
  if (corners == 4) emit(0, 2, 3);
}

Piece<3> contour_brick(const Grid& g, const CellBox& box, const float* values, float level) {
  PieceBuilder<3> pb(g, box, values, level);
  // Kuhn's six tetrahedra: 000 -> e_a -> e_a + e_b -> 111 for each order (a, b, c) of the axes.
  constexpr int kOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int i = box.lo[0]; i < box.hi[0]; ++i) {
    for (int j = box.lo[1]; j < box.hi[1]; ++j) {
      for (int k = box.lo[2]; k < box.hi[2]; ++k) {
        const Point3 base{i, j, k};
        // Skip cells with all eight corners on one side.
        bool any_in = false, any_out = false;
        for (int c = 0; c < 8; ++c) {
          const bool v = pb.inside({i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)});
          any_in = any_in || v;
          any_out = any_out || !v;
        }
        if (!any_in || !any_out) continue;
        for (const auto& order : kOrders) {
          std::array<Point3, 4> t{base, base, base, base};
          t[1][order[0]] += 1;
          t[2] = t[1];
          t[2][order[1]] += 1;
          t[3] = {i + 1, j + 1, k + 1};
          tetrahedron(pb, t);
        }
      }
    }
  }
  return std::move(pb.piece);
}

// Segments of one triangle, inside on the left.
void triangle(PieceBuilder<2>& pb, const std::array<Point3, 3>& t) {
  int ni = 0;
  for (int v = 0; v < 3; ++v) ni += pb.inside(t[v]) ? 1 : 0;
  if (ni == 0 || ni == 3) return;
  // The lone corner (the one on its own side) and the other two.
  int u = 0;
  for (int v = 0; v < 3; ++v) {
    const int same = (pb.inside(t[v]) == pb.inside(t[(v + 1) % 3]) ? 1 : 0) +
                     (pb.inside(t[v]) == pb.inside(t[(v + 2) % 3]) ? 1 : 0);
    if (same == 0) u = v;
  }
  const int w1 = (u + 1) % 3, w2 = (u + 2) % 3;
  const auto x = [&](int v) { return pb.position(t[v]); };
  const std::array<double, 3> m1 = midpoint(x(u), x(w1)), m2 = midpoint(x(u), x(w2));
  std::array<double, 3> towards_inside = sub(x(u), midpoint(x(w1), x(w2)));
  if (!pb.inside(t[u])) towards_inside = sub(midpoint(x(w1), x(w2)), x(u));
  const std::array<double, 3> d = sub(m2, m1);
  const bool left = d[0] * towards_inside[1] - d[1] * towards_inside[0] > 0;
  const int a = pb.vertex(t[u], t[w1]), b = pb.vertex(t[u], t[w2]);
  pb.piece.elements.push_back(left ? std::array<int, 2>{a, b} : std::array<int, 2>{b, a});
}

Piece<2> contour_square_brick(const Grid& g, const CellBox& box, const float* values, float level) {
  PieceBuilder<2> pb(g, box, values, level);
  for (int i = box.lo[0]; i < box.hi[0]; ++i) {
    for (int j = box.lo[1]; j < box.hi[1]; ++j) {
      const Point3 p00{i, j, 0}, p10{i + 1, j, 0}, p01{i, j + 1, 0}, p11{i + 1, j + 1, 0};
      triangle(pb, {p00, p10, p11});
      triangle(pb, {p00, p01, p11});
    }
  }
  return std::move(pb.piece);
}

// Runs `contour` on every active brick, in batches (memory stays bounded), and merges the
// pieces: vertices with the same key become one. The pieces' float positions are stored in
// `vertices` as they are (float for contours, double for meshes: exact either way).
template <int kDim, class Vertex, class Contour>
void extract(Extractor& ex, const MeshOptions& o, MeshStats& stats, Contour contour,
             std::vector<Vertex>& vertices, std::vector<std::array<int, kDim>>& elements) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<CellBox> bricks = ex.active_bricks(stats);
  stats.bricks = bricks.size();
  const Grid& g = ex.grid();
  stats.cells = g.n;
  stats.grid_points = static_cast<std::size_t>(g.n[0] + 1) * static_cast<std::size_t>(g.n[1] + 1) *
                      static_cast<std::size_t>(g.n[2] + 1);
  // Pieces contoured in parallel and merged in brick order, so that the result does not depend
  // on the number of threads.
  const auto level = static_cast<float>(o.level);
  const std::vector<std::vector<float>> values = ex.evaluate(bricks, stats);
  std::vector<Piece<kDim>> pieces(bricks.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, bricks.size(), 1), [&](const auto& range) {
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      pieces[b] = contour(g, bricks[b], values[b].data(), level);
    }
  });
  std::unordered_map<std::uint64_t, int> global;
  for (const Piece<kDim>& piece : pieces) {
    std::vector<int> ids(piece.keys.size());
    for (std::size_t v = 0; v < piece.keys.size(); ++v) {
      auto [it, fresh] = global.try_emplace(piece.keys[v], static_cast<int>(vertices.size()));
      if (fresh) {
        Vertex p{};
        for (int c = 0; c < kDim; ++c) p[c] = piece.positions[v][c];
        vertices.push_back(p);
      }
      ids[v] = it->second;
    }
    for (const auto& e : piece.elements) {
      std::array<int, kDim> m{};
      for (int c = 0; c < kDim; ++c) m[c] = ids[e[c]];
      elements.push_back(m);
    }
  }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template <class F>
auto in_arena(int threads, F&& f) {
  check_threads(threads);
  if (threads <= 0) return f();
  tbb::task_arena arena(threads);
  return arena.execute(f);
}

}  // namespace

TriangleMesh extract_mesh(const Tree& tree, std::span<const double> params,
                          const MeshOptions& options, MeshStats* stats) {
  if (tree.dim != 3) throw InputError("extract_mesh: the tree is 2D (use its contours)");
  return in_arena(options.threads, [&] {
    Extractor ex(tree, params, options);
    MeshStats local;
    TriangleMesh mesh;
    extract<3>(ex, options, local, contour_brick, mesh.vertices, mesh.triangles);
    if (stats) *stats = local;
    return mesh;
  });
}

Contours extract_contours(const Tree& tree, std::span<const double> params,
                          const MeshOptions& options, MeshStats* stats) {
  if (tree.dim != 2) throw InputError("extract_contours: the tree is 3D (use its mesh)");
  return in_arena(options.threads, [&] {
    Extractor ex(tree, params, options);
    MeshStats local;
    std::vector<std::array<float, 2>> vertices;
    std::vector<std::array<int, 2>> segments;
    extract<2>(ex, options, local, contour_square_brick, vertices, segments);
    if (stats) *stats = local;
    // Every vertex starts exactly one segment and ends one: follow them into loops.
    std::vector<int> next(vertices.size(), -1);
    for (const auto& s : segments) next[static_cast<std::size_t>(s[0])] = s[1];
    std::vector<char> used(vertices.size(), 0);
    Contours c;
    for (const auto& s : segments) {
      int v = s[0];
      if (used[static_cast<std::size_t>(v)]) continue;
      std::vector<std::array<float, 2>> loop;
      while (v >= 0 && !used[static_cast<std::size_t>(v)]) {
        used[static_cast<std::size_t>(v)] = 1;
        loop.push_back(vertices[static_cast<std::size_t>(v)]);
        v = next[static_cast<std::size_t>(v)];
      }
      c.loops.push_back(std::move(loop));
    }
    return c;
  });
}

std::size_t open_or_misoriented_edges(const TriangleMesh& mesh) {
  // Each directed edge must appear once and its reverse once.
  std::unordered_map<std::uint64_t, int> directed;
  directed.reserve(mesh.triangles.size() * 3);
  const auto key = [](int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
  };
  for (const auto& t : mesh.triangles) {
    for (int e = 0; e < 3; ++e) ++directed[key(t[e], t[(e + 1) % 3])];
  }
  std::size_t bad = 0;
  for (const auto& [k, count] : directed) {
    const int a = static_cast<int>(k >> 32), b = static_cast<int>(k & 0xffffffffu);
    auto it = directed.find(key(b, a));
    if (count != 1 || it == directed.end() || it->second != 1) ++bad;
  }
  return bad;
}

double contours_area(const Contours& contours) {
  double area = 0.0;
  for (const auto& loop : contours.loops) {
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const auto& a = loop[i];
      const auto& b = loop[(i + 1) % loop.size()];
      area += (static_cast<double>(a[0]) * b[1] - static_cast<double>(b[0]) * a[1]) / 2.0;
    }
  }
  return area;
}

}  // namespace fuzzycsg
