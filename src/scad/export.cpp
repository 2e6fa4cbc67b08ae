// OpenSCAD export: the crisp counterpart of a tree as a .scad program (scad.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "fuzzycsg/core/bezier.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/limits.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/placement.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/mesh/mesh.hpp"
#include "fuzzycsg/scad/scad.hpp"

namespace fuzzycsg::scad {

namespace {

using Point = std::array<double, 3>;

constexpr double kCoverMargin = 0.1;  // the cover: the domain grown by this fraction per side

// 9 significant digits: enough for every float (mesh vertices) and 5e-10 relative for doubles.
std::string num(double v) {
  if (v == 0.0) return "0";  // also -0
  return fmt::format("{:.9g}", v);
}

// A polygon (x0, y0, x1, y1, ...) without the vertices that lie on the straight line between
// their neighbours (a straight side of an extrude's profile is sampled 15 times): the same
// polygon, written once per corner.
std::vector<double> without_straight_points(const std::vector<double>& xy) {
  const std::size_t n = xy.size() / 2;
  if (n < 4) return xy;
  double extent = 0;
  for (const double v : xy) extent = std::max(extent, std::abs(v));
  const double tolerance = 1e-12 * std::max(extent * extent, 1e-300);
  std::vector<double> out;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t p = (i + n - 1) % n, q = (i + 1) % n;
    const double ax = xy[2 * i] - xy[2 * p], ay = xy[2 * i + 1] - xy[2 * p + 1];
    const double bx = xy[2 * q] - xy[2 * i], by = xy[2 * q + 1] - xy[2 * i + 1];
    const bool straight = std::abs(ax * by - ay * bx) <= tolerance && ax * bx + ay * by > 0;
    if (!straight) {
      out.push_back(xy[2 * i]);
      out.push_back(xy[2 * i + 1]);
    }
  }
  return out.size() >= 6 ? out : xy;
}

std::string vec(std::span<const double> v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + num(v[i]);
  return s + "]";
}

// Text safe inside a // comment: one line, printable ASCII.
std::string comment_text(std::string_view s) {
  std::string out;
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    out += (c >= 0x20 && c < 0x7f) ? ch : '?';
  }
  return out;
}

// One statement of OpenSCAD as lines of text, each with its indentation (relative depth).
struct Lines {
  std::vector<std::pair<int, std::string>> lines;
  void add(int depth, std::string text) { lines.emplace_back(depth, std::move(text)); }
  void append(const Lines& other, int depth) {
    for (const auto& [d, t] : other.lines) lines.emplace_back(depth + d, t);
  }
  // `prefix` (a transformation) applied to the statement: written before its first line that
  // is not a comment.
  void prefix_statement(const std::string& prefix) {
    for (auto& [d, t] : lines) {
      if (t.rfind("//", 0) == 0) continue;
      t = prefix + t;
      return;
    }
  }
};

Domain grown(const Domain& d, int dim, double fraction) {
  Domain out = d;
  for (int i = 0; i < dim; ++i) {
    const auto a = static_cast<std::size_t>(i);
    const double m = fraction * (d.max[a] - d.min[a]);
    out.min[a] -= m;
    out.max[a] += m;
  }
  for (int i = dim; i < 3; ++i)
    out.min[static_cast<std::size_t>(i)] = out.max[static_cast<std::size_t>(i)] = 0;
  return out;
}

std::vector<Point> corners(const Domain& d, int dim) {
  std::vector<Point> out;
  for (int m = 0; m < (1 << dim); ++m) {
    Point p{0, 0, 0};
    for (int i = 0; i < dim; ++i) {
      const auto a = static_cast<std::size_t>(i);
      p[a] = (m >> i) & 1 ? d.max[a] : d.min[a];
    }
    out.push_back(p);
  }
  return out;
}

// A leaf's placement: p_local = R^T (p - t) / s.
struct Frame {
  int dim = 3;
  std::array<double, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major 3x3 (2D: upper-left 2x2)
  Point t{0, 0, 0};
  double s = 1.0;
  Point to_local(const Point& p) const {
    Point out{0, 0, 0};
    for (int c = 0; c < dim; ++c) {
      double acc = 0.0;
      for (int k = 0; k < dim; ++k) {
        acc += r[static_cast<std::size_t>(k * 3 + c)] *
               (p[static_cast<std::size_t>(k)] - t[static_cast<std::size_t>(k)]);
      }
      out[static_cast<std::size_t>(c)] = acc / s;
    }
    return out;
  }
};

Frame frame_of(const Tree& tree, std::span<const double> params, const Node& n) {
  Frame f;
  f.dim = tree.dim;
  const auto& pl = n.placement;
  if (!pl.rotate.empty()) {
    if (tree.dim == 3) {
      f.r = placement::rotation_3d(params[pl.rotate[0].index], params[pl.rotate[1].index],
                                   params[pl.rotate[2].index]);
    } else {
      const auto m = placement::rotation_2d(params[pl.rotate[0].index]);
      f.r = {m[0], m[1], 0, m[2], m[3], 0, 0, 0, 1};
    }
  }
  for (std::size_t i = 0; i < pl.translate.size(); ++i) f.t[i] = params[pl.translate[i].index];
  if (pl.scale) f.s = params[pl.scale->index];
  return f;
}

// The leaf's f (world) at x.
double leaf_value(const Tree& tree, std::span<const double> params, const Node& n, const Point& x,
                  std::vector<double>& theta) {
  const Frame f = frame_of(tree, params, n);
  const Point p = f.to_local(x);
  theta.resize(n.intrinsic.size());
  for (std::size_t i = 0; i < theta.size(); ++i) theta[i] = params[n.intrinsic[i].index];
  return f.s * primitive_value<double>(n.shape, std::span<const double>(theta), p.data());
}

