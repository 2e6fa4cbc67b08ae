// Primitive families: values at known points, exactness of the distances (unit gradient,
// zero on constructed surface points, agreement with brute-force distances to densely sampled
// surfaces), every gradient against central finite differences, float against double, and
// finite results at degenerate points.
#include "fuzzycsg/core/primitives.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/profiles.hpp"
#include "fuzzycsg/core/bezier.hpp"

namespace fuzzycsg {
namespace {

using Vec = std::vector<double>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

constexpr std::array kAllTypes{
    PrimitiveType::kSphere,   PrimitiveType::kBox,       PrimitiveType::kCylinder,
    PrimitiveType::kCone,     PrimitiveType::kTorus,     PrimitiveType::kPlane,
    PrimitiveType::kQuadric3, PrimitiveType::kEllipsoid, PrimitiveType::kCapsule,
    PrimitiveType::kMlp,      PrimitiveType::kCircle,    PrimitiveType::kRectangle,
    PrimitiveType::kEllipse,  PrimitiveType::kHalfPlane, PrimitiveType::kPolygon,
    PrimitiveType::kQuadric2, PrimitiveType::kExtrude,
};

// Families whose f is an exact Euclidean signed distance (the ellipse included: it is solved
// to full precision).
bool is_exact(PrimitiveType t) {
  return t != PrimitiveType::kQuadric3 && t != PrimitiveType::kQuadric2 &&
         t != PrimitiveType::kEllipsoid && t != PrimitiveType::kMlp;
}

int dim_of(PrimitiveType t) { return primitive_info(t).dim; }
std::string name_of(PrimitiveType t) {
  return std::string(primitive_info(t).name) + "/" + std::to_string(dim_of(t)) + "d";
}

struct Instance {
  PrimitiveShape shape;
  Vec theta;
};

Instance make(PrimitiveType t, Vec theta, std::vector<int> hidden = {}) {
  Instance in;
  in.shape.type = t;
  in.shape.hidden = std::move(hidden);
  in.theta = std::move(theta);
  return in;
}

double value(const Instance& in, const Vec& p) {
  return primitive_value<double>(in.shape, in.theta, p.data());
}

struct Grad {
  double f = kNaN;
  Vec dp;
  Vec dtheta;
};

// Outputs start as NaN so that an entry the implementation forgets to write fails the tests.
Grad gradient(const Instance& in, const Vec& p) {
  Grad g;
  g.dp.assign(p.size(), kNaN);
  g.dtheta.assign(in.theta.size(), kNaN);
  g.f = primitive_value_grad<double>(in.shape, in.theta, p.data(), g.dp.data(), g.dtheta.data());
  return g;
}

// f at x_i +- h and the central difference wrt input i (the point's coordinates first, then
// theta).
struct Difference {
  double plus, minus, slope;
};
Difference central_difference(Instance& in, Vec& p, std::size_t i, double h) {
  double& x = i < p.size() ? p[i] : in.theta[i - p.size()];
  const double x0 = x;
  x = x0 + h;
  const double fp = value(in, p);
  x = x0 - h;
  const double fm = value(in, p);
  x = x0;
  return {fp, fm, (fp - fm) / (2 * h)};
}

double norm(const Vec& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s);
}

double uniform(std::mt19937& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

Vec random_point(std::mt19937& rng, int dim, double extent) {
  Vec p(static_cast<std::size_t>(dim));
  for (double& x : p) x = uniform(rng, -extent, extent);
  return p;
}

Vec random_unit(std::mt19937& rng, int dim) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vec u(static_cast<std::size_t>(dim));
  double len = 0.0;
  while (len < 1e-3) {
    for (double& x : u) x = n(rng);
    len = norm(u);
  }
  for (double& x : u) x /= len;
  return u;
}

// A star-shaped, generally non-convex polygon, either orientation.
Vec random_polygon(std::mt19937& rng) {
  const int n = std::uniform_int_distribution<int>(5, 9)(rng);
  Vec v;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * (i + uniform(rng, 0.1, 0.9)) / n;
    const double r = uniform(rng, 0.35, 1.1);
    v.push_back(r * std::cos(a));
    v.push_back(r * std::sin(a));
  }
  if (uniform(rng, 0.0, 1.0) < 0.5) {
    Vec w;
    for (int i = n - 1; i >= 0; --i) {
      w.push_back(v[2 * i]);
      w.push_back(v[2 * i + 1]);
    }
    v = w;
  }
  return v;
}

// A closed Bézier profile of 2 to 4 segments: its 3n points spread around the origin (a
// star-shaped control polygon, either orientation).
Vec random_profile(std::mt19937& rng) {
  const int segments = std::uniform_int_distribution<int>(2, 4)(rng);
  const int points = 3 * segments;
  const double turn = uniform(rng, 0.0, 1.0) < 0.5 ? 1.0 : -1.0;
  Vec c;
  for (int i = 0; i < points; ++i) {
    const double a = turn * 2.0 * std::numbers::pi * (i + uniform(rng, 0.15, 0.85)) / points;
    const double r = uniform(rng, 0.5, 1.0);
    c.push_back(r * std::cos(a));
    c.push_back(r * std::sin(a));
  }
  return c;
}

// The extrude's parameters: a profile, then the height.
Vec extrude_theta(Vec profile, double height) {
  profile.push_back(height);
  return profile;
}

using test::straight_profile;

// The profile (without the height) of an extrude's parameters.
Vec profile_of(const Vec& theta) { return Vec(theta.begin(), theta.end() - 1); }

// The exact prism distance from a 2D signed distance d and the height h.
double prism(double d, double z, double h) {
  const double wz = std::abs(z) - 0.5 * h;
  return std::min(std::max(d, wz), 0.0) + std::hypot(std::max(d, 0.0), std::max(wz, 0.0));
}

Instance random_instance(PrimitiveType t, std::mt19937& rng) {
  auto u = [&](double lo, double hi) { return uniform(rng, lo, hi); };
  switch (t) {
    case PrimitiveType::kSphere:
      return make(t, {u(0.3, 1.2)});
    case PrimitiveType::kBox:
      return make(t, {u(0.4, 2.0), u(0.4, 2.0), u(0.4, 2.0)});
    case PrimitiveType::kCylinder:
      return make(t, {u(0.3, 1.0), u(0.5, 2.0)});
    case PrimitiveType::kCone: {
      double r1 = u(0.0, 1.0);
      double r2 = u(0.0, 1.0);
      if (u(0.0, 1.0) < 0.25) (u(0.0, 1.0) < 0.5 ? r1 : r2) = 0.0;
      return make(t, {r1, r2, u(0.5, 2.0)});
    }
    case PrimitiveType::kTorus:
      return make(t, {u(0.6, 1.2), u(0.1, 0.5)});
    case PrimitiveType::kPlane: {
      Vec n = random_unit(rng, 3);
      const double s = u(0.3, 3.0);
      return make(t, {n[0] * s, n[1] * s, n[2] * s, u(-0.5, 0.5)});
    }
    case PrimitiveType::kQuadric3: {
      Vec q(10);
      for (double& x : q) x = u(-1.0, 1.0);
      return make(t, q);
    }
    case PrimitiveType::kEllipsoid:
      return make(t, {u(0.3, 1.5), u(0.3, 1.5), u(0.3, 1.5)});
    case PrimitiveType::kCapsule:
      return make(t, {u(0.2, 0.6), u(0.0, 1.5)});
    case PrimitiveType::kMlp: {
      std::vector<int> hidden = {8, 6};
      Vec w(static_cast<std::size_t>(mlp_weight_count(3, hidden)));
      std::normal_distribution<double> n(0.0, 0.6);
      for (double& x : w) x = n(rng);
      return make(t, w, hidden);
    }
    case PrimitiveType::kCircle:
      return make(t, {u(0.3, 1.2)});
    case PrimitiveType::kRectangle:
      return make(t, {u(0.4, 2.0), u(0.4, 2.0)});
    case PrimitiveType::kEllipse:
      return make(t, {u(0.2, 1.5), u(0.2, 1.5)});
    case PrimitiveType::kHalfPlane: {
      Vec n = random_unit(rng, 2);
      const double s = u(0.3, 3.0);
      return make(t, {n[0] * s, n[1] * s, u(-0.5, 0.5)});
    }
    case PrimitiveType::kPolygon:
      return make(t, random_polygon(rng));
    case PrimitiveType::kQuadric2: {
      Vec q(6);
      for (double& x : q) x = u(-1.0, 1.0);
      return make(t, q);
    }
    case PrimitiveType::kExtrude:
      return make(t, extrude_theta(random_profile(rng), u(0.5, 2.0)));
  }
  return {};
}

// ------------------------------------------------------------------------------------------
// Values at known points.

