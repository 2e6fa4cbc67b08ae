// Bézier profiles and their polygons; triangulation of simple polygons by ear clipping.
//
// The ear clipping is written here rather than taken from a library: Debian packages no C++
// earcut (only Python bindings), and CGAL's constrained triangulation would be a heavy header
// dependency for polygons of a few hundred points.
#include "fuzzycsg/core/bezier.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg {

namespace {

std::size_t profile_segments(std::span<const double> control, const char* fn) {
  if (control.size() % 6 != 0) {
    throw InputError(std::string(fn) + ": control has " + std::to_string(control.size()) +
                     " numbers; a profile has 6 per segment (P, A, B as [x, y])");
  }
  const std::size_t segments = control.size() / 6;
  if (segments < static_cast<std::size_t>(kBezierMinSegments)) {
    throw InputError(std::string(fn) + ": a closed profile needs at least " +
                     std::to_string(kBezierMinSegments) + " segments (got " +
                     std::to_string(segments) + ")");
  }
  return segments;
}

void check_samples(int samples, const char* fn) {
  if (samples < 1) {
    throw InputError(std::string(fn) + ": samples must be >= 1 (got " + std::to_string(samples) +
                     ")");
  }
}

// ---------------------------------------------------------------------------------------------
// Triangulation

struct Pt {
  double x, y;
};

// (b - a) x (c - a): > 0 when a, b, c turn counter-clockwise.
double cross(const Pt& a, const Pt& b, const Pt& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

[[noreturn]] void fail(const std::string& problem) {
  throw InputError("triangulate_polygon: " + problem);
}

std::string edge_name(std::size_t i, std::size_t n) {
  return "edge " + std::to_string(i) + " (points " + std::to_string(i) + ", " +
         std::to_string((i + 1) % n) + ")";
}

// Sign of an orientation with values within `tol` of 0 taken as 0.
int sign(double v, double tol) { return v > tol ? 1 : (v < -tol ? -1 : 0); }

// Whether c, collinear with a and b, lies on the closed segment ab.
bool within(const Pt& a, const Pt& b, const Pt& c) {
  return std::min(a.x, b.x) <= c.x && c.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= c.y &&
         c.y <= std::max(a.y, b.y);
}

// Whether the closed segments ab and cd share a point (orientations within tol count as 0).
bool segments_meet(const Pt& a, const Pt& b, const Pt& c, const Pt& d, double tol) {
  const int o1 = sign(cross(a, b, c), tol);
  const int o2 = sign(cross(a, b, d), tol);
  const int o3 = sign(cross(c, d, a), tol);
  const int o4 = sign(cross(c, d, b), tol);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return (o1 == 0 && within(a, b, c)) || (o2 == 0 && within(a, b, d)) ||
         (o3 == 0 && within(c, d, a)) || (o4 == 0 && within(c, d, b));
}

// Throws unless the closed polyline is simple: non-adjacent edges share no point, and adjacent
// edges meet only at their common point (no spike doubling back).
void check_simple(const std::vector<Pt>& p, double tol) {
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Pt& a = p[i];
    const Pt& b = p[(i + 1) % n];
    const Pt& c = p[(i + 2) % n];
    // The next edge b -> c runs back along a -> b.
    if (sign(cross(a, b, c), tol) == 0 &&
        (b.x - a.x) * (c.x - b.x) + (b.y - a.y) * (c.y - b.y) < 0) {
      fail("the outline doubles back on itself at point " + std::to_string((i + 1) % n) +
           " (the polygon is self-intersecting)");
    }
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through point 0
      if (segments_meet(a, b, p[j], p[(j + 1) % n], tol)) {
        fail(edge_name(i, n) + " and " + edge_name(j, n) +
             " meet (the polygon is self-intersecting)");
      }
    }
  }
}

}  // namespace

std::vector<double> bezier_profile(std::span<const double> control, int samples) {
  const std::size_t segments = profile_segments(control, "bezier_profile");
  check_samples(samples, "bezier_profile");
  const auto per = static_cast<std::size_t>(samples);
  std::vector<double> out(2 * segments * per);
  for (std::size_t k = 0; k < segments; ++k) {
    for (std::size_t s = 0; s < per; ++s) {
      bezier_point(control, k, bezier_sample_weights(static_cast<int>(s), samples),
                   out.data() + 2 * (k * per + s));
    }
  }
  return out;
}

std::vector<double> bezier_profile_vjp(std::span<const double> grad_polygon, int segments,
                                       int samples) {
  if (segments < kBezierMinSegments) {
    throw InputError("bezier_profile_vjp: a closed profile needs at least " +
                     std::to_string(kBezierMinSegments) + " segments (got " +
                     std::to_string(segments) + ")");
  }
  check_samples(samples, "bezier_profile_vjp");
  const auto n = static_cast<std::size_t>(segments);
  const auto per = static_cast<std::size_t>(samples);
  if (grad_polygon.size() != 2 * n * per) {
    throw InputError("bezier_profile_vjp: grad_polygon has " + std::to_string(grad_polygon.size()) +
                     " numbers, expected " + std::to_string(2 * n * per) + " (2 per point, " +
                     std::to_string(samples) + " points per segment)");
  }
  std::vector<double> out(6 * n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t s = 0; s < per; ++s) {
      const auto w = bezier_sample_weights(static_cast<int>(s), samples);
      const double* g = grad_polygon.data() + 2 * (k * per + s);
      for (int j = 0; j < 4; ++j) {
        const std::size_t c = 2 * bezier_control_index(n, k, j);
        out[c] += w[static_cast<std::size_t>(j)] * g[0];
        out[c + 1] += w[static_cast<std::size_t>(j)] * g[1];
      }
    }
  }
  return out;
}

