// The clamped uniform B-spline basis of the fuzzy spline node: partition of unity and range
// over random points inside and outside the box (1D, and tensor products in 2D and 3D), against
// the literal Cox-de Boor recursion on an explicitly built knot vector and closed forms, and the
// support test that bounds and simplification rely on.
#include "fuzzycsg/core/bspline.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace fuzzycsg {
namespace {

// The knot vector written out as the definition says: d + 1 copies of 0, the interior knots
// 1 .. m - 1, d + 1 copies of m (m = n - d).
std::vector<double> clamped_knots(int n, int d) {
  std::vector<double> t;
  for (int j = 0; j <= d; ++j) t.push_back(0);
  for (int j = 1; j < n - d; ++j) t.push_back(j);
  for (int j = 0; j <= d; ++j) t.push_back(n - d);
  return t;
}

// Cox-de Boor, literally: N_{i,0} is the indicator of [t_i, t_{i+1}) (the last non-empty span
// closed), N_{i,p} = (u - t_i) / (t_{i+p} - t_i) N_{i,p-1}
//                  + (t_{i+p+1} - u) / (t_{i+p+1} - t_{i+1}) N_{i+1,p-1}, with 0/0 = 0.
double cox_de_boor(const std::vector<double>& t, int i, int p, double u) {
  if (p == 0) {
    const double m = t.back();
    if (u == m)
      return t[static_cast<std::size_t>(i)] < m && t[static_cast<std::size_t>(i) + 1] == m;
    return t[static_cast<std::size_t>(i)] <= u && u < t[static_cast<std::size_t>(i) + 1];
  }
  const auto at = [&](int j) { return t[static_cast<std::size_t>(j)]; };
  double v = 0.0;
  if (at(i + p) > at(i)) v += (u - at(i)) / (at(i + p) - at(i)) * cox_de_boor(t, i, p - 1, u);
  if (at(i + p + 1) > at(i + 1)) {
    v += (at(i + p + 1) - u) / (at(i + p + 1) - at(i + 1)) * cox_de_boor(t, i + 1, p - 1, u);
  }
  return v;
}

// The parameter of x on the axis [lo, hi] for n functions of degree d, as the node maps it.
double param(double x, double lo, double hi, int n, int d) {
  return bspline::parameter<double>(x, lo, (n - d) / (hi - lo), n - d);
}

TEST(BSpline, KnotsAreClamped) {
  for (int d = 1; d <= bspline::kMaxDegree; ++d) {
    for (int n = d + 1; n <= d + 6; ++n) {
      const std::vector<double> t = clamped_knots(n, d);
      ASSERT_EQ(t.size(), static_cast<std::size_t>(n + d + 1));
      for (int j = 0; j <= n + d; ++j)
        EXPECT_EQ(bspline::knot(j, n, d), t[static_cast<std::size_t>(j)]);
    }
  }
}

TEST(BSpline, PartitionOfUnityOnOneAxisInsideAndOutside) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> x(-2.0, 2.5);
  for (int d = 1; d <= bspline::kMaxDegree; ++d) {
    for (int n = d + 1; n <= d + 7; ++n) {
      for (int s = 0; s < 400; ++s) {
        // The axis [-0.7, 1.3]; a quarter of the points outside it, and the ends themselves.
        const double p = s == 0 ? -0.7 : s == 1 ? 1.3 : x(rng);
        const double u = param(p, -0.7, 1.3, n, d);
        double sum = 0.0;
        for (int i = 0; i < n; ++i) {
          const double b = bspline::basis<double>(i, n, d, u);
          ASSERT_GE(b, 0.0) << "d " << d << " n " << n << " i " << i << " x " << p;
          ASSERT_LE(b, 1.0) << "d " << d << " n " << n << " i " << i << " x " << p;
          sum += b;
        }
        ASSERT_NEAR(sum, 1.0, 1e-14) << "d " << d << " n " << n << " x " << p;
        // In float as the kernel computes it.
        float sumf = 0.0f;
        const auto uf = static_cast<float>(u);
        for (int i = 0; i < n; ++i) {
          const float b = bspline::basis<float>(i, n, d, uf);
          ASSERT_GE(b, 0.0f);
          ASSERT_LE(b, 1.0f);
          sumf += b;
        }
        ASSERT_NEAR(sumf, 1.0f, 1e-6f);
      }
    }
  }
}

// Tensor products over random boxes and points (a third of them outside the box).
TEST(BSpline, TensorProductsArePartitionsOfUnityIn2DAnd3D) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::uniform_int_distribution<int> extra(0, 3);
  for (int dim : {2, 3}) {
    for (int d = 1; d <= 3; ++d) {
      for (int trial = 0; trial < 20; ++trial) {
        int cells[3], total = 1;
        double lo[3], hi[3];
        for (int a = 0; a < dim; ++a) {
          cells[a] = d + 1 + extra(rng);
          total *= cells[a];
          lo[a] = -1.0 + 0.5 * u01(rng);
          hi[a] = lo[a] + 0.5 + u01(rng);
        }
        for (int s = 0; s < 50; ++s) {
          double x[3];
          for (int a = 0; a < dim; ++a) x[a] = lo[a] - 0.5 + (hi[a] - lo[a] + 1.0) * u01(rng);
          double sum = 0.0;
          for (int k = 0; k < total; ++k) {
            double w = 1.0;
            int rest = k;
            for (int a = 0; a < dim; ++a) {
              w *= bspline::basis<double>(rest % cells[a], cells[a], d,
                                          param(x[a], lo[a], hi[a], cells[a], d));
              rest /= cells[a];
            }
            ASSERT_GE(w, 0.0);
            ASSERT_LE(w, 1.0);
            sum += w;
          }
          ASSERT_NEAR(sum, 1.0, 1e-13) << dim << "D degree " << d;
        }
      }
    }
  }
}

