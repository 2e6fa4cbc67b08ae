// Bézier profiles (the sketches of the extrude family): the Bernstein weights, the sampled
// polygon (interpolation of the segment ends, straight segments, linearity and the transposed
// map of the gradient), and ear-clipping triangulation of convex, concave and sampled polygons
// in both orientations, with its errors.
#include "fuzzycsg/core/bezier.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/profiles.hpp"
#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg {
namespace {

using Vec = std::vector<double>;

// A random profile of `segments` segments: its 3n points spread around the origin.
Vec random_profile(std::mt19937& rng, int segments) {
  std::uniform_real_distribution<double> jitter(0.15, 0.85), radius(0.5, 1.0);
  Vec c;
  const int points = 3 * segments;
  for (int i = 0; i < points; ++i) {
    const double a = 2 * std::numbers::pi * (i + jitter(rng)) / points;
    const double r = radius(rng);
    c.push_back(r * std::cos(a));
    c.push_back(r * std::sin(a));
  }
  return c;
}

using test::straight_profile;

// A D: a straight side from (0, -1) up to (0, 1) (controls at thirds), then a cubic bulging to
// +x back down to (0, -1).
const Vec kDProfile = {0, -1, 0, -1.0 / 3, 0, 1.0 / 3, 0, 1, 1.3, 1, 1.3, -1};

Vec reversed(const Vec& points) {
  Vec r;
  for (std::size_t i = points.size() / 2; i-- > 0;) {
    r.push_back(points[2 * i]);
    r.push_back(points[2 * i + 1]);
  }
  return r;
}

double signed_area(const Vec& p) {
  const std::size_t n = p.size() / 2;
  double a = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    a += p[2 * i] * p[2 * j + 1] - p[2 * j] * p[2 * i + 1];
  }
  return 0.5 * a;
}

TEST(BezierProfile, BernsteinWeights) {
  EXPECT_EQ(kBezierSamples, 15);
  const auto w0 = bezier_sample_weights(0, kBezierSamples);
  EXPECT_EQ(w0, (std::array<double, 4>{1, 0, 0, 0}));
  const auto half = bernstein_weights(0.5);
  EXPECT_DOUBLE_EQ(half[0], 0.125);
  EXPECT_DOUBLE_EQ(half[1], 0.375);
  EXPECT_DOUBLE_EQ(half[2], 0.375);
  EXPECT_DOUBLE_EQ(half[3], 0.125);
  for (int s = 0; s < kBezierSamples; ++s) {
    const auto w = bezier_sample_weights(s, kBezierSamples);
    const double t = static_cast<double>(s) / kBezierSamples;
    EXPECT_NEAR(w[0] + w[1] + w[2] + w[3], 1.0, 1e-15) << s;
    EXPECT_DOUBLE_EQ(w[3], t * t * t) << s;
    for (double x : w) EXPECT_GE(x, 0.0) << s;
  }
  // Control indices: A_k, B_k after P_k; the last segment ends at P_0.
  EXPECT_EQ(bezier_control_index(4, 1, 0), 3u);
  EXPECT_EQ(bezier_control_index(4, 1, 2), 5u);
  EXPECT_EQ(bezier_control_index(4, 1, 3), 6u);
  EXPECT_EQ(bezier_control_index(4, 3, 3), 0u);
}

TEST(BezierProfile, ProfileInterpolatesTheSegmentEnds) {
  std::mt19937 rng(3);
  for (int segments : {2, 3, 5}) {
    for (int samples : {1, 2, 7, kBezierSamples}) {
      const Vec c = random_profile(rng, segments);
      const Vec poly = bezier_profile(c, samples);
      ASSERT_EQ(poly.size(), static_cast<std::size_t>(2 * segments * samples));
      for (int k = 0; k < segments; ++k) {
        const std::size_t at = 2 * static_cast<std::size_t>(k * samples);
        EXPECT_EQ(poly[at], c[6 * static_cast<std::size_t>(k)]) << segments << " " << samples;
        EXPECT_EQ(poly[at + 1], c[6 * static_cast<std::size_t>(k) + 1]);
      }
    }
  }
  // The default is kBezierSamples per segment; sample 1 of 2 is the curve at t = 1/2.
  const Vec c = random_profile(rng, 3);
  EXPECT_EQ(bezier_profile(c).size(), 2u * 3 * kBezierSamples);
  const Vec half = bezier_profile(c, 2);
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t q = 6 * ((k + 1) % 3);
    for (std::size_t x = 0; x < 2; ++x) {
      const double expected =
          (c[6 * k + x] + 3 * c[6 * k + 2 + x] + 3 * c[6 * k + 4 + x] + c[q + x]) / 8;
      EXPECT_NEAR(half[2 * (2 * k + 1) + x], expected, 1e-15);
    }
  }
}