TEST(PrimitiveValues, Sphere) {
  const Instance s = make(PrimitiveType::kSphere, {1.0});
  EXPECT_DOUBLE_EQ(value(s, {0, 0, 0}), -1.0);
  EXPECT_DOUBLE_EQ(value(s, {2, 0, 0}), 1.0);
  EXPECT_DOUBLE_EQ(value(s, {0, 3, 4}), 4.0);
  EXPECT_DOUBLE_EQ(value(s, {0, 0.6, 0}), -0.4);
}

TEST(PrimitiveValues, Box) {
  const Instance b = make(PrimitiveType::kBox, {2.0, 4.0, 6.0});  // half extents 1, 2, 3
  EXPECT_DOUBLE_EQ(value(b, {0, 0, 0}), -1.0);
  EXPECT_DOUBLE_EQ(value(b, {0.5, 0, 0}), -0.5);
  EXPECT_DOUBLE_EQ(value(b, {0, 0, -2.5}), -0.5);
  EXPECT_DOUBLE_EQ(value(b, {2, 0, 0}), 1.0);
  EXPECT_DOUBLE_EQ(value(b, {-2, 3, 0}), std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(value(b, {2, -3, 4}), std::sqrt(3.0));
  EXPECT_DOUBLE_EQ(value(b, {1, 0, 0}), 0.0);
}

TEST(PrimitiveValues, Cylinder) {
  const Instance c = make(PrimitiveType::kCylinder, {1.0, 2.0});
  EXPECT_DOUBLE_EQ(value(c, {0, 0, 0}), -1.0);
  EXPECT_DOUBLE_EQ(value(c, {0.9, 0, 0}), -0.1);
  EXPECT_NEAR(value(c, {0, 0, 0.95}), -0.05, 1e-15);
  EXPECT_DOUBLE_EQ(value(c, {0, 2, 0}), 1.0);
  EXPECT_DOUBLE_EQ(value(c, {0, 0, -3}), 2.0);
  EXPECT_DOUBLE_EQ(value(c, {0.6, 0.8, 0}), 0.0);
  EXPECT_DOUBLE_EQ(value(c, {1.2, 1.6, 2}), std::sqrt(2.0));
}

TEST(PrimitiveValues, Cone) {
  // Radius 1 at z = -1 narrowing to an apex at z = +1.
  const Instance c = make(PrimitiveType::kCone, {1.0, 0.0, 2.0});
  EXPECT_NEAR(value(c, {0, 0, 0}), -1.0 / std::sqrt(5.0), 1e-15);
  EXPECT_DOUBLE_EQ(value(c, {0, 0, 2}), 1.0);               // above the apex
  EXPECT_DOUBLE_EQ(value(c, {0, 0, -2}), 1.0);              // below the base
  EXPECT_DOUBLE_EQ(value(c, {2, 0, -1}), 1.0);              // level with the rim
  EXPECT_DOUBLE_EQ(value(c, {0, -3, -2}), std::sqrt(5.0));  // beyond the rim, below it
  EXPECT_NEAR(value(c, {0, 0.5, 0}), 0.0, 1e-15);           // on the side
  EXPECT_NEAR(value(c, {0, 0, -0.9}), -0.1, 1e-15);         // just above the base
  // Apex at the bottom, radius 2 on top: a point on the axis below the apex.
  const Instance d = make(PrimitiveType::kCone, {0.0, 2.0, 2.0});
  EXPECT_DOUBLE_EQ(value(d, {0, 0, -1.5}), 0.5);
  // r1 == r2: a cylinder.
  const Instance e = make(PrimitiveType::kCone, {1.0, 1.0, 2.0});
  const Instance cyl = make(PrimitiveType::kCylinder, {1.0, 2.0});
  for (const Vec& p : {Vec{0.3, 0.2, 0.1}, Vec{1.5, 0, 1.5}, Vec{0, 0.5, -0.9}, Vec{2, 2, 0}}) {
    EXPECT_NEAR(value(e, p), value(cyl, p), 1e-15);
  }
}

TEST(PrimitiveValues, Torus) {
  const Instance t = make(PrimitiveType::kTorus, {1.0, 0.25});
  EXPECT_DOUBLE_EQ(value(t, {1, 0, 0}), -0.25);
  EXPECT_DOUBLE_EQ(value(t, {0, -1, 0}), -0.25);
  EXPECT_DOUBLE_EQ(value(t, {0, 0, 0}), 0.75);
  EXPECT_DOUBLE_EQ(value(t, {2, 0, 0}), 0.75);
  EXPECT_DOUBLE_EQ(value(t, {0, 1, 1}), 0.75);
  EXPECT_DOUBLE_EQ(value(t, {0, 0, 1}), std::sqrt(2.0) - 0.25);
}

TEST(PrimitiveValues, Plane) {
  const Instance pl = make(PrimitiveType::kPlane, {0.0, 0.0, 2.0, 0.5});
  EXPECT_DOUBLE_EQ(value(pl, {0, 0, 1}), 0.5);
  EXPECT_DOUBLE_EQ(value(pl, {1, 1, 0}), -0.5);
  const Instance tilted = make(PrimitiveType::kPlane, {3.0, 4.0, 0.0, 1.0});
  EXPECT_DOUBLE_EQ(value(tilted, {3, 4, 7}), 4.0);
}

TEST(PrimitiveValues, Quadric3) {
  const Instance unit = make(PrimitiveType::kQuadric3, {1, 1, 1, 0, 0, 0, 0, 0, 0, -1});
  EXPECT_DOUBLE_EQ(value(unit, {1, 1, 1}), 2.0);
  EXPECT_DOUBLE_EQ(value(unit, {0, 0, 0}), -1.0);
  const Vec q = {0.5, -1, 2, 3, -0.25, 1.5, 0.1, -0.2, 0.3, 0.7};
  const Instance g = make(PrimitiveType::kQuadric3, q);
  const double x = 0.3, y = -1.1, z = 0.8;
  const double expected = q[0] * x * x + q[1] * y * y + q[2] * z * z + q[3] * x * y + q[4] * y * z +
                          q[5] * z * x + q[6] * x + q[7] * y + q[8] * z + q[9];
  EXPECT_NEAR(value(g, {x, y, z}), expected, 1e-14);
}

TEST(PrimitiveValues, Ellipsoid) {
  const Instance e = make(PrimitiveType::kEllipsoid, {1.0, 2.0, 3.0});
  EXPECT_DOUBLE_EQ(value(e, {0, 0, 0}), -1.0);  // -min(r) at the centre
  // Along an axis the bound is the exact distance |x| - r.
  EXPECT_NEAR(value(e, {2, 0, 0}), 1.0, 1e-15);
  EXPECT_NEAR(value(e, {0, -3, 0}), 1.0, 1e-15);
  EXPECT_NEAR(value(e, {0, 0, 1.5}), -1.5, 1e-15);
  EXPECT_NEAR(value(e, {0, 0, 3}), 0.0, 1e-15);
  // A sphere when the radii agree.
  const Instance s = make(PrimitiveType::kEllipsoid, {0.7, 0.7, 0.7});
  EXPECT_NEAR(value(s, {0.3, -0.4, 1.2}), std::sqrt(0.09 + 0.16 + 1.44) - 0.7, 1e-14);
  // The sign is the inside test (x/a)^2 + (y/b)^2 + (z/c)^2 < 1.
  EXPECT_LT(value(e, {0.5, 1.0, 1.5}), 0.0);  // 0.25 + 0.25 + 0.25
  EXPECT_GT(value(e, {0.7, 1.2, 1.8}), 0.0);  // 0.49 + 0.36 + 0.36
}

TEST(PrimitiveValues, Capsule) {
  const Instance c = make(PrimitiveType::kCapsule, {0.5, 2.0});
  EXPECT_DOUBLE_EQ(value(c, {0, 0, 0}), -0.5);
  EXPECT_DOUBLE_EQ(value(c, {0, 0, 2}), 0.5);
  EXPECT_DOUBLE_EQ(value(c, {1, 0, 0.3}), 0.5);
  EXPECT_DOUBLE_EQ(value(c, {0.6, 0.8, -1}), 0.5);
  EXPECT_DOUBLE_EQ(value(c, {0.3, 0.4, -2}), std::sqrt(1.25) - 0.5);
  const Instance ball = make(PrimitiveType::kCapsule, {0.5, 0.0});
  EXPECT_DOUBLE_EQ(value(ball, {0, 0, 1}), 0.5);
}

TEST(PrimitiveValues, Mlp) {
  // No hidden layer: f = w.p + b.
  const Instance lin = make(PrimitiveType::kMlp, {1.0, -2.0, 0.5, 0.25}, {});
  EXPECT_DOUBLE_EQ(value(lin, {1, 1, 2}), 1.0 - 2.0 + 1.0 + 0.25);
  // One hidden layer of width 2, by hand.
  const Vec w = {0.1,  0.2,   0.3, -0.4, 0.5, -0.6,  // W1 (2 x 3)
                 0.05, -0.05,                        // b1
                 1.5,  -2.0,                         // output weights
                 0.3};                               // output bias
  ASSERT_EQ(w.size(), static_cast<std::size_t>(mlp_weight_count(3, std::vector<int>{2})));
  const Instance m = make(PrimitiveType::kMlp, w, {2});
  const double x = 0.7, y = -0.2, z = 1.1;
  const double h0 = std::tanh(0.1 * x + 0.2 * y + 0.3 * z + 0.05);
  const double h1 = std::tanh(-0.4 * x + 0.5 * y - 0.6 * z - 0.05);
  EXPECT_NEAR(value(m, {x, y, z}), 1.5 * h0 - 2.0 * h1 + 0.3, 1e-15);
}

TEST(PrimitiveValues, TwoDimensional) {
  const Instance c = make(PrimitiveType::kCircle, {1.5});
  EXPECT_DOUBLE_EQ(value(c, {0, 0}), -1.5);
  EXPECT_DOUBLE_EQ(value(c, {3, 4}), 3.5);
  const Instance r = make(PrimitiveType::kRectangle, {2.0, 4.0});
  EXPECT_DOUBLE_EQ(value(r, {0, 0}), -1.0);
  EXPECT_DOUBLE_EQ(value(r, {0, 1.5}), -0.5);
  EXPECT_DOUBLE_EQ(value(r, {2, 3}), std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(value(r, {-3, 0}), 2.0);
  const Instance h = make(PrimitiveType::kHalfPlane, {0.0, -3.0, 1.0});
  EXPECT_DOUBLE_EQ(value(h, {5, -2}), 1.0);
  EXPECT_DOUBLE_EQ(value(h, {5, 0}), -1.0);
  const Instance q = make(PrimitiveType::kQuadric2, {1, 2, 3, 4, 5, 6});
  EXPECT_DOUBLE_EQ(value(q, {1, -1}), 1 + 2 - 3 + 4 - 5 + 6);
}

TEST(PrimitiveValues, Ellipse) {
  const Instance e = make(PrimitiveType::kEllipse, {2.0, 1.0});
  EXPECT_NEAR(value(e, {3, 0}), 1.0, 1e-15);
  EXPECT_NEAR(value(e, {0, -2}), 1.0, 1e-15);
  EXPECT_NEAR(value(e, {0, 0}), -1.0, 1e-15);
  EXPECT_NEAR(value(e, {2, 0}), 0.0, 1e-15);
  EXPECT_NEAR(value(e, {1.5, 0}), -0.5, 1e-15);  // beyond the evolute's cusp at x = 1.5
  // On the major axis inside the evolute the nearest point leaves the axis:
  // distance b sqrt(1 - x^2 / (a^2 - b^2)).
  for (double x : {0.0, 0.4, -1.0, 1.49}) {
    EXPECT_NEAR(value(e, {x, 0}), -std::sqrt(1.0 - x * x / 3.0), 1e-14) << x;
  }
  // Just off the major axis, up to the evolute's cusp, where the nearest point is the
  // hardest to find: f moves by at most |y| from its value on the axis.
  for (double x : {0.7, 1.4999, 1.5 * (1 - 1e-6), 1.5, 1.5 * (1 + 1e-6), 1.7}) {
    const double on_axis = x < 1.5 ? -std::sqrt(1.0 - x * x / 3.0) : x - 2.0;
    for (double y : {1e-300, 1e-200, 1e-100, 1e-30, 1e-12}) {
      EXPECT_NEAR(value(e, {x, y}), on_axis, 1e-12) << x << " " << y;
      EXPECT_NEAR(value(e, {-x, -y}), on_axis, 1e-12) << x << " " << y;
    }
  }
  // The same with the axes swapped.
  const Instance tall = make(PrimitiveType::kEllipse, {1.0, 2.0});
  EXPECT_NEAR(value(tall, {0, 0.4}), -std::sqrt(1.0 - 0.16 / 3.0), 1e-14);
  EXPECT_NEAR(value(tall, {-4, 0}), 3.0, 1e-15);
  // A circle when the radii agree, also for nearly equal radii.
  const Instance circle = make(PrimitiveType::kEllipse, {0.8, 0.8});
  const Instance near_circle = make(PrimitiveType::kEllipse, {0.8, 0.8 * (1 - 1e-13)});
  for (const Vec& p : {Vec{0.1, 0.2}, Vec{-1.0, 0.3}, Vec{0.0, 0.0}, Vec{1e-9, 1e-200}}) {
    const double expected = std::hypot(p[0], p[1]) - 0.8;
    EXPECT_NEAR(value(circle, p), expected, 1e-15);
    EXPECT_NEAR(value(near_circle, p), expected, 1e-13);
  }
}

TEST(PrimitiveValues, Polygon) {
  const Vec ccw = {0, 0, 1, 0, 1, 1, 0, 1};
  const Vec cw = {0, 0, 0, 1, 1, 1, 1, 0};
  for (const Vec& v : {ccw, cw}) {
    const Instance sq = make(PrimitiveType::kPolygon, v);
    EXPECT_DOUBLE_EQ(value(sq, {0.5, 0.5}), -0.5);
    EXPECT_DOUBLE_EQ(value(sq, {0.5, 0.2}), -0.2);
    EXPECT_DOUBLE_EQ(value(sq, {2, 0.5}), 1.0);
    EXPECT_DOUBLE_EQ(value(sq, {2, 2}), std::sqrt(2.0));
    EXPECT_DOUBLE_EQ(value(sq, {0, 0.5}), 0.0);
    // A point level with a vertex (the ray passes through it) is classified once.
    EXPECT_DOUBLE_EQ(value(sq, {-1, 1}), 1.0);
    EXPECT_DOUBLE_EQ(value(sq, {-1, 0}), 1.0);
  }
  // An L shape: the notch is outside.
  const Instance l = make(PrimitiveType::kPolygon, {0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2});
  EXPECT_DOUBLE_EQ(value(l, {1.5, 1.5}), 0.5);
  EXPECT_DOUBLE_EQ(value(l, {1.5, 1.25}), 0.25);
  EXPECT_DOUBLE_EQ(value(l, {0.5, 1.5}), -0.5);
  EXPECT_DOUBLE_EQ(value(l, {0.5, 0.3}), -0.3);
  EXPECT_NEAR(value(l, {0.9, 0.9}), -0.1 * std::sqrt(2.0), 1e-15);  // the reflex corner
  EXPECT_NEAR(value(l, {1.3, 1.4}), 0.3, 1e-15);
  // Even-odd: the overlap of a self-intersecting outline's two loops... a bow tie has none;
  // its two triangles are inside, the region beside the crossing outside.
  const Instance bow = make(PrimitiveType::kPolygon, {0, 0, 2, 2, 2, 0, 0, 2});
  EXPECT_LT(value(bow, {0.3, 1.0}), 0.0);
  EXPECT_LT(value(bow, {1.7, 1.0}), 0.0);
  EXPECT_GT(value(bow, {1.0, 0.3}), 0.0);
}

// A profile with straight segments (controls at the thirds of the edges) is its polygon: for a
// square it is the box, value and gradient, also with respect to the height and (summed over
// the control points of a side) the size.
TEST(PrimitiveValues, ExtrudeOfAStraightSquareIsTheBox) {
  const double a = 0.6, h = 0.8;
  const Vec square = straight_profile({-a, -a, a, -a, a, a, -a, a});
  for (const Vec& profile : {square, straight_profile({-a, -a, -a, a, a, a, a, -a})}) {
    const Instance ex = make(PrimitiveType::kExtrude, extrude_theta(profile, h));
    const Instance box = make(PrimitiveType::kBox, {2 * a, 2 * a, h});
    std::mt19937 rng(53);
    for (int k = 0; k < 400; ++k) {
      const Vec p = random_point(rng, 3, k % 2 == 0 ? 0.7 : 1.5);
      const Grad ge = gradient(ex, p);
      const Grad gb = gradient(box, p);
      ASSERT_NEAR(ge.f, gb.f, 1e-14) << p[0] << " " << p[1] << " " << p[2];
      for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(ge.dp[i], gb.dp[i], 1e-12) << i;
      EXPECT_NEAR(ge.dtheta.back(), gb.dtheta[2], 1e-12);
      // Moving the sides x = +-a (y = +-a) apart by 2 delta is the box's size[0] (size[1])
      // growing by 2 delta.
      for (std::size_t axis = 0; axis < 2; ++axis) {
        double apart = 0.0;
        for (std::size_t c = 0; c < profile.size() / 2; ++c) {
          const double x = profile[2 * c + axis];
          if (x == a) apart += ge.dtheta[2 * c + axis];
          if (x == -a) apart -= ge.dtheta[2 * c + axis];
        }
        EXPECT_NEAR(apart, 2 * gb.dtheta[axis], 1e-12) << axis;
      }
    }
  }
}

// An L and a star with straight segments: the prism over the polygon family's distance.
TEST(PrimitiveValues, ExtrudeOfStraightEdgesIsThePolygonPrism) {
  std::mt19937 rng(59);
  const Vec l_shape = {0, 0, 1.2, 0, 1.2, 0.5, 0.5, 0.5, 0.5, 1.2, 0, 1.2};
  Vec star;
  for (int i = 0; i < 10; ++i) {
    const double r = i % 2 == 0 ? 1.0 : 0.4;
    star.push_back(r * std::cos(std::numbers::pi * i / 5));
    star.push_back(r * std::sin(std::numbers::pi * i / 5));
  }
  for (const Vec& corners : {l_shape, star}) {
    const double h = 0.7;
    const Instance ex = make(PrimitiveType::kExtrude, extrude_theta(straight_profile(corners), h));
    const Instance poly = make(PrimitiveType::kPolygon, corners);
    for (int k = 0; k < 300; ++k) {
      const Vec p = random_point(rng, 3, 1.3);
      EXPECT_NEAR(value(ex, p), prism(value(poly, {p[0], p[1]}), p[2], h), 1e-14);
    }
  }
}

// Straight sides evaluated forward only take the polygon of the segments' ends; with the
// gradient, the sampled polygon. Both are the prism over bezier_profile's polygon: with the
// controls anywhere on the chord in order, and when a control lies on the chord's line beyond
// its end (the side overshoots and comes back: not a straight side of the fast path).
TEST(PrimitiveValues, ExtrudeForwardAndGradientAgreeOnStraightSides) {
  std::mt19937 rng(67);
  // A square, its controls at 0.1 and 0.7 of each side.
  const Vec uneven = {0, 0, 0.1, 0, 0.7, 0, 1, 0, 1, 0.1, 1, 0.7,
                      1, 1, 0.9, 1, 0.3, 1, 0, 1, 0, 0.9, 0, 0.3};
  // The same square, the first side's controls at x = 1.3 (beyond P1): that side runs out to
  // x = 1.14 along y = 0 and back, a spike of no area.
  Vec overshoot = uneven;
  overshoot[2] = overshoot[4] = 1.3;
  for (const Vec& profile : {uneven, overshoot}) {
    const double h = 0.6;
    const Instance ex = make(PrimitiveType::kExtrude, extrude_theta(profile, h));
    const Instance poly = make(PrimitiveType::kPolygon, bezier_profile(profile));
    for (int k = 0; k < 300; ++k) {
      const Vec p = random_point(rng, 3, 1.5);
      const double v = value(ex, p);
      EXPECT_NEAR(v, gradient(ex, p).f, 1e-14);
      EXPECT_NEAR(v, prism(value(poly, {p[0], p[1]}), p[2], h), 1e-14);
    }
  }
  // On the spike: distance 0 to the sampled outline, where the square's would be 0.05.
  EXPECT_NEAR(value(make(PrimitiveType::kExtrude, extrude_theta(overshoot, 0.6)), {1.05, 0, 0}),
              0.0, 1e-12);
}

// A curved profile: the prism over bezier_profile's polygon, which interpolates every P_k.
TEST(PrimitiveValues, ExtrudeIsThePrismOverTheSampledProfile) {
  std::mt19937 rng(61);
  const Vec d_shape = {0, -1, 0, -1.0 / 3, 0, 1.0 / 3, 0, 1, 1.3, 1, 1.3, -1};
  const double h = 0.5;
  const Instance ex = make(PrimitiveType::kExtrude, extrude_theta(d_shape, h));
  const Instance poly = make(PrimitiveType::kPolygon, bezier_profile(d_shape));
  for (int k = 0; k < 300; ++k) {
    const Vec p = random_point(rng, 3, 1.4);
    EXPECT_NEAR(value(ex, p), prism(value(poly, {p[0], p[1]}), p[2], h), 1e-15);
  }
  EXPECT_NEAR(value(ex, {-0.3, 0.2, 0.1}), 0.3, 1e-15);    // beside the straight side
  EXPECT_NEAR(value(ex, {0.3, 0.0, 0.45}), 0.2, 1e-15);    // above the top cap
  EXPECT_NEAR(value(ex, {0.2, 0.1, -0.2}), -0.05, 1e-15);  // nearest the bottom cap
  EXPECT_NEAR(value(ex, {0.1, 0.0, 0.0}), -0.1, 1e-15);    // nearest the straight side
  EXPECT_NEAR(value(ex, {-0.3, 0.0, 0.65}), 0.5, 1e-15);   // beyond the rim: |(0.3, 0.4)|
  EXPECT_NEAR(value(ex, {0, 1, 0.1}), 0.0, 1e-15);         // on P1
  // The curved side x(t) = 3.9 t (1 - t) crosses y = 0 at t = 1/2, between its samples at
  // t = 7/15 and 8/15 (y = +-337/3375): the polygon's chord there is at x = 3.9 * 56 / 225,
  // inside the curve's 0.975.
  EXPECT_NEAR(value(ex, {3.9 * 56 / 225, 0.0, 0.0}), 0.0, 1e-15);
  EXPECT_NEAR(value(ex, {0.975, 0.0, 0.0}), 0.975 - 3.9 * 56 / 225, 1e-12);
}

TEST(PrimitiveValues, ValueAndGradAgree) {
  std::mt19937 rng(7);
  for (PrimitiveType t : kAllTypes) {
    for (int k = 0; k < 50; ++k) {
      const Instance in = random_instance(t, rng);
      const Vec p = random_point(rng, dim_of(t), k % 2 == 0 ? 0.6 : 1.6);
      EXPECT_NEAR(gradient(in, p).f, value(in, p), 1e-14) << name_of(t);
    }
  }
}

// ------------------------------------------------------------------------------------------
// Exactness of the distances.

TEST(PrimitiveExactness, UnitGradientAtRandomPoints) {
  std::mt19937 rng(11);
  for (PrimitiveType t : kAllTypes) {
    if (!is_exact(t)) continue;
    int inside = 0;
    for (int k = 0; k < 300; ++k) {
      const Instance in = random_instance(t, rng);
      const Vec p = random_point(rng, dim_of(t), k % 2 == 0 ? 0.6 : 1.6);
      const Grad g = gradient(in, p);
      inside += g.f < 0.0;
      EXPECT_NEAR(norm(g.dp), 1.0, 1e-9) << name_of(t) << " f=" << g.f;
    }
    EXPECT_GT(inside, 5) << name_of(t);  // both sides were visited
    EXPECT_LT(inside, 295) << name_of(t);
  }
}

// A point on the surface of a random instance, with the outward normal where it is known
// to be smooth there.
struct SurfacePoint {
  Vec p;
};

SurfacePoint surface_point(PrimitiveType t, const Vec& th, std::mt19937& rng) {
  auto u = [&](double lo, double hi) { return uniform(rng, lo, hi); };
  switch (t) {
    case PrimitiveType::kSphere:
    case PrimitiveType::kCircle: {
      Vec d = random_unit(rng, dim_of(t));
      for (double& x : d) x *= th[0];
      return {d};
    }
    case PrimitiveType::kBox:
    case PrimitiveType::kRectangle: {
      const int dim = dim_of(t);
      Vec p(static_cast<std::size_t>(dim));
      for (int i = 0; i < dim; ++i) p[i] = u(-0.5, 0.5) * th[i];
      const int face = std::uniform_int_distribution<int>(0, dim - 1)(rng);
      p[face] = (u(0, 1) < 0.5 ? -0.5 : 0.5) * th[face];
      return {p};
    }
    case PrimitiveType::kCylinder: {
      const double a = u(0, 2 * std::numbers::pi);
      if (u(0, 1) < 0.5) return {{th[0] * std::cos(a), th[0] * std::sin(a), u(-0.5, 0.5) * th[1]}};
      const double r = th[0] * std::sqrt(u(0, 1));
      return {{r * std::cos(a), r * std::sin(a), (u(0, 1) < 0.5 ? -0.5 : 0.5) * th[1]}};
    }
    case PrimitiveType::kCone: {
      const double a = u(0, 2 * std::numbers::pi);
      const double h = th[2];
      const double c = u(0, 1);
      if (c < 0.6) {
        const double s = u(0, 1);
        const double r = th[0] + (th[1] - th[0]) * s;
        return {{r * std::cos(a), r * std::sin(a), -0.5 * h + s * h}};
      }
      const bool top = c < 0.8;
      const double r = (top ? th[1] : th[0]) * std::sqrt(u(0, 1));
      return {{r * std::cos(a), r * std::sin(a), (top ? 0.5 : -0.5) * h}};
    }
    case PrimitiveType::kTorus: {
      const double a = u(0, 2 * std::numbers::pi);
      const double b = u(0, 2 * std::numbers::pi);
      const double r = th[0] + th[1] * std::cos(b);
      return {{r * std::cos(a), r * std::sin(a), th[1] * std::sin(b)}};
    }
    case PrimitiveType::kCapsule: {
      Vec d = random_unit(rng, 3);
      if (u(0, 1) < 0.5) {  // the side
        const double a = u(0, 2 * std::numbers::pi);
        return {{th[0] * std::cos(a), th[0] * std::sin(a), u(-0.5, 0.5) * th[1]}};
      }
      const double end = d[2] < 0 ? -0.5 * th[1] : 0.5 * th[1];  // a hemispherical end
      return {{th[0] * d[0], th[0] * d[1], end + th[0] * d[2]}};
    }
    case PrimitiveType::kEllipsoid: {
      Vec d = random_unit(rng, 3);
      return {{th[0] * d[0], th[1] * d[1], th[2] * d[2]}};
    }
    case PrimitiveType::kEllipse: {
      const double a = u(0, 2 * std::numbers::pi);
      return {{th[0] * std::cos(a), th[1] * std::sin(a)}};
    }
    case PrimitiveType::kPlane:
    case PrimitiveType::kHalfPlane: {
      const int dim = dim_of(t);
      Vec n(th.begin(), th.begin() + dim);
      const double len = norm(n);
      Vec p = random_point(rng, dim, 1.0);
      double along = 0.0;
      for (int i = 0; i < dim; ++i) along += p[i] * n[i] / len;
      for (int i = 0; i < dim; ++i) p[i] += (th[dim] - along) * n[i] / len;
      return {p};
    }
    case PrimitiveType::kPolygon: {
      const std::size_t n = th.size() / 2;
      const std::size_t a = std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
      const std::size_t b = (a + 1) % n;
      const double s = u(0, 1);
      return {{th[2 * a] + s * (th[2 * b] - th[2 * a]),
               th[2 * a + 1] + s * (th[2 * b + 1] - th[2 * a + 1])}};
    }
    case PrimitiveType::kExtrude: {
      const double h = th.back();
      if (u(0, 1) < 0.6) {  // the wall: on the profile's polygon, at any height
        const Vec poly = bezier_profile(profile_of(th));
        const std::size_t n = poly.size() / 2;
        const std::size_t a = std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
        const std::size_t b = (a + 1) % n;
        const double s = u(0, 1);
        return {{poly[2 * a] + s * (poly[2 * b] - poly[2 * a]),
                 poly[2 * a + 1] + s * (poly[2 * b + 1] - poly[2 * a + 1]), u(-0.5, 0.5) * h}};
      }
      const Instance in = make(t, th);  // a cap: inside the profile, at z = +-h/2
      while (true) {
        Vec p = {u(-1, 1), u(-1, 1), 0.0};
        if (value(in, p) < -1e-3) {
          p[2] = (u(0, 1) < 0.5 ? -0.5 : 0.5) * h;
          return {p};
        }
      }
    }
    default:
      return {};
  }
}

TEST(PrimitiveExactness, ZeroOnSurfaceWithOutwardUnitNormal) {
  std::mt19937 rng(13);
  for (PrimitiveType t : kAllTypes) {
    if (!is_exact(t) && t != PrimitiveType::kEllipsoid) continue;
    int smooth = 0;
    for (int k = 0; k < 200; ++k) {
      const Instance in = random_instance(t, rng);
      const Vec p = surface_point(t, in.theta, rng).p;
      const Grad g = gradient(in, p);
      EXPECT_NEAR(g.f, 0.0, 1e-12) << name_of(t);
      // The gradient on the surface is a unit normal (not the zero subgradient of a norm).
      EXPECT_NEAR(norm(g.dp), 1.0, 1e-9) << name_of(t);
      // Where the surface is smooth the gradient points outward: stepping along it leaves the
      // solid, stepping against it enters. At edges (detected by the two probes disagreeing
      // with the linear model) only the sign is required.
      const double eps = 1e-5;
      Vec out = p;
      Vec in_pt = p;
      for (std::size_t i = 0; i < p.size(); ++i) {
        out[i] += eps * g.dp[i];
        in_pt[i] -= eps * g.dp[i];
      }
      const double fo = value(in, out);
      const double fi = value(in, in_pt);
      EXPECT_GT(fo, 0.0) << name_of(t);
      EXPECT_LE(fi, 1e-12) << name_of(t);
      if (std::abs(fo - eps) < 1e-8 && std::abs(fi + eps) < 1e-8) ++smooth;
    }
    EXPECT_GT(smooth, 150) << name_of(t);
  }
}

// Brute-force distance to a dense sample of the surface: the sample's nearest distance is at
// least the true distance and at most the true distance plus the sampling's covering radius.
void expect_matches_samples(const Instance& in, const std::vector<Vec>& samples,
                            const std::vector<Vec>& queries, double cover,
                            bool (*inside)(const Vec& th, const Vec& p)) {
  for (const Vec& q : queries) {
    double best = std::numeric_limits<double>::infinity();
    for (const Vec& s : samples) {
      double d2 = 0.0;
      for (std::size_t i = 0; i < q.size(); ++i) d2 += (q[i] - s[i]) * (q[i] - s[i]);
      best = std::min(best, d2);
    }
    best = std::sqrt(best);
    const double f = value(in, q);
    EXPECT_LE(std::abs(f), best + 1e-12) << name_of(in.shape.type);
    EXPECT_GE(std::abs(f), best - cover) << name_of(in.shape.type);
    if (best > cover) {
      EXPECT_EQ(f < 0.0, inside(in.theta, q)) << name_of(in.shape.type);
    }
  }
}

std::vector<Vec> random_queries(std::mt19937& rng, int dim, double extent, int n) {
  std::vector<Vec> q;
  for (int i = 0; i < n; ++i) q.push_back(random_point(rng, dim, extent));
  return q;
}

TEST(PrimitiveExactness, ConeMatchesBruteForce) {
  std::mt19937 rng(17);
  const int na = 360, nz = 120, nr = 60;
  for (const Vec& th : {Vec{0.9, 0.3, 1.6}, Vec{0.0, 0.8, 1.2}, Vec{0.5, 0.0, 2.0}}) {
    const Instance in = make(PrimitiveType::kCone, th);
    std::vector<Vec> samples;
    for (int i = 0; i < na; ++i) {
      const double a = 2 * std::numbers::pi * i / na;
      for (int j = 0; j <= nz; ++j) {
        const double s = static_cast<double>(j) / nz;
        const double r = th[0] + (th[1] - th[0]) * s;
        samples.push_back({r * std::cos(a), r * std::sin(a), -0.5 * th[2] + s * th[2]});
      }
      for (int j = 0; j <= nr; ++j) {
        const double s = static_cast<double>(j) / nr;
        samples.push_back({s * th[0] * std::cos(a), s * th[0] * std::sin(a), -0.5 * th[2]});
        samples.push_back({s * th[1] * std::cos(a), s * th[1] * std::sin(a), 0.5 * th[2]});
      }
    }
    const double cover = 0.5 * std::hypot(2 * std::numbers::pi * 0.9 / na, 2.0 / nz);
    auto inside = [](const Vec& t, const Vec& p) {
      const double s = (p[2] + 0.5 * t[2]) / t[2];
      return s >= 0 && s <= 1 && std::hypot(p[0], p[1]) <= t[0] + (t[1] - t[0]) * s;
    };
    expect_matches_samples(in, samples, random_queries(rng, 3, 1.5, 40), cover, inside);
  }
}

TEST(PrimitiveExactness, TorusMatchesBruteForce) {
  std::mt19937 rng(19);
  const Vec th = {0.8, 0.3};
  const Instance in = make(PrimitiveType::kTorus, th);
  const int na = 400, nb = 160;
  std::vector<Vec> samples;
  for (int i = 0; i < na; ++i) {
    for (int j = 0; j < nb; ++j) {
      const double a = 2 * std::numbers::pi * i / na;
      const double b = 2 * std::numbers::pi * j / nb;
      const double r = th[0] + th[1] * std::cos(b);
      samples.push_back({r * std::cos(a), r * std::sin(a), th[1] * std::sin(b)});
    }
  }
  const double cover =
      0.5 * std::hypot(2 * std::numbers::pi * 1.1 / na, 2 * std::numbers::pi * 0.3 / nb);
  auto inside = [](const Vec& t, const Vec& p) {
    return std::hypot(std::hypot(p[0], p[1]) - t[0], p[2]) <= t[1];
  };
  expect_matches_samples(in, samples, random_queries(rng, 3, 1.3, 40), cover, inside);
}

TEST(PrimitiveExactness, CylinderMatchesBruteForce) {
  std::mt19937 rng(23);
  const Vec th = {0.6, 1.4};
  const Instance in = make(PrimitiveType::kCylinder, th);
  const int na = 360, nz = 140, nr = 60;
  std::vector<Vec> samples;
  for (int i = 0; i < na; ++i) {
    const double a = 2 * std::numbers::pi * i / na;
    for (int j = 0; j <= nz; ++j) {
      samples.push_back({0.6 * std::cos(a), 0.6 * std::sin(a), -0.7 + 1.4 * j / nz});
    }
    for (int j = 0; j <= nr; ++j) {
      const double r = 0.6 * j / nr;
      samples.push_back({r * std::cos(a), r * std::sin(a), -0.7});
      samples.push_back({r * std::cos(a), r * std::sin(a), 0.7});
    }
  }
  const double cover = 0.5 * std::hypot(2 * std::numbers::pi * 0.6 / na, 1.4 / nz);
  auto inside = [](const Vec& t, const Vec& p) {
    return std::hypot(p[0], p[1]) <= t[0] && std::abs(p[2]) <= 0.5 * t[1];
  };
  expect_matches_samples(in, samples, random_queries(rng, 3, 1.2, 40), cover, inside);
}

// Winding number by summed angles, independent of the crossing test under test.
bool polygon_contains(const Vec& v, const Vec& p) {
  const std::size_t n = v.size() / 2;
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    const double a = std::atan2(v[2 * i + 1] - p[1], v[2 * i] - p[0]);
    double d = std::atan2(v[2 * j + 1] - p[1], v[2 * j] - p[0]) - a;
    while (d > std::numbers::pi) d -= 2 * std::numbers::pi;
    while (d < -std::numbers::pi) d += 2 * std::numbers::pi;
    total += d;
  }
  return std::abs(total) > std::numbers::pi;
}

TEST(PrimitiveExactness, PolygonMatchesBruteForce) {
  std::mt19937 rng(29);
  for (int k = 0; k < 4; ++k) {
    const Vec v = random_polygon(rng);
    const Instance in = make(PrimitiveType::kPolygon, v);
    std::vector<Vec> samples;
    const std::size_t n = v.size() / 2;
    const int per_edge = 2000;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      for (int s = 0; s < per_edge; ++s) {
        const double c = static_cast<double>(s) / per_edge;
        samples.push_back({v[2 * i] + c * (v[2 * j] - v[2 * i]),
                           v[2 * i + 1] + c * (v[2 * j + 1] - v[2 * i + 1])});
      }
    }
    const double cover = 2.2 / per_edge;  // edges are shorter than 2.2
    expect_matches_samples(in, samples, random_queries(rng, 2, 1.4, 60), cover, polygon_contains);
  }
}

