#pragma once
// Numerical kernels shared by the smooth steps (steps.hpp) and the fuzzy operators (logic.hpp).
//
// Li & Tian's smooth unit step H_n (eq. 2) is the cumulative distribution function of
// S_n = U_1 + ... + U_n, the U_i independent and uniform on [-1, 1]; with t = (x + n) / 2 it is
// the Irwin-Hall distribution function F_n(t) of n uniforms on [0, 1]. (The tests compare it
// with the literal recursion of eq. 2 for n = 0..8 and the closed form up to n = 14.) Written with
// the cardinal B-splines N_m (order m, support [0, m]):
//   F_n(t)           = sum_{j >= 0} N_{n+1}(t - j)
//   F_n'(t)          = N_n(t)
//   int_0^t F_n      = sum_{j >= 0} (j + 1) N_{n+2}(t - j)
// Every term is non-negative, so the sums are free of cancellation; the B-spline values come
// from the Cox-de Boor triangle at the local coordinate u = t - floor(t), O(n^2) operations.
//
// Li & Tian's upper smooth absolute value (eq. 8) is |x|_n = E|x - S_n| (checked against the
// literal recursion of eq. 8 in the tests), hence
//   d|x|_n / dx = 2 H_n(x) - 1,      |x|_n = 2 int_{-inf}^x H_n(s) ds - x.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace fuzzycsg::detail {

// Scratch storage: on the stack for small sizes, on the heap beyond.
template <class T, std::size_t kInline>
class Scratch {
 public:
  explicit Scratch(std::size_t size) {
    if (size <= kInline) {
      data_ = inline_;
    } else {
      heap_.resize(size);
      data_ = heap_.data();
    }
  }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }

 private:
  T inline_[kInline];
  std::vector<T> heap_;
  T* data_;
};

// H_n and its first derivative and integral at a point z <= 0 (the lower tail, where all three
// are small and computed with full relative accuracy).
template <class T>
struct StepTail {
  T cdf{};       // H_n(z)
  T density{};   // H_n'(z)
  T integral{};  // int_{-inf}^z H_n(s) ds (only when requested)
};

// Fixed-degree form of step_tail (below): the triangle has compile-time extent, is fully
// unrolled and kept in registers, and every point runs the same branch-free code (entries
// beyond k0 are computed and masked out; they never feed the entries at or below k0).
template <class T, int N, bool kIntegral>
inline StepTail<T> step_tail_fixed(T z) {
  static_assert(N >= 1);
  constexpr int kLen = N / 2 + 1;
  constexpr int kTop = kIntegral ? N + 2 : N + 1;
  StepTail<T> r;
  const T t = (static_cast<T>(N) + z) * static_cast<T>(0.5);
  if (!(t > T(0))) return r;
  const int k0 = static_cast<int>(t);
  const T u = t - static_cast<T>(k0);
  std::array<T, kLen> v{};
  v[0] = T(1);
  T density_raw = N == 1 ? T(1) : T(0);  // N = 1: k0 = 0 (t <= 1/2)
#pragma GCC unroll 32
  for (int m = 2; m <= kTop; ++m) {
    const T inv = T(1) / static_cast<T>(m - 1);
    if constexpr (kLen > 1) {
      const T mu = static_cast<T>(m) - u;
#pragma GCC unroll 16
      for (int k = std::min(kLen - 1, m - 1); k >= 1; --k) {
        const T kk = static_cast<T>(k);
        const auto i = static_cast<std::size_t>(k);
        v[i] = ((u + kk) * v[i] + (mu - kk) * v[i - 1]) * inv;
      }
    }
    v[0] = u * v[0] * inv;
    if (m == N) {
      T s = T(0);
#pragma GCC unroll 16
      for (int k = 0; k < kLen; ++k) s += k == k0 ? v[static_cast<std::size_t>(k)] : T(0);
      density_raw = s;
    }
    if (m == N + 1) {
      T s = T(0);
#pragma GCC unroll 16
      for (int k = 0; k < kLen; ++k) s += k <= k0 ? v[static_cast<std::size_t>(k)] : T(0);
      r.cdf = s;
    }
  }
  if constexpr (kIntegral) {
    T s = T(0);
#pragma GCC unroll 16
    for (int k = 0; k < kLen; ++k) {
      s += k <= k0 ? static_cast<T>(k0 - k + 1) * v[static_cast<std::size_t>(k)] : T(0);
    }
    r.integral = T(2) * s;
  }
  r.density = T(0.5) * density_raw;
  return r;
}

template <class T, bool kIntegral>
inline StepTail<T> step_tail_any(int n, T z);