// The leaf's placement as OpenSCAD transforms; a translation or rotation by zero, which is no
// transform, is left out.
std::string placement_prefix(const Tree& tree, std::span<const double> params, const Node& n) {
  const auto& pl = n.placement;
  const auto zero = [&](const std::vector<ParamRef>& refs) {
    return std::all_of(refs.begin(), refs.end(), [&](ParamRef r) { return params[r.index] == 0; });
  };
  std::string s;
  if (!pl.translate.empty() && !zero(pl.translate)) {
    std::vector<double> t;
    for (const ParamRef r : pl.translate) t.push_back(params[r.index]);
    s += "translate(" + vec(t) + ") ";
  }
  if (!pl.rotate.empty() && !zero(pl.rotate)) {
    if (tree.dim == 3) {
      std::vector<double> r;
      for (const ParamRef p : pl.rotate) r.push_back(params[p.index]);
      s += "rotate(" + vec(r) + ") ";
    } else {
      s += "rotate(" + num(params[pl.rotate[0].index]) + ") ";
    }
  }
  if (pl.scale) s += "scale(" + num(params[pl.scale->index]) + ") ";
  return s;
}

std::string multmatrix(const QuadricClass& c) {
  const auto m = c.affine();
  if (c.dim == 3) {
    return fmt::format("multmatrix([{}, {}, {}, [0, 0, 0, 1]]) ",
                       vec(std::span<const double>(m.data(), 4)),
                       vec(std::span<const double>(m.data() + 4, 4)),
                       vec(std::span<const double>(m.data() + 8, 4)));
  }
  return fmt::format("multmatrix([[{}, {}, 0, {}], [{}, {}, 0, {}], [0, 0, 1, 0], [0, 0, 0, 1]]) ",
                     num(m[0]), num(m[1]), num(m[3]), num(m[4]), num(m[5]), num(m[7]));
}

std::string box_statement(int dim, const Point& lo, const Point& hi) {
  if (dim == 3) {
    return fmt::format("translate({}) cube({});", vec(lo),
                       vec(Point{hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}));
  }
  return fmt::format("translate({}) square({});", vec(std::span<const double>(lo.data(), 2)),
                     vec(std::array<double, 2>{hi[0] - lo[0], hi[1] - lo[1]}));
}

// The half-space n.p < offset (n a unit vector) as a classified plane: v_dim < 0 with the
// normal as the last canonical axis.
QuadricClass plane_class(int dim, const Point& n, double offset) {
  QuadricClass c;
  c.dim = dim;
  c.kind = QuadricKind::kPlane;
  for (int i = 0; i < dim; ++i)
    c.center[static_cast<std::size_t>(i)] = offset * n[static_cast<std::size_t>(i)];
  if (dim == 2) {
    c.rotation = {n[1], n[0], 0, -n[0], n[1], 0, 0, 0, 1};
    return c;
  }
  // t1: n crossed with the axis it is least aligned with; t2 = n x t1; columns t1, t2, n.
  const int k = std::abs(n[0]) <= std::abs(n[1]) && std::abs(n[0]) <= std::abs(n[2]) ? 0
                : std::abs(n[1]) <= std::abs(n[2])                                   ? 1
                                                                                     : 2;
  Point e{0, 0, 0};
  e[static_cast<std::size_t>(k)] = 1.0;
  const auto cross = [](const Point& a, const Point& b) {
    return Point{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  Point t1 = cross(n, e);
  const double l = std::sqrt(t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2]);
  for (double& v : t1) v /= l;
  const Point t2 = cross(n, t1);
  c.rotation = {t1[0], t2[0], n[0], t1[1], t2[1], n[1], t1[2], t2[2], n[2]};
  return c;
}

// The mesh's vertices in double precision, each moved along its grid edge to at least `gap`
// from the nearest grid point. Marching tetrahedra puts a vertex wherever its edge crosses the
// level, so where the surface passes near a grid point several vertices (on the edges from that
// point) nearly coincide; OpenSCAD merges vertices closer than about 2^-20 and then finds the
// mesh open. A vertex stays on its edge, so the mesh stays closed and free of
// self-intersections.
std::vector<Point> apart_from_grid(const TriangleMesh& m, const Domain& box, int resolution,
                                   int dim, double gap) {
  double longest = 0.0;
  for (int a = 0; a < dim; ++a) {
    longest = std::max(longest,
                       box.max[static_cast<std::size_t>(a)] - box.min[static_cast<std::size_t>(a)]);
  }
  std::array<int, 3> n{1, 1, 1};
  for (int a = 0; a < dim; ++a) {
    const auto i = static_cast<std::size_t>(a);
    n[i] = std::max(
        1, static_cast<int>(std::lround(resolution * (box.max[i] - box.min[i]) / longest)));
  }
  std::vector<Point> out(m.vertices.size()), grid_point(m.vertices.size());
  std::vector<int> close;
  for (std::size_t v = 0; v < m.vertices.size(); ++v) {
    Point p{m.vertices[v][0], m.vertices[v][1], m.vertices[v][2]};
    Point g = p;  // the nearest grid point
    double d2 = 0.0;
    for (int a = 0; a < dim; ++a) {
      const auto i = static_cast<std::size_t>(a);
      const double len = box.max[i] - box.min[i];
      const double k = std::round((p[i] - box.min[i]) / len * n[i]);
      g[i] = box.min[i] + len * k / n[i];
      d2 += (p[i] - g[i]) * (p[i] - g[i]);
    }
    const double d = std::sqrt(d2);
    grid_point[v] = g;
    if (d < gap) {
      // Below a hundredth of the gap the direction is rounding (float vertices): see below.
      if (d > 0.01 * gap) {
        for (std::size_t i = 0; i < 3; ++i) p[i] = g[i] + (p[i] - g[i]) * (gap / d);
      } else {
        p = g;
        close.push_back(static_cast<int>(v));
      }
    }
    out[v] = p;
  }
  // A vertex on a grid point (to rounding): moved along the grid edge that points most nearly
  // towards the mean of its neighbours in the mesh (its triangles lie in the tetrahedra around
  // its edge), a different edge for each vertex on the same point.
  if (!close.empty()) {
    std::vector<Point> sum(m.vertices.size(), Point{0, 0, 0});
    std::vector<int> neighbours(m.vertices.size(), 0);
    for (const auto& t : m.triangles) {
      for (std::size_t c = 0; c < 3; ++c) {
        const auto v = static_cast<std::size_t>(t[c]);
        for (std::size_t o = 1; o <= 2; ++o) {
          const Point& q = out[static_cast<std::size_t>(t[(c + o) % 3])];
          for (std::size_t i = 0; i < 3; ++i) sum[v][i] += q[i];
        }
        neighbours[v] += 2;
      }
    }
    std::array<double, 3> cell{1, 1, 1};
    for (int a = 0; a < dim; ++a) {
      const auto i = static_cast<std::size_t>(a);
      cell[i] = (box.max[i] - box.min[i]) / n[i];
    }
    std::vector<Point> edges;  // unit directions to the neighbouring grid points
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = dim == 3 ? -1 : 0; dz <= (dim == 3 ? 1 : 0); ++dz) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          Point e{dx * cell[0], dy * cell[1], dz * cell[2]};
          const double l = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
          for (double& c : e) c /= l;
          edges.push_back(e);
        }
      }
    }
    // Vertices grouped by their grid point (they were snapped onto it exactly).
    std::map<Point, std::vector<int>> groups;
    for (const int v : close) groups[grid_point[static_cast<std::size_t>(v)]].push_back(v);
    for (const auto& [g, members] : groups) {
      std::vector<char> taken(edges.size(), 0);
      for (const int v : members) {
        const auto vi = static_cast<std::size_t>(v);
        Point dir{0, 0, 0};
        if (neighbours[vi] > 0) {
          for (std::size_t i = 0; i < 3; ++i) dir[i] = sum[vi][i] / neighbours[vi] - g[i];
        }
        std::size_t best = edges.size();
        double best_score = -2.0;
        for (std::size_t e = 0; e < edges.size(); ++e) {
          if (taken[e]) continue;
          const double score = dir[0] * edges[e][0] + dir[1] * edges[e][1] + dir[2] * edges[e][2];
          if (score > best_score) {
            best_score = score;
            best = e;
          }
        }
        if (best == edges.size()) continue;
        taken[best] = 1;
        for (std::size_t i = 0; i < 3; ++i) out[vi][i] = g[i] + gap * edges[best][i];
      }
    }
  }
  return out;
}