TEST(PrimitiveExactness, ExtrudeMatchesBruteForce) {
  std::mt19937 rng(67);
  const double k = 4.0 / 3.0 * 0.3;
  // A rounded slot (two straight sides, two half-round ends) and a random profile.
  const Vec slot = {-0.4, -0.3, -0.4 + 0.8 / 3, -0.3, 0.4 - 0.8 / 3,  -0.3,
                    0.4,  -0.3, 0.4 + k,        -0.3, 0.4 + k,        0.3,
                    0.4,  0.3,  0.4 - 0.8 / 3,  0.3,  -0.4 + 0.8 / 3, 0.3,
                    -0.4, 0.3,  -0.4 - k,       0.3,  -0.4 - k,       -0.3};
  for (const Vec& th : {extrude_theta(slot, 0.6), extrude_theta(random_profile(rng), 0.9)}) {
    const Instance in = make(PrimitiveType::kExtrude, th);
    const Vec poly = bezier_profile(profile_of(th));
    const double h = th.back();
    const std::size_t n = poly.size() / 2;
    const int per_edge = 40, nz = 60;
    const double grid = 0.02;
    std::vector<Vec> samples;
    double longest = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      longest = std::max(longest,
                         std::hypot(poly[2 * j] - poly[2 * i], poly[2 * j + 1] - poly[2 * i + 1]));
      for (int e = 0; e < per_edge; ++e) {
        const double c = static_cast<double>(e) / per_edge;
        for (int zi = 0; zi <= nz; ++zi) {
          samples.push_back({poly[2 * i] + c * (poly[2 * j] - poly[2 * i]),
                             poly[2 * i + 1] + c * (poly[2 * j + 1] - poly[2 * i + 1]),
                             -0.5 * h + h * zi / nz});
        }
      }
    }
    for (double x = -1.2; x <= 1.2; x += grid) {
      for (double y = -1.2; y <= 1.2; y += grid) {
        if (!polygon_contains(poly, {x, y})) continue;
        samples.push_back({x, y, -0.5 * h});
        samples.push_back({x, y, 0.5 * h});
      }
    }
    const double cover =
        std::max(0.5 * std::hypot(longest / per_edge, h / nz), std::sqrt(0.5) * grid);
    auto inside = [](const Vec& t, const Vec& p) {
      return std::abs(p[2]) <= 0.5 * t.back() && polygon_contains(bezier_profile(profile_of(t)), p);
    };
    expect_matches_samples(in, samples, random_queries(rng, 3, 1.3, 40), cover, inside);
  }
}