// n >= 1, z <= 0. kIntegral: also compute `integral` (one more level of the triangle).
// Degrees up to 8 use the unrolled fixed-degree kernel, higher ones the general loop.
template <class T, bool kIntegral>
inline StepTail<T> step_tail(int n, T z) {
  switch (n) {
    case 1:
      return step_tail_fixed<T, 1, kIntegral>(z);
    case 2:
      return step_tail_fixed<T, 2, kIntegral>(z);
    case 3:
      return step_tail_fixed<T, 3, kIntegral>(z);
    case 4:
      return step_tail_fixed<T, 4, kIntegral>(z);
    case 5:
      return step_tail_fixed<T, 5, kIntegral>(z);
    case 6:
      return step_tail_fixed<T, 6, kIntegral>(z);
    case 7:
      return step_tail_fixed<T, 7, kIntegral>(z);
    case 8:
      return step_tail_fixed<T, 8, kIntegral>(z);
    default:
      return step_tail_any<T, kIntegral>(n, z);
  }
}

// General degree: the same triangle with run-time extent k0 + 1.
template <class T, bool kIntegral>
inline StepTail<T> step_tail_any(int n, T z) {
  StepTail<T> r;
  const T t = (static_cast<T>(n) + z) * static_cast<T>(0.5);
  if (!(t > T(0))) return r;  // at or below -n (or NaN)
  // t <= n / 2, so only the B-spline values N_m(u + k) with k <= k0 <= n / 2 are needed.
  const int k0 = static_cast<int>(t);
  const T u = t - static_cast<T>(k0);
  const std::size_t len = static_cast<std::size_t>(k0) + 1;
  Scratch<T, 16> v(len);
  v[0] = T(1);  // order 1: N_1(u) = 1 on [0, 1)
  for (std::size_t k = 1; k < len; ++k) v[k] = T(0);
  T density_raw = (n == 1 && k0 == 0) ? T(1) : T(0);
  const int top = kIntegral ? n + 2 : n + 1;
  for (int m = 2; m <= top; ++m) {
    // N_m(s) = (s N_{m-1}(s) + (m - s) N_{m-1}(s - 1)) / (m - 1), s = u + k; both weights are
    // non-negative for k <= m - 1.
    const T inv = T(1) / static_cast<T>(m - 1);
    const int kmax = std::min(k0, m - 1);
    const T mu = static_cast<T>(m) - u;
    for (int k = kmax; k >= 1; --k) {
      const T kk = static_cast<T>(k);
      const auto i = static_cast<std::size_t>(k);
      v[i] = ((u + kk) * v[i] + (mu - kk) * v[i - 1]) * inv;
    }
    v[0] = u * v[0] * inv;
    if (m == n) density_raw = v[len - 1];
    if (m == n + 1) {
      T s = T(0);
      for (std::size_t k = 0; k < len; ++k) s += v[k];
      r.cdf = s;
    }
  }
  if constexpr (kIntegral) {
    T s = T(0);
    for (std::size_t k = 0; k < len; ++k) s += static_cast<T>(len - k) * v[k];
    r.integral = T(2) * s;  // dx = 2 dt
  }
  r.density = T(0.5) * density_raw;  // dt/dx = 1/2
  return r;
}

// q^e for q >= 0, finite: q == 0 with e < 0 (a derivative that is infinite at an end point of
// [0, 1]) is answered with a large finite number rather than infinity, so that a zero upstream
// gradient still gives zero. Results are clamped to the largest finite value.
template <class T>
inline T pow_finite(T q, T e) {
  if (q == T(0)) {
    if (e > T(0)) return T(0);
    if (e == T(0)) return T(1);
    const T eps = std::numeric_limits<T>::epsilon();
    return T(1) / (eps * eps);
  }
  return std::min(std::pow(q, e), std::numeric_limits<T>::max());
}

// The p-norm r = (a^p + b^p)^(1/p) of a, b >= 0 with its partial derivatives, evaluated with
// scaling by max(a, b) so that large a, b (Dombi) or large p (Yager) neither overflow nor
// underflow. At a = b = 0 everything is zero.
template <class T>
struct PNorm {
  T r{}, da{}, db{}, dp{};
};
// kGrad: also the derivatives (da, db, dp); otherwise only r.
template <class T, bool kGrad>
inline PNorm<T> pnorm2(T a, T b, T p) {
  PNorm<T> out;
  const T big = std::max(a, b);
  if (!(big > T(0))) return out;
  const T ra = a / big, rb = b / big;  // one of them is 1
  const T pa = std::pow(ra, p), pb = std::pow(rb, p);
  const T s = pa + pb;  // in [1, 2]
  const T root = std::pow(s, T(1) / p);
  out.r = big * root;
  if constexpr (kGrad) {
    // dr/da = (a / r)^(p - 1)
    out.da = pow_finite(ra / root, p - T(1));
    out.db = pow_finite(rb / root, p - T(1));
    // d ln r / dp = -ln s / p^2 + (ra^p ln ra + rb^p ln rb) / (p s)
    const T la = ra > T(0) ? pa * std::log(ra) : T(0);
    const T lb = rb > T(0) ? pb * std::log(rb) : T(0);
    out.dp = out.r * (-std::log(s) / (p * p) + (la + lb) / (p * s));
  }
  return out;
}

}  // namespace fuzzycsg::detail
