#pragma once
// Scan conversion as row spans (internal to the trace module): for_each_span() calls
// f(row, col0, col1) for every row of the bitmap where the primitive covers the pixel centres
// of columns [col0, col1), exactly those for which contains() holds.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "fuzzycsg/trace/csg.hpp"

// The hot loops of the module count bits and round coordinates; on x86-64 they are compiled
// three times, for the baseline, x86-64-v2 (POPCNT, SSE4.1 rounding) and x86-64-v3 (AVX2),
// and the loader picks the one the processor runs.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FUZZYCSG_TRACE_HOT \
  __attribute__((target_clones("arch=x86-64-v3", "arch=x86-64-v2", "default")))
#else
#define FUZZYCSG_TRACE_HOT
#endif

namespace fuzzycsg::trace::detail {

// contains() with the rotation computed once; the same arithmetic, so the same answers.
struct PreparedPrimitive {
  explicit PreparedPrimitive(const Primitive& prim) : p(prim) {
    if (prim.shape == Shape::kRectangle) rotation(prim.theta, c, s);
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

// The columns of row j inside the primitive, given the approximate open interval (lo, hi) of x
// where the row is inside, found exactly by point tests at the ends. Returns false when none.
inline bool exact_span(const PreparedPrimitive& prep, const PixelBox& box, int j, double lo,
                       double hi, int& c0, int& c1) {
  const double py = j + 0.5;
  const auto inside = [&](int i) { return prep.inside(i + 0.5, py); };
  int i0 = clamp_index(std::ceil(lo - 0.5), box.col0, box.col1 - 1);
  int i1 = clamp_index(std::floor(hi - 0.5), box.col0, box.col1 - 1);
  if (i0 > i1) {
    // Empty or a sliver: only the pixel nearest the interval can be inside.
    i0 = i1 = clamp_index(std::floor((lo + hi) / 2), box.col0, box.col1 - 1);
    if (!inside(i0)) return false;
  }
  // Exact ends by the point test (the row's inside pixels are contiguous: the shapes are
  // convex).
  while (i0 <= i1 && !inside(i0)) ++i0;
  while (i1 >= i0 && !inside(i1)) --i1;
  if (i0 > i1) return false;
  while (i0 > box.col0 && inside(i0 - 1)) --i0;
  while (i1 + 1 < box.col1 && inside(i1 + 1)) ++i1;
  c0 = i0;
  c1 = i1 + 1;
  return true;
}

// Calls f(row, col0, col1) for the span of every row in `box`, from the approximate open
// intervals (lo, hi) of x where the rows are inside that interval(first row, count, lo, hi)
// writes (lo > hi: none), a block of rows at a time so that the arithmetic vectorises.
template <class Interval, class F>
[[gnu::always_inline]] inline void spans_of(const PreparedPrimitive& prep, const PixelBox& box,
                                            Interval&& interval, F&& f) {
  constexpr int kBlock = 32;
  alignas(64) double lo[kBlock], hi[kBlock];
  alignas(64) int c0[kBlock], c1[kBlock], near[kBlock];
  for (int j0 = box.row0; j0 < box.row1; j0 += kBlock) {
    const int n = std::min(kBlock, box.row1 - j0);
    interval(j0, n, lo, hi);
    for (int k = 0; k < n; ++k) {
      const double a = lo[k] - 0.5, b = hi[k] - 0.5;
      // Away from pixel centres (by far more than the rounding of lo and hi, for coordinates
      // up to 1e6) the interval decides; near one, the point test does.
      // (Non-short-circuit operators, so that the loop has no branches.)
      const double ca = std::ceil(a), fb = std::floor(b);
      const bool a_small = std::abs(a) < 1e6, b_small = std::abs(b) < 1e6;
      const bool a_off = std::abs(a - std::floor(a + 0.5)) > 1e-7;
      const bool b_off = std::abs(b - std::floor(b + 0.5)) > 1e-7;
      const bool sure = a_small & b_small & a_off & b_off;
      const bool none = !(lo[k] < hi[k]);  // also NaN
      near[k] = (!none) & (!sure);
      c0[k] = static_cast<int>(sure ? ca : 0.0);
      c1[k] = static_cast<int>(sure ? fb + 1 : 0.0);
    }
    for (int k = 0; k < n; ++k) {
      const int j = j0 + k;
      if (near[k]) {
        int e0 = 0, e1 = 0;
        if (exact_span(prep, box, j, lo[k], hi[k], e0, e1)) f(j, e0, e1);
        continue;
      }
      const int f0 = std::max(box.col0, c0[k]), f1 = std::min(box.col1, c1[k]);
      if (f0 < f1) f(j, f0, f1);
    }
  }
}

template <class F>
[[gnu::always_inline]] inline void for_each_span(const Primitive& p, const PixelBox& box, F&& f) {
  if (box.empty()) return;
  const PreparedPrimitive prep(p);
  const double x = p.x, y = p.y;
  if (p.shape == Shape::kCircle) {
    const double r2 = p.r * p.r;
    spans_of(
        prep, box,
        [&](int j0, int n, double* lo, double* hi) {
          for (int k = 0; k < n; ++k) {
            const double dy = (j0 + k) + 0.5 - y, d2 = r2 - dy * dy;
            // d2 <= 0: dx^2 + dy^2 >= dy^2 >= r^2 for every dx, no pixel.
            const double half = std::sqrt(d2 > 0 ? d2 : 0.0);
            lo[k] = d2 > 0 ? x - half : HUGE_VAL;
            hi[k] = d2 > 0 ? x + half : -HUGE_VAL;
          }
        },
        f);
    return;
  }
  // |c dx + s dy| < w / 2 and |-s dx + c dy| < h / 2: for each, dx within
  // ((-half - b dy) / a, (half - b dy) / a), swapped when a < 0.
  const double c = prep.c, s = prep.s;
  const double hw = p.w / 2, hh = p.h / 2;
  const bool degenerate_u = std::abs(c) < 1e-300, degenerate_v = std::abs(s) < 1e-300;
  const double inv_u = degenerate_u ? 0 : 1 / c, inv_v = degenerate_v ? 0 : -1 / s;
  spans_of(
      prep, box,
      [&](int j0, int n, double* lo, double* hi) {
        for (int k = 0; k < n; ++k) {
          const double dy = (j0 + k) + 0.5 - y;
          const double bu = s * dy, bv = c * dy;
          const double u0 = (-hw - bu) * inv_u, u1 = (hw - bu) * inv_u;
          const double v0 = (-hh - bv) * inv_v, v1 = (hh - bv) * inv_v;
          double l = std::max(u0 < u1 ? u0 : u1, v0 < v1 ? v0 : v1);
          double h = std::min(u0 < u1 ? u1 : u0, v0 < v1 ? v1 : v0);
          if (degenerate_u) {
            l = v0 < v1 ? v0 : v1;
            h = v0 < v1 ? v1 : v0;
            if (!(std::abs(bu) < hw)) l = HUGE_VAL, h = -HUGE_VAL;
          } else if (degenerate_v) {
            l = u0 < u1 ? u0 : u1;
            h = u0 < u1 ? u1 : u0;
            if (!(std::abs(bv) < hh)) l = HUGE_VAL, h = -HUGE_VAL;
          }
          lo[k] = x + l;
          hi[k] = x + h;
        }
      },
      f);
}

}  // namespace fuzzycsg::trace::detail