TEST(PrimitiveExactness, EllipseMatchesBruteForce) {
  std::mt19937 rng(31);
  for (const Vec& th : {Vec{1.2, 0.4}, Vec{0.3, 0.9}, Vec{0.7, 0.69}}) {
    const Instance in = make(PrimitiveType::kEllipse, th);
    std::vector<Vec> samples;
    const int n = 40000;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * i / n;
      samples.push_back({th[0] * std::cos(a), th[1] * std::sin(a)});
    }
    const double cover = std::numbers::pi * std::max(th[0], th[1]) / n;
    auto inside = [](const Vec& t, const Vec& p) {
      return (p[0] / t[0]) * (p[0] / t[0]) + (p[1] / t[1]) * (p[1] / t[1]) <= 1.0;
    };
    std::vector<Vec> queries = random_queries(rng, 2, 1.5, 60);
    // Points near the major axis inside, where the nearest point is hardest to find.
    for (int i = 0; i < 10; ++i) {
      const double major = std::max(th[0], th[1]);
      Vec q = {uniform(rng, -major, major), uniform(rng, -1e-3, 1e-3)};
      if (th[1] > th[0]) std::swap(q[0], q[1]);
      queries.push_back(q);
    }
    expect_matches_samples(in, samples, queries, cover, inside);
  }
}