struct Writer {
  const Tree& tree;
  std::span<const double> params;
  const ExportOptions& o;
  ExportReport& report;
  std::vector<std::string> paths;
  Domain domain, cover;
  bool unbounded = false;  // something was cut to the cover

  int dim() const { return tree.dim; }

  Lines empty() const {
    Lines l;
    l.add(0, "union() {}  // empty");
    return l;
  }
  Lines space() {
    unbounded = true;
    Lines l;
    l.add(0, "fuzzycsg_space();");
    return l;
  }

  // The set of `cls`, cut so that it is exact within the points `pts` (the cover's corners in
  // the class's frame). One statement.
  // The half-space n.p <= offset (n a unit vector) where it meets the cover (`pts`: its
  // corners), as a cube turned so that its top face lies in the plane: rotate([0, ay, az])
  // takes z onto n, and the cube [-s, s]^2 x [offset - 2s, offset] holds every point of the
  // cover on the inner side when s is at least the farthest corner's distance (rounded up to
  // two significant digits, for a readable line).
  Lines half_space(const Point& n, double offset, std::span<const Point> pts) {
    double reach = 0.0;
    for (const Point& p : pts) reach = std::max(reach, std::hypot(p[0], p[1], p[2]));
    if (offset <= -reach) return empty();
    if (offset >= reach) return space();
    unbounded = true;
    const double quantum = std::pow(10.0, std::floor(std::log10(reach)) - 1.0);
    const double half = std::ceil(reach / quantum) * quantum;
    constexpr double kDegrees = 180.0 / std::numbers::pi;
    const double ay = std::acos(std::clamp(n[2], -1.0, 1.0)) * kDegrees;
    const double az = std::hypot(n[0], n[1]) > 1e-12 ? std::atan2(n[1], n[0]) * kDegrees : 0.0;
    // Angles to a millionth of a degree: what an axis within rounding of a world axis reads as.
    const auto angle = [](double a) { return num(std::round(a * 1e6) / 1e6); };
    Lines l;
    const auto component = [](double v) {
      return v == 0 ? std::string("0") : fmt::format("{:.4g}", v);
    };
    l.add(0, fmt::format("rotate([0, {}, {}]) translate([{}, {}, {}]) cube({});  // half-space "
                         "({}, {}, {}) . p <= {}",
                         angle(ay), angle(az), num(-half), num(-half), num(offset - 2 * half),
                         num(2 * half), component(n[0]), component(n[1]), component(n[2]),
                         num(offset)));
    return l;
  }

