// Smooth unit steps: Li & Tian's H_n (eq. 2-3), the logistic H_inf (eq. 1), the Heaviside step.
#include "fuzzycsg/core/steps.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/numeric_support.hpp"

namespace fuzzycsg {
namespace {

using test::central_diff;
using test::literal_hn;

TEST(Heaviside, Values) {
  EXPECT_EQ(steps::heaviside(-1e-300), 0.0);
  EXPECT_EQ(steps::heaviside(0.0), 0.5);
  EXPECT_EQ(steps::heaviside(1e-300), 1.0);
  EXPECT_EQ(steps::heaviside(-2.0f), 0.0f);
  EXPECT_EQ(steps::hn(0, 0.0), 0.5);
  EXPECT_EQ(steps::hn(0, -3.0), 0.0);
  EXPECT_EQ(steps::hn(0, 3.0), 1.0);
}

// The recursion eq. 2 is the distribution function of a sum of n uniforms on [-1, 1]: compare
// the literal recursion with the Irwin-Hall closed form at t = (x + n) / 2.
TEST(Hn, LiteralRecursionIsScaledIrwinHall) {
  for (int n = 1; n <= 8; ++n) {
    for (int i = -220; i <= 220; ++i) {
      const double x = i * 0.0413;
      EXPECT_NEAR(literal_hn(n, x), test::irwin_hall_cdf(n, 0.5 * (x + n)), 1e-12)
          << "n=" << n << " x=" << x;
    }
  }
}

// The library's H_n against the Irwin-Hall closed form, beyond the degrees where the literal
// recursion is cheap (degrees above 8 take the general kernel, the others the unrolled one).
TEST(Hn, MatchesIrwinHallUpToDegree14) {
  for (int n = 1; n <= 14; ++n) {
    for (int i = -300; i <= 300; ++i) {
      const double x = i * (n + 1) / 280.0;
      EXPECT_NEAR(steps::hn(n, x), test::irwin_hall_cdf(n, 0.5 * (x + n)), 1e-13)
          << "n=" << n << " x=" << x;
    }
  }
}

// The unrolled fixed-degree kernel and the general one agree.
TEST(Hn, FixedAndGeneralKernelsAgree) {
  for (int n = 1; n <= 8; ++n) {
    for (int i = -200; i <= 0; ++i) {
      const double z = i * (n + 0.5) / 200.0;
      const auto a = detail::step_tail<double, true>(n, z);
      const auto b = detail::step_tail_any<double, true>(n, z);
      EXPECT_NEAR(a.cdf, b.cdf, 1e-15) << n << " " << z;
      EXPECT_NEAR(a.density, b.density, 1e-15) << n << " " << z;
      EXPECT_NEAR(a.integral, b.integral, 1e-15) << n << " " << z;
      const auto af = detail::step_tail<float, false>(n, static_cast<float>(z));
      const auto bf = detail::step_tail_any<float, false>(n, static_cast<float>(z));
      EXPECT_NEAR(af.cdf, bf.cdf, 1e-6f) << n << " " << z;
      EXPECT_NEAR(af.density, bf.density, 1e-6f) << n << " " << z;
    }
  }
}

TEST(Hn, MatchesLiteralRecursion) {
  for (int n = 0; n <= 8; ++n) {
    for (int i = -500; i <= 500; ++i) {
      const double x = i * 0.0191;  // crosses every knot region of H_8
      EXPECT_NEAR(steps::hn(n, x), literal_hn(n, x), 1e-13) << "n=" << n << " x=" << x;
    }
    // On the knots themselves (integers of the parity of n, and the others).
    for (int k = -n - 1; k <= n + 1; ++k) {
      EXPECT_NEAR(steps::hn(n, static_cast<double>(k)), literal_hn(n, k), 1e-13)
          << "n=" << n << " x=" << k;
    }
  }
}

TEST(Hn, PropertiesOneToFour) {
  for (int n = 0; n <= 16; ++n) {
    double prev = -1.0;
    for (int i = -2000; i <= 2000; ++i) {
      const double x = i * 0.01;
      const double h = steps::hn(n, x);
      EXPECT_GE(h, prev) << "monotone, n=" << n << " x=" << x;
      prev = h;
      if (x < -n || (n > 0 && x <= -n)) {
        EXPECT_EQ(h, 0.0) << "n=" << n << " x=" << x;
      }
      if (x > n || (n > 0 && x >= n)) {
        EXPECT_EQ(h, 1.0) << "n=" << n << " x=" << x;
      }
      EXPECT_NEAR(h + steps::hn(n, -x), 1.0, 1e-14) << "n=" << n << " x=" << x;
      EXPECT_GE(h, 0.0);
      EXPECT_LE(h, 1.0);
    }
    EXPECT_NEAR(steps::hn(n, 0.0), 0.5, 1e-15) << n;
    EXPECT_NEAR(steps::hn(n, 0.0f), 0.5f, 1e-6f) << n;
  }
  // Strictly increasing inside (-n, n).
  for (int n = 1; n <= 16; ++n) {
    EXPECT_LT(steps::hn(n, -n + 0.01), steps::hn(n, -n + 0.02));
    EXPECT_GT(steps::hn(n, -n + 0.01), 0.0);
  }
}

TEST(Hn, RangeForm) {
  for (int n = 1; n <= 6; ++n) {
    for (double range : {0.1, 0.5, 2.0}) {
      EXPECT_EQ(steps::hn_range(n, -range, range), 0.0);
      EXPECT_EQ(steps::hn_range(n, range, range), 1.0);
      EXPECT_GT(steps::hn_range(n, -0.99 * range, range), 0.0);
      EXPECT_LT(steps::hn_range(n, 0.99 * range, range), 1.0);
      for (double x : {-0.3, 0.01, 0.2}) {
        EXPECT_DOUBLE_EQ(steps::hn_range(n, x, range), steps::hn(n, n * x / range));
      }
    }
  }
}

TEST(Hn, DerivativesMatchCentralDifferences) {
  for (int n = 1; n <= 16; ++n) {
    for (int i = -60; i <= 60; ++i) {
      const double x = i * (n / 50.0) + 1e-3;
      const auto g = steps::hn_grad(n, x);
      EXPECT_EQ(g.v, steps::hn(n, x));
      const double fd = central_diff([n](double s) { return steps::hn(n, s); }, x, 1e-6);
      EXPECT_NEAR(g.dx, fd, 2e-6 * (1.0 + std::abs(fd))) << "n=" << n << " x=" << x;
      EXPECT_EQ(g.dp, 0.0);
    }
  }
  // H_1' jumps at +-1: away from those points the derivative is 1/2.
  EXPECT_DOUBLE_EQ(steps::hn_grad(1, 0.3).dx, 0.5);
  EXPECT_DOUBLE_EQ(steps::hn_grad(1, 1.3).dx, 0.0);
}

TEST(Hn, RangeDerivatives) {
  for (int n = 1; n <= 8; ++n) {
    for (double range : {0.2, 1.0, 3.0}) {
      for (double x : {-0.7, -0.1, 0.05, 0.13, 0.6}) {
        const auto g = steps::hn_range_grad(n, x, range);
        EXPECT_DOUBLE_EQ(g.v, steps::hn_range(n, x, range));
        const double fx =
            central_diff([&](double s) { return steps::hn_range(n, s, range); }, x, 1e-7);
        const double fr =
            central_diff([&](double r) { return steps::hn_range(n, x, r); }, range, 1e-7);
        EXPECT_NEAR(g.dx, fx, 1e-5 * (1.0 + std::abs(fx))) << n << " " << x << " " << range;
        EXPECT_NEAR(g.dp, fr, 1e-5 * (1.0 + std::abs(fr))) << n << " " << x << " " << range;
      }
    }
  }
}

// H_n is C^{n-1}: at every knot (x = -n + 2j) the one-sided Taylor coefficients agree up to
// order n-1 and differ at order n. Checked on H_n itself and on its analytic derivative. The
// coefficients are normalized by width^k / k! (numeric_support.hpp), so the order-n jump is
// about C(n, j) 0.9^n / n! (>= 1e-5 for n <= 8) against a rounding level near 1e-12.
TEST(Hn, SmoothnessAtKnots) {
  for (int n = 1; n <= 8; ++n) {
    const auto f = [n](double x) { return steps::hn(n, x); };
    const auto g = [n](double x) { return steps::hn_grad(n, x).dx; };
    for (int j = 0; j <= n; ++j) {
      const double knot = -n + 2.0 * j;
      const auto jf = test::taylor_jumps(f, knot, 1.8, n);
      for (int k = 0; k < n; ++k) {
        EXPECT_LT(jf[static_cast<std::size_t>(k)], 1e-9)
            << "n=" << n << " knot=" << knot << " order=" << k;
      }
      EXPECT_GT(jf[static_cast<std::size_t>(n)], 1e-6) << "n=" << n << " knot=" << knot;
      // Analytic derivative: C^{n-2}, jump at order n-1 (normalized by width 1.8).
      const auto jg = test::taylor_jumps(g, knot, 1.8, n - 1);
      for (int k = 0; k + 1 < n; ++k) {
        EXPECT_LT(jg[static_cast<std::size_t>(k)], 1e-9) << "n=" << n << " knot=" << knot;
      }
      EXPECT_GT(jg[static_cast<std::size_t>(n - 1)], 1e-6) << "n=" << n << " knot=" << knot;
    }
  }
}

TEST(Hn, FloatAgreesWithDouble) {
  for (int n = 0; n <= 16; ++n) {
    for (int i = -100; i <= 100; ++i) {
      const double x = i * (n + 1) / 90.0;
      const auto gd = steps::hn_grad(n, x);
      const auto gf = steps::hn_grad(n, static_cast<float>(x));
      EXPECT_NEAR(gf.v, gd.v, 2e-6) << n << " " << x;
      EXPECT_NEAR(gf.dx, gd.dx, 2e-6) << n << " " << x;
    }
  }
}

TEST(Logistic, ValuesAndDerivatives) {
  EXPECT_DOUBLE_EQ(steps::logistic(0.0, 5.0), 0.5);
  EXPECT_DOUBLE_EQ(steps::logistic(1.0, 2.0) + steps::logistic(-1.0, 2.0), 1.0);
  // Far tails do not overflow.
  EXPECT_EQ(steps::logistic(-1000.0, 10.0), 0.0);
  EXPECT_EQ(steps::logistic(1000.0, 10.0), 1.0);
  EXPECT_GT(steps::logistic(-30.0f, 1.0f), 0.0f);
  const auto far = steps::logistic_grad(-1000.0, 10.0);
  EXPECT_TRUE(std::isfinite(far.dx) && std::isfinite(far.dp));
  for (double alpha : {0.5, 3.0, 40.0}) {
    for (double x : {-0.9, -0.05, 0.0, 0.02, 0.4}) {
      const auto g = steps::logistic_grad(x, alpha);
      EXPECT_NEAR(g.v, steps::logistic(x, alpha), 1e-15);
      const double fx = central_diff([&](double s) { return steps::logistic(s, alpha); }, x, 1e-7);
      const double fa = central_diff([&](double a) { return steps::logistic(x, a); }, alpha, 1e-7);
      EXPECT_NEAR(g.dx, fx, 1e-6 * (1.0 + std::abs(fx)));
      EXPECT_NEAR(g.dp, fa, 1e-6 * (1.0 + std::abs(fa)));
      const auto gf = steps::logistic_grad(static_cast<float>(x), static_cast<float>(alpha));
      EXPECT_NEAR(gf.v, g.v, 1e-6);
      EXPECT_NEAR(gf.dx, g.dx, 1e-5 * (1.0 + std::abs(g.dx)));
    }
  }
}

}  // namespace
}  // namespace fuzzycsg
