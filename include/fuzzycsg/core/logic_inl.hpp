#pragma once
// Definitions of the templates declared in logic.hpp (included at its end).
//
// Conventions at points where an operator is not differentiable (a kink or a clamp):
//   * Godel min at x == y: the derivative goes to x (dx = 1, dy = 0); the union max likewise.
//   * Lukasiewicz, Weber, Yager on their zero boundary: the clamped side (all derivatives 0).
//   * Dubois-Prade on max(x, y) == k: the k branch (xy / k); at x == y > k: the x side.
// Where an exact derivative is infinite (Yager and Dombi with p < 1 at x = 1, the Yager
// complement at an end point) a large finite number is returned, never inf or NaN.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>

#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/spline_kernel.hpp"

namespace fuzzycsg::logic {

namespace impl {

template <class T>
inline T sign_or_zero(T x) {
  return x > T(0) ? T(1) : (x < T(0) ? T(-1) : T(0));
}

template <class T>
inline T huge_slope() {
  const T eps = std::numeric_limits<T>::epsilon();
  return T(1) / (eps * eps);
}

// ---- classical t-norms ----

template <class T>
inline Grad2<T> godel_grad(T x, T y) {
  if (x <= y) return {x, T(1), T(0), T(0)};
  return {y, T(0), T(1), T(0)};
}

template <class T>
inline Grad2<T> lukasiewicz_grad(T x, T y) {
  const T s = x + y - T(1);
  if (s > T(0)) return {s, T(1), T(1), T(0)};
  return {};
}

template <class T>
inline T yager(T x, T y, T p) {
  const T r = fuzzycsg::detail::pnorm2<T, false>(T(1) - x, T(1) - y, p).r;
  return r < T(1) ? T(1) - r : T(0);
}

template <class T>
inline Grad2<T> yager_grad(T x, T y, T p) {
  const T a = T(1) - x, b = T(1) - y;
  // At x = y = 1 the directional derivatives along the axes are 1 (T(x, 1) = x).
  if (!(a > T(0)) && !(b > T(0))) return {T(1), T(1), T(1), T(0)};
  const auto r = fuzzycsg::detail::pnorm2<T, true>(a, b, p);
  if (r.r >= T(1)) return {};
  // T = 1 - r(1 - x, 1 - y): dT/dx = dr/da, dT/dp = -dr/dp.
  return {T(1) - r.r, r.da, r.db, -r.dp};
}

// Hamacher with parameter a >= 0 (Einstein is a = 2). D = a + (1 - a)(x + y - xy) > 0 except
// for a = 0 at x = y = 0, where the operator is 0 with zero derivatives (the limit along the
// axes).
template <class T>
inline T hamacher(T x, T y, T a) {
  const T d = a + (T(1) - a) * (x + y - x * y);
  if (!(d > T(0))) return T(0);
  return x * y / d;
}

template <class T>
inline Grad2<T> hamacher_grad(T x, T y, T a) {
  const T d = a + (T(1) - a) * (x + y - x * y);
  if (!(d > T(0))) return {};
  const T inv = T(1) / d;
  const T inv2 = inv * inv;
  // dT/dx = y (a + (1 - a) y) / D^2;  dT/da = -xy (1 - x)(1 - y) / D^2.
  return {x * y * inv, y * (a + (T(1) - a) * y) * inv2, x * (a + (T(1) - a) * x) * inv2,
          -x * y * (T(1) - x) * (T(1) - y) * inv2};
}

template <class T>
inline T einstein(T x, T y) {
  return x * y / (T(1) + (T(1) - x) * (T(1) - y));
}

template <class T>
inline Grad2<T> einstein_grad(T x, T y) {
  const T inv = T(1) / (T(1) + (T(1) - x) * (T(1) - y));
  const T inv2 = inv * inv;
  return {x * y * inv, y * (T(2) - y) * inv2, x * (T(2) - x) * inv2, T(0)};
}

// Dombi: 1 / (1 + r) with r the lambda-norm of X = (1 - x) / x, Y = (1 - y) / y. x = 0 (or
// subnormal, where X would overflow) gives 0; there dT/dx = 1 for y > 0 (T(x, y) = x + o(x)).
template <class T>
inline T dombi(T x, T y, T lambda) {
  const T tiny = std::numeric_limits<T>::min();
  if (!(x >= tiny) || !(y >= tiny)) return T(0);
  const T r = fuzzycsg::detail::pnorm2<T, false>((T(1) - x) / x, (T(1) - y) / y, lambda).r;
  return T(1) / (T(1) + r);
}

template <class T>
inline Grad2<T> dombi_grad(T x, T y, T lambda) {
  const T tiny = std::numeric_limits<T>::min();
  const bool x0 = !(x >= tiny), y0 = !(y >= tiny);
  if (x0 || y0) return {T(0), (x0 && !y0) ? T(1) : T(0), (y0 && !x0) ? T(1) : T(0), T(0)};
  const T bx = (T(1) - x) / x, by = (T(1) - y) / y;
  if (!(bx > T(0)) && !(by > T(0))) return {T(1), T(1), T(1), T(0)};  // x = y = 1
  const auto r = fuzzycsg::detail::pnorm2<T, true>(bx, by, lambda);
  const T v = T(1) / (T(1) + r.r);
  // dT/dx = -T^2 dr/dX dX/dx = (T / x)^2 dr/dX, with T / x = 1 / (x (1 + r)) bounded.
  const T gx = T(1) / (x * (T(1) + r.r));
  const T gy = T(1) / (y * (T(1) + r.r));
  return {v, gx * gx * r.da, gy * gy * r.db, -v * v * r.dp};
}

template <class T>
inline T dubois_prade(T x, T y, T k) {
  if (k >= x && k >= y) return k > T(0) ? x * y / k : T(0);
  return std::min(x, y);
}

template <class T>
inline Grad2<T> dubois_prade_grad(T x, T y, T k) {
  if (k >= x && k >= y) {
    if (!(k > T(0))) return {};
    return {x * y / k, y / k, x / k, -x * y / (k * k)};
  }
  if (x <= y) return {x, T(1), T(0), T(0)};  // max is y: T = x
  return {y, T(0), T(1), T(0)};
}

template <class T>
inline T weber(T x, T y, T k) {
  const T s = x + y + k * x * y - T(1);
  return s > T(0) ? s / (T(1) + k) : T(0);
}

template <class T>
inline Grad2<T> weber_grad(T x, T y, T k) {
  const T s = x + y + k * x * y - T(1);
  if (!(s > T(0))) return {};
  const T inv = T(1) / (T(1) + k);
  return {s * inv, (T(1) + k * y) * inv, (T(1) + k * x) * inv, (T(1) - x) * (T(1) - y) * inv * inv};
}

// ---- Bézier operator ----

// Bernstein basis of degree d at x into b[0..d] (de Casteljau triangle, stable for any d).
template <class T, class Buf>
inline void bernstein_basis(int d, T x, Buf& b) {
  const T xb = T(1) - x;
  b[0] = T(1);
  for (int m = 1; m <= d; ++m) {
    const auto mm = static_cast<std::size_t>(m);
    b[mm] = x * b[mm - 1];
    for (std::size_t i = mm - 1; i >= 1; --i) b[i] = xb * b[i] + x * b[i - 1];
    b[0] = xb * b[0];
  }
}

// B_n(x, y) = sum_{i,j} min(i, j)/n B_i(x) B_j(y) = (1/n) sum_{k=1}^{n} T_k(x) T_k(y), with
// T_k = sum_{i>=k} B_i^(n) the binomial upper tail (min(i, j) = #{k >= 1 : i >= k, j >= k}).
// With b the degree n-1 basis and tau_k = sum_{i>=k} b_i: T_k(x) = tau_k(x) + x b_{k-1}(x), and
// dT_k/dx = n b_{k-1}(x). O(n^2) for the basis, O(n) for the sum.
template <class T, bool kGrad>
inline Grad2<T> bezier_impl(int n, T x, T y) {
  n = std::max(n, 1);
  const auto len = static_cast<std::size_t>(n);
  fuzzycsg::detail::Scratch<T, 32> bx(len), by(len);
  bernstein_basis(n - 1, x, bx);
  bernstein_basis(n - 1, y, by);
  T tx = T(0), ty = T(0), sum = T(0), dx = T(0), dy = T(0);
  for (std::size_t k = len; k >= 1; --k) {
    const T tkx = tx + x * bx[k - 1];
    const T tky = ty + y * by[k - 1];
    sum += tkx * tky;
    if constexpr (kGrad) {
      dx += bx[k - 1] * tky;
      dy += by[k - 1] * tkx;
    }
    tx += bx[k - 1];
    ty += by[k - 1];
  }
  return {sum / static_cast<T>(n), dx, dy, T(0)};
}

// ---- Li & Tian ----

// Upper absolute value |x|_n with d/dx; n >= 1. |x|_n = 2 G(-|x|) + |x|, G the integral of
// H_n, and d|x|_n/dx = 2 H_n(x) - 1 (spline_kernel.hpp).
template <class T>
inline Grad1<T> upper_abs_unit(int n, T x) {
  const T ax = std::abs(x);
  const auto tail = fuzzycsg::detail::step_tail<T, true>(n, -ax);
  const T slope = T(1) - T(2) * tail.cdf;  // 2 H_n(|x|) - 1 >= 0
  return {T(2) * tail.integral + ax, x >= T(0) ? slope : -slope, T(0)};
}

// The boundary-corrected smooth minimum shared by AND_{n,delta} and hat-AND_{n,delta}.
//
// With m(x, y) = (x + y - A(x - y)) / 2 a smooth minimum built from a smooth absolute value A,
// the deviation of m from the exact boundary values (0 on x = 0 and y = 0, the other argument on
// x = 1 and y = 1) is, by translation invariance of m, c(x) = m(x, 0) on y = 0 and
// c(1 - x) = m(x, 1) - x on y = 1 (and symmetrically in y). The operator subtracts the Coons
// patch of these four curves:
//   E(x, y) = (1 - y) c(x) + y c(1 - x) + (1 - x) c(y) + x c(1 - y)
//             - [c(0) (1 - x - y + 2xy) + c(1) (x + y - 2xy)],
// the bracket being the bilinear interpolation of the corner values (c(0) at (0,0), (1,1);
// c(1) at (1,0), (0,1)). Then m - E equals 0 on x = 0, y = 0 and the other argument on x = 1,
// y = 1, for every delta > 0.
//
// Li & Tian's eq. 19 writes the bilinear term as alpha (1 - x - y + 2xy) with
// alpha = -|0|_{n,delta}. The corner value is c(0) = -|0|_{n,delta} / 2, and c(1) = 0 only
// when delta <= 1 (|1|_{n,delta} = 1); with their alpha, AND(0, 0) = -|0|_{n,delta} / 2 != 0,
// and for delta > 1 (e.g. the delta = 1.5 of their figures) AND(1, 0) != 0. The general corner
// term above restores the identity and dominance laws they state. Their hat-AND (eq. 21-25) has
// no corner term; its corners c(0) = 0 and c(1) = H_n(-n / delta) vanish only for delta <= 1,
// and the same correction is applied.
template <class T, class Abs>
inline Grad2<T> coons_min(T x, T y, const Abs& abs_fn) {
  const auto d = abs_fn(x - y);
  const T m = T(0.5) * (x + y - d.v);
  const T mx = T(0.5) * (T(1) - d.dx);
  const T my = T(0.5) * (T(1) + d.dx);
  const T md = T(-0.5) * d.dp;
  // c(s) = (s - A(s)) / 2 with c' and dc/ddelta.
  const auto c = [&abs_fn](T s) {
    const auto a = abs_fn(s);
    return Grad1<T>{T(0.5) * (s - a.v), T(0.5) * (T(1) - a.dx), T(-0.5) * a.dp};
  };
  const auto cx = c(x), cxb = c(T(1) - x), cy = c(y), cyb = c(T(1) - y);
  const auto c0 = c(T(0)), c1 = c(T(1));
  const T w0 = T(1) - x - y + T(2) * x * y;  // bilinear weight of the (0,0), (1,1) corners
  const T w1 = x + y - T(2) * x * y;         // of the (1,0), (0,1) corners
  const T e = (T(1) - y) * cx.v + y * cxb.v + (T(1) - x) * cy.v + x * cyb.v - c0.v * w0 - c1.v * w1;
  const T ex = (T(1) - y) * cx.dx - y * cxb.dx - cy.v + cyb.v - c0.v * (T(2) * y - T(1)) -
               c1.v * (T(1) - T(2) * y);
  const T ey = (T(1) - x) * cy.dx - x * cyb.dx - cx.v + cxb.v - c0.v * (T(2) * x - T(1)) -
               c1.v * (T(1) - T(2) * x);
  const T ed =
      (T(1) - y) * cx.dp + y * cxb.dp + (T(1) - x) * cy.dp + x * cyb.dp - c0.dp * w0 - c1.dp * w1;
  return {m - e, mx - ex, my - ey, md - ed};
}

}  // namespace impl

// ---- Li & Tian building blocks ----

// Degrees n < 1 are treated as n = 1 (the product).
template <class T>
inline T bezier(int n, T x, T y) {
  return impl::bezier_impl<T, false>(n, x, y).v;
}
template <class T>
inline Grad2<T> bezier_grad(int n, T x, T y) {
  return impl::bezier_impl<T, true>(n, x, y);
}

template <class T>
inline T upper_abs(int n, T x) {
  if (n <= 0) return std::abs(x);
  return impl::upper_abs_unit(n, x).v;
}
template <class T>
inline Grad1<T> upper_abs_grad(int n, T x) {
  if (n <= 0) return {std::abs(x), impl::sign_or_zero(x), T(0)};
  return impl::upper_abs_unit(n, x);
}

// |x|_{n,delta} = (delta / n) |n x / delta|_n; exactly |x| for |x| >= delta. n = 0 (or
// delta <= 0) gives |x|.
template <class T>
inline Grad1<T> upper_abs_grad(int n, T x, T delta) {
  if (n <= 0 || !(delta > T(0)) || std::abs(x) >= delta) {
    return {std::abs(x), impl::sign_or_zero(x), T(0)};
  }
  const T nn = static_cast<T>(n);
  const T w = nn * x / delta;
  const auto g = impl::upper_abs_unit(n, w);
  // d/ddelta (delta/n) |w|_n = (|w|_n - w |w|_n') / n.
  return {delta / nn * g.v, g.dx, (g.v - w * g.dx) / nn};
}
template <class T>
inline T upper_abs(int n, T x, T delta) {
  return upper_abs_grad(n, x, delta).v;
}

// hat|x|_n = x (2 H_n(x) - 1).
template <class T>
inline Grad1<T> lower_abs_grad(int n, T x) {
  if (n <= 0) return {std::abs(x), impl::sign_or_zero(x), T(0)};
  const auto tail = fuzzycsg::detail::step_tail<T, false>(n, -std::abs(x));
  const T s = x <= T(0) ? T(2) * tail.cdf - T(1) : T(1) - T(2) * tail.cdf;  // 2 H_n(x) - 1
  return {x * s, s + T(2) * x * tail.density, T(0)};
}
template <class T>
inline T lower_abs(int n, T x) {
  return lower_abs_grad(n, x).v;
}

// hat|x|_{n,delta} = (delta / n) hat|n x / delta|_n = x (2 H_n(n x / delta) - 1).
template <class T>
inline Grad1<T> lower_abs_grad(int n, T x, T delta) {
  if (n <= 0 || !(delta > T(0)) || std::abs(x) >= delta) {
    return {std::abs(x), impl::sign_or_zero(x), T(0)};
  }
  const T scale = static_cast<T>(n) / delta;
  const T w = scale * x;
  const auto tail = fuzzycsg::detail::step_tail<T, false>(n, -std::abs(w));
  const T s = w <= T(0) ? T(2) * tail.cdf - T(1) : T(1) - T(2) * tail.cdf;
  const T hx = T(2) * x * tail.density;  // 2 x H_n'(w)
  return {x * s, s + hx * scale, -hx * w / delta};
}
template <class T>
inline T lower_abs(int n, T x, T delta) {
  return lower_abs_grad(n, x, delta).v;
}

template <class T>
inline Grad2<T> smooth_min_grad(int n, T x, T y, T delta) {
  const auto a = upper_abs_grad(n, x - y, delta);
  return {T(0.5) * (x + y - a.v), T(0.5) * (T(1) - a.dx), T(0.5) * (T(1) + a.dx), T(-0.5) * a.dp};
}
template <class T>
inline T smooth_min(int n, T x, T y, T delta) {
  return T(0.5) * (x + y - upper_abs(n, x - y, delta));
}

template <class T>
inline Grad2<T> smooth_min_hat_grad(int n, T x, T y, T delta) {
  const auto a = lower_abs_grad(n, x - y, delta);
  return {T(0.5) * (x + y - a.v), T(0.5) * (T(1) - a.dx), T(0.5) * (T(1) + a.dx), T(-0.5) * a.dp};
}
template <class T>
inline T smooth_min_hat(int n, T x, T y, T delta) {
  return T(0.5) * (x + y - lower_abs(n, x - y, delta));
}

// AND_{n,delta} (eq. 14-20, with the general Coons corner term of impl::coons_min). n = 0 or
// delta <= 0 is the limit min(x, y).
template <class T>
inline Grad2<T> li_tian_and_grad(int n, T x, T y, T delta) {
  if (n <= 0 || !(delta > T(0))) return impl::godel_grad(x, y);
  return impl::coons_min(x, y, [n, delta](T s) { return upper_abs_grad(n, s, delta); });
}
template <class T>
inline T li_tian_and(int n, T x, T y, T delta) {
  return li_tian_and_grad(n, x, y, delta).v;
}

// hat-AND_{n,delta} (eq. 21-25, with the Coons corner term; see impl::coons_min). The boundary
// curves eq. 21-22 are c(s) = (s - hat|s|_{n,delta}) / 2 = s H_n(-n s / delta) and c(1 - s).
template <class T>
inline Grad2<T> li_tian_hat_and_grad(int n, T x, T y, T delta) {
  if (n <= 0 || !(delta > T(0))) return impl::godel_grad(x, y);
  return impl::coons_min(x, y, [n, delta](T s) { return lower_abs_grad(n, s, delta); });
}
template <class T>
inline T li_tian_hat_and(int n, T x, T y, T delta) {
  return li_tian_hat_and_grad(n, x, y, delta).v;
}

// ---- t-norms, t-conorms ----

template <class T>
inline T tnorm(Family f, T x, T y, T p, int n) {
  switch (f) {
    case Family::kProduct:
      return x * y;
    case Family::kGodel:
      return std::min(x, y);
    case Family::kLukasiewicz:
      return std::max(T(0), x + y - T(1));
    case Family::kYager:
      return impl::yager(x, y, p);
    case Family::kEinstein:
      return impl::einstein(x, y);
    case Family::kHamacher:
      return impl::hamacher(x, y, p);
    case Family::kDombi:
      return impl::dombi(x, y, p);
    case Family::kDuboisPrade:
      return impl::dubois_prade(x, y, p);
    case Family::kWeber:
      return impl::weber(x, y, p);
    case Family::kBezier:
      return bezier(n, x, y);
    case Family::kLiTian:
      return li_tian_and(n, x, y, p);
    case Family::kLiTianHat:
      return li_tian_hat_and(n, x, y, p);
  }
  return T(0);
}

template <class T>
inline Grad2<T> tnorm_grad(Family f, T x, T y, T p, int n) {
  switch (f) {
    case Family::kProduct:
      return {x * y, y, x, T(0)};
    case Family::kGodel:
      return impl::godel_grad(x, y);
    case Family::kLukasiewicz:
      return impl::lukasiewicz_grad(x, y);
    case Family::kYager:
      return impl::yager_grad(x, y, p);
    case Family::kEinstein:
      return impl::einstein_grad(x, y);
    case Family::kHamacher:
      return impl::hamacher_grad(x, y, p);
    case Family::kDombi:
      return impl::dombi_grad(x, y, p);
    case Family::kDuboisPrade:
      return impl::dubois_prade_grad(x, y, p);
    case Family::kWeber:
      return impl::weber_grad(x, y, p);
    case Family::kBezier:
      return bezier_grad(n, x, y);
    case Family::kLiTian:
      return li_tian_and_grad(n, x, y, p);
    case Family::kLiTianHat:
      return li_tian_hat_and_grad(n, x, y, p);
  }
  return {};
}

// S(x, y) = 1 - T(1 - x, 1 - y); product, Godel and Lukasiewicz in their exact closed forms.
template <class T>
inline T tconorm(Family f, T x, T y, T p, int n) {
  switch (f) {
    case Family::kProduct:
      return x + y - x * y;
    case Family::kGodel:
      return std::max(x, y);
    case Family::kLukasiewicz:
      return std::min(T(1), x + y);
    default:
      return T(1) - tnorm(f, T(1) - x, T(1) - y, p, n);
  }
}

template <class T>
inline Grad2<T> tconorm_grad(Family f, T x, T y, T p, int n) {
  switch (f) {
    case Family::kProduct:
      return {x + y - x * y, T(1) - y, T(1) - x, T(0)};
    case Family::kGodel:
      if (x >= y) return {x, T(1), T(0), T(0)};
      return {y, T(0), T(1), T(0)};
    default: {
      const auto g = tnorm_grad(f, T(1) - x, T(1) - y, p, n);
      return {T(1) - g.v, g.dx, g.dy, -g.dp};
    }
  }
}

// ---- complements ----

template <class T>
inline T complement(Complement c, T x, T lambda) {
  switch (c) {
    case Complement::kStandard:
      return T(1) - x;
    case Complement::kSugeno:
      return (T(1) - x) / (T(1) + lambda * x);
    case Complement::kYager:
      if (!(x > T(0))) return T(1);
      if (x >= T(1)) return T(0);
      return std::pow(-std::expm1(lambda * std::log(x)), T(1) / lambda);
    case Complement::kCosine:
      return T(0.5) * (T(1) + std::cos(std::numbers::pi_v<T> * x));
  }
  return T(0);
}

template <class T>
inline Grad1<T> complement_grad(Complement c, T x, T lambda) {
  switch (c) {
    case Complement::kStandard:
      return {T(1) - x, T(-1), T(0)};
    case Complement::kSugeno: {
      const T inv = T(1) / (T(1) + lambda * x);
      return {(T(1) - x) * inv, -(T(1) + lambda) * inv * inv, -(T(1) - x) * x * inv * inv};
    }
    case Complement::kYager: {
      // C = (1 - x^l)^(1/l): dC/dx = -(x / C)^(l - 1),
      // dC/dl = C (-ln(1 - x^l) / l^2 - x^l ln x / (l (1 - x^l))).
      if (!(x > T(0))) return {T(1), -fuzzycsg::detail::pow_finite(T(0), lambda - T(1)), T(0)};
      if (x >= T(1)) {
        const T slope = lambda > T(1) ? impl::huge_slope<T>() : (lambda == T(1) ? T(1) : T(0));
        return {T(0), -slope, T(0)};
      }
      const T lx = std::log(x);
      const T xl = std::exp(lambda * lx);
      const T om = -std::expm1(lambda * lx);  // 1 - x^l
      const T v = std::pow(om, T(1) / lambda);
      T dx;
      if (v > T(0)) {
        dx = -fuzzycsg::detail::pow_finite(x / v, lambda - T(1));
      } else {
        dx = lambda > T(1) ? -impl::huge_slope<T>() : (lambda == T(1) ? T(-1) : T(0));
      }
      const T dl = v * (-std::log(om) / (lambda * lambda) - xl * lx / (lambda * om));
      return {v, dx, dl};
    }
    case Complement::kCosine: {
      const T px = std::numbers::pi_v<T> * x;
      return {T(0.5) * (T(1) + std::cos(px)), T(-0.5) * std::numbers::pi_v<T> * std::sin(px), T(0)};
    }
  }
  return {};
}

template <class T>
inline T difference(Family f, Complement c, T x, T y, T p, int n, T lambda) {
  return tnorm(f, x, complement(c, y, lambda), p, n);
}

template <class T>
inline DifferenceGrad<T> difference_grad(Family f, Complement c, T x, T y, T p, int n, T lambda) {
  const auto cy = complement_grad(c, y, lambda);
  const auto g = tnorm_grad(f, x, cy.v, p, n);
  return {g.v, g.dx, g.dy * cy.dx, g.dp, g.dy * cy.dp};
}

// ---- unified operator ----

template <class T>
inline T unified(const std::array<T, 4>& c, T x, T y) {
  return (c[1] + c[2]) * x + (c[1] + c[3]) * y + (c[0] - c[1] - c[2] - c[3]) * x * y;
}

template <class T>
inline UnifiedGrad<T> unified_grad(const std::array<T, 4>& c, T x, T y) {
  const T k = c[0] - c[1] - c[2] - c[3];
  const T xy = x * y;
  UnifiedGrad<T> g;
  g.v = (c[1] + c[2]) * x + (c[1] + c[3]) * y + k * xy;
  g.dx = c[1] + c[2] + k * y;
  g.dy = c[1] + c[3] + k * x;
  g.dc = {xy, x + y - xy, x - xy, y - xy};
  return g;
}

}  // namespace fuzzycsg::logic