TEST(BezierProfile, StraightSegmentsAreSampledUniformly) {
  const Vec corners = {-0.5, -0.2, 0.7, -0.4, 0.3, 0.9};
  const Vec poly = bezier_profile(straight_profile(corners), kBezierSamples);
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t m = (k + 1) % 3;
    for (std::size_t s = 0; s < kBezierSamples; ++s) {
      const double t = static_cast<double>(s) / kBezierSamples;
      for (std::size_t x = 0; x < 2; ++x) {
        EXPECT_NEAR(poly[2 * (k * kBezierSamples + s) + x],
                    corners[2 * k + x] + t * (corners[2 * m + x] - corners[2 * k + x]), 1e-15);
      }
    }
  }
}

TEST(BezierProfile, ProfileIsLinearAndTheVjpIsItsTranspose) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int segments : {2, 4}) {
    for (int samples : {3, kBezierSamples}) {
      const Vec a = random_profile(rng, segments), b = random_profile(rng, segments);
      Vec combo(a.size());
      for (std::size_t i = 0; i < a.size(); ++i) combo[i] = 2.5 * a[i] - b[i];
      const Vec pa = bezier_profile(a, samples), pb = bezier_profile(b, samples);
      const Vec pc = bezier_profile(combo, samples);
      for (std::size_t i = 0; i < pc.size(); ++i) EXPECT_NEAR(pc[i], 2.5 * pa[i] - pb[i], 1e-14);
      // <vjp(g), c> = <g, profile(c)> for every g and c.
      Vec grad(pa.size());
      for (double& x : grad) x = g(rng);
      const Vec back = bezier_profile_vjp(grad, segments, samples);
      ASSERT_EQ(back.size(), a.size());
      double lhs = 0.0, rhs = 0.0;
      for (std::size_t i = 0; i < a.size(); ++i) lhs += back[i] * a[i];
      for (std::size_t i = 0; i < pa.size(); ++i) rhs += grad[i] * pa[i];
      EXPECT_NEAR(lhs, rhs, 1e-12 * (1 + std::abs(rhs)));
      // One polygon point at a time: its sample's weights on its segment's four controls.
      const std::size_t point = static_cast<std::size_t>(samples) + 1;  // segment 1, sample 1
      Vec unit(pa.size(), 0.0);
      unit[2 * point] = 1.0;
      const Vec column = bezier_profile_vjp(unit, segments, samples);
      const auto w = bezier_sample_weights(1, samples);
      for (int j = 0; j < 4; ++j) {
        const auto s = static_cast<std::size_t>(segments);
        EXPECT_DOUBLE_EQ(column[2 * bezier_control_index(s, 1, j)], w[static_cast<std::size_t>(j)]);
        EXPECT_EQ(column[2 * bezier_control_index(s, 1, j) + 1], 0.0);
      }
    }
  }
}

