// What keeps a mesh from bounding a solid (mesh_file.hpp, find_mesh_defects and mesh_defect):
// vertices welded within a tolerance, degenerate triangles ignored, seams closed at T-junctions,
// then the edges counted.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "fuzzycsg/target/mesh_file.hpp"

namespace fuzzycsg {

namespace {

using Position = std::array<double, 3>;
using Cell = std::array<std::int64_t, 3>;

// Welding and seam tolerance, relative to the diagonal of the box around the triangles' corners.
constexpr double kRelativeTolerance = 1e-9;

Position minus(const Position& a, const Position& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const Position& a, const Position& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Position cross(const Position& a, const Position& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double length(const Position& a) { return std::sqrt(dot(a, a)); }

struct CellHash {
  std::size_t operator()(const Cell& c) const {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (const std::int64_t x : c) h = (h ^ static_cast<std::uint64_t>(x)) * 0x100000001b3ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

// Ids at points, bucketed in cubic cells `size` wide from `origin`.
class Grid {
 public:
  Grid(const Position& origin, double size) : origin_(origin), size_(size) {}

  Cell cell(const Position& p) const {
    Cell c{};
    // Clamped far inside int64's range (only coordinates near overflow reach it), so that
    // neighbouring cells' indices do not overflow either.
    constexpr double kLimit = 0x1p60;
    for (std::size_t k = 0; k < 3; ++k) {
      const double x = std::floor((p[k] - origin_[k]) / size_);
      c[k] = static_cast<std::int64_t>(std::clamp(std::isnan(x) ? 0.0 : x, -kLimit, kLimit));
    }
    return c;
  }
  void insert(const Position& p, int id) { cells_[cell(p)].push_back(id); }
  // The number of cells from lo to hi (inclusive), as a double: it may be huge.
  static double span(const Cell& lo, const Cell& hi) {
    double n = 1.0;
    for (std::size_t k = 0; k < 3; ++k) n *= static_cast<double>(hi[k] - lo[k] + 1);
    return n;
  }
  // f(id) for every id in the cells from lo to hi (inclusive).
  template <class F>
  void visit(const Cell& lo, const Cell& hi, const F& f) const {
    for (std::int64_t x = lo[0]; x <= hi[0]; ++x) {
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z) {
          const auto it = cells_.find(Cell{x, y, z});
          if (it == cells_.end()) continue;
          for (const int id : it->second) f(id);
        }
      }
    }
  }

 private:
  Position origin_;
  double size_;
  std::unordered_map<Cell, std::vector<int>, CellHash> cells_;
};

std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::min(a, b))) << 32) |
         static_cast<std::uint32_t>(std::max(a, b));
}

struct Uses {
  int count = 0;
  int forward = 0;  // uses from the smaller id to the larger
};

using EdgeUses = std::unordered_map<std::uint64_t, Uses>;

void add_edge(EdgeUses& edges, int a, int b) {
  Uses& u = edges[edge_key(a, b)];
  ++u.count;
  u.forward += a < b ? 1 : 0;
}

// Welded vertices: one id per vertex that a triangle uses (-1 for the others), and the position
// of each id (that of its first vertex).
struct Welding {
  std::vector<int> id;
  std::vector<Position> where;
  std::size_t joined_unequal = 0;
};

Welding weld(const TriangleMesh& mesh, const std::vector<char>& used, const Position& lo,
             double tolerance) {
  Welding w;
  w.id.assign(mesh.vertices.size(), -1);
  // Cells as wide as the tolerance: a vertex within it of another is in a neighbouring cell.
  Grid grid(lo, tolerance > 0 ? tolerance : 1.0);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!used[v]) continue;
    const Position& p = mesh.vertices[v];
    const Cell c = grid.cell(p);
    int best = -1;
    grid.visit({c[0] - 1, c[1] - 1, c[2] - 1}, {c[0] + 1, c[1] + 1, c[2] + 1}, [&](int id) {
      if ((best < 0 || id < best) &&
          length(minus(w.where[static_cast<std::size_t>(id)], p)) <= tolerance) {
        best = id;
      }
    });
    if (best < 0) {
      best = static_cast<int>(w.where.size());
      w.where.push_back(p);
      grid.insert(p, best);
    } else if (w.where[static_cast<std::size_t>(best)] != p) {
      ++w.joined_unequal;
    }
    w.id[v] = best;
  }
  return w;
}