  Lines classified(const QuadricClass& cls, std::span<const Point> pts) {
    if (cls.kind == QuadricKind::kEmpty) return empty();
    if (cls.kind == QuadricKind::kFull) return space();
    const int d = dim();
    // The bounding box of the points in canonical coordinates, grown by 1%.
    Point lo{0, 0, 0}, hi{0, 0, 0};
    for (int c = 0; c < d; ++c) {
      lo[static_cast<std::size_t>(c)] = std::numeric_limits<double>::infinity();
      hi[static_cast<std::size_t>(c)] = -std::numeric_limits<double>::infinity();
    }
    for (const Point& p : pts) {
      for (int c = 0; c < d; ++c) {
        double v = 0.0;
        for (int r = 0; r < d; ++r) {
          v += cls.rotation[static_cast<std::size_t>(r * 3 + c)] *
               (p[static_cast<std::size_t>(r)] - cls.center[static_cast<std::size_t>(r)]);
        }
        v /= cls.axes[static_cast<std::size_t>(c)];
        lo[static_cast<std::size_t>(c)] = std::min(lo[static_cast<std::size_t>(c)], v);
        hi[static_cast<std::size_t>(c)] = std::max(hi[static_cast<std::size_t>(c)], v);
      }
    }
    for (int c = 0; c < d; ++c) {
      const auto a = static_cast<std::size_t>(c);
      const double m = 0.01 * (hi[a] - lo[a]) + 1e-9 * std::max(std::abs(lo[a]), std::abs(hi[a]));
      lo[a] -= m;
      hi[a] += m;
    }
    const std::size_t last = static_cast<std::size_t>(d - 1);
    const std::string mm = multmatrix(cls);
    Lines shape;
    bool none = false;  // the kind's set misses the cover
    const int segments = std::max(32, o.fn);
    switch (cls.kind) {
      case QuadricKind::kSphere:
      case QuadricKind::kEllipsoid:
        shape.add(0, mm + (d == 3 ? "sphere(r = 1);" : "circle(r = 1);"));
        break;
      case QuadricKind::kCylinder:
        shape.add(0, mm + fmt::format("translate([0, 0, {}]) cylinder(h = {}, r = 1);", num(lo[2]),
                                      num(hi[2] - lo[2])));
        unbounded = true;
        break;
      case QuadricKind::kCone: {
        unbounded = true;
        std::vector<std::string> nappes;
        if (hi[2] > 0)
          nappes.push_back(fmt::format("cylinder(h = {0}, r1 = 0, r2 = {0});", num(hi[2])));
        if (lo[2] < 0) {
          nappes.push_back(
              fmt::format("mirror([0, 0, 1]) cylinder(h = {0}, r1 = 0, r2 = {0});", num(-lo[2])));
        }
        if (nappes.size() == 1) {
          shape.add(0, mm + nappes[0]);
        } else {
          shape.add(0, mm + "union() {");
          for (const auto& n : nappes) shape.add(1, n);
          shape.add(0, "}");
        }
        break;
      }
      case QuadricKind::kParaboloid: {
        unbounded = true;
        const double h = hi[last];
        if (!(h > 0)) {
          none = true;
          break;
        }
        // The profile r^2 < z up to z = h, sampled uniformly in r (inscribed).
        std::string pts2;
        const double rmax = std::sqrt(h);
        if (d == 3) {
          pts2 = "[0, 0]";
          for (int k = 1; k <= segments; ++k) {
            const double r = rmax * k / segments;
            pts2 += fmt::format(", [{}, {}]", num(r), num(k == segments ? h : r * r));
          }
          pts2 += fmt::format(", [0, {}]", num(h));
          shape.add(0, mm + "rotate_extrude() polygon([" + pts2 + "]);");
        } else {
          for (int k = -segments; k <= segments; ++k) {
            const double r = rmax * k / segments;
            pts2 += fmt::format("{}[{}, {}]", k == -segments ? "" : ", ", num(r),
                                num(std::abs(k) == segments ? h : r * r));
          }
          shape.add(0, mm + "polygon([" + pts2 + "]);");
        }
        break;
      }
      case QuadricKind::kPlane: {
        unbounded = true;
        if (!(lo[last] < 0)) {
          none = true;
          break;
        }
        Point top = hi;
        top[last] = std::min(hi[last], 0.0);
        shape.add(0, mm + box_statement(d, lo, top));
        break;
      }
      case QuadricKind::kSlab: {
        unbounded = true;
        Point a = lo, b = hi;
        a[last] = std::max(lo[last], -1.0);
        b[last] = std::min(hi[last], 1.0);
        if (!(a[last] < b[last])) {
          none = true;
          break;
        }
        shape.add(0, mm + box_statement(d, a, b));
        break;
      }
      default:
        throw Error("scad export: unexpected quadric kind");
    }
    if (none) return cls.outside ? space() : empty();
    if (!cls.outside) return shape;
    unbounded = true;
    Lines l;
    l.add(0, "difference() {");
    l.add(1, "fuzzycsg_space();");
    l.append(shape, 1);
    l.add(0, "}");
    return l;
  }

  // The box meshed leaves and blends are meshed over: the domain grown by two cells (`cell`:
  // the domain's longest side over the resolution), the grid shifted by an odd fraction of a
  // cell so that its points seldom fall on round coordinates, where hand-made leaves tend to
  // have exact zeros.
  Domain mesh_box(double& cell) const {
    double longest = 0.0;
    for (int i = 0; i < dim(); ++i) {
      longest = std::max(longest, domain.max[static_cast<std::size_t>(i)] -
                                      domain.min[static_cast<std::size_t>(i)]);
    }
    cell = longest / o.resolution;
    Domain box = domain;
    for (int i = 0; i < dim(); ++i) {
      box.min[static_cast<std::size_t>(i)] -= (2 + 0.0123) * cell;
      box.max[static_cast<std::size_t>(i)] += (2 - 0.0123) * cell;
    }
    return box;
  }

