#pragma once
// Scan conversion as row spans (internal to the trace module): for_each_span() calls
// f(row, col0, col1) for every row of the bitmap where the primitive covers the pixel centres
// of columns [col0, col1), exactly those for which contains() holds.

#include <cmath>
#include <numbers>
#include <utility>

#include "fuzzycsg/trace/csg.hpp"

// The hot loops of the module count bits and round coordinates; on x86-64 they are compiled
// twice, for the baseline and for x86-64-v2 (POPCNT, SSE4.1 rounding), and the loader picks
// the one the processor runs.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FUZZYCSG_TRACE_HOT __attribute__((target_clones("arch=x86-64-v2", "default")))
#else
#define FUZZYCSG_TRACE_HOT
#endif

namespace fuzzycsg::trace::detail {

// contains() with the rotation computed once; the same arithmetic, so the same answers.
struct PreparedPrimitive {
  explicit PreparedPrimitive(const Primitive& prim) : p(prim) {
    if (prim.shape == Shape::kRectangle) {
      const double t = prim.theta * (std::numbers::pi / 180.0);
      c = std::cos(t);
      s = std::sin(t);
    }
  }
  bool inside(double px, double py) const {
    const double dx = px - p.x, dy = py - p.y;
    if (p.shape == Shape::kCircle) return dx * dx + dy * dy < p.r * p.r;
    const double u = c * dx + s * dy, v = -s * dx + c * dy;
    return std::abs(u) < p.w / 2 && std::abs(v) < p.h / 2;
  }
  const Primitive& p;
  double c = 1, s = 0;
};

// The index of the first pixel centre (k + 1/2) at or after v, as a clamped integer.
inline int clamp_index(double v, int lo, int hi) {
  if (!(v > lo)) return lo;  // also NaN
  if (!(v < hi)) return hi;
  return static_cast<int>(v);
}

template <class F>
[[gnu::always_inline]] inline void for_each_span(const Primitive& p, const PixelBox& box, F&& f) {
  if (box.empty()) return;
  const PreparedPrimitive prep(p);
  const double c = prep.c, s = prep.s;
  for (int j = box.row0; j < box.row1; ++j) {
    const double py = j + 0.5, dy = py - p.y;
    // The open interval (lo, hi) of x where the row is inside, approximately.
    double lo = 0, hi = 0;
    if (p.shape == Shape::kCircle) {
      const double d2 = p.r * p.r - dy * dy;
      if (!(d2 > 0)) continue;  // dx^2 + dy^2 >= dy^2 >= r^2 for every dx
      const double half = std::sqrt(d2);
      lo = p.x - half;
      hi = p.x + half;
    } else {
      lo = -HUGE_VAL;
      hi = HUGE_VAL;
      // |c dx + s dy| < w / 2 and |-s dx + c dy| < h / 2.
      const auto slab = [&](double a, double b, double half) {
        if (std::abs(a) < 1e-300) {
          if (!(std::abs(b) < half)) hi = lo = 0;
          return;
        }
        double t0 = (-half - b) / a, t1 = (half - b) / a;
        if (t0 > t1) std::swap(t0, t1);
        lo = std::max(lo, p.x + t0);
        hi = std::min(hi, p.x + t1);
      };
      slab(c, s * dy, p.w / 2);
      slab(-s, c * dy, p.h / 2);
    }
    const auto inside = [&](int i) { return prep.inside(i + 0.5, py); };
    const double a = lo - 0.5, b = hi - 0.5;
    // Away from pixel centres (by far more than the rounding of lo and hi, for coordinates up
    // to 1e6) the interval decides; near one, the point test does.
    if (std::abs(a) < 1e6 && std::abs(b) < 1e6 && std::abs(a - std::floor(a + 0.5)) > 1e-7 &&
        std::abs(b - std::floor(b + 0.5)) > 1e-7) {
      const int f0 = std::max(box.col0, static_cast<int>(std::ceil(a)));
      const int f1 = std::min(box.col1 - 1, static_cast<int>(std::floor(b)));
      if (f0 <= f1) f(j, f0, f1 + 1);
      continue;
    }
    int i0 = clamp_index(std::ceil(a), box.col0, box.col1 - 1);
    int i1 = clamp_index(std::floor(b), box.col0, box.col1 - 1);
    if (i0 > i1) {
      // Empty or a sliver: only the pixel nearest the interval can be inside.
      i0 = i1 = clamp_index(std::floor((lo + hi) / 2), box.col0, box.col1 - 1);
      if (!inside(i0)) continue;
    }
    // Exact ends by the point test (the row's inside pixels are contiguous: the shapes are
    // convex).
    while (i0 <= i1 && !inside(i0)) ++i0;
    while (i1 >= i0 && !inside(i1)) --i1;
    if (i0 > i1) continue;
    while (i0 > box.col0 && inside(i0 - 1)) --i0;
    while (i1 + 1 < box.col1 && inside(i1 + 1)) ++i1;
    f(j, i0, i1 + 1);
  }
}

}  // namespace fuzzycsg::trace::detail
