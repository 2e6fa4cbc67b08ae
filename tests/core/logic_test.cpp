// t-norms, t-conorms, complements, difference, the unified operator and the block forms.
#include "fuzzycsg/core/logic.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/numeric_support.hpp"
#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg {
namespace {

using logic::Complement;
using logic::Family;

struct Case {
  Family f;
  double p;
  int n;
};

std::string describe(const Case& c) {
  return std::string(logic::family_name(c.f)) + " p=" + std::to_string(c.p) +
         " n=" + std::to_string(c.n);
}

// Every t-norm family with parameters across its range.
std::vector<Case> tnorm_cases() {
  return {
      {Family::kProduct, 0, 0},       {Family::kGodel, 0, 0},      {Family::kLukasiewicz, 0, 0},
      {Family::kYager, 0.5, 0},       {Family::kYager, 1.0, 0},    {Family::kYager, 2.0, 0},
      {Family::kYager, 5.0, 0},       {Family::kEinstein, 0, 0},   {Family::kHamacher, 0.0, 0},
      {Family::kHamacher, 0.5, 0},    {Family::kHamacher, 2.0, 0}, {Family::kDombi, 0.5, 0},
      {Family::kDombi, 1.0, 0},       {Family::kDombi, 3.0, 0},    {Family::kDuboisPrade, 0.3, 0},
      {Family::kDuboisPrade, 1.0, 0}, {Family::kWeber, -0.5, 0},   {Family::kWeber, 0.0, 0},
      {Family::kWeber, 2.0, 0},
  };
}

// Bézier and Li & Tian operators (not t-norms).
std::vector<Case> smooth_cases() {
  return {
      {Family::kBezier, 0, 1},      {Family::kBezier, 0, 2},      {Family::kBezier, 0, 3},
      {Family::kBezier, 0, 7},      {Family::kLiTian, 0.5, 1},    {Family::kLiTian, 1.5, 2},
      {Family::kLiTian, 1.0, 3},    {Family::kLiTian, 0.2, 2},    {Family::kLiTianHat, 0.5, 1},
      {Family::kLiTianHat, 1.5, 2}, {Family::kLiTianHat, 1.0, 3}, {Family::kLiTianHat, 0.2, 3},
  };
}

std::vector<Case> all_cases() {
  auto v = tnorm_cases();
  const auto s = smooth_cases();
  v.insert(v.end(), s.begin(), s.end());
  return v;
}

double tn(const Case& c, double x, double y) { return logic::tnorm(c.f, x, y, c.p, c.n); }
double tc(const Case& c, double x, double y) { return logic::tconorm(c.f, x, y, c.p, c.n); }

TEST(Names, FamiliesRoundTripAndTNormFlags) {
  for (const auto& c : all_cases()) {
    EXPECT_EQ(logic::family_from_name(logic::family_name(c.f)), c.f);
  }
  for (const auto& c : tnorm_cases()) EXPECT_TRUE(logic::is_tnorm(c.f)) << describe(c);
  for (const auto& c : smooth_cases()) EXPECT_FALSE(logic::is_tnorm(c.f)) << describe(c);
}

// ---- axioms ----

TEST(TNorm, BoundaryConditions) {
  const auto g = test::unit_grid(200);
  for (const auto& c : all_cases()) {
    for (double x : g) {
      EXPECT_NEAR(tn(c, x, 1.0), x, 1e-13) << describe(c) << " x=" << x;
      EXPECT_NEAR(tn(c, 1.0, x), x, 1e-13) << describe(c) << " x=" << x;
      EXPECT_NEAR(tn(c, x, 0.0), 0.0, 1e-13) << describe(c) << " x=" << x;
      EXPECT_NEAR(tn(c, 0.0, x), 0.0, 1e-13) << describe(c) << " x=" << x;
    }
  }
}

TEST(TNorm, CommutativityAndRange) {
  const auto g = test::unit_grid(100);
  for (const auto& c : all_cases()) {
    for (double x : g) {
      for (double y : g) {
        const double v = tn(c, x, y);
        EXPECT_NEAR(v, tn(c, y, x), 1e-14) << describe(c) << " " << x << " " << y;
        EXPECT_GE(v, -1e-14) << describe(c) << " " << x << " " << y;
        EXPECT_LE(v, 1.0 + 1e-14) << describe(c) << " " << x << " " << y;
      }
    }
  }
}

// Monotone in each argument (by commutativity, in y suffices), for every t-norm and for B_n.
TEST(TNorm, Monotonicity) {
  auto cases = tnorm_cases();
  cases.push_back({Family::kBezier, 0, 2});
  cases.push_back({Family::kBezier, 0, 6});
  const auto g = test::unit_grid(100);
  for (const auto& c : cases) {
    for (double x : g) {
      for (std::size_t j = 0; j + 1 < g.size(); ++j) {
        EXPECT_LE(tn(c, x, g[j]), tn(c, x, g[j + 1]) + 1e-14)
            << describe(c) << " x=" << x << " y=" << g[j];
      }
    }
  }
}

TEST(TNorm, Associativity) {
  const auto g = test::unit_grid(20);
  for (const auto& c : tnorm_cases()) {
    for (double x : g) {
      for (double y : g) {
        for (double z : g) {
          EXPECT_NEAR(tn(c, x, tn(c, y, z)), tn(c, tn(c, x, y), z), 1e-12)
              << describe(c) << " " << x << " " << y << " " << z;
        }
      }
    }
  }
}

// The smooth operators are not associative (why is_tnorm is false for them).
TEST(TNorm, SmoothOperatorsAreNotAssociative) {
  for (const auto& c : smooth_cases()) {
    if (c.f == Family::kBezier && c.n == 1) continue;  // B_1 is the product
    double worst = 0.0;
    const auto g = test::unit_grid(10);
    for (double x : g) {
      for (double y : g) {
        for (double z : g) {
          worst = std::max(worst, std::abs(tn(c, x, tn(c, y, z)) - tn(c, tn(c, x, y), z)));
        }
      }
    }
    EXPECT_GT(worst, 1e-4) << describe(c);
  }
}

// Families that contain each other at particular parameters.
TEST(TNorm, KnownCoincidences) {
  for (const auto& pt : test::random_pairs(200, 0.0, 1.0, 7)) {
    const auto x = pt.first;
    const auto y = pt.second;
    const double prod = x * y;
    EXPECT_NEAR(logic::tnorm(Family::kHamacher, x, y, 1.0, 0), prod, 1e-15);
    EXPECT_NEAR(logic::tnorm(Family::kHamacher, x, y, 2.0, 0),
                logic::tnorm(Family::kEinstein, x, y, 0.0, 0), 1e-15);
    EXPECT_NEAR(logic::tnorm(Family::kDombi, x, y, 1.0, 0),
                logic::tnorm(Family::kHamacher, x, y, 0.0, 0), 1e-14);
    EXPECT_NEAR(logic::tnorm(Family::kYager, x, y, 1.0, 0), std::max(0.0, x + y - 1.0), 1e-15);
    EXPECT_NEAR(logic::tnorm(Family::kWeber, x, y, 0.0, 0), std::max(0.0, x + y - 1.0), 1e-15);
    EXPECT_NEAR(logic::tnorm(Family::kDuboisPrade, x, y, 1.0, 0), prod, 1e-15);
    // Yager tends to min as p grows; Dombi too.
    EXPECT_NEAR(logic::tnorm(Family::kYager, x, y, 400.0, 0), std::min(x, y), 5e-3);
    EXPECT_NEAR(logic::tnorm(Family::kDombi, x, y, 400.0, 0), std::min(x, y), 5e-3);
  }
}

TEST(TConorm, Axioms) {
  const auto g = test::unit_grid(60);
  for (const auto& c : tnorm_cases()) {
    for (double x : g) {
      EXPECT_NEAR(tc(c, x, 0.0), x, 1e-13) << describe(c);
      EXPECT_NEAR(tc(c, 0.0, x), x, 1e-13) << describe(c);
      EXPECT_NEAR(tc(c, x, 1.0), 1.0, 1e-13) << describe(c);
      for (std::size_t j = 0; j < g.size(); ++j) {
        const double y = g[j];
        EXPECT_NEAR(tc(c, x, y), tc(c, y, x), 1e-14) << describe(c);
        EXPECT_GE(tc(c, x, y), std::max(x, y) - 1e-14) << describe(c);  // S >= max
        if (j + 1 < g.size()) {
          EXPECT_LE(tc(c, x, y), tc(c, x, g[j + 1]) + 1e-14) << describe(c);
        }
      }
    }
    const auto g3 = test::unit_grid(12);
    for (double x : g3) {
      for (double y : g3) {
        for (double z : g3) {
          EXPECT_NEAR(tc(c, x, tc(c, y, z)), tc(c, tc(c, x, y), z), 1e-12) << describe(c);
        }
      }
    }
  }
}

TEST(TConorm, IsDualOfTNormForEveryFamily) {
  for (const auto& c : all_cases()) {
    for (const auto& pt : test::random_pairs(50, 0.0, 1.0, 11)) {
      const auto x = pt.first;
      const auto y = pt.second;
      EXPECT_NEAR(tc(c, x, y), 1.0 - tn(c, 1.0 - x, 1.0 - y), 1e-14) << describe(c);
    }
  }
}

TEST(TNorm, ProductDeMorganAndDifference) {
  const auto g = test::unit_grid(50);
  for (double x : g) {
    for (double y : g) {
      const double s = logic::tconorm(Family::kProduct, x, y, 0.0, 0);
      EXPECT_NEAR(s, x + y - x * y, 1e-15);
      // not(x or y) = not x and not y, with the standard complement.
      EXPECT_NEAR(logic::complement(Complement::kStandard, s, 0.0),
                  logic::tnorm(Family::kProduct, logic::complement(Complement::kStandard, x, 0.0),
                               logic::complement(Complement::kStandard, y, 0.0), 0.0, 0),
                  1e-15);
      EXPECT_NEAR(logic::difference(Family::kProduct, Complement::kStandard, x, y, 0.0, 0, 0.0),
                  x - x * y, 1e-15);
      EXPECT_EQ(logic::tconorm(Family::kGodel, x, y, 0.0, 0), std::max(x, y));
    }
  }
}

// ---- complements ----

struct ComplementCase {
  Complement c;
  double lambda;
};
std::vector<ComplementCase> complement_cases() {
  return {{Complement::kStandard, 0.0}, {Complement::kSugeno, -0.6}, {Complement::kSugeno, 0.0},
          {Complement::kSugeno, 3.0},   {Complement::kYager, 0.5},   {Complement::kYager, 1.0},
          {Complement::kYager, 2.5},    {Complement::kCosine, 0.0}};
}

TEST(Complement, BoundaryMonotonicityInvolution) {
  const auto g = test::unit_grid(400);
  for (const auto& cl : complement_cases()) {
    const auto c = cl.c;
    const auto lambda = cl.lambda;
    const std::string name =
        std::string(logic::complement_name(c)) + " lambda=" + std::to_string(lambda);
    EXPECT_NEAR(logic::complement(c, 0.0, lambda), 1.0, 1e-15) << name;
    EXPECT_NEAR(logic::complement(c, 1.0, lambda), 0.0, 1e-15) << name;
    for (std::size_t i = 0; i + 1 < g.size(); ++i) {
      EXPECT_GT(logic::complement(c, g[i], lambda), logic::complement(c, g[i + 1], lambda))
          << name << " x=" << g[i];
    }
    if (c != Complement::kCosine) {  // the others are involutions
      for (double x : g) {
        EXPECT_NEAR(logic::complement(c, logic::complement(c, x, lambda), lambda), x, 1e-12)
            << name << " x=" << x;
      }
    }
  }
  for (double x : g) {
    EXPECT_NEAR(logic::complement(Complement::kYager, x, 1.0), 1.0 - x, 1e-15);
    EXPECT_NEAR(logic::complement(Complement::kSugeno, x, 0.0), 1.0 - x, 1e-15);
  }
  EXPECT_TRUE(logic::complement_uses_lambda(Complement::kSugeno));
  EXPECT_FALSE(logic::complement_uses_lambda(Complement::kCosine));
}

TEST(Complement, DerivativesMatchCentralDifferences) {
  for (const auto& cl : complement_cases()) {
    const auto c = cl.c;
    const auto lambda = cl.lambda;
    for (int i = 1; i < 50; ++i) {
      const double x = i / 50.0 + 1e-3;
      const auto g = logic::complement_grad(c, x, lambda);
      EXPECT_NEAR(g.v, logic::complement(c, x, lambda), 1e-15);
      const double fx =
          test::central_diff([&](double s) { return logic::complement(c, s, lambda); }, x, 1e-7);
      EXPECT_NEAR(g.dx, fx, 1e-6 * (1.0 + std::abs(fx)))
          << logic::complement_name(c) << " " << lambda << " x=" << x;
      if (logic::complement_uses_lambda(c)) {
        const double fl =
            test::central_diff([&](double l) { return logic::complement(c, x, l); }, lambda, 1e-7);
        EXPECT_NEAR(g.dp, fl, 1e-6 * (1.0 + std::abs(fl)))
            << logic::complement_name(c) << " " << lambda << " x=" << x;
      } else {
        EXPECT_EQ(g.dp, 0.0);
      }
      const auto gf = logic::complement_grad(c, static_cast<float>(x), static_cast<float>(lambda));
      EXPECT_NEAR(gf.v, g.v, 1e-6);
      EXPECT_NEAR(gf.dx, g.dx, 1e-4 * (1.0 + std::abs(g.dx)));
      EXPECT_NEAR(gf.dp, g.dp, 1e-4 * (1.0 + std::abs(g.dp)));
    }
  }
  // End points of the Yager complement: finite.
  for (double lambda : {0.5, 1.0, 2.0}) {
    for (double x : {0.0, 1.0}) {
      const auto g = logic::complement_grad(Complement::kYager, x, lambda);
      EXPECT_TRUE(std::isfinite(g.v) && std::isfinite(g.dx) && std::isfinite(g.dp));
      EXPECT_LE(g.dx, 0.0);
    }
  }
}

// ---- derivatives of the binary operators ----

// True near the points where the family is not differentiable.
bool near_kink(const Case& c, double x, double y, double eps) {
  switch (c.f) {
    case Family::kGodel:
      return std::abs(x - y) < eps;
    case Family::kLukasiewicz:
      return std::abs(x + y - 1.0) < eps;
    case Family::kYager: {
      const double r = std::pow(std::pow(1.0 - x, c.p) + std::pow(1.0 - y, c.p), 1.0 / c.p);
      return std::abs(r - 1.0) < eps;
    }
    case Family::kDuboisPrade:
      return std::abs(std::max(x, y) - c.p) < eps || std::abs(x - y) < eps;
    case Family::kWeber:
      return std::abs(x + y + c.p * x * y - 1.0) < eps;
    default:
      return false;
  }
}

void expect_derivatives(const Case& c, double x, double y, bool conorm) {
  const auto op = [&](double a, double b, double p) {
    return conorm ? logic::tconorm(c.f, a, b, p, c.n) : logic::tnorm(c.f, a, b, p, c.n);
  };
  const auto g =
      conorm ? logic::tconorm_grad(c.f, x, y, c.p, c.n) : logic::tnorm_grad(c.f, x, y, c.p, c.n);
  const double h = 1e-6;
  EXPECT_NEAR(g.v, op(x, y, c.p), 1e-14) << describe(c);
  const double fx = test::central_diff([&](double s) { return op(s, y, c.p); }, x, h);
  const double fy = test::central_diff([&](double s) { return op(x, s, c.p); }, y, h);
  const double tol = 2e-5;
  EXPECT_NEAR(g.dx, fx, tol * (1.0 + std::abs(fx))) << describe(c) << " x=" << x << " y=" << y;
  EXPECT_NEAR(g.dy, fy, tol * (1.0 + std::abs(fy))) << describe(c) << " x=" << x << " y=" << y;
  if (logic::uses_p(c.f)) {
    const double hp = h * std::max(1.0, std::abs(c.p));
    const double fp = test::central_diff([&](double s) { return op(x, y, s); }, c.p, hp);
    EXPECT_NEAR(g.dp, fp, tol * (1.0 + std::abs(fp))) << describe(c) << " x=" << x << " y=" << y;
  } else {
    EXPECT_EQ(g.dp, 0.0) << describe(c);
  }
}

TEST(TNormGrad, MatchesCentralDifferences) {
  const auto pts = test::random_pairs(150, 0.01, 0.99, 3);
  for (const auto& c : all_cases()) {
    int checked = 0;
    for (const auto& pt : pts) {
      const auto x = pt.first;
      const auto y = pt.second;
      if (near_kink(c, x, y, 1e-4)) continue;
      expect_derivatives(c, x, y, false);
      ++checked;
    }
    EXPECT_GT(checked, 100) << describe(c);
  }
}

TEST(TConormGrad, MatchesCentralDifferences) {
  const auto pts = test::random_pairs(100, 0.01, 0.99, 5);
  for (const auto& c : all_cases()) {
    for (const auto& pt : pts) {
      const auto x = pt.first;
      const auto y = pt.second;
      if (near_kink(c, 1.0 - x, 1.0 - y, 1e-4)) continue;
      expect_derivatives(c, x, y, true);
    }
  }
}

TEST(TNormGrad, FloatAgreesWithDouble) {
  const auto pts = test::random_pairs(100, 0.02, 0.98, 9);
  for (const auto& c : all_cases()) {
    for (const auto& pt : pts) {
      const auto x = pt.first;
      const auto y = pt.second;
      if (near_kink(c, x, y, 1e-3)) continue;
      const auto gd = logic::tnorm_grad(c.f, x, y, c.p, c.n);
      const auto gf = logic::tnorm_grad(c.f, static_cast<float>(x), static_cast<float>(y),
                                        static_cast<float>(c.p), c.n);
      const float vf = logic::tnorm(c.f, static_cast<float>(x), static_cast<float>(y),
                                    static_cast<float>(c.p), c.n);
      EXPECT_NEAR(vf, gd.v, 2e-6) << describe(c);
      EXPECT_NEAR(gf.v, gd.v, 2e-6) << describe(c);
      EXPECT_NEAR(gf.dx, gd.dx, 2e-4 * (1.0 + std::abs(gd.dx))) << describe(c);
      EXPECT_NEAR(gf.dy, gd.dy, 2e-4 * (1.0 + std::abs(gd.dy))) << describe(c);
      EXPECT_NEAR(gf.dp, gd.dp, 2e-4 * (1.0 + std::abs(gd.dp))) << describe(c);
    }
  }
}

// Everywhere on the closed square (end points, kinks, singular points): finite values and
// derivatives, in double and float.
TEST(TNormGrad, FiniteEverywhere) {
  const auto g = test::unit_grid(40);
  auto cases = all_cases();
  cases.push_back({Family::kDuboisPrade, 1e-9, 0});
  cases.push_back({Family::kYager, 0.05, 0});
  cases.push_back({Family::kDombi, 0.05, 0});
  cases.push_back({Family::kDombi, 40.0, 0});
  for (const auto& c : cases) {
    for (double x : g) {
      for (double y : g) {
        for (bool conorm : {false, true}) {
          const auto d = conorm ? logic::tconorm_grad(c.f, x, y, c.p, c.n)
                                : logic::tnorm_grad(c.f, x, y, c.p, c.n);
          const auto fl = logic::tnorm_grad(c.f, static_cast<float>(x), static_cast<float>(y),
                                            static_cast<float>(c.p), c.n);
          for (double v :
               {d.v, d.dx, d.dy, d.dp, double{fl.v}, double{fl.dx}, double{fl.dy}, double{fl.dp}}) {
            EXPECT_TRUE(std::isfinite(v)) << describe(c) << " x=" << x << " y=" << y;
          }
        }
      }
    }
  }
}

// At a kink the returned derivative is one of the one-sided derivatives.
TEST(TNormGrad, KinksGiveOneSidedDerivatives) {
  struct Kink {
    Case c;
    double x, y;
  };
  const std::vector<Kink> kinks = {
      {{Family::kGodel, 0, 0}, 0.4, 0.4},
      {{Family::kLukasiewicz, 0, 0}, 0.3, 0.7},
      {{Family::kYager, 2.0, 0}, 1.0 - 0.6, 1.0 - 0.8},
      {{Family::kDuboisPrade, 0.5, 0}, 0.5, 0.3},
      {{Family::kDuboisPrade, 0.5, 0}, 0.7, 0.7},
      {{Family::kWeber, 1.0, 0}, 0.5, 1.0 / 3.0},
      {{Family::kDombi, 2.0, 0}, 0.0, 0.6},
      {{Family::kHamacher, 0.0, 0}, 0.0, 0.6},
      {{Family::kHamacher, 0.0, 0}, 0.0, 0.0},
      {{Family::kDombi, 0.5, 0}, 0.0, 0.0},
  };
  const double h = 1e-7;
  for (const auto& kink : kinks) {
    const auto c = kink.c;
    const auto x = kink.x;
    const auto y = kink.y;
    const auto g = logic::tnorm_grad(c.f, x, y, c.p, c.n);
    EXPECT_NEAR(g.v, tn(c, x, y), 1e-15) << describe(c);
    const auto one_sided = [&](bool along_x, double s) {
      const double xa = along_x ? x + s * h : x, ya = along_x ? y : y + s * h;
      return (tn(c, xa, ya) - tn(c, x, y)) / (s * h);
    };
    for (bool along_x : {true, false}) {
      const double d = along_x ? g.dx : g.dy;
      const double coord = along_x ? x : y;
      bool matches = false;
      for (double s : {-1.0, 1.0}) {
        if (coord + s * h < 0.0 || coord + s * h > 1.0) continue;
        if (std::abs(one_sided(along_x, s) - d) < 1e-5) matches = true;
      }
      EXPECT_TRUE(matches) << describe(c) << " x=" << x << " y=" << y << " along_x=" << along_x
                           << " d=" << d;
    }
  }
  // Conventions: min and max give the derivative to x on a tie.
  EXPECT_EQ(logic::tnorm_grad(Family::kGodel, 0.4, 0.4, 0.0, 0).dx, 1.0);
  EXPECT_EQ(logic::tconorm_grad(Family::kGodel, 0.4, 0.4, 0.0, 0).dx, 1.0);
  // Dombi and Hamacher(0) grow like x along the y > 0 edge x = 0.
  EXPECT_EQ(logic::tnorm_grad(Family::kDombi, 0.0, 0.6, 2.0, 0).dx, 1.0);
  EXPECT_NEAR(logic::tnorm_grad(Family::kHamacher, 0.0, 0.6, 0.0, 0).dx, 1.0, 1e-15);
}

// ---- difference ----

TEST(Difference, IsTNormOfComplementWithDerivatives) {
  const auto pts = test::random_pairs(30, 0.02, 0.98, 13);
  for (const auto& c : all_cases()) {
    for (const auto& cl : complement_cases()) {
      const auto cc = cl.c;
      const auto lambda = cl.lambda;
      for (const auto& pt : pts) {
        const auto x = pt.first;
        const auto y = pt.second;
        const double cy = logic::complement(cc, y, lambda);
        const double v = logic::difference(c.f, cc, x, y, c.p, c.n, lambda);
        EXPECT_NEAR(v, tn(c, x, cy), 1e-15);
        if (near_kink(c, x, cy, 1e-4)) continue;
        const auto g = logic::difference_grad(c.f, cc, x, y, c.p, c.n, lambda);
        EXPECT_NEAR(g.v, v, 1e-14);
        const auto op = [&](double a, double b, double p, double l) {
          return logic::difference(c.f, cc, a, b, p, c.n, l);
        };
        const double h = 1e-6;
        const double fy = test::central_diff([&](double s) { return op(x, s, c.p, lambda); }, y, h);
        EXPECT_NEAR(g.dy, fy, 2e-5 * (1.0 + std::abs(fy))) << describe(c);
        const double fx = test::central_diff([&](double s) { return op(s, y, c.p, lambda); }, x, h);
        EXPECT_NEAR(g.dx, fx, 2e-5 * (1.0 + std::abs(fx))) << describe(c);
        if (logic::complement_uses_lambda(cc)) {
          const double fl =
              test::central_diff([&](double s) { return op(x, y, c.p, s); }, lambda, h);
          EXPECT_NEAR(g.dlambda, fl, 2e-5 * (1.0 + std::abs(fl))) << describe(c);
        } else {
          EXPECT_EQ(g.dlambda, 0.0);
        }
        if (logic::uses_p(c.f)) {
          const double hp = h * std::max(1.0, c.p);
          const double fp =
              test::central_diff([&](double s) { return op(x, y, s, lambda); }, c.p, hp);
          EXPECT_NEAR(g.dp, fp, 2e-5 * (1.0 + std::abs(fp))) << describe(c);
        }
      }
    }
  }
}

// ---- unified operator ----

TEST(Unified, OneHotReproducesProductLogic) {
  const auto g = test::unit_grid(40);
  for (double x : g) {
    for (double y : g) {
      EXPECT_NEAR(logic::unified<double>({1, 0, 0, 0}, x, y), x * y, 1e-15);
      EXPECT_NEAR(logic::unified<double>({0, 1, 0, 0}, x, y), x + y - x * y, 1e-15);
      EXPECT_NEAR(logic::unified<double>({0, 0, 1, 0}, x, y), x - x * y, 1e-15);
      EXPECT_NEAR(logic::unified<double>({0, 0, 0, 1}, x, y), y - x * y, 1e-15);
      // The same as the product-logic operators of this module.
      EXPECT_NEAR(logic::unified<double>({0, 0, 1, 0}, x, y),
                  logic::difference(Family::kProduct, Complement::kStandard, x, y, 0.0, 0, 0.0),
                  1e-15);
      EXPECT_NEAR(logic::unified<double>({0, 1, 0, 0}, x, y),
                  logic::tconorm(Family::kProduct, x, y, 0.0, 0), 1e-15);
    }
  }
}

// Along each of the 6 edges of the tetrahedron the operator is the convex combination of the
// two vertex operators, so it moves monotonically from one to the other.
TEST(Unified, MonotoneAlongTetrahedronEdges) {
  const auto g = test::unit_grid(12);
  const auto s_grid = test::unit_grid(50);
  for (std::size_t i = 0; i < 4; ++i) {
    for (std::size_t j = i + 1; j < 4; ++j) {
      for (double x : g) {
        for (double y : g) {
          std::array<double, 4> ci{}, cj{};
          ci[i] = 1.0;
          cj[j] = 1.0;
          const double vi = logic::unified(ci, x, y), vj = logic::unified(cj, x, y);
          double prev = vi;
          for (double s : s_grid) {
            std::array<double, 4> c{};
            c[i] = 1.0 - s;
            c[j] = s;
            const double v = logic::unified(c, x, y);
            EXPECT_NEAR(v, (1.0 - s) * vi + s * vj, 1e-15);
            if (vj >= vi) {
              EXPECT_GE(v, prev - 1e-15);
            } else {
              EXPECT_LE(v, prev + 1e-15);
            }
            EXPECT_GE(v, std::min(vi, vj) - 1e-15);
            EXPECT_LE(v, std::max(vi, vj) + 1e-15);
            prev = v;
          }
        }
      }
    }
  }
}

TEST(Unified, GradientMatchesCentralDifferences) {
  const std::array<double, 4> c{0.1, 0.45, 0.3, 0.15};
  for (const auto& pt : test::random_pairs(50, 0.0, 1.0, 17)) {
    const auto x = pt.first;
    const auto y = pt.second;
    const auto g = logic::unified_grad(c, x, y);
    EXPECT_NEAR(g.v, logic::unified(c, x, y), 1e-15);
    const double h = 1e-6;
    EXPECT_NEAR(g.dx, test::central_diff([&](double s) { return logic::unified(c, s, y); }, x, h),
                1e-8);
    EXPECT_NEAR(g.dy, test::central_diff([&](double s) { return logic::unified(c, x, s); }, y, h),
                1e-8);
    for (std::size_t i = 0; i < 4; ++i) {
      const double fd = test::central_diff(
          [&](double s) {
            auto cc = c;
            cc[i] = s;
            return logic::unified(cc, x, y);
          },
          c[i], h);
      EXPECT_NEAR(g.dc[i], fd, 1e-8) << i;
    }
    const std::array<float, 4> cf{0.1f, 0.45f, 0.3f, 0.15f};
    const auto gf = logic::unified_grad(cf, static_cast<float>(x), static_cast<float>(y));
    EXPECT_NEAR(gf.v, g.v, 1e-6);
    EXPECT_NEAR(gf.dx, g.dx, 1e-6);
    EXPECT_NEAR(gf.dc[1], g.dc[1], 1e-6);
  }
}

TEST(UnifiedWeights, SoftmaxOfSine) {
  const std::array<double, 4> logits{0.3, -0.2, 0.05, 0.4};
  const double t = 2.0, omega = 10.0;
  const auto c = logic::unified_weights(logits, t, omega);
  double zsum = 0.0;
  for (double l : logits) zsum += std::exp(std::sin(omega * l) * t);
  double sum = 0.0;
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(c[i], std::exp(std::sin(omega * logits[i]) * t) / zsum, 1e-15);
    sum += c[i];
  }
  EXPECT_NEAR(sum, 1.0, 1e-15);
  // A large temperature does not overflow and is nearly one-hot on the largest sin.
  const auto hot = logic::unified_weights(logits, 1e3, omega);
  double hot_sum = 0.0;
  for (double v : hot) {
    EXPECT_TRUE(std::isfinite(v));
    EXPECT_GE(v, 0.0);
    hot_sum += v;
  }
  EXPECT_NEAR(hot_sum, 1.0, 1e-15);
  std::size_t arg = 0;
  for (std::size_t i = 1; i < 4; ++i) {
    if (std::sin(omega * logits[i]) > std::sin(omega * logits[arg])) arg = i;
  }
  EXPECT_GT(hot[arg], 1.0 - 1e-12);
  const auto huge = logic::unified_weights(logits, 1e300, omega);
  for (double v : huge) EXPECT_TRUE(std::isfinite(v));
}