  // The leaf alone meshed (3D: polyhedron) or contoured (2D: polygon) over the domain grown by
  // two cells (where the leaf reaches that box its mesh is capped there, outside the domain).
  Lines meshed(int index) {
    const Node& src = tree.node(index);
    ++report.meshed_leaves;
    double cell = 0.0;
    const Domain box = mesh_box(cell);
    // The leaf's f sampled to scale a sigmoid that is close to linear near the surface, so that
    // the mesh's vertices interpolate f = 0.
    std::mt19937_64 rng(o.classify.seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<double> theta;
    double fmax = 0.0;
    for (int s = 0; s < 4096; ++s) {
      Point x{0, 0, 0};
      for (int i = 0; i < dim(); ++i) {
        const auto a = static_cast<std::size_t>(i);
        x[a] = box.min[a] + unit(rng) * (box.max[a] - box.min[a]);
      }
      const double f = leaf_value(tree, params, src, x, theta);
      if (std::isfinite(f)) fmax = std::max(fmax, std::abs(f));
    }
    if (!(fmax > 0)) return empty();  // f == 0: f < 0 nowhere
    Tree t;
    t.dim = tree.dim;
    t.domain = box;
    t.params = tree.params;
    Node leaf = src;
    leaf.children.clear();
    leaf.step = Step{StepKind::kSigmoid, 0,
                     t.params.add(Parameter{"fuzzycsg_export_sharpness", 4.0 / fmax, true, false,
                                            Range::positive()})};
    t.nodes = {leaf};
    t.root = 0;
    std::vector<double> values(params.begin(), params.end());
    values.push_back(4.0 / fmax);
    return polytope(t, values, box, cell);
  }

  // A spline node (a blend, not a boolean: its crisp counterpart is the 0.5 level set of its
  // occupancy) meshed or contoured as a whole, like a leaf, over the domain grown by two cells.
  Lines meshed_subtree(int index) {
    ++report.meshed_subtrees;
    double cell = 0.0;
    const Domain box = mesh_box(cell);
    Tree t;
    t.dim = tree.dim;
    t.domain = box;
    t.params = tree.params;
    // The subtree's nodes, re-indexed in pre-order.
    std::vector<int> stack{index};
    std::vector<int> order;
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      order.push_back(i);
      const auto& kids = tree.node(i).children;
      for (auto it = kids.rbegin(); it != kids.rend(); ++it) stack.push_back(*it);
    }
    std::vector<int> remap(tree.nodes.size(), -1);
    for (std::size_t k = 0; k < order.size(); ++k)
      remap[static_cast<std::size_t>(order[k])] = static_cast<int>(k);
    for (const int i : order) {
      Node copy = tree.node(i);
      for (int& c : copy.children) c = remap[static_cast<std::size_t>(c)];
      t.nodes.push_back(std::move(copy));
    }
    t.root = 0;
    const std::vector<double> values(params.begin(), params.end());
    return polytope(t, values, box, cell);
  }

