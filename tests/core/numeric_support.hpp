#pragma once
// Numerical helpers for the logic and step tests: literal reference recursions, central
// differences and one-sided polynomial fits for smoothness checks across knots.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

namespace fuzzycsg::test {

// Li & Tian eq. 2, literally (2^n evaluations).
inline double literal_hn(int n, double x) {
  if (n == 0) return x < 0.0 ? 0.0 : (x > 0.0 ? 1.0 : 0.5);
  const double nn = n;
  return 0.5 * ((1.0 + x / nn) * literal_hn(n - 1, x + 1.0) +
                (1.0 - x / nn) * literal_hn(n - 1, x - 1.0));
}

// Li & Tian eq. 8, literally.
inline double literal_upper_abs(int n, double x) {
  if (n == 0) return std::abs(x);
  const double nn = n;
  return ((nn - x) * literal_upper_abs(n - 1, 1.0 - x) +
          (nn + x) * literal_upper_abs(n - 1, 1.0 + x)) /
         (2.0 * (nn + 1.0));
}

// Irwin-Hall distribution function of the sum of n uniforms on [0, 1] (alternating sum in
// long double, fine for small n; the upper half through F(t) = 1 - F(n - t)).
inline double irwin_hall_cdf(int n, double t) {
  if (t <= 0.0) return 0.0;
  if (t >= n) return 1.0;
  if (t > 0.5 * n) return 1.0 - irwin_hall_cdf(n, n - t);
  long double sum = 0.0L;
  long double binom = 1.0L;  // C(n, k)
  long double fact = 1.0L;   // n!
  for (int i = 2; i <= n; ++i) fact *= i;
  for (int k = 0; k <= n && k < t; ++k) {
    const long double term = binom * std::pow(static_cast<long double>(t) - k, n);
    sum += (k % 2 == 0) ? term : -term;
    binom = binom * (n - k) / (k + 1);
  }
  return static_cast<double>(sum / fact);
}

// Central difference of a scalar function.
inline double central_diff(const std::function<double(double)>& f, double x, double h) {
  return (f(x + h) - f(x - h)) / (2.0 * h);
}

// Solve the dense linear system a z = b (Gaussian elimination with partial pivoting).
inline std::vector<double> solve_dense(std::vector<std::vector<double>> a, std::vector<double> b) {
  const std::size_t n = b.size();
  for (std::size_t col = 0; col < n; ++col) {
    std::size_t piv = col;
    for (std::size_t r = col + 1; r < n; ++r) {
      if (std::abs(a[r][col]) > std::abs(a[piv][col])) piv = r;
    }
    std::swap(a[col], a[piv]);
    std::swap(b[col], b[piv]);
    for (std::size_t r = col + 1; r < n; ++r) {
      const double factor = a[r][col] / a[col][col];
      for (std::size_t c = col; c < n; ++c) a[r][c] -= factor * a[col][c];
      b[r] -= factor * b[col];
    }
  }
  std::vector<double> z(n);
  for (std::size_t i = n; i-- > 0;) {
    double s = b[i];
    for (std::size_t c = i + 1; c < n; ++c) s -= a[i][c] * z[c];
    z[i] = s / a[i][i];
  }
  return z;
}

// One-sided Taylor coefficients at x0 of a function that is a polynomial of degree <= degree on
// [x0, x0 + side * width] (side = +1 or -1): the interpolating polynomial at Chebyshev nodes
// strictly inside the interval, in the variable tau = (x - x0) / width. Entry k is
// f^(k)(x0 from that side) width^k / k!, so coefficients of both sides are directly
// comparable and of the size of f's variation over the interval.
inline std::vector<double> one_sided_taylor(const std::function<double(double)>& f, double x0,
                                            int side, double width, int degree) {
  const auto m = static_cast<std::size_t>(degree + 1);
  std::vector<std::vector<double>> a(m, std::vector<double>(m));
  std::vector<double> b(m);
  for (std::size_t i = 0; i < m; ++i) {
    const double tau = 0.5 * (1.0 - std::cos(std::numbers::pi * (static_cast<double>(i) + 0.5) /
                                             static_cast<double>(m)));
    double pw = 1.0;
    for (std::size_t k = 0; k < m; ++k) {
      a[i][k] = pw;
      pw *= tau;
    }
    b[i] = f(x0 + side * width * tau);
  }
  auto coef = solve_dense(std::move(a), std::move(b));
  if (side < 0) {
    for (std::size_t k = 1; k < m; k += 2) coef[k] = -coef[k];  // d/dx = -d/dtau
  }
  return coef;
}

// |left - right| of the normalized Taylor coefficients (see one_sided_taylor) at a knot x0,
// for orders 0..degree: entry k is the jump of f^(k) times width^k / k!.
inline std::vector<double> taylor_jumps(const std::function<double(double)>& f, double x0,
                                        double width, int degree) {
  const auto left = one_sided_taylor(f, x0, -1, width, degree);
  const auto right = one_sided_taylor(f, x0, +1, width, degree);
  std::vector<double> jumps(left.size());
  for (std::size_t k = 0; k < left.size(); ++k) jumps[k] = std::abs(left[k] - right[k]);
  return jumps;
}

// Uniform points of [lo, hi]^2 from a fixed seed.
inline std::vector<std::pair<double, double>> random_pairs(std::size_t count, double lo, double hi,
                                                           unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> dist(lo, hi);
  std::vector<std::pair<double, double>> out(count);
  for (auto& [x, y] : out) {
    x = dist(rng);
    y = dist(rng);
  }
  return out;
}

// 0, 1/k, ..., 1.
inline std::vector<double> unit_grid(int k) {
  std::vector<double> g(static_cast<std::size_t>(k) + 1);
  for (int i = 0; i <= k; ++i) g[static_cast<std::size_t>(i)] = static_cast<double>(i) / k;
  return g;
}

}  // namespace fuzzycsg::test