TEST(BezierProfile, ProfileErrors) {
  const auto message = [](auto&& f) -> std::string {
    try {
      f();
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  const Vec one_segment = {0, 0, 1, 0, 1, 1};
  EXPECT_EQ(message([&] { bezier_profile(one_segment); }),
            "bezier_profile: a closed profile needs at least 2 segments (got 1)");
  const Vec odd(13, 0.0);
  EXPECT_EQ(message([&] { bezier_profile(odd); }),
            "bezier_profile: control has 13 numbers; a profile has 6 per segment (P, A, B as [x, "
            "y])");
  EXPECT_EQ(message([&] { bezier_profile(kDProfile, 0); }),
            "bezier_profile: samples must be >= 1 (got 0)");
  EXPECT_EQ(message([&] { bezier_profile_vjp(Vec(10, 0.0), 2, 3); }),
            "bezier_profile_vjp: grad_polygon has 10 numbers, expected 12 (2 per point, 3 points "
            "per segment)");
}

// ---------------------------------------------------------------------------------------------
// Triangulation

// Checks that `tris` triangulates the polygon: n - 2 triangles of distinct indices, each of
// positive (not negligible) area in the polygon's orientation, areas summing to the polygon's,
// every edge of the polygon used once in its own direction and every other edge twice, once each
// way.
void expect_triangulation(const Vec& p, const std::vector<PolygonTriangle>& tris) {
  const int n = static_cast<int>(p.size() / 2);
  ASSERT_EQ(static_cast<int>(tris.size()), n - 2);
  const double area = signed_area(p);
  const double orient = area > 0 ? 1.0 : -1.0;
  double total = 0.0;
  std::map<std::pair<int, int>, int> directed;
  for (const PolygonTriangle& t : tris) {
    for (int i : t) {
      ASSERT_GE(i, 0);
      ASSERT_LT(i, n);
    }
    ASSERT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
    const Vec tri = {p[2 * t[0]],     p[2 * t[0] + 1], p[2 * t[1]],
                     p[2 * t[1] + 1], p[2 * t[2]],     p[2 * t[2] + 1]};
    const double a = signed_area(tri);
    // Positive, and not a sliver of collinear points clipped because rounding made them turn.
    EXPECT_GT(orient * a, 1e-9 * std::abs(area)) << t[0] << " " << t[1] << " " << t[2];
    total += a;
    for (int e = 0; e < 3; ++e) ++directed[{t[e], t[(e + 1) % 3]}];
  }
  EXPECT_NEAR(total, area, 1e-12 * std::abs(area));
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << edge.first << " -> " << edge.second;
    const bool boundary = edge.second == (edge.first + 1) % n;
    if (!boundary) {
      EXPECT_EQ(directed.count({edge.second, edge.first}), 1u)
          << "diagonal " << edge.first << " -> " << edge.second << " used once";
    }
  }
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(directed.count({i, (i + 1) % n}), 1u) << "boundary edge " << i;
  }
}

// Points 0..T-1 teeth of a comb: many reflex vertices.
Vec comb(int teeth) {
  Vec p = {0, 0, 2.0 * teeth - 1, 0};
  for (int i = teeth - 1; i >= 0; --i) {
    p.insert(p.end(), {2.0 * i + 1, 3, 2.0 * i, 3});
    if (i > 0) p.insert(p.end(), {2.0 * i, 1, 2.0 * i - 1, 1});
  }
  return p;
}

Vec star(int tips, double inner, double outer) {
  Vec p;
  for (int i = 0; i < 2 * tips; ++i) {
    const double a = std::numbers::pi * i / tips;
    const double r = i % 2 == 0 ? outer : inner;
    p.push_back(r * std::cos(a));
    p.push_back(r * std::sin(a));
  }
  return p;
}