  // The 0.5 level set of `t` (whose domain is `box`) as a polyhedron (3D) or polygon (2D).
  Lines polytope(const Tree& t, std::span<const double> values, const Domain& box, double cell) {
    MeshOptions mo;
    mo.resolution = o.resolution + 4;
    mo.threads = o.threads;
    const auto at_edge = [&](const auto& v) {
      for (int i = 0; i < dim(); ++i) {
        const auto a = static_cast<std::size_t>(i);
        if (v[a] - box.min[a] < 1.5 * cell || box.max[a] - v[a] < 1.5 * cell) return true;
      }
      return false;
    };
    Lines l;
    if (dim() == 3) {
      const TriangleMesh mesh = extract_mesh(t, values, mo);
      if (mesh.triangles.empty()) return empty();
      const std::vector<Point> points = apart_from_grid(
          mesh, box, mo.resolution, 3, std::min(0.1 * cell, std::max(1e-3 * cell, 1e-5)));
      std::string text = "polyhedron(points = [";
      for (std::size_t v = 0; v < points.size(); ++v) {
        const auto& p = points[v];
        if (at_edge(p)) unbounded = true;
        text += fmt::format("{}[{}, {}, {}]", v ? ", " : "", num(p[0]), num(p[1]), num(p[2]));
      }
      // OpenSCAD wants the faces clockwise seen from outside; the mesh's are counter-clockwise.
      text += "], faces = [";
      for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
        const auto& tri = mesh.triangles[f];
        text += fmt::format("{}[{}, {}, {}]", f ? ", " : "", tri[0], tri[2], tri[1]);
      }
      l.add(0, text + "], convexity = 10);");
    } else {
      const Contours contours = extract_contours(t, values, mo);
      if (contours.loops.empty()) return empty();
      std::string points, loops;
      int k = 0;
      for (const auto& loop : contours.loops) {
        loops += loops.empty() ? "[" : ", [";
        for (std::size_t v = 0; v < loop.size(); ++v) {
          if (at_edge(loop[v])) unbounded = true;
          points += fmt::format("{}[{}, {}]", k ? ", " : "", num(loop[v][0]), num(loop[v][1]));
          loops += fmt::format("{}{}", v ? ", " : "", k++);
        }
        loops += "]";
      }
      l.add(0, "polygon(points = [" + points + "], paths = [" + loops + "], convexity = 10);");
    }
    return l;
  }

  // The leaf in its local frame (placement applied by the caller), for families OpenSCAD has.
  Lines exact(const Node& n, const Frame& frame) {
    std::vector<double> th(n.intrinsic.size());
    for (std::size_t i = 0; i < th.size(); ++i) th[i] = params[n.intrinsic[i].index];
    Lines l;
    switch (n.shape.type) {
      case PrimitiveType::kSphere:
        l.add(0, fmt::format("sphere(r = {});", num(th[0])));
        break;
      case PrimitiveType::kBox:
        l.add(0, fmt::format("cube({}, center = true);", vec(th)));
        break;
      case PrimitiveType::kCylinder:
        l.add(0, fmt::format("cylinder(h = {}, r = {}, center = true);", num(th[1]), num(th[0])));
        break;
      case PrimitiveType::kCone:
        l.add(0, fmt::format("cylinder(h = {}, r1 = {}, r2 = {}, center = true);", num(th[2]),
                             num(th[0]), num(th[1])));
        break;
      case PrimitiveType::kTorus:
        if (th[0] >= th[1]) {
          l.add(0, fmt::format("rotate_extrude() translate([{}, 0]) circle(r = {});", num(th[0]),
                               num(th[1])));
        } else {
          // A spindle torus: the section is the part of the circle with x >= 0.
          l.add(0, "rotate_extrude() intersection() {");
          l.add(1, fmt::format("translate([{}, 0]) circle(r = {});", num(th[0]), num(th[1])));
          l.add(1, fmt::format("translate([0, {}]) square([{}, {}]);", num(-th[1]),
                               num(th[0] + th[1]), num(2 * th[1])));
          l.add(0, "}");
        }
        break;
      case PrimitiveType::kEllipsoid:
        l.add(0, fmt::format("scale({}) sphere(r = 1);", vec(th)));
        break;
      case PrimitiveType::kCapsule:
        if (th[1] == 0) {
          l.add(0, fmt::format("sphere(r = {});", num(th[0])));
        } else {
          l.add(0, "hull() {");
          l.add(1, fmt::format("translate([0, 0, {}]) sphere(r = {});", num(-0.5 * th[1]),
                               num(th[0])));
          l.add(1,
                fmt::format("translate([0, 0, {}]) sphere(r = {});", num(0.5 * th[1]), num(th[0])));
          l.add(0, "}");
        }
        break;
      case PrimitiveType::kCircle:
        l.add(0, fmt::format("circle(r = {});", num(th[0])));
        break;
      case PrimitiveType::kRectangle:
        l.add(0, fmt::format("square({}, center = true);", vec(th)));
        break;
      case PrimitiveType::kEllipse:
        l.add(0, fmt::format("scale({}) circle(r = 1);", vec(th)));
        break;
      case PrimitiveType::kPolygon: {
        std::string pts;
        for (std::size_t v = 0; v + 1 < th.size(); v += 2) {
          pts += fmt::format("{}[{}, {}]", v ? ", " : "", num(th[v]), num(th[v + 1]));
        }
        l.add(0, "polygon([" + pts + "]);");
        break;
      }
      case PrimitiveType::kExtrude: {
        // The prism over the profile's polygon, the one the implicit function uses.
        const std::span<const double> all(th);
        const std::vector<double> polygon =
            without_straight_points(bezier_profile(all.first(th.size() - 1)));
        std::string pts;
        for (std::size_t v = 0; v + 1 < polygon.size(); v += 2) {
          pts += fmt::format("{}[{}, {}]", v ? ", " : "", num(polygon[v]), num(polygon[v + 1]));
        }
        l.add(0, fmt::format("linear_extrude(height = {}, center = true) polygon([{}]);",
                             num(th.back()), pts));
        break;
      }
      case PrimitiveType::kPlane:
      case PrimitiveType::kHalfPlane: {
        // n.p < d as a classified plane in the local frame, cut to the cover seen from there.
        const int d = dim();
        double norm = 0.0;
        for (int i = 0; i < d; ++i)
          norm += th[static_cast<std::size_t>(i)] * th[static_cast<std::size_t>(i)];
        norm = std::sqrt(norm);
        Point unit{0, 0, 0};
        for (int i = 0; i < d; ++i) {
          unit[static_cast<std::size_t>(i)] = th[static_cast<std::size_t>(i)] / norm;
        }
        std::vector<Point> pts;
        for (const Point& c : corners(cover, d)) pts.push_back(frame.to_local(c));
        if (d == 3) {
          l = half_space(unit, th[3], pts);
          break;
        }
        const QuadricClass cls = plane_class(d, unit, th[static_cast<std::size_t>(d)]);
        l = classified(cls, pts);
        break;
      }
      default:
        throw Error("scad export: no OpenSCAD primitive for this family");
    }
    return l;
  }

  Lines leaf(int index) {
    const Node& n = tree.node(index);
    ++report.leaves;
    LeafReport lr;
    lr.path = paths[static_cast<std::size_t>(index)];
    lr.type = std::string(primitive_info(n.shape.type).name);
    Lines out;
    const std::string label =
        comment_text(lr.path) + (n.name.empty() ? "" : " \"" + comment_text(n.name) + "\"");
    const PrimitiveType type = n.shape.type;
    if (type == PrimitiveType::kQuadric3 || type == PrimitiveType::kQuadric2) {
      ++report.quadric_leaves;
      lr.quadric = true;
      const std::vector<double> q = world_quadric(tree, params, index);
      lr.classification = classify_quadric(dim(), q, domain, o.classify);
      const QuadricClass& cls = lr.classification;
      if (cls.kind != QuadricKind::kNone) {
        ++report.quadrics_classified;
        lr.written = std::string(kind_name(cls.kind, dim()));
        if (cls.outside) ++report.quadrics_outside;
        const bool vowel = lr.written.find_first_of("aeiou") == 0;
        out.add(0, fmt::format("// {}: quadric, {}{} (signs agree on {:.2f}% of the samples)",
                               label, cls.outside ? "the outside of " : "",
                               (vowel ? "an " : "a ") + lr.written, cls.agreement * 100.0));
        out.append(classified(cls, corners(cover, dim())), 0);
      } else {
        lr.written = dim() == 3 ? "polyhedron" : "polygon";
        out.add(0, fmt::format("// {}: quadric, {}: meshed at resolution {}", label,
                               cls.note.empty() ? "not classified" : comment_text(cls.note),
                               o.resolution));
        out.append(meshed(index), 0);
      }
      ++report.quadric_kinds[lr.written];
    } else if (type == PrimitiveType::kMlp) {
      lr.written = "polyhedron";
      out.add(0, fmt::format("// {}: mlp, meshed at resolution {}", label, o.resolution));
      out.append(meshed(index), 0);
    } else {
      lr.written = lr.type;
      Lines body = exact(n, frame_of(tree, params, n));
      body.prefix_statement(placement_prefix(tree, params, n));
      if (o.leaf_comments) {
        out.add(0, "// " + label + ": " + lr.type);
      } else if (!n.name.empty()) {
        out.add(0, "// \"" + comment_text(n.name) + "\"");
      }
      out.append(body, 0);
    }
    report.leaf_reports.push_back(std::move(lr));
    return out;
  }

  // A plain union, intersection or difference (not unified, complement or spline).
  bool plain(int index, OpKind op) const {
    const Node& n = tree.node(index);
    return n.kind == NodeKind::kOperator && n.op == op;
  }

  // The children of a plain boolean as one OpenSCAD statement takes them, nested booleans that
  // mean the same folded in: a union's (an intersection's) children that are unions
  // (intersections) give their own children in their place; a difference's first child that is
  // a difference gives its children, and its later children that are unions give theirs
  // (difference() takes every later child away from the first). Folded operators are counted.
  std::vector<int> operands(int index) {
    const Node& n = tree.node(index);
    std::vector<int> out;
    for (std::size_t k = 0; k < n.children.size(); ++k) {
      const int c = n.children[k];
      const OpKind fold = n.op != OpKind::kDifference ? n.op
                          : k == 0                    ? OpKind::kDifference
                                                      : OpKind::kUnion;
      if (!plain(c, fold)) {
        out.push_back(c);
        continue;
      }
      ++report.operators;
      const std::vector<int> inner = operands(c);
      out.insert(out.end(), inner.begin(), inner.end());
    }
    return out;
  }

  Lines node(int index) {
    const Node& n = tree.node(index);
    if (n.kind == NodeKind::kPrimitive) return leaf(index);
    ++report.operators;
    Lines l;
    std::vector<int> kids = n.children;
    std::string op;
    switch (n.op) {
      case OpKind::kUnion:
        op = "union";
        break;
      case OpKind::kIntersection:
        op = "intersection";
        break;
      case OpKind::kDifference:
        op = "difference";
        break;
      case OpKind::kComplement:
        unbounded = true;
        l.add(0, "difference() {  // complement");
        l.add(1, "fuzzycsg_space();");
        l.append(node(kids[0]), 1);
        l.add(0, "}");
        return l;
      case OpKind::kSpline: {
        l.add(0, fmt::format("// {}: spline blend of {} shapes, meshed at resolution {}",
                             comment_text(paths[static_cast<std::size_t>(index)]), kids.size(),
                             o.resolution));
        l.append(meshed_subtree(index), 0);
        return l;
      }
      case OpKind::kUnified: {
        std::array<double, 4> c{};
        for (std::size_t k = 0; k < 4; ++k) c[k] = params[n.unified[k].index];
        if (n.unified_logits) {
          c = logic::unified_weights(c, params[n.temperature->index], params[n.omega->index]);
        }
        const auto best = static_cast<int>(std::max_element(c.begin(), c.end()) - c.begin());
        static constexpr std::array<const char*, 4> kOps{"intersection", "union", "difference",
                                                         "difference"};
        static constexpr std::array<const char*, 4> kWhat{"A & B", "A | B", "A \\ B", "B \\ A"};
        op = kOps[static_cast<std::size_t>(best)];
        if (best == 3) std::swap(kids[0], kids[1]);
        l.add(0, fmt::format(
                     "{}() {{  // unified, snapped to {} (c = [{:.3g}, {:.3g}, {:.3g}, {:.3g}])",
                     op, kWhat[static_cast<std::size_t>(best)], c[0], c[1], c[2], c[3]));
        for (const int k : kids) l.append(node(k), 1);
        l.add(0, "}");
        return l;
      }
    }
    l.add(0, op + "() {");
    for (const int k : operands(index)) l.append(node(k), 1);
    l.add(0, "}");
    return l;
  }
};