TEST(UnifiedWeights, VjpMatchesCentralDifferences) {
  const std::array<double, 4> logits{0.3, -0.2, 0.05, 0.4};
  const std::array<double, 4> g{0.7, -1.3, 0.2, 2.1};
  const double t = 1.7, omega = 3.0;
  const auto loss = [&](const std::array<double, 4>& l, double tt, double om) {
    const auto c = logic::unified_weights(l, tt, om);
    double s = 0.0;
    for (std::size_t i = 0; i < 4; ++i) s += g[i] * c[i];
    return s;
  };
  double dt = 0.0, domega = 0.0;
  const auto dl = logic::unified_weights_vjp(logits, t, omega, g, &dt, &domega);
  const double h = 1e-6;
  for (std::size_t i = 0; i < 4; ++i) {
    const double fd = test::central_diff(
        [&](double s) {
          auto l = logits;
          l[i] = s;
          return loss(l, t, omega);
        },
        logits[i], h);
    EXPECT_NEAR(dl[i], fd, 1e-8) << i;
  }
  EXPECT_NEAR(dt, test::central_diff([&](double s) { return loss(logits, s, omega); }, t, h), 1e-8);
  EXPECT_NEAR(domega, test::central_diff([&](double s) { return loss(logits, t, s); }, omega, h),
              1e-8);
  // The optional outputs may be omitted.
  const auto dl2 = logic::unified_weights_vjp(logits, t, omega, g);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(dl2[i], dl[i]);
}

