#pragma once
// Definitions of the templates declared in steps.hpp (included at its end).

#include <cmath>

#include "fuzzycsg/core/spline_kernel.hpp"
#include "fuzzycsg/core/steps.hpp"

namespace fuzzycsg::steps {

template <class T>
inline T heaviside(T x) {
  if (x > T(0)) return T(1);
  if (x < T(0)) return T(0);
  return T(0.5);
}

// H_n through the Irwin-Hall form (spline_kernel.hpp): the lower tail H_n(-|x|) is computed
// directly, the upper one by symmetry H_n(x) = 1 - H_n(-x).
template <class T>
inline T hn(int n, T x) {
  if (n <= 0) return heaviside(x);
  const T f = detail::step_tail<T, false>(n, -std::abs(x)).cdf;
  return x <= T(0) ? f : T(1) - f;
}

template <class T>
inline logic::Grad1<T> hn_grad(int n, T x) {
  if (n <= 0) return {heaviside(x), T(0), T(0)};
  const auto tail = detail::step_tail<T, false>(n, -std::abs(x));
  return {x <= T(0) ? tail.cdf : T(1) - tail.cdf, tail.density, T(0)};
}

// Eq. 3 degenerates at n = 0 (H_0(0 x / R) = 1/2); there H_{0,R} is taken as the step H_0(x).
template <class T>
inline T hn_range(int n, T x, T range) {
  if (n <= 0) return heaviside(x);
  return hn(n, static_cast<T>(n) * x / range);
}

template <class T>
inline logic::Grad1<T> hn_range_grad(int n, T x, T range) {
  if (n <= 0) return {heaviside(x), T(0), T(0)};
  const T scale = static_cast<T>(n) / range;
  const auto g = hn_grad(n, scale * x);
  // d/dx H_n(n x / R) = H_n' n / R;  d/dR = -H_n' n x / R^2.
  return {g.v, g.dx * scale, -g.dx * scale * x / range};
}

template <class T>
inline T logistic(T x, T alpha) {
  const T z = alpha * x;
  if (z >= T(0)) return T(1) / (T(1) + std::exp(-z));
  const T e = std::exp(z);
  return e / (T(1) + e);
}

template <class T>
inline logic::Grad1<T> logistic_grad(T x, T alpha) {
  const T z = alpha * x;
  const T e = std::exp(-std::abs(z));  // in (0, 1]
  const T inv = T(1) / (T(1) + e);
  const T v = z >= T(0) ? inv : e * inv;
  const T s = e * inv * inv;  // sigma (1 - sigma), without cancellation
  return {v, s * alpha, s * x};
}

}  // namespace fuzzycsg::steps