// Corners within `tolerance` of the line through the longest side (or two corners at one id).
bool degenerate(const std::array<int, 3>& ids, const std::vector<Position>& where,
                double tolerance) {
  if (ids[0] == ids[1] || ids[1] == ids[2] || ids[2] == ids[0]) return true;
  const Position& a = where[static_cast<std::size_t>(ids[0])];
  const Position& b = where[static_cast<std::size_t>(ids[1])];
  const Position& c = where[static_cast<std::size_t>(ids[2])];
  const double longest = std::max({length(minus(b, a)), length(minus(c, b)), length(minus(a, c))});
  // Twice the area over the longest side: the height over it, the largest distance of a corner
  // from the line through it.
  return length(cross(minus(b, a), minus(c, a))) <= tolerance * longest;
}

// The boundary edges (directed as their triangles run them) split at the corners of other
// boundary edges that lie on them: each edge replaced by its chain of pieces, in order.
// Returns the number of distinct corners split at.
std::size_t split_at_t_junctions(std::vector<std::pair<int, int>>& boundary,
                                 const std::vector<Position>& where, const Position& lo,
                                 double tolerance) {
  if (boundary.empty()) return 0;
  std::vector<int> corners;
  std::vector<double> lengths;
  for (const auto& [a, b] : boundary) {
    corners.push_back(a);
    corners.push_back(b);
    lengths.push_back(
        length(minus(where[static_cast<std::size_t>(b)], where[static_cast<std::size_t>(a)])));
  }
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  // Cells about as wide as a typical boundary edge: an edge's box covers a few of them.
  std::nth_element(lengths.begin(),
                   lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2),
                   lengths.end());
  const double size =
      std::max({lengths[lengths.size() / 2], tolerance, std::numeric_limits<double>::min()});
  Grid grid(lo, size);
  for (const int c : corners) grid.insert(where[static_cast<std::size_t>(c)], c);

  std::vector<std::pair<int, int>> pieces;
  std::unordered_set<int> split_at;
  std::vector<std::pair<double, int>> on_edge;  // (parameter along the edge, corner)
  for (const auto& edge : boundary) {
    const int a = edge.first;  // plain names: lambdas below capture them
    const int b = edge.second;
    const Position& pa = where[static_cast<std::size_t>(a)];
    const Position& pb = where[static_cast<std::size_t>(b)];
    const Position d = minus(pb, pa);
    const double len = length(d);
    on_edge.clear();
    const auto consider = [&](int c) {
      if (c == a || c == b) return;
      const Position q = minus(where[static_cast<std::size_t>(c)], pa);
      const double along = dot(q, d) / len;  // distance from a along the edge
      if (!(along > tolerance && along < len - tolerance)) return;
      if (length(cross(q, d)) / len > tolerance) return;  // distance from the line
      on_edge.emplace_back(along, c);
    };
    Position box_lo{}, box_hi{};
    for (std::size_t k = 0; k < 3; ++k) {
      box_lo[k] = std::min(pa[k], pb[k]) - tolerance;
      box_hi[k] = std::max(pa[k], pb[k]) + tolerance;
    }
    const Cell from = grid.cell(box_lo), to = grid.cell(box_hi);
    if (Grid::span(from, to) <= static_cast<double>(corners.size())) {
      grid.visit(from, to, consider);
    } else {
      for (const int c : corners) consider(c);
    }
    std::sort(on_edge.begin(), on_edge.end());
    int previous = a;
    for (const auto& [along, c] : on_edge) {
      pieces.emplace_back(previous, c);
      split_at.insert(c);
      previous = c;
    }
    pieces.emplace_back(previous, b);
  }
  boundary = std::move(pieces);
  return split_at.size();
}

}  // namespace