// ---- block forms ----

TEST(Block, MatchesScalarForEveryFamily) {
  std::vector<float> x, y;
  for (const auto& pt : test::random_pairs(257, 0.0, 1.0, 19)) {
    const auto a = pt.first;
    const auto b = pt.second;
    x.push_back(static_cast<float>(a));
    y.push_back(static_cast<float>(b));
  }
  x.push_back(0.0f);
  y.push_back(0.0f);
  x.push_back(1.0f);
  y.push_back(0.3f);
  std::vector<float> out(x.size()), out2(x.size());
  for (const auto& c : all_cases()) {
    const auto p = static_cast<float>(c.p);
    logic::tnorm_block(c.f, x, y, out, p, c.n);
    logic::tconorm_block(c.f, x, y, out2, p, c.n);
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_NEAR(out[i], logic::tnorm(c.f, x[i], y[i], p, c.n), 1e-6f) << describe(c);
      EXPECT_NEAR(out2[i], logic::tconorm(c.f, x[i], y[i], p, c.n), 1e-6f) << describe(c);
    }
  }
  std::vector<float> short_out(3);
  EXPECT_THROW(logic::tnorm_block(Family::kProduct, x, y, short_out, 0.0f, 0), Error);
}

}  // namespace
}  // namespace fuzzycsg