std::string render(const Lines& l) {
  std::string s;
  for (const auto& [d, t] : l.lines) {
    s.append(static_cast<std::size_t>(2 * d), ' ');
    s += t;
    s += '\n';
  }
  return s;
}

std::string box_module(const char* name, const Domain& d, int dim) {
  const Point lo{d.min[0], d.min[1], d.min[2]}, hi{d.max[0], d.max[1], d.max[2]};
  return fmt::format("module {}() {}\n", name, box_statement(dim, lo, hi));
}

}  // namespace

std::string report_json(const ExportReport& r) {
  nlohmann::ordered_json j;
  j["dim"] = r.dim;
  j["leaves"] = r.leaves;
  j["operators"] = r.operators;
  j["quadric_leaves"] = r.quadric_leaves;
  j["quadrics_classified"] = r.quadrics_classified;
  j["quadric_kinds"] = r.quadric_kinds;
  j["quadrics_outside"] = r.quadrics_outside;
  j["meshed_leaves"] = r.meshed_leaves;
  j["meshed_subtrees"] = r.meshed_subtrees;
  j["clipped_to_domain"] = r.clipped;
  nlohmann::ordered_json leaves = nlohmann::ordered_json::array();
  for (const LeafReport& l : r.leaf_reports) {
    nlohmann::ordered_json e;
    e["path"] = l.path;
    e["type"] = l.type;
    e["written"] = l.written;
    if (l.quadric) {
      const QuadricClass& c = l.classification;
      e["kind"] = std::string(kind_name(c.kind, c.dim));
      e["outside"] = c.outside;
      if (c.kind != QuadricKind::kNone || c.agreement > 0) e["agreement"] = c.agreement;
      if (c.kind != QuadricKind::kNone && c.kind != QuadricKind::kEmpty &&
          c.kind != QuadricKind::kFull) {
        const auto n = static_cast<std::size_t>(c.dim);
        e["center"] =
            std::vector<double>(c.center.begin(), c.center.begin() + static_cast<long>(n));
        e["axes"] = std::vector<double>(c.axes.begin(), c.axes.begin() + static_cast<long>(n));
        e["rotation"] = c.rotation;
      }
      if (!c.note.empty()) e["note"] = c.note;
    }
    leaves.push_back(std::move(e));
  }
  j["leaf_details"] = std::move(leaves);
  return j.dump(2) + "\n";
}