// ------------------------------------------------------------------------------------------
// Gradients against central finite differences.

// Compares every derivative (point coordinates, then parameters) with central differences.
// Returns false, checking nothing, when the point is within the step of a kink.
bool check_against_finite_differences(Instance in, Vec p) {
  const double h = 1e-6;
  const Grad g = gradient(in, p);
  const std::size_t n_in = p.size() + in.theta.size();
  std::vector<double> fd(n_in);
  for (std::size_t i = 0; i < n_in; ++i) {
    const auto [fp, fm, slope] = central_difference(in, p, i, h);
    fd[i] = slope;
    // A slope that jumps inside [x - h, x + h] is a kink, not a gradient error.
    if (std::abs((fp - g.f) - (g.f - fm)) > 1e-2 * h * (1.0 + std::abs(fd[i]))) return false;
  }
  for (std::size_t i = 0; i < n_in; ++i) {
    const double analytic = i < p.size() ? g.dp[i] : g.dtheta[i - p.size()];
    EXPECT_NEAR(analytic, fd[i], 2e-6 * (1.0 + std::abs(fd[i])))
        << name_of(in.shape.type) << " input " << i << " (" << p.size()
        << " coordinates first) at f = " << g.f;
  }
  return true;
}

TEST(PrimitiveGradients, MatchFiniteDifferences) {
  std::mt19937 rng(37);
  for (PrimitiveType t : kAllTypes) {
    const int samples = t == PrimitiveType::kMlp ? 40 : 150;
    int checked = 0;
    for (int k = 0; k < samples; ++k) {
      const Instance in = random_instance(t, rng);
      checked += check_against_finite_differences(
          in, random_point(rng, dim_of(t), k % 2 == 0 ? 0.6 : 1.6));
    }
    EXPECT_GE(checked, samples * 9 / 10) << name_of(t);
  }
}