TEST(BSpline, MatchesTheLiteralCoxDeBoorRecursion) {
  for (int d = 1; d <= bspline::kMaxDegree; ++d) {
    for (int n = d + 1; n <= d + 6; ++n) {
      const std::vector<double> t = clamped_knots(n, d);
      const int m = n - d;
      for (int s = 0; s <= 200 * m; ++s) {
        const double u = static_cast<double>(s) / 200.0;  // knots and the ends included
        for (int i = 0; i < n; ++i) {
          ASSERT_NEAR(bspline::basis<double>(i, n, d, u), cox_de_boor(t, i, d, u), 1e-13)
              << "d " << d << " n " << n << " i " << i << " u " << u;
        }
      }
    }
  }
}

TEST(BSpline, ClosedForms) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  // Degree 1: hats centred at the integers, N_i(u) = max(0, 1 - |u - i|).
  for (int n = 2; n <= 7; ++n) {
    for (int s = 0; s < 200; ++s) {
      const double u = (n - 1) * u01(rng);
      for (int i = 0; i < n; ++i) {
        EXPECT_NEAR(bspline::basis<double>(i, n, 1, u), std::max(0.0, 1.0 - std::abs(u - i)),
                    1e-15);
      }
    }
  }
  // Degree 2 with 3 functions: the Bernstein basis (1 - u)^2, 2u(1 - u), u^2.
  for (int s = 0; s < 200; ++s) {
    const double u = u01(rng);
    EXPECT_NEAR(bspline::basis<double>(0, 3, 2, u), (1 - u) * (1 - u), 1e-15);
    EXPECT_NEAR(bspline::basis<double>(1, 3, 2, u), 2 * u * (1 - u), 1e-15);
    EXPECT_NEAR(bspline::basis<double>(2, 3, 2, u), u * u, 1e-15);
  }
  // Degree 2 with 7 functions: the end function (1 - u)^2 on [0, 1], and the interior ones
  // (2 <= i <= 4) the cardinal quadratic B-spline on [i - 2, i + 1].
  const auto quadratic = [](double v) {
    if (v < 0 || v >= 3) return 0.0;
    if (v < 1) return v * v / 2;
    if (v < 2) return (-2 * v * v + 6 * v - 3) / 2;
    return (3 - v) * (3 - v) / 2;
  };
  for (int s = 0; s < 500; ++s) {
    const double u = 5 * u01(rng);
    EXPECT_NEAR(bspline::basis<double>(0, 7, 2, u), u < 1 ? (1 - u) * (1 - u) : 0.0, 1e-14);
    for (int i = 2; i <= 4; ++i) {
      EXPECT_NEAR(bspline::basis<double>(i, 7, 2, u), quadratic(u - (i - 2)), 1e-14) << i;
    }
  }
}

TEST(BSpline, EndsInterpolateAndOutsideIsClamped) {
  for (int d = 1; d <= bspline::kMaxDegree; ++d) {
    const int n = d + 3;
    EXPECT_EQ(bspline::basis<double>(0, n, d, param(-5.0, 0.0, 1.0, n, d)), 1.0);
    EXPECT_EQ(bspline::basis<double>(0, n, d, 0.0), 1.0);
    EXPECT_EQ(bspline::basis<double>(n - 1, n, d, param(7.0, 0.0, 1.0, n, d)), 1.0);
    EXPECT_EQ(bspline::basis<double>(n - 1, n, d, static_cast<double>(n - d)), 1.0);
    for (int i = 1; i < n; ++i) EXPECT_EQ(bspline::basis<double>(i, n, d, 0.0), 0.0);
  }
}

// positive_on is what bounds and per-brick simplification use to drop children: it must be
// true wherever the function is positive (sampled), and false only where it is 0 throughout.
TEST(BSpline, SupportTestIsExactOnSamples) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int d = 1; d <= 4; ++d) {
    for (int n = d + 1; n <= d + 5; ++n) {
      const double m = n - d;
      for (int trial = 0; trial < 300; ++trial) {
        double a = m * u01(rng), b = m * u01(rng);
        if (trial % 5 == 0) b = a;                         // a point
        if (trial % 7 == 0) a = std::floor(a), b = a;      // a knot
        if (trial % 11 == 0) a = 0, b = std::min(b, 0.3);  // at the start
        if (a > b) std::swap(a, b);
        for (int i = 0; i < n; ++i) {
          double most = 0.0;
          for (int s = 0; s <= 200; ++s) {
            most = std::max(most, bspline::basis<double>(i, n, d, a + (b - a) * s / 200.0));
          }
          if (most > 0.0) {
            EXPECT_TRUE(bspline::positive_on(i, n, d, a, b))
                << "d " << d << " n " << n << " i " << i << " [" << a << ", " << b << "]";
          }
          // A non-trivial interval inside the support: the samples see it.
          if (bspline::positive_on(i, n, d, a, b) && b - a > 1e-3) {
            EXPECT_GT(most, 0.0) << "d " << d << " n " << n << " i " << i;
          }
        }
      }
    }
  }
  // Touching a support's end is not meeting it: N_2 of 4 linear hats lives on (1, 3).
  EXPECT_FALSE(bspline::positive_on(2, 4, 1, 0.0, 1.0));
  EXPECT_TRUE(bspline::positive_on(2, 4, 1, 0.0, 1.0 + 1e-12));
  EXPECT_FALSE(bspline::positive_on(0, 4, 1, 1.0, 3.0));
  EXPECT_TRUE(bspline::positive_on(0, 4, 1, 0.0, 0.0));
  EXPECT_TRUE(bspline::positive_on(3, 4, 1, 3.0, 3.0));
}

}  // namespace
}  // namespace fuzzycsg
