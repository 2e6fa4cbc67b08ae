#pragma once
// Closed profiles of piecewise cubic Bézier curves, the sketches of the `extrude` family
// (DiffCSG's sketch-extrude primitive, Yuan et al. 2024, Fig. 6d), their polygons and the
// triangulation of simple polygons.
//
// A profile of n >= 2 segments is a flat list of 3n points, two numbers each
// (x0, y0, x1, y1, ...), in the order P0, A0, B0, P1, A1, B1, ..., P(n-1), A(n-1), B(n-1):
// segment k is the cubic Bézier curve from P_k through the controls A_k and B_k to
// P_((k+1) mod n), so the profile is closed.
//
// A profile is polygonised by sampling every segment `samples` times, at t = s / samples for
// s = 0 .. samples - 1: sample 0 of segment k is P_k itself, and P_(k+1) is sample 0 of the next
// segment. Each sample is a fixed combination of four control points with the Bernstein weights
// of its t, so the polygon is a linear map of the control points, the same for every profile of
// n segments: the gradient of anything computed from the polygon with respect to the control
// points is its gradient with respect to the polygon's points times the transposed weights
// (bezier_profile_vjp).

#include <array>
#include <cstddef>
#include <span>
#include <vector>

namespace fuzzycsg {

// Samples per segment (DiffCSG samples each curve 15 times).
inline constexpr int kBezierSamples = 15;
// Segments of the smallest profile.
inline constexpr int kBezierMinSegments = 2;

// The cubic Bernstein weights at t, of P_k, A_k, B_k and P_(k+1):
// ((1 - t)^3, 3 t (1 - t)^2, 3 t^2 (1 - t), t^3).
constexpr std::array<double, 4> bernstein_weights(double t) {
  const double u = 1.0 - t;
  return {u * u * u, 3.0 * t * u * u, 3.0 * t * t * u, t * t * t};
}

// The weights of sample s of a segment sampled `samples` times (t = s / samples); sample 0 has
// the weights (1, 0, 0, 0).
constexpr std::array<double, 4> bezier_sample_weights(int sample, int samples) {
  return bernstein_weights(static_cast<double>(sample) / static_cast<double>(samples));
}

// The point index (0 .. 3n - 1) of control j of segment k in a profile of n segments:
// j = 0 is P_k, 1 is A_k, 2 is B_k and 3 is P_((k+1) mod n).
constexpr std::size_t bezier_control_index(std::size_t segments, std::size_t k, int j) {
  return j < 3 ? 3 * k + static_cast<std::size_t>(j) : 3 * ((k + 1) % segments);
}

// The point of segment k with Bernstein weights w into out[0..2). `control` holds the profile's
// 6n numbers. Every user (bezier_profile, the extrude family's distance) sums in this order, so
// they agree bit for bit.
template <class T>
inline void bezier_point(std::span<const T> control, std::size_t k, const std::array<double, 4>& w,
                         T* out) {
  const std::size_t segments = control.size() / 6;
  for (int c = 0; c < 2; ++c) {
    T s = T(0);
    for (int j = 0; j < 4; ++j) {
      s += static_cast<T>(w[static_cast<std::size_t>(j)]) *
           control[2 * bezier_control_index(segments, k, j) + static_cast<std::size_t>(c)];
    }
    out[c] = s;
  }
}

// The closed polygon of a profile: n * samples points (2 numbers each), sample s of segment k
// at point k * samples + s. Throws InputError unless `control` holds 6n numbers with n >= 2 and
// samples >= 1.
std::vector<double> bezier_profile(std::span<const double> control, int samples = kBezierSamples);

// The transpose of bezier_profile's linear map: the gradient with respect to the 6n control
// numbers of a function of the polygon whose gradient with respect to the polygon's points is
// `grad_polygon` (2 n samples numbers). Throws InputError when the sizes do not fit.
std::vector<double> bezier_profile_vjp(std::span<const double> grad_polygon, int segments,
                                       int samples = kBezierSamples);

// A triangle of a triangulation: three point indices.
using PolygonTriangle = std::array<int, 3>;

// The triangles of a simple polygon (points as x0, y0, x1, y1, ...; either orientation) by ear
// clipping: n - 2 triangles with positive area, each in the polygon's own orientation (counter-
// clockwise for a counter-clockwise polygon), together covering it exactly. Collinear points
// (a straight stretch sampled many times) are kept as vertices and never clipped as flat ears.
// Throws InputError when the polygon is degenerate (fewer than 3 points, a repeated consecutive
// point, a non-finite coordinate, zero area) or self-intersecting (edges that cross, touch or
// overlap, a spike that doubles back on itself).
std::vector<PolygonTriangle> triangulate_polygon(std::span<const double> points);

}  // namespace fuzzycsg
