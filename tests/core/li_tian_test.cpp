// Li & Tian 2008: the Bézier operators B_n (eq. 4-7), the smooth absolute values (eq. 8-11),
// the smooth minima (eq. 12-13) and the shape-preserving operators AND_{n,delta} (eq. 14-20)
// and hat-AND_{n,delta} (eq. 21-25).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "core/numeric_support.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/steps.hpp"

namespace fuzzycsg {
namespace {

using test::central_diff;
using test::literal_hn;
using test::literal_upper_abs;

// ---- Bézier operators ----

double binomial(int n, int k) {
  double c = 1.0;
  for (int i = 0; i < k; ++i) c = c * (n - i) / (i + 1);
  return c;
}
double bernstein(int n, int k, double t) {
  return binomial(n, k) * std::pow(1.0 - t, n - k) * std::pow(t, k);
}
// Eq. 4 term by term.
double literal_bezier(int n, double x, double y) {
  double s = 0.0;
  for (int k = 1; k <= n; ++k)
    s += static_cast<double>(k) / n * bernstein(n, k, x) * bernstein(n, k, y);
  for (int j = 1; j <= n; ++j) {
    for (int i = j + 1; i <= n; ++i) {
      s += static_cast<double>(j) / n *
           (bernstein(n, i, x) * bernstein(n, j, y) + bernstein(n, i, y) * bernstein(n, j, x));
    }
  }
  return s;
}

TEST(Bezier, ClosedFormsEq5To7) {
  const auto g = test::unit_grid(50);
  for (double x : g) {
    for (double y : g) {
      const double xb = 1.0 - x, yb = 1.0 - y;
      EXPECT_NEAR(logic::bezier(1, x, y), x * y, 1e-15);
      EXPECT_NEAR(logic::bezier(2, x, y), x * y * (1.0 + xb * yb), 1e-15);
      EXPECT_NEAR(logic::bezier(3, x, y), x * y * (1.0 + xb * yb * (1.0 + x * y + xb * yb)), 1e-15);
    }
  }
}

TEST(Bezier, MatchesLiteralEq4) {
  for (int n = 1; n <= 12; ++n) {
    for (const auto& pt : test::random_pairs(60, 0.0, 1.0, 23)) {
      const auto x = pt.first;
      const auto y = pt.second;
      EXPECT_NEAR(logic::bezier(n, x, y), literal_bezier(n, x, y), 1e-14) << n;
    }
  }
}

TEST(Bezier, StatedProperties) {
  const auto g = test::unit_grid(60);
  for (int n = 1; n <= 20; ++n) {
    EXPECT_NEAR(logic::bezier(n, 1.0, 1.0), 1.0, 1e-14);
    for (double x : g) {
      EXPECT_NEAR(logic::bezier(n, x, 1.0), x, 1e-14) << n;
      EXPECT_NEAR(logic::bezier(n, 1.0, x), x, 1e-14) << n;
      EXPECT_NEAR(logic::bezier(n, x, 0.0), 0.0, 1e-15) << n;
      EXPECT_NEAR(logic::bezier(n, 0.0, x), 0.0, 1e-15) << n;
      for (double y : g) {
        const double b = logic::bezier(n, x, y);
        EXPECT_LE(b, std::min(x, y) + 1e-15) << n << " " << x << " " << y;
        EXPECT_NEAR(b, logic::bezier(n, y, x), 1e-15);
        EXPECT_LE(b, logic::bezier(n + 1, x, y) + 1e-15) << n << " " << x << " " << y;
      }
    }
  }
  // Strictly between the product and min inside the square for n >= 2.
  EXPECT_GT(logic::bezier(2, 0.5, 0.5), 0.25);
  EXPECT_LT(logic::bezier(2, 0.5, 0.5), 0.5);
}

// sup_n B_n = min; also exercises the heap path of large degrees.
TEST(Bezier, LargeDegreeApproachesMin) {
  for (const auto& pt : test::random_pairs(40, 0.0, 1.0, 29)) {
    const auto x = pt.first;
    const auto y = pt.second;
    EXPECT_NEAR(logic::bezier(400, x, y), std::min(x, y), 0.03);
    EXPECT_LE(logic::bezier(400, x, y), std::min(x, y) + 1e-13);
    EXPECT_GE(logic::bezier(400, x, y), logic::bezier(100, x, y) - 1e-14);
  }
}

TEST(Bezier, DerivativesMatchCentralDifferences) {
  for (int n : {1, 2, 3, 4, 5, 8, 12, 40}) {
    for (const auto& pt : test::random_pairs(40, 0.0, 1.0, 31)) {
      const auto x = pt.first;
      const auto y = pt.second;
      const auto g = logic::bezier_grad(n, x, y);
      EXPECT_NEAR(g.v, logic::bezier(n, x, y), 1e-15);
      const double fx = central_diff([&](double s) { return logic::bezier(n, s, y); }, x, 1e-6);
      const double fy = central_diff([&](double s) { return logic::bezier(n, x, s); }, y, 1e-6);
      EXPECT_NEAR(g.dx, fx, 1e-7 * (1.0 + std::abs(fx))) << n;
      EXPECT_NEAR(g.dy, fy, 1e-7 * (1.0 + std::abs(fy))) << n;
      const auto gf = logic::bezier_grad(n, static_cast<float>(x), static_cast<float>(y));
      EXPECT_NEAR(gf.v, g.v, 2e-6);
      EXPECT_NEAR(gf.dx, g.dx, 1e-4 * (1.0 + std::abs(g.dx)));
    }
  }
}

// ---- smooth absolute values ----

TEST(UpperAbs, MatchesLiteralEq8) {
  for (int n = 0; n <= 8; ++n) {
    for (int i = -500; i <= 500; ++i) {
      const double x = i * 0.0193;
      EXPECT_NEAR(logic::upper_abs(n, x), literal_upper_abs(n, x), 1e-12) << n << " " << x;
    }
    for (int k = -n - 1; k <= n + 1; ++k) {
      EXPECT_NEAR(logic::upper_abs(n, static_cast<double>(k)), literal_upper_abs(n, k), 1e-12);
    }
  }
}

// d|x|_n/dx = 2 H_n(x) - 1, checked on the literal recursions.
TEST(UpperAbs, DerivativeIsTwoHnMinusOne) {
  for (int n = 1; n <= 7; ++n) {
    for (int i = -70; i <= 70; ++i) {
      const double x = i * (n + 1) / 70.0 + 1e-3;
      const double fd = central_diff([n](double s) { return literal_upper_abs(n, s); }, x, 1e-5);
      EXPECT_NEAR(fd, 2.0 * literal_hn(n, x) - 1.0, 1e-7) << n << " " << x;
      EXPECT_NEAR(logic::upper_abs_grad(n, x).dx, 2.0 * steps::hn(n, x) - 1.0, 1e-14);
    }
  }
}

TEST(UpperAbs, Proposition31) {
  for (int n = 0; n <= 16; ++n) {
    for (int i = -3000; i <= 3000; ++i) {
      const double x = i * 0.01;
      const double a = logic::upper_abs(n, x);
      EXPECT_GE(a, std::abs(x)) << n << " " << x;
      if (std::abs(x) >= n) {
        EXPECT_EQ(a, std::abs(x)) << n << " " << x;
      }
      // Strictly above inside (near +-n the gap, of order (n - |x|)^(n+2), is below rounding).
      if (2.0 * std::abs(x) < n) {
        EXPECT_GT(a, std::abs(x)) << n << " " << x;
      }
      EXPECT_NEAR(a, logic::upper_abs(n, -x), 1e-14);
    }
  }
}

TEST(LowerAbs, Eq10AndBounds) {
  for (int n = 0; n <= 8; ++n) {
    for (int i = -500; i <= 500; ++i) {
      const double x = i * 0.0193;
      const double a = logic::lower_abs(n, x);
      EXPECT_NEAR(a, 2.0 * x * literal_hn(n, x) - x, 2e-12 * (1.0 + std::abs(x))) << n << " " << x;
      EXPECT_LE(a, std::abs(x) + 1e-15);
      EXPECT_GE(a, 0.0);
      if (std::abs(x) >= n) {
        EXPECT_NEAR(a, std::abs(x), 1e-15);
      }
    }
  }
}

TEST(ScaledAbs, Eq9And11) {
  for (int n = 1; n <= 6; ++n) {
    for (double delta : {0.1, 0.7, 1.5}) {
      for (int i = -100; i <= 100; ++i) {
        const double x = i * 0.021;
        const double w = n * x / delta;
        if (std::abs(x) >= delta) {
          EXPECT_EQ(logic::upper_abs(n, x, delta), std::abs(x));
          EXPECT_EQ(logic::lower_abs(n, x, delta), std::abs(x));
        }
        // The literal recursions lose accuracy far outside [-n, n] (cancellation), where the
        // library returns |x| exactly; compare on [-n - 2, n + 2].
        if (std::abs(w) > n + 2) continue;
        const double tol = 2e-12 * (1.0 + std::abs(w));
        EXPECT_NEAR(logic::upper_abs(n, x, delta), delta / n * literal_upper_abs(n, w), tol);
        EXPECT_NEAR(logic::lower_abs(n, x, delta), delta / n * (2.0 * w * literal_hn(n, w) - w),
                    tol);
      }
    }
  }
  // Degree 0 is the absolute value.
  EXPECT_EQ(logic::upper_abs(0, -0.3, 0.5), 0.3);
  EXPECT_EQ(logic::lower_abs(0, -0.3, 0.5), 0.3);
}

TEST(SmoothAbs, DerivativesMatchCentralDifferences) {
  for (int n = 1; n <= 8; ++n) {
    for (double delta : {0.15, 1.0, 1.6}) {
      for (int i = -40; i <= 40; ++i) {
        const double x = i * 0.0517 * delta + 1e-3;
        const double h = 1e-6;
        const auto up = logic::upper_abs_grad(n, x, delta);
        const auto lo = logic::lower_abs_grad(n, x, delta);
        EXPECT_NEAR(up.v, logic::upper_abs(n, x, delta), 1e-15);
        EXPECT_NEAR(lo.v, logic::lower_abs(n, x, delta), 1e-15);
        const auto fu = [&](double s, double d) { return logic::upper_abs(n, s, d); };
        const auto fl = [&](double s, double d) { return logic::lower_abs(n, s, d); };
        const double tol = 1e-5;
        const double ux = central_diff([&](double s) { return fu(s, delta); }, x, h);
        const double ud = central_diff([&](double d) { return fu(x, d); }, delta, h);
        const double lx = central_diff([&](double s) { return fl(s, delta); }, x, h);
        const double ld = central_diff([&](double d) { return fl(x, d); }, delta, h);
        EXPECT_NEAR(up.dx, ux, tol * (1.0 + std::abs(ux))) << n << " " << delta << " " << x;
        EXPECT_NEAR(up.dp, ud, tol * (1.0 + std::abs(ud))) << n << " " << delta << " " << x;
        EXPECT_NEAR(lo.dx, lx, tol * (1.0 + std::abs(lx))) << n << " " << delta << " " << x;
        EXPECT_NEAR(lo.dp, ld, tol * (1.0 + std::abs(ld))) << n << " " << delta << " " << x;
        // Unscaled forms.
        const auto u1 = logic::upper_abs_grad(n, x * n);
        const auto l1 = logic::lower_abs_grad(n, x * n);
        EXPECT_NEAR(u1.dx, central_diff([&](double s) { return logic::upper_abs(n, s); }, x * n, h),
                    tol * (1.0 + std::abs(u1.dx)));
        EXPECT_NEAR(l1.dx, central_diff([&](double s) { return logic::lower_abs(n, s); }, x * n, h),
                    tol * (1.0 + std::abs(l1.dx)));
        // Float.
        const auto uf = logic::upper_abs_grad(n, static_cast<float>(x), static_cast<float>(delta));
        const auto lf = logic::lower_abs_grad(n, static_cast<float>(x), static_cast<float>(delta));
        EXPECT_NEAR(uf.v, up.v, 2e-6 * (1.0 + up.v));
        EXPECT_NEAR(uf.dp, up.dp, 1e-4 * (1.0 + std::abs(up.dp)));
        EXPECT_NEAR(lf.dx, lo.dx, 1e-4 * (1.0 + std::abs(lo.dx)));
      }
    }
  }
}

// |x|_n is C^n and hat|x|_n is C^{n-1}: the one-sided Taylor coefficients at the knots
// x = -n + 2j agree up to those orders, and differ at the next one (for hat|x|_n at the knots
// other than 0, where the factor x of x (2 H_n - 1) cancels the jump).
TEST(SmoothAbs, SmoothnessAtKnots) {
  for (int n = 1; n <= 7; ++n) {
    const auto up = [n](double x) { return logic::upper_abs(n, x); };
    const auto up_dx = [n](double x) { return logic::upper_abs_grad(n, x).dx; };
    const auto lo = [n](double x) { return logic::lower_abs(n, x); };
    const auto lo_dx = [n](double x) { return logic::lower_abs_grad(n, x).dx; };
    for (int j = 0; j <= n; ++j) {
      const double knot = -n + 2.0 * j;
      const auto ju = test::taylor_jumps(up, knot, 1.8, n + 1);
      const auto jud = test::taylor_jumps(up_dx, knot, 1.8, n);
      for (int k = 0; k <= n; ++k) {
        EXPECT_LT(ju[static_cast<std::size_t>(k)], 1e-8) << n << " " << knot << " " << k;
      }
      for (int k = 0; k < n; ++k) {
        EXPECT_LT(jud[static_cast<std::size_t>(k)], 1e-8) << n << " " << knot << " " << k;
      }
      EXPECT_GT(ju[static_cast<std::size_t>(n + 1)], 1e-6) << n << " " << knot;
      EXPECT_GT(jud[static_cast<std::size_t>(n)], 1e-6) << n << " " << knot;

      const auto jl = test::taylor_jumps(lo, knot, 1.8, n + 1);
      const auto jld = test::taylor_jumps(lo_dx, knot, 1.8, n);
      for (int k = 0; k < n; ++k) {
        EXPECT_LT(jl[static_cast<std::size_t>(k)], 1e-8) << n << " " << knot << " " << k;
      }
      for (int k = 0; k + 1 < n; ++k) {
        EXPECT_LT(jld[static_cast<std::size_t>(k)], 1e-8) << n << " " << knot << " " << k;
      }
      if (knot != 0.0) {
        EXPECT_GT(jl[static_cast<std::size_t>(n)], 1e-6) << n << " " << knot;
        EXPECT_GT(jld[static_cast<std::size_t>(n - 1)], 1e-6) << n << " " << knot;
      }
    }
  }
}

// ---- smooth minima ----

TEST(SmoothMin, Eq12And13WithDerivatives) {
  for (int n : {1, 2, 4}) {
    for (double delta : {0.2, 1.5}) {
      for (const auto& pt : test::random_pairs(40, -0.2, 1.2, 37)) {
        const auto x = pt.first;
        const auto y = pt.second;
        EXPECT_NEAR(logic::smooth_min(n, x, y, delta),
                    0.5 * (x + y - logic::upper_abs(n, x - y, delta)), 1e-15);
        EXPECT_NEAR(logic::smooth_min_hat(n, x, y, delta),
                    0.5 * (x + y - logic::lower_abs(n, x - y, delta)), 1e-15);
        EXPECT_LE(logic::smooth_min(n, x, y, delta), std::min(x, y) + 1e-15);
        EXPECT_GE(logic::smooth_min_hat(n, x, y, delta), std::min(x, y) - 1e-15);
        const double h = 1e-6;
        for (int which = 0; which < 2; ++which) {
          const auto f = [&](double a, double b, double d) {
            return which == 0 ? logic::smooth_min(n, a, b, d) : logic::smooth_min_hat(n, a, b, d);
          };
          const auto g = which == 0 ? logic::smooth_min_grad(n, x, y, delta)
                                    : logic::smooth_min_hat_grad(n, x, y, delta);
          EXPECT_NEAR(g.v, f(x, y, delta), 1e-15);
          const double fx = central_diff([&](double s) { return f(s, y, delta); }, x, h);
          const double fy = central_diff([&](double s) { return f(x, s, delta); }, y, h);
          const double fd = central_diff([&](double s) { return f(x, y, s); }, delta, h);
          EXPECT_NEAR(g.dx, fx, 1e-5 * (1.0 + std::abs(fx)));
          EXPECT_NEAR(g.dy, fy, 1e-5 * (1.0 + std::abs(fy)));
          EXPECT_NEAR(g.dp, fd, 1e-5 * (1.0 + std::abs(fd)));
        }
      }
    }
  }
}

// ---- AND_{n,delta} and hat-AND_{n,delta} ----

using AndFn = std::function<double(int, double, double, double)>;
struct Variant {
  const char* name;
  AndFn f;
  logic::Family family;
};
std::vector<Variant> variants() {
  return {
      {"and", [](int n, double x, double y, double d) { return logic::li_tian_and(n, x, y, d); },
       logic::Family::kLiTian},
      {"hat-and",
       [](int n, double x, double y, double d) { return logic::li_tian_hat_and(n, x, y, d); },
       logic::Family::kLiTianHat},
  };
}
const std::vector<int> kDegrees = {1, 2, 3, 5, 8};
const std::vector<double> kDeltas = {0.05, 0.2, 0.5, 1.0, 1.5, 3.0};

// Identity and dominance laws: AND(1, x) = AND(x, 1) = x, AND(0, x) = AND(x, 0) = 0, for every
// delta (the paper's figures use delta = 1.5, 1.0, 0.5).
TEST(LiTianAnd, IdentityAndDominanceLaws) {
  const auto g = test::unit_grid(200);
  for (const auto& var : variants()) {
    for (int n : kDegrees) {
      for (double d : kDeltas) {
        for (double x : g) {
          EXPECT_NEAR(var.f(n, 1.0, x, d), x, 1e-14) << var.name << " n=" << n << " d=" << d;
          EXPECT_NEAR(var.f(n, x, 1.0, d), x, 1e-14) << var.name << " n=" << n << " d=" << d;
          EXPECT_NEAR(var.f(n, 0.0, x, d), 0.0, 1e-14) << var.name << " n=" << n << " d=" << d;
          EXPECT_NEAR(var.f(n, x, 0.0, d), 0.0, 1e-14) << var.name << " n=" << n << " d=" << d;
        }
        EXPECT_NEAR(var.f(n, 1.0, 1.0, d), 1.0, 1e-14);
        EXPECT_NEAR(var.f(n, 0.0, 0.0, d), 0.0, 1e-14);
      }
    }
  }
  // Degree 0 is min.
  EXPECT_EQ(logic::li_tian_and(0, 0.3, 0.6, 0.5), 0.3);
  EXPECT_EQ(logic::li_tian_hat_and(0, 0.7, 0.6, 0.5), 0.6);
}

// The Coons correction as printed (eq. 19 with alpha = -|0|_{n,delta}; hat-AND without corner
// term) breaks those laws; the general corner term is needed.
TEST(LiTianAnd, PrintedCornerTermBreaksBoundaryLaws) {
  const int n = 2;
  const auto c0 = [&](double s, double d) { return 0.5 * (s - logic::upper_abs(n, s, d)); };
  const auto printed = [&](double x, double y, double d, double alpha) {
    const double s1 = (1 - y) * c0(x, d) + y * c0(1 - x, d);
    const double s2 = (1 - x) * c0(y, d) + x * c0(1 - y, d);
    const double s3 = alpha * (1 - x - y + 2 * x * y);
    return logic::smooth_min(n, x, y, d) - (s1 + s2 - s3);
  };
  for (double d : {0.5, 1.0, 1.5}) {
    const double a0 = logic::upper_abs(n, 0.0, d);
    // alpha = -|0|: AND(0, 0) = -|0| / 2 instead of 0.
    EXPECT_NEAR(printed(0.0, 0.0, d, -a0), -0.5 * a0, 1e-15);
    EXPECT_GT(std::abs(printed(0.0, 0.0, d, -a0)), 0.1 * d);
    // alpha = -|0| / 2 fixes it for delta <= 1 ...
    EXPECT_NEAR(printed(0.0, 0.0, d, -0.5 * a0), 0.0, 1e-15);
    EXPECT_NEAR(printed(0.0, 0.0, d, -0.5 * a0), logic::li_tian_and(n, 0.0, 0.0, d), 1e-15);
    if (d <= 1.0) {
      EXPECT_NEAR(printed(1.0, 0.0, d, -0.5 * a0), 0.0, 1e-15);
    } else {
      // ... but not for delta > 1, where the corners (1, 0), (0, 1) are not 0.
      EXPECT_GT(std::abs(printed(1.0, 0.0, d, -0.5 * a0)), 1e-3);
    }
    EXPECT_NEAR(logic::li_tian_and(n, 1.0, 0.0, d), 0.0, 1e-15);
  }
  // hat-AND without a corner term at delta = 1.5: AND(1, 0) = -H_n(-n / delta) != 0.
  const double d = 1.5;
  const auto hc0 = [&](double s) { return s * steps::hn(n, -n * s / d); };
  const auto hat_printed = [&](double x, double y) {
    return logic::smooth_min_hat(n, x, y, d) -
           ((1 - y) * hc0(x) + y * hc0(1 - x) + (1 - x) * hc0(y) + x * hc0(1 - y));
  };
  EXPECT_NEAR(hat_printed(1.0, 0.0), -steps::hn(n, -n / d), 1e-15);
  EXPECT_GT(std::abs(hat_printed(1.0, 0.0)), 1e-3);
  EXPECT_NEAR(logic::li_tian_hat_and(n, 1.0, 0.0, d), 0.0, 1e-15);
  // For delta <= 1 the printed hat-AND and ours coincide.
  for (const auto& pt : test::random_pairs(50, 0.0, 1.0, 41)) {
    const auto x = pt.first;
    const auto y = pt.second;
    const double dd = 0.7;
    const auto hc = [&](double s) { return s * steps::hn(n, -n * s / dd); };
    const double v = logic::smooth_min_hat(n, x, y, dd) -
                     ((1 - y) * hc(x) + y * hc(1 - x) + (1 - x) * hc(y) + x * hc(1 - y));
    EXPECT_NEAR(logic::li_tian_hat_and(n, x, y, dd), v, 1e-14);
  }
}

// Approximation of min: for both operators and every delta > 0, n >= 1,
//   |AND(x, y) - min(x, y)| <= |0|_{n,delta} = (delta / n) |0|_n <= delta / 2.
// (For AND: the smooth-min error is in [-|0|/2, 0] and the Coons patch in [-|0|, |0|/2]. For
// hat-AND: by Markov's inequality w H_n(-w) <= E[S_n^-] = |0|_n / 2, which bounds the boundary
// curves and corners by |0|_{n,delta} / 2.) Also |0|_n = E|S_n| <= sqrt(n / 3).
TEST(LiTianAnd, WithinZeroAbsOfMin) {
  const auto g = test::unit_grid(100);
  for (int n : kDegrees) {
    EXPECT_LE(logic::upper_abs(n, 0.0), std::sqrt(n / 3.0) + 1e-15);
    EXPECT_LE(logic::upper_abs(n, 0.0) / n, 0.5 + 1e-15);
    for (double d : kDeltas) {
      const double bound = logic::upper_abs(n, 0.0, d);
      EXPECT_LE(bound, d / 2 + 1e-15);
      for (const auto& var : variants()) {
        double worst = 0.0;
        for (double x : g) {
          for (double y : g) worst = std::max(worst, std::abs(var.f(n, x, y, d) - std::min(x, y)));
        }
        EXPECT_LE(worst, bound + 1e-14) << var.name << " n=" << n << " d=" << d;
        EXPECT_GT(worst, 0.0);
      }
    }
  }
}

// Observed range: 0 <= AND <= min(x, y) (it never blends above min), 0 <= hat-AND <= 1.
TEST(LiTianAnd, Range) {
  const auto g = test::unit_grid(100);
  for (int n : kDegrees) {
    for (double d : kDeltas) {
      for (double x : g) {
        for (double y : g) {
          const double a = logic::li_tian_and(n, x, y, d);
          EXPECT_GE(a, -1e-15) << n << " " << d << " " << x << " " << y;
          EXPECT_LE(a, std::min(x, y) + 1e-15) << n << " " << d << " " << x << " " << y;
          const double b = logic::li_tian_hat_and(n, x, y, d);
          EXPECT_GE(b, -1e-15) << n << " " << d << " " << x << " " << y;
          EXPECT_LE(b, 1.0 + 1e-15) << n << " " << d << " " << x << " " << y;
        }
      }
    }
  }
}

// hat-AND is exactly min on {delta <= x, y <= 1 - delta, |x - y| >= delta}, a region of area
// (1 - 3 delta)^2 for delta <= 1/3 (the paper's statement); AND is not min anywhere inside.
TEST(LiTianHatAnd, EqualsMinOnPreservedRegion) {
  const int k = 300;
  const auto g = test::unit_grid(k);
  for (int n : {1, 2, 3, 6}) {
    for (double d : {0.05, 0.1, 0.2, 0.3}) {
      int in_region = 0;
      for (double x : g) {
        for (double y : g) {
          const bool region = x >= d && x <= 1 - d && y >= d && y <= 1 - d && std::abs(x - y) >= d;
          if (!region) continue;
          ++in_region;
          EXPECT_NEAR(logic::li_tian_hat_and(n, x, y, d), std::min(x, y), 1e-15)
              << n << " " << d << " " << x << " " << y;
          if (x > 0.0 && x < 1.0 && y > 0.0 && y < 1.0) {
            EXPECT_LT(logic::li_tian_and(n, x, y, d), std::min(x, y)) << n << " " << d;
          }
        }
      }
      const double area = static_cast<double>(in_region) / ((k + 1.0) * (k + 1.0));
      EXPECT_NEAR(area, (1 - 3 * d) * (1 - 3 * d), 0.02) << d;
    }
  }
}

// Knots of AND(., y0) in (0, 1) with their distance to the nearest other knot (or to 0, 1).
struct Knot {
  double x;
  double width;
  bool from_difference;  // a knot of |x - y0|
};
std::vector<Knot> knots_along_line(int n, double delta, double y0) {
  std::set<double> all;
  std::set<double> diff;
  for (int j = 0; j <= n; ++j) {
    const double s = delta / n * (-n + 2.0 * j);
    diff.insert(y0 + s);
    all.insert(y0 + s);
    all.insert(s);
    all.insert(1.0 - s);
  }
  all.insert(0.0);
  all.insert(1.0);
  std::vector<double> sorted(all.begin(), all.end());
  std::vector<Knot> out;
  for (std::size_t i = 1; i + 1 < sorted.size(); ++i) {
    const double x = sorted[i];
    if (x <= 0.0 || x >= 1.0) continue;
    const double w = 0.9 * std::min(x - sorted[i - 1], sorted[i + 1] - x);
    if (w < 0.02) continue;
    out.push_back({x, w, diff.count(x) > 0});
  }
  return out;
}

// AND_{n,delta} is C^n and hat-AND_{n,delta} C^{n-1}: along lines y = y0 the one-sided Taylor
// coefficients at every knot agree up to those orders and jump at the next one (hat-AND on the
// diagonal excepted: x (2 H_n - 1) hides the jump at x = y0). The same on the analytic dx.
TEST(LiTianAnd, SmoothnessAcrossKnots) {
  struct Setup {
    int n;
    double delta, y0;
  };
  const std::vector<Setup> setups = {{1, 0.3, 0.5}, {2, 0.3, 0.5}, {3, 0.3, 0.5},  {4, 0.4, 0.37},
                                     {4, 0.4, 0.5}, {2, 1.5, 0.5}, {3, 0.25, 0.61}};
  for (const auto& setup : setups) {
    const auto n = setup.n;
    const auto delta = setup.delta;
    const auto y0 = setup.y0;
    const auto knots = knots_along_line(n, delta, y0);
    ASSERT_GE(knots.size(), 1u);
    for (const auto& knot : knots) {
      for (int hat = 0; hat < 2; ++hat) {
        const int smooth = hat ? n - 1 : n;  // claimed C^smooth
        const auto f = [&](double x) {
          return hat ? logic::li_tian_hat_and(n, x, y0, delta)
                     : logic::li_tian_and(n, x, y0, delta);
        };
        const auto fdx = [&](double x) {
          return hat ? logic::li_tian_hat_and_grad(n, x, y0, delta).dx
                     : logic::li_tian_and_grad(n, x, y0, delta).dx;
        };
        const auto jf = test::taylor_jumps(f, knot.x, knot.width, n + 1);
        const auto jd = test::taylor_jumps(fdx, knot.x, knot.width, n);
        const std::string where = std::string(hat ? "hat" : "and") + " n=" + std::to_string(n) +
                                  " d=" + std::to_string(delta) + " knot=" + std::to_string(knot.x);
        for (int k = 0; k <= smooth; ++k) {
          EXPECT_LT(jf[static_cast<std::size_t>(k)], 1e-10) << where << " order " << k;
        }
        for (int k = 0; k < smooth; ++k) {
          EXPECT_LT(jd[static_cast<std::size_t>(k)], 1e-10) << where << " dx order " << k;
        }
        const bool hidden = hat && knot.from_difference && std::abs(knot.x - y0) < 1e-12;
        if (!hidden) {
          EXPECT_GT(jf[static_cast<std::size_t>(smooth + 1)], 1e-9) << where;
          EXPECT_GT(jd[static_cast<std::size_t>(smooth)], 1e-9) << where;
        }
      }
    }
  }
}

TEST(LiTianAnd, DerivativesMatchCentralDifferences) {
  const auto pts = test::random_pairs(80, 0.0, 1.0, 43);
  for (const auto& var : variants()) {
    for (int n : {1, 2, 3, 5}) {
      // (Not delta = 1 for hat-AND: its corner value H_n(-n / delta) is only C^{n-1} in delta
      // there, so at n = 1 the derivative in delta jumps at delta = 1.)
      for (double d : {0.1, 0.5, 0.8, 1.5}) {
        for (const auto& pt : pts) {
          const auto x = pt.first;
          const auto y = pt.second;
          const auto g = var.family == logic::Family::kLiTian
                             ? logic::li_tian_and_grad(n, x, y, d)
                             : logic::li_tian_hat_and_grad(n, x, y, d);
          EXPECT_NEAR(g.v, var.f(n, x, y, d), 1e-15);
          const double h = 1e-6;
          const double fx = central_diff([&](double s) { return var.f(n, s, y, d); }, x, h);
          const double fy = central_diff([&](double s) { return var.f(n, x, s, d); }, y, h);
          const double fd = central_diff([&](double s) { return var.f(n, x, y, s); }, d, h);
          const std::string where =
              std::string(var.name) + " n=" + std::to_string(n) + " d=" + std::to_string(d);
          EXPECT_NEAR(g.dx, fx, 2e-5 * (1.0 + std::abs(fx))) << where;
          EXPECT_NEAR(g.dy, fy, 2e-5 * (1.0 + std::abs(fy))) << where;
          EXPECT_NEAR(g.dp, fd, 2e-5 * (1.0 + std::abs(fd))) << where;
          // Through the generic entry points.
          const auto t = logic::tnorm_grad(var.family, x, y, d, n);
          EXPECT_EQ(t.v, g.v);
          EXPECT_EQ(t.dp, g.dp);
        }
      }
    }
  }
}

}  // namespace
}  // namespace fuzzycsg