TEST(Triangulate, ConvexConcaveAndSampledPolygonsInBothOrientations) {
  Vec hexagon;
  for (int i = 0; i < 6; ++i) {
    hexagon.push_back(std::cos(std::numbers::pi * i / 3));
    hexagon.push_back(std::sin(std::numbers::pi * i / 3));
  }
  const Vec l_shape = {0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2};
  // A square with a point on each side (collinear points) and a rounded slot sampled from its
  // profile: its straight sides are 15 collinear points each.
  const Vec square_midpoints = {0, 0, 1, 0, 2, 0, 2, 1, 2, 2, 1, 2, 0, 2, 0, 1};
  const double k = 4.0 / 3.0 * 0.25;
  const double third = 1.0 / 6.0;
  const Vec slot = {-0.5,    -0.25, -third,  -0.25, third,    -0.25, 0.5,      -0.25,
                    0.5 + k, -0.25, 0.5 + k, 0.25,  0.5,      0.25,  third,    0.25,
                    -third,  0.25,  -0.5,    0.25,  -0.5 - k, 0.25,  -0.5 - k, -0.25};
  const std::vector<std::pair<std::string, Vec>> cases = {
      {"triangle", {0, 0, 1, 0, 0, 1}},
      {"hexagon", hexagon},
      {"L", l_shape},
      {"star", star(7, 0.35, 1.0)},
      {"comb", comb(6)},
      {"square with midpoints", square_midpoints},
      {"D", bezier_profile(kDProfile)},
      {"slot", bezier_profile(slot)},
      // Point 0 lies within rounding below the straight bottom side: it turns left by 2e-16,
      // and clipping it would leave a flat sliver.
      {"collinear with rounding", {0.4, -1e-15, 0.5, 0, 1, 0, 0.5, 1, 0, 0, 0.3, 0}},
  };
  for (const auto& [name, p] : cases) {
    for (const Vec& q : {p, reversed(p)}) {
      SCOPED_TRACE(name + (signed_area(q) > 0 ? " (counter-clockwise)" : " (clockwise)"));
      expect_triangulation(q, triangulate_polygon(q));
    }
  }
}

TEST(Triangulate, RandomStarShapedPolygons) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> jitter(0.05, 0.95), radius(0.1, 1.0);
  for (int trial = 0; trial < 30; ++trial) {
    const int n = 5 + trial * 3;
    Vec p;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * (i + jitter(rng)) / n;
      const double r = radius(rng);
      p.push_back(r * std::cos(a));
      p.push_back(r * std::sin(a));
    }
    if (trial % 2 == 1) p = reversed(p);
    SCOPED_TRACE(trial);
    expect_triangulation(p, triangulate_polygon(p));
  }
}

TEST(Triangulate, RejectsSelfIntersectingAndDegeneratePolygons) {
  const auto message = [](const Vec& p) -> std::string {
    try {
      triangulate_polygon(p);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message({0, 0, 2, 2, 2, 0, 0, 2}),
            "triangulate_polygon: edge 0 (points 0, 1) and edge 2 (points 2, 3) meet (the "
            "polygon is self-intersecting)");
  // A vertex on another edge, and a spike that doubles back.
  EXPECT_EQ(message({0, 0, 4, 0, 4, 4, 0, 4, 2, 0}),
            "triangulate_polygon: edge 0 (points 0, 1) and edge 3 (points 3, 4) meet (the "
            "polygon is self-intersecting)");
  EXPECT_EQ(message({0, 0, 2, 0, 2, 2, 2, 3, 2, 2.5, 0, 2}),
            "triangulate_polygon: the outline doubles back on itself at point 3 (the polygon is "
            "self-intersecting)");
  // A figure eight sampled from a profile whose segments cross.
  const Vec eight = bezier_profile(
      Vec{-1, -1, 0, 0, 0, 0, 1, 1, 2, 0, 2, 0, 1, -1, 0, 0, 0, 0, -1, 1, -2, 0, -2, 0});
  EXPECT_NE(message(eight).find("self-intersecting"), std::string::npos) << message(eight);
  // Three collinear points: the outline runs back from the last to the first.
  EXPECT_EQ(message({0, 0, 1, 1, 2, 2}),
            "triangulate_polygon: the outline doubles back on itself at point 2 (the polygon is "
            "self-intersecting)");
  EXPECT_EQ(message({0, 0, 1, 0, 0.5, 1e-12}),
            "triangulate_polygon: the polygon has zero area (a degenerate polygon)");
  EXPECT_EQ(message({0, 0, 1, 0, 1, 0, 0, 1}),
            "triangulate_polygon: points 1 and 2 coincide (a degenerate polygon)");
  EXPECT_EQ(message({0, 0, 1, 0}),
            "triangulate_polygon: a polygon needs at least 3 points (got 2)");
  EXPECT_EQ(message({0, 0, 1, 0, 1}), "triangulate_polygon: points has 5 numbers, not 2 per point");
  EXPECT_EQ(message({0, 0, 1, std::numeric_limits<double>::quiet_NaN(), 0, 1}),
            "triangulate_polygon: point 1 is not finite");
}

}  // namespace
}  // namespace fuzzycsg