// Every piece of the piecewise families, inside and outside, at chosen points.
TEST(PrimitiveGradients, EveryPieceMatchesFiniteDifferences) {
  const std::vector<std::pair<Instance, std::vector<Vec>>> cases = {
      // Cone r1 = 0.8 (z = -0.6), r2 = 0.3 (z = 0.6): inside near the bottom, the top and the
      // side; outside below the bottom cap, above the top cap, beside the side, beyond each
      // rim, and on the axis beyond each cap.
      {make(PrimitiveType::kCone, {0.8, 0.3, 1.2}),
       {{0.1, 0.05, -0.5},
        {0.05, 0.1, 0.55},
        {0.4, 0.1, 0.0},
        {0.3, 0.2, -0.9},
        {0.1, -0.1, 0.9},
        {0.8, 0.4, 0.1},
        {1.1, 0.1, -0.8},
        {0.5, 0.1, 0.9},
        {0.0, 0.0, -1.0},
        {0.0, 0.0, 1.0}}},
      // The same with an apex at the top and an apex at the bottom.
      {make(PrimitiveType::kCone, {0.7, 0.0, 1.0}),
       {{0.1, 0.0, -0.4}, {0.2, 0.1, 0.0}, {0.3, 0.2, 0.8}, {0.1, 0.0, 0.7}, {0.9, 0.3, -0.7}}},
      {make(PrimitiveType::kCone, {0.0, 0.7, 1.0}),
       {{0.1, 0.0, 0.4}, {0.2, 0.1, 0.0}, {0.3, 0.2, -0.8}, {0.1, 0.0, -0.7}, {0.9, 0.3, 0.7}}},
      {make(PrimitiveType::kCylinder, {0.6, 1.0}),
       {{0.1, 0.2, 0.0},
        {0.1, 0.1, 0.45},
        {0.1, 0.1, -0.45},
        {0.9, 0.1, 0.1},
        {0.1, 0.1, 0.9},
        {0.8, 0.5, -0.8}}},
      {make(PrimitiveType::kCapsule, {0.3, 1.0}),
       {{0.1, 0.1, 0.0}, {0.1, 0.1, 0.6}, {0.2, 0.1, -0.7}, {0.5, 0.1, 0.2}, {0.0, 0.1, -0.9}}},
      {make(PrimitiveType::kBox, {1.0, 0.6, 0.4}),
       {{0.4, 0.0, 0.0},
        {0.0, -0.25, 0.05},
        {0.1, 0.1, -0.15},
        {0.7, 0.1, 0.1},
        {-0.7, 0.5, 0.1},
        {0.6, -0.4, 0.3}}},
      {make(PrimitiveType::kTorus, {0.7, 0.2}),
       {{0.7, 0.1, 0.1}, {0.0, 0.2, 0.0}, {0.3, -0.3, 0.5}, {-1.0, 0.2, -0.1}}},
  };
  for (const auto& [in, points] : cases) {
    for (const Vec& p : points) {
      EXPECT_TRUE(check_against_finite_differences(in, p))
          << name_of(in.shape.type) << " kink at " << p[0] << " " << p[1] << " " << p[2];
    }
  }
}