std::vector<PolygonTriangle> triangulate_polygon(std::span<const double> points) {
  if (points.size() % 2 != 0) {
    fail("points has " + std::to_string(points.size()) + " numbers, not 2 per point");
  }
  const std::size_t n = points.size() / 2;
  if (n < 3) fail("a polygon needs at least 3 points (got " + std::to_string(n) + ")");
  std::vector<Pt> p(n);
  double lo_x = points[0], hi_x = points[0], lo_y = points[1], hi_y = points[1];
  for (std::size_t i = 0; i < n; ++i) {
    p[i] = {points[2 * i], points[2 * i + 1]};
    if (!std::isfinite(p[i].x) || !std::isfinite(p[i].y)) {
      fail("point " + std::to_string(i) + " is not finite");
    }
    lo_x = std::min(lo_x, p[i].x);
    hi_x = std::max(hi_x, p[i].x);
    lo_y = std::min(lo_y, p[i].y);
    hi_y = std::max(hi_y, p[i].y);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Pt& a = p[i];
    const Pt& b = p[(i + 1) % n];
    if (a.x == b.x && a.y == b.y) {
      fail("points " + std::to_string(i) + " and " + std::to_string((i + 1) % n) +
           " coincide (a degenerate polygon)");
    }
  }
  // Orientation tests are taken as 0 within a tolerance relative to the polygon's size, so that
  // points sampled along a straight line count as collinear despite rounding.
  const double extent = std::hypot(hi_x - lo_x, hi_y - lo_y);
  const double tol = 1e-13 * extent * extent;
  double area2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Pt& a = p[i];
    const Pt& b = p[(i + 1) % n];
    area2 += a.x * b.y - b.x * a.y;
  }
  check_simple(p, tol);
  if (!(std::abs(area2) > 1e3 * tol)) fail("the polygon has zero area (a degenerate polygon)");
  const double orient = area2 > 0 ? 1.0 : -1.0;

  // Ear clipping on a doubly linked ring. An ear is a vertex v, strictly convex, whose triangle
  // (u, v, w) with its neighbours holds no other remaining point, boundary included; clipping
  // it leaves a simple polygon with one point fewer. Every simple polygon of positive area has
  // one, also when some of its points are collinear (those are never clipped themselves, which
  // would make a flat triangle). The first pass asks for convexity beyond rounding and treats
  // points within rounding of the triangle as inside; the second, only taken when the first
  // finds nothing, uses the plain signs.
  std::vector<std::size_t> prev(n), next(n);
  for (std::size_t i = 0; i < n; ++i) {
    prev[i] = (i + n - 1) % n;
    next[i] = (i + 1) % n;
  }
  const auto is_ear = [&](std::size_t v, double convex_tol, double inside_tol) {
    const std::size_t u = prev[v];
    const std::size_t w = next[v];
    const Pt& a = p[u];
    const Pt& b = p[v];
    const Pt& c = p[w];
    const double turn = orient * cross(a, b, c);
    if (!(turn >
          convex_tol * std::hypot(b.x - a.x, b.y - a.y) * std::hypot(c.x - b.x, c.y - b.y))) {
      return false;
    }
    for (std::size_t x = next[w]; x != u; x = next[x]) {
      const Pt& q = p[x];
      if (orient * cross(a, b, q) >= -inside_tol && orient * cross(b, c, q) >= -inside_tol &&
          orient * cross(c, a, q) >= -inside_tol) {
        return false;
      }
    }
    return true;
  };
  std::vector<PolygonTriangle> out;
  out.reserve(n - 2);
  const auto emit = [&](std::size_t u, std::size_t v, std::size_t w) {
    out.push_back({static_cast<int>(u), static_cast<int>(v), static_cast<int>(w)});
  };
  std::size_t left = n;
  std::size_t v = 0;
  while (left > 3) {
    std::size_t found = n;
    for (const auto& [convex_tol, inside_tol] : {std::pair{1e-10, tol}, std::pair{0.0, 0.0}}) {
      std::size_t x = v;
      for (std::size_t k = 0; k < left; ++k, x = next[x]) {
        if (is_ear(x, convex_tol, inside_tol)) {
          found = x;
          break;
        }
      }
      if (found != n) break;
    }
    if (found == n) fail("no ear left to clip (the polygon is degenerate or self-intersecting)");
    const std::size_t u = prev[found];
    const std::size_t w = next[found];
    emit(u, found, w);
    next[u] = w;
    prev[w] = u;
    --left;
    v = w;  // go on from the clipped ear's neighbour: ears tend to be found next to each other
  }
  emit(prev[v], v, next[v]);
  return out;
}

}  // namespace fuzzycsg