MeshDefects find_mesh_defects(const TriangleMesh& mesh) {
  MeshDefects d;
  d.triangles = mesh.triangles.size();
  // The corners: vertices of the mesh with finite coordinates, and the box around them.
  std::vector<char> used(mesh.vertices.size(), 0);
  Position lo{}, hi{};
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (const auto& t : mesh.triangles) {
    for (const int v : t) {
      if (v < 0 || static_cast<std::size_t>(v) >= mesh.vertices.size()) {
        ++d.bad_corners;
        continue;
      }
      const Position& p = mesh.vertices[static_cast<std::size_t>(v)];
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
        ++d.bad_corners;
        continue;
      }
      used[static_cast<std::size_t>(v)] = 1;
      for (std::size_t k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    }
  }
  if (d.bad_corners > 0 || mesh.triangles.empty()) return d;
  // The diagonal may overflow where the coordinates do not: then no tolerance is finite either.
  const double diagonal = length(minus(hi, lo));
  const double tolerance = std::isfinite(diagonal) ? kRelativeTolerance * diagonal : 0.0;
  const Welding w = weld(mesh, used, lo, tolerance);
  d.welded_vertices = w.joined_unequal;

  EdgeUses edges;
  edges.reserve(mesh.triangles.size() * 2);
  std::vector<char> kept(w.where.size(), 0);
  for (const auto& t : mesh.triangles) {
    std::array<int, 3> ids{};
    for (std::size_t k = 0; k < 3; ++k) ids[k] = w.id[static_cast<std::size_t>(t[k])];
    if (degenerate(ids, w.where, tolerance)) {
      ++d.degenerate_triangles;
      continue;
    }
    for (std::size_t k = 0; k < 3; ++k) {
      kept[static_cast<std::size_t>(ids[k])] = 1;
      add_edge(edges, ids[k], ids[(k + 1) % 3]);
    }
  }
  if (d.empty()) return d;
  d.vertices = static_cast<std::size_t>(std::count(kept.begin(), kept.end(), 1));

  // Boundary edges, as their one triangle runs them, split where a seam has T-junctions; the
  // pieces replace them in the count.
  std::vector<std::pair<int, int>> boundary;
  for (auto it = edges.begin(); it != edges.end();) {
    if (it->second.count != 1) {
      ++it;
      continue;
    }
    const int small = static_cast<int>(it->first >> 32);
    const int large = static_cast<int>(it->first & 0xffffffffu);
    boundary.push_back(it->second.forward == 1 ? std::pair{small, large} : std::pair{large, small});
    it = edges.erase(it);
  }
  // Hash order is not the edges' order: sorted, the splits do not depend on the library.
  std::sort(boundary.begin(), boundary.end());
  d.t_junctions = split_at_t_junctions(boundary, w.where, lo, tolerance);
  for (const auto& [a, b] : boundary) add_edge(edges, a, b);

  d.edges = edges.size();
  for (const auto& [key, u] : edges) {
    if (u.count == 1) ++d.boundary_edges;
    if (u.count > 2) ++d.nonmanifold_edges;
    if (u.count == 2 && u.forward != 1) ++d.misoriented_edges;
  }
  return d;
}

std::optional<std::string> mesh_defect(const TriangleMesh& mesh) {
  const MeshDefects d = find_mesh_defects(mesh);
  // "1 boundary edge", "2 boundary edges".
  const auto count = [](std::size_t n, const char* one, const char* many) {
    return fmt::format("{} {}", n, n == 1 ? one : many);
  };
  if (d.triangles == 0) return "mesh is empty: no triangles";
  if (d.bad_corners > 0) {
    return fmt::format("mesh has {} (not finite, or not one of its vertices)",
                       count(d.bad_corners, "bad corner", "bad corners"));
  }
  if (d.empty()) {
    return d.triangles == 1
               ? std::string("mesh is empty: its one triangle is degenerate")
               : fmt::format("mesh is empty: all {} triangles are degenerate", d.triangles);
  }
  std::string out;
  const auto problem = [&](const std::string& text) { out += (out.empty() ? "" : "; ") + text; };
  if (d.boundary_edges > 0) {
    problem("mesh is open: " + count(d.boundary_edges, "boundary edge", "boundary edges"));
  }
  if (d.nonmanifold_edges > 0) {
    problem("mesh is not manifold: " + count(d.nonmanifold_edges, "edge", "edges") +
            " in more than two triangles");
  }
  if (d.misoriented_edges > 0) {
    problem("mesh is not consistently oriented: " +
            count(d.misoriented_edges, "edge runs the same way in both of its triangles",
                  "edges run the same way in both of their triangles"));
  }
  if (out.empty()) return std::nullopt;
  return out;
}

}  // namespace fuzzycsg