// The extrude's gradient (point, every control point, height) at points inside near the wall
// and near a cap, outside beside the wall, above a cap and beyond a rim, and at random points
// around a curved profile.
TEST(PrimitiveGradients, ExtrudeMatchesFiniteDifferencesNearWallsAndCaps) {
  const Vec d_shape = {0, -1, 0, -1.0 / 3, 0, 1.0 / 3, 0, 1, 1.3, 1, 1.3, -1};
  const Instance d = make(PrimitiveType::kExtrude, extrude_theta(d_shape, 0.6));
  for (const Vec& p :
       {Vec{0.05, 0.2, 0.0}, Vec{0.9, 0.1, 0.1}, Vec{0.5, 0.3, 0.27}, Vec{0.4, -0.2, -0.28},
        Vec{-0.2, 0.3, 0.1}, Vec{1.1, -0.3, 0.0}, Vec{0.5, 0.1, 0.5}, Vec{0.6, -0.4, -0.45},
        Vec{-0.1, 0.4, 0.4}, Vec{1.2, 0.2, -0.5}, Vec{0.3, 1.2, 0.1}, Vec{-1.5, 2.0, 1.0}}) {
    EXPECT_TRUE(check_against_finite_differences(d, p))
        << "kink at " << p[0] << " " << p[1] << " " << p[2];
  }
  std::mt19937 rng(71);
  for (int trial = 0; trial < 4; ++trial) {
    const Instance in = make(PrimitiveType::kExtrude, extrude_theta(random_profile(rng), 0.8));
    int checked = 0;
    const int samples = 60;
    for (int k = 0; k < samples; ++k) {
      Vec p = random_point(rng, 3, 1.2);
      p[2] = uniform(rng, -0.7, 0.7);  // around the caps
      checked += check_against_finite_differences(in, p);
    }
    EXPECT_GE(checked, samples * 9 / 10);
  }
}

TEST(PrimitiveGradients, MlpDeeperAndShallowerNetworks) {
  std::mt19937 rng(41);
  for (const std::vector<int>& hidden :
       {std::vector<int>{}, std::vector<int>{5}, std::vector<int>{4, 7, 3}}) {
    Vec w(static_cast<std::size_t>(mlp_weight_count(3, hidden)));
    std::normal_distribution<double> n(0.0, 0.7);
    for (double& x : w) x = n(rng);
    Instance in = make(PrimitiveType::kMlp, w, hidden);
    Vec p = random_point(rng, 3, 1.0);
    const Grad g = gradient(in, p);
    const double h = 1e-6;
    for (std::size_t i = 0; i < p.size() + w.size(); ++i) {
      const double analytic = i < p.size() ? g.dp[i] : g.dtheta[i - p.size()];
      EXPECT_NEAR(analytic, central_difference(in, p, i, h).slope, 1e-7)
          << hidden.size() << " layers, input " << i;
    }
  }
}

TEST(PrimitiveGradients, NearlyCircularEllipseSplitsTheRadiusDerivative) {
  // For a circle of radius r, growing the semi-axis a by da moves the nearest point by
  // cos(angle) da along x: df/da = -(x/|p|)^2, df/db = -(y/|p|)^2.
  for (const Vec& radii :
       {Vec{0.8, 0.8}, Vec{0.8, 0.8 * (1 - 1e-12)}, Vec{0.8 * (1 - 1e-12), 0.8}}) {
    const Instance e = make(PrimitiveType::kEllipse, radii);
    for (const Vec& p : {Vec{0.3, -0.4}, Vec{-1.2, 0.5}, Vec{0.05, 0.7}}) {
      const Grad g = gradient(e, p);
      const double r = std::hypot(p[0], p[1]);
      EXPECT_NEAR(g.dp[0], p[0] / r, 1e-9);
      EXPECT_NEAR(g.dp[1], p[1] / r, 1e-9);
      EXPECT_NEAR(g.dtheta[0], -(p[0] / r) * (p[0] / r), 1e-9);
      EXPECT_NEAR(g.dtheta[1], -(p[1] / r) * (p[1] / r), 1e-9);
    }
  }
}

