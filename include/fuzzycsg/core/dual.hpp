#pragma once
// Forward-mode dual numbers: a value and its derivatives along N fixed directions. Used for the
// exact gradients of small closed-form functions (the primitive families): seed each input
// with `variable(x, i)`, evaluate the function on duals, read `d[i]`. Fixed size, no heap.
//
// Non-smooth points take a one-sided derivative so that results stay finite:
//   sqrt(0) has derivative 0 (the distance |v| at v = 0 gets the subgradient 0),
//   abs(0) has derivative +1, comparisons look at values only.

#include <array>
#include <cmath>

namespace fuzzycsg {

template <class T, int N>
struct Dual {
  static_assert(N > 0, "a dual number needs at least one direction");

  T v = T(0);
  std::array<T, N> d{};

  constexpr Dual() = default;
  constexpr explicit Dual(T value) : v(value) {}

  // The independent variable number `index` (0 <= index < N) at `value`.
  static constexpr Dual variable(T value, int index) {
    Dual r(value);
    r.d[static_cast<std::size_t>(index)] = T(1);
    return r;
  }

  constexpr Dual& operator+=(const Dual& b) {
    v += b.v;
    for (int i = 0; i < N; ++i) d[i] += b.d[i];
    return *this;
  }
  constexpr Dual& operator-=(const Dual& b) {
    v -= b.v;
    for (int i = 0; i < N; ++i) d[i] -= b.d[i];
    return *this;
  }
  constexpr Dual& operator*=(const Dual& b) {
    for (int i = 0; i < N; ++i) d[i] = d[i] * b.v + v * b.d[i];
    v *= b.v;
    return *this;
  }
  constexpr Dual& operator/=(const Dual& b) {
    const T inv = T(1) / b.v;
    v *= inv;
    for (int i = 0; i < N; ++i) d[i] = (d[i] - v * b.d[i]) * inv;
    return *this;
  }
  constexpr Dual& operator+=(T b) {
    v += b;
    return *this;
  }
  constexpr Dual& operator-=(T b) {
    v -= b;
    return *this;
  }
  constexpr Dual& operator*=(T b) {
    v *= b;
    for (int i = 0; i < N; ++i) d[i] *= b;
    return *this;
  }
  constexpr Dual& operator/=(T b) { return *this *= (T(1) / b); }

  friend constexpr Dual operator-(Dual a) {
    a.v = -a.v;
    for (int i = 0; i < N; ++i) a.d[i] = -a.d[i];
    return a;
  }
  friend constexpr Dual operator+(Dual a, const Dual& b) { return a += b; }
  friend constexpr Dual operator-(Dual a, const Dual& b) { return a -= b; }
  friend constexpr Dual operator*(Dual a, const Dual& b) { return a *= b; }
  friend constexpr Dual operator/(Dual a, const Dual& b) { return a /= b; }
  friend constexpr Dual operator+(Dual a, T b) { return a += b; }
  friend constexpr Dual operator-(Dual a, T b) { return a -= b; }
  friend constexpr Dual operator*(Dual a, T b) { return a *= b; }
  friend constexpr Dual operator/(Dual a, T b) { return a /= b; }
  friend constexpr Dual operator+(T a, Dual b) { return b += a; }
  friend constexpr Dual operator-(T a, const Dual& b) { return Dual(a) -= b; }
  friend constexpr Dual operator*(T a, Dual b) { return b *= a; }
  friend constexpr Dual operator/(T a, const Dual& b) {
    const T inv = T(1) / b.v;
    Dual r(a * inv);
    const T k = -r.v * inv;
    for (int i = 0; i < N; ++i) r.d[i] = k * b.d[i];
    return r;
  }

  friend constexpr bool operator<(const Dual& a, const Dual& b) { return a.v < b.v; }
  friend constexpr bool operator>(const Dual& a, const Dual& b) { return a.v > b.v; }
  friend constexpr bool operator<=(const Dual& a, const Dual& b) { return a.v <= b.v; }
  friend constexpr bool operator>=(const Dual& a, const Dual& b) { return a.v >= b.v; }
  friend constexpr bool operator<(const Dual& a, T b) { return a.v < b; }
  friend constexpr bool operator>(const Dual& a, T b) { return a.v > b; }
  friend constexpr bool operator<=(const Dual& a, T b) { return a.v <= b; }
  friend constexpr bool operator>=(const Dual& a, T b) { return a.v >= b; }
  friend constexpr bool operator<(T a, const Dual& b) { return a < b.v; }
  friend constexpr bool operator>(T a, const Dual& b) { return a > b.v; }
  friend constexpr bool operator<=(T a, const Dual& b) { return a <= b.v; }
  friend constexpr bool operator>=(T a, const Dual& b) { return a >= b.v; }
};

// Derivative 0 at 0 (see the header comment).
template <class T, int N>
Dual<T, N> sqrt(const Dual<T, N>& a) {
  const T s = std::sqrt(a.v);
  const T k = a.v > T(0) ? T(0.5) / s : T(0);
  Dual<T, N> r(s);
  for (int i = 0; i < N; ++i) r.d[i] = k * a.d[i];
  return r;
}

// Derivative +1 at 0.
template <class T, int N>
Dual<T, N> abs(const Dual<T, N>& a) {
  return a.v < T(0) ? -a : a;
}

template <class T, int N>
Dual<T, N> tanh(const Dual<T, N>& a) {
  const T t = std::tanh(a.v);
  const T k = T(1) - t * t;
  Dual<T, N> r(t);
  for (int i = 0; i < N; ++i) r.d[i] = k * a.d[i];
  return r;
}

template <class T, int N>
Dual<T, N> exp(const Dual<T, N>& a) {
  const T e = std::exp(a.v);
  Dual<T, N> r(e);
  for (int i = 0; i < N; ++i) r.d[i] = e * a.d[i];
  return r;
}

// The underlying real type of a scalar or a dual number.
template <class S>
struct DualScalar {
  using type = S;
};
template <class T, int N>
struct DualScalar<Dual<T, N>> {
  using type = T;
};
template <class S>
using dual_scalar_t = typename DualScalar<S>::type;

}  // namespace fuzzycsg