std::string export_scad(const Tree& tree, std::span<const double> params,
                        const ExportOptions& options, ExportReport* report) {
  if (options.fn < 3 || options.fn > 10000) {
    throw OptionError("fn", fmt::format("must be in [3, 10000] (got {})", options.fn));
  }
  const ClassifyOptions& c = options.classify;
  if (!(c.tolerance >= 0 && c.tolerance < 1)) {
    throw OptionError("classify.tolerance", fmt::format("must be in [0, 1) (got {})", c.tolerance));
  }
  if (c.samples < 1) {
    throw OptionError("classify.samples", fmt::format("must be >= 1 (got {})", c.samples));
  }
  if (!(c.min_agreement >= 0 && c.min_agreement <= 1)) {
    throw OptionError("classify.min_agreement",
                      fmt::format("must be in [0, 1] (got {})", c.min_agreement));
  }
  check_threads(options.threads);
  const int max_resolution = kMaxMeshResolution - 4;
  if (options.resolution < 2 || options.resolution > max_resolution) {
    throw OptionError("resolution", fmt::format("must be in [2, {}] (got {})", max_resolution,
                                                options.resolution));
  }
  if (params.size() != tree.params.size()) {
    throw Error(fmt::format("export_scad: {} parameters given, the tree has {}", params.size(),
                            tree.params.size()));
  }
  validate(tree, options.source.empty() ? "export_scad" : options.source);
  ExportReport local;
  ExportReport& rep = report ? *report : local;
  rep = ExportReport{};
  rep.dim = tree.dim;
  const Domain domain = grown(tree.domain_or_default(), tree.dim, 0.0);
  Writer w{
      tree, params, options, rep, node_paths(tree), domain, grown(domain, tree.dim, kCoverMargin)};
  const Lines body = w.node(tree.root);
  rep.clipped = options.clip == Clip::kAlways || (options.clip == Clip::kAuto && w.unbounded);

  std::string s;
  const std::string source = options.source.empty() ? "a tree" : comment_text(options.source);
  s += fmt::format("// {} ({}D, {} lea{}, {} operator{}) as OpenSCAD, written by {}.\n", source,
                   tree.dim, rep.leaves, rep.leaves == 1 ? "f" : "ves", rep.operators,
                   rep.operators == 1 ? "" : "s", options.writer);
  if (!options.note.empty()) {
    s += "// " + comment_text(options.note) + "\n";
  } else {
    s +=
        "// The crisp counterpart of the tree: every leaf is its set f < 0 and every operator the\n"
        "// crisp boolean of the same kind (unified operators snapped to their largest weight),\n"
        "// whatever the tree's steps, sharpnesses and logic families: a soft tree is exported as\n"
        "// its crisp counterpart.\n";
  }
  if (rep.quadric_leaves > 0) {
    std::string kinds;
    for (const auto& [k, count] : rep.quadric_kinds)
      kinds += fmt::format("{}{} {}", kinds.empty() ? "" : ", ", k, count);
    s += fmt::format("// Quadric leaves: {} of {} classified; written as: {}.\n",
                     rep.quadrics_classified, rep.quadric_leaves, kinds);
  }
  if (rep.meshed_leaves > 0) {
    s += fmt::format(
        "// {} leaves meshed at resolution {} (cells along the domain's longest side).\n",
        rep.meshed_leaves, options.resolution);
  }
  std::string extent;
  for (int i = 0; i < tree.dim; ++i) {
    extent +=
        fmt::format("{}[{}, {}]", i ? " x " : "", num(domain.min[static_cast<std::size_t>(i)]),
                    num(domain.max[static_cast<std::size_t>(i)]));
  }
  s += fmt::format(
      "// Domain {}; {}.\n", extent,
      rep.clipped ? "the model is intersected with it" : "the model is not clipped to it");
  s += fmt::format("$fn = {};\n\n", options.fn);
  // The boxes only where the program uses them.
  if (w.unbounded || rep.clipped) {
    s += "// The tree's domain, and the cover (the domain grown by 10% on every side) that stands\n"
         "// in for all of space in complements and cuts unbounded sets.\n";
    s += box_module("fuzzycsg_domain", domain, tree.dim);
    s += box_module("fuzzycsg_space", w.cover, tree.dim);
    s += "\n";
  }
  if (rep.clipped) {
    Lines clip;
    clip.add(0, "intersection() {");
    clip.add(1, "fuzzycsg_domain();");
    clip.append(body, 1);
    clip.add(0, "}");
    s += render(clip);
  } else {
    s += render(body);
  }
  return s;
}

void write_scad(const Tree& tree, std::span<const double> params, const std::filesystem::path& path,
                const ExportOptions& options, ExportReport* report) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".scad") {
    throw InputError(
        fmt::format("{}: unknown format '{}' (export writes .scad)", path.string(), ext));
  }
  io::write_text_file_atomic(path, export_scad(tree, params, options, report));
}

}  // namespace fuzzycsg::scad