TEST(PrimitiveGradients, PlaneNormalDerivativeIncludesNormalization) {
  // Scaling the normal does not move the plane: the derivative along n itself is 0.
  const Instance pl = make(PrimitiveType::kPlane, {1.0, 2.0, -2.0, 0.3});
  const Grad g = gradient(pl, {0.4, -0.1, 0.9});
  const double along = g.dtheta[0] * 1.0 + g.dtheta[1] * 2.0 + g.dtheta[2] * -2.0;
  EXPECT_NEAR(along, 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(g.dtheta[3], -1.0);
  EXPECT_NEAR(g.dp[0], 1.0 / 3.0, 1e-15);
}

// ------------------------------------------------------------------------------------------
// Float against double.

TEST(PrimitivePrecision, FloatAgreesWithDouble) {
  std::mt19937 rng(43);
  for (PrimitiveType t : kAllTypes) {
    for (int k = 0; k < 100; ++k) {
      const Instance in = random_instance(t, rng);
      const Vec p = random_point(rng, dim_of(t), k % 2 == 0 ? 0.6 : 1.6);
      const Grad g = gradient(in, p);
      std::vector<float> thf(in.theta.begin(), in.theta.end());
      std::vector<float> pf(p.begin(), p.end());
      std::vector<float> dpf(p.size(), std::numeric_limits<float>::quiet_NaN());
      std::vector<float> dthf(thf.size(), std::numeric_limits<float>::quiet_NaN());
      const float vf = primitive_value<float>(in.shape, thf, pf.data());
      const float gf =
          primitive_value_grad<float>(in.shape, thf, pf.data(), dpf.data(), dthf.data());
      // The inputs were rounded to float; compare with double evaluated at the rounded inputs.
      Instance rounded = in;
      rounded.theta.assign(thf.begin(), thf.end());
      const Vec pr(pf.begin(), pf.end());
      const Grad gr = gradient(rounded, pr);
      const double tol = 2e-5 * (1.0 + std::abs(gr.f));
      EXPECT_NEAR(vf, gr.f, tol) << name_of(t);
      EXPECT_NEAR(gf, gr.f, tol) << name_of(t);
      for (std::size_t i = 0; i < p.size(); ++i) {
        EXPECT_NEAR(dpf[i], gr.dp[i], 1e-3 * (1.0 + std::abs(gr.dp[i]))) << name_of(t);
      }
      for (std::size_t i = 0; i < thf.size(); ++i) {
        EXPECT_NEAR(dthf[i], gr.dtheta[i], 1e-3 * (1.0 + std::abs(gr.dtheta[i]))) << name_of(t);
      }
      (void)g;
    }
  }
}

// ------------------------------------------------------------------------------------------
// Degenerate points.

void expect_finite(const Instance& in, const Vec& p, const char* what) {
  const Grad g = gradient(in, p);
  EXPECT_TRUE(std::isfinite(g.f)) << name_of(in.shape.type) << " " << what;
  for (double x : g.dp) EXPECT_TRUE(std::isfinite(x)) << name_of(in.shape.type) << " " << what;
  for (double x : g.dtheta) {
    EXPECT_TRUE(std::isfinite(x)) << name_of(in.shape.type) << " " << what;
  }
  if (is_exact(in.shape.type)) {
    EXPECT_LE(norm(g.dp), 1.0 + 1e-12) << name_of(in.shape.type) << " " << what;
  }
  std::vector<float> thf(in.theta.begin(), in.theta.end());
  std::vector<float> pf(p.begin(), p.end());
  std::vector<float> dpf(p.size());
  std::vector<float> dthf(thf.size());
  const float f = primitive_value_grad<float>(in.shape, thf, pf.data(), dpf.data(), dthf.data());
  EXPECT_TRUE(std::isfinite(f)) << name_of(in.shape.type) << " float " << what;
  for (float x : dpf) EXPECT_TRUE(std::isfinite(x)) << name_of(in.shape.type) << " " << what;
  for (float x : dthf) EXPECT_TRUE(std::isfinite(x)) << name_of(in.shape.type) << " " << what;
}

TEST(PrimitiveDegenerate, OriginOfEveryFamily) {
  std::mt19937 rng(47);
  for (PrimitiveType t : kAllTypes) {
    const Instance in = random_instance(t, rng);
    expect_finite(in, Vec(static_cast<std::size_t>(dim_of(t)), 0.0), "origin");
  }
}

TEST(PrimitiveDegenerate, EdgesAxesAndCentres) {
  const Instance box = make(PrimitiveType::kBox, {2, 2, 2});
  for (const Vec& p : {Vec{1, 1, 0}, Vec{1, 1, 1}, Vec{0.5, 0.5, 0}, Vec{-1, 0.3, 1}}) {
    expect_finite(box, p, "box edge");
  }
  const Instance rect = make(PrimitiveType::kRectangle, {2, 1});
  expect_finite(rect, {1, 0.5}, "rectangle corner");
  expect_finite(rect, {0.25, 0}, "rectangle medial axis");
  const Instance cyl = make(PrimitiveType::kCylinder, {1, 2});
  for (const Vec& p : {Vec{0, 0, 0.5}, Vec{0, 0, 1}, Vec{0, 0, 3}, Vec{1, 0, 1}}) {
    expect_finite(cyl, p, "cylinder axis/rim");
  }
  const Instance cone = make(PrimitiveType::kCone, {1, 0, 2});
  for (const Vec& p : {Vec{0, 0, 1}, Vec{0, 0, 2}, Vec{0, 0, -1}, Vec{1, 0, -1}, Vec{0, 0, 0}}) {
    expect_finite(cone, p, "cone apex/axis/rim");
  }
  const Instance needle = make(PrimitiveType::kCone, {0, 0, 1});
  expect_finite(needle, {0, 0, 0}, "zero-radius cone");
  expect_finite(needle, {0.5, 0, 0}, "zero-radius cone");
  const Instance torus = make(PrimitiveType::kTorus, {1, 0.3});
  for (const Vec& p : {Vec{0, 0, 0}, Vec{0, 0, 1}, Vec{1, 0, 0}, Vec{0, -1, 0}}) {
    expect_finite(torus, p, "torus axis/core");
  }
  const Instance capsule = make(PrimitiveType::kCapsule, {0.3, 1});
  for (const Vec& p : {Vec{0, 0, 0.5}, Vec{0, 0, 0.2}}) expect_finite(capsule, p, "capsule core");
  const Instance ellipsoid = make(PrimitiveType::kEllipsoid, {1, 2, 3});
  expect_finite(ellipsoid, {1e-300, 0, 0}, "ellipsoid near centre");
  expect_finite(ellipsoid, {0, 1e-30, 1e-30}, "ellipsoid near centre");
  const Instance flat_plane = make(PrimitiveType::kPlane, {0, 0, 0, 0.5});
  expect_finite(flat_plane, {1, 2, 3}, "plane with zero normal");
  EXPECT_DOUBLE_EQ(value(flat_plane, {1, 2, 3}), -0.5);
  const Instance ellipse = make(PrimitiveType::kEllipse, {2, 1});
  for (const Vec& p : {Vec{0, 0}, Vec{1.5, 0}, Vec{0.3, 0}, Vec{0, 0.5}, Vec{0, 1}, Vec{2, 0},
                       Vec{1.5, 1e-200}, Vec{1e-300, 1e-300}, Vec{-1.5, -1e-160}}) {
    expect_finite(ellipse, p, "ellipse axes/centre/cusp");
  }
  const Instance circle_ellipse = make(PrimitiveType::kEllipse, {1, 1});
  expect_finite(circle_ellipse, {0, 0}, "circular ellipse centre");
  const Instance square = make(PrimitiveType::kPolygon, {0, 0, 1, 0, 1, 1, 0, 1});
  for (const Vec& p : {Vec{0, 0}, Vec{1, 1}, Vec{0.5, 0}, Vec{0.5, 0.5}, Vec{0.25, 0.25}}) {
    expect_finite(square, p, "polygon vertex/edge/medial axis");
  }
  const Instance repeated = make(PrimitiveType::kPolygon, {0, 0, 1, 0, 1, 0, 1, 1, 0, 1});
  expect_finite(repeated, {1, 0}, "polygon with a repeated vertex");
  expect_finite(repeated, {0.5, 0.5}, "polygon with a repeated vertex");
  const Instance ex =
      make(PrimitiveType::kExtrude, extrude_theta(straight_profile({0, 0, 1, 0, 1, 1, 0, 1}), 1.0));
  for (const Vec& p : {Vec{0, 0, 0}, Vec{1, 1, 0.5}, Vec{0.5, 0, 0.5}, Vec{0.5, 0.5, 0},
                       Vec{0.25, 0.25, 0.25}, Vec{0.5, 0.5, 0.5}, Vec{0.5, 0.5, 2}}) {
    expect_finite(ex, p, "extrude vertex/edge/medial axis/cap");
  }
  // A degenerate segment (all four controls at one point) repeats that point 15 times.
  const Instance pinched = make(PrimitiveType::kExtrude, {0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 1, 0, 1, 0,
                                                          1, 1, 0, 1, 1.0});  // 3 segments, height
  for (const Vec& p : {Vec{0, 0, 0}, Vec{0.3, 0.1, 0.2}, Vec{-1, -1, 0}}) {
    expect_finite(pinched, p, "extrude with a degenerate segment");
  }
  const Instance sphere = make(PrimitiveType::kSphere, {1});
  const Grad g = gradient(sphere, {0, 0, 0});
  EXPECT_DOUBLE_EQ(g.f, -1.0);
  EXPECT_DOUBLE_EQ(g.dtheta[0], -1.0);
}

// On the boundary the gradient is the edge normal whatever the orientation.
TEST(PrimitiveDegenerate, PolygonBoundaryNormalIsOutward) {
  for (const Vec& v : {Vec{0, 0, 1, 0, 1, 1, 0, 1}, Vec{0, 0, 0, 1, 1, 1, 1, 0}}) {
    const Instance sq = make(PrimitiveType::kPolygon, v);
    const Grad g = gradient(sq, {0.5, 0});
    EXPECT_DOUBLE_EQ(g.f, 0.0);
    EXPECT_DOUBLE_EQ(g.dp[0], 0.0);
    EXPECT_DOUBLE_EQ(g.dp[1], -1.0);
  }
}

}  // namespace
}  // namespace fuzzycsg
