#pragma once
// The basis of the fuzzy spline node (Li & Tian 2008, §2.2): F(p) = sum_k L_k(p) B_k(p), the
// L_k fuzzy sets and the B_k tensor products of clamped (open) uniform B-splines, one family per
// axis, so that 0 <= B_k <= 1 and sum_k B_k = 1 everywhere and F is again a fuzzy set.
//
// One axis has n basis functions N_0 .. N_{n-1} of degree d (n >= d + 1) over [lo, hi]. They
// are written in the normalised parameter u = (x - lo) (n - d) / (hi - lo), clamped to
// [0, m] with m = n - d, where the knot vector is d + 1 zeros, the interior knots 1 .. m - 1 and
// d + 1 copies of m: knot j is clamp(j - d, 0, m), j = 0 .. n + d. A coordinate outside
// [lo, hi] is clamped to it, so the basis stays a partition of unity everywhere.
//
// N_i is positive on the open interval (t_i, t_{i+d+1}) and 0 outside it, except that the clamped
// ends give N_0(0) = 1 and N_{n-1}(m) = 1.

#include <algorithm>
#include <cstddef>

namespace fuzzycsg::bspline {

inline constexpr int kMinDegree = 1;
inline constexpr int kMaxDegree = 5;
inline constexpr int kDefaultDegree = 2;
inline constexpr int kMaxCells = 256;  // basis functions per axis

// Knot j (0 <= j <= n + d) of the clamped uniform knot vector, in the normalised parameter.
constexpr int knot(int j, int n, int d) { return std::clamp(j - d, 0, n - d); }

// The normalised parameter of coordinate x on an axis that starts at lo, with
// scale = (n - d) / (hi - lo), clamped to [0, m].
template <class T>
inline T parameter(T x, T lo, T scale, T m) {
  const T u = (x - lo) * scale;
  return u < T(0) ? T(0) : (u > m ? m : u);
}

// N_{i,d}(u) for 0 <= i < n and u in [0, n - d]: the Cox-de Boor triangle over the d + 1 knot
// spans of N_i's support (The NURBS Book, algorithm A2.4), O(d^2). Spans are half-open,
// [t_j, t_{j+1}), except that u = m belongs to the last one. 1 <= d <= kMaxDegree.
template <class T>
inline T basis(int i, int n, int d, T u) {
  const int m = n - d;
  if (i == 0 && u <= T(0)) return T(1);
  if (i == n - 1 && u >= static_cast<T>(m)) return T(1);
  if (!(u >= static_cast<T>(knot(i, n, d)) && u < static_cast<T>(knot(i + d + 1, n, d)))) {
    return T(0);
  }
  T v[kMaxDegree + 1];
  for (int j = 0; j <= d; ++j) {
    v[j] = (u >= static_cast<T>(knot(i + j, n, d)) && u < static_cast<T>(knot(i + j + 1, n, d)))
               ? T(1)
               : T(0);
  }
  for (int k = 1; k <= d; ++k) {
    const T ti = static_cast<T>(knot(i, n, d));
    T saved = v[0] == T(0) ? T(0) : (u - ti) * v[0] / (static_cast<T>(knot(i + k, n, d)) - ti);
    for (int j = 0; j <= d - k; ++j) {
      const T left = static_cast<T>(knot(i + j + 1, n, d));
      const T right = static_cast<T>(knot(i + j + k + 1, n, d));
      if (v[j + 1] == T(0)) {
        v[j] = saved;
        saved = T(0);
      } else {
        const T t = v[j + 1] / (right - left);
        v[j] = saved + (right - u) * t;
        saved = (u - left) * t;
      }
    }
  }
  return v[0];
}

// Whether N_{i,d} is positive somewhere on [a, b], 0 <= a <= b <= n - d.
inline bool positive_on(int i, int n, int d, double a, double b) {
  if (i == 0 && a <= 0.0) return true;
  if (i == n - 1 && b >= static_cast<double>(n - d)) return true;
  return a < static_cast<double>(knot(i + d + 1, n, d)) && b > static_cast<double>(knot(i, n, d));
}

// The parameter interval [a, b] of the coordinates [x0, x1] (x0 <= x1) on an axis as in
// parameter(). It is not widened: a box that ends on a knot must not count the function that
// starts there. Rounding of u by a few ulps can only misjudge a basis function whose values on
// the box are of that order (each N_i is continuous and 0 at the ends of its support, with
// |N_i'| <= 2 d), far below the slack that bounds and meshing allow.
inline void parameter_interval(double x0, double x1, double lo, double scale, double m, double& a,
                               double& b) {
  a = std::clamp((x0 - lo) * scale, 0.0, m);
  b = std::clamp((x1 - lo) * scale, 0.0, m);
}

// Bounds [lo, hi] of N_{i,d} over [a, b] (0 <= a <= b <= n - d). B-splines are unimodal (log-
// concave, Curry & Schoenberg), so the minimum is at an end; the maximum is bounded through the
// midpoint with the Lipschitz constant d of N_i in u (N_i' = d (N_{i,d-1} / (t_{i+d} - t_i) -
// N_{i+1,d-1} / (t_{i+d+1} - t_{i+1})), the knots at least 1 apart), and by 1.
inline void basis_range(int i, int n, int d, double a, double b, double& lo, double& hi) {
  if (!positive_on(i, n, d, a, b)) {
    lo = hi = 0.0;
    return;
  }
  lo = std::min(basis<double>(i, n, d, a), basis<double>(i, n, d, b));
  hi = std::min(1.0, basis<double>(i, n, d, 0.5 * (a + b)) + d * 0.5 * (b - a));
}

// Whether the tensor-product basis function k (x index fastest) of a spline with cells[axis]
// functions of degree d per axis is positive somewhere on the box whose parameter intervals
// are [a[axis], b[axis]].
inline bool tensor_positive_on(std::size_t k, int dim, const int* cells, int d, const double* a,
                               const double* b) {
  for (int axis = 0; axis < dim; ++axis) {
    const auto n = static_cast<std::size_t>(cells[axis]);
    if (!positive_on(static_cast<int>(k % n), cells[axis], d, a[axis], b[axis])) return false;
    k /= n;
  }
  return true;
}

}  // namespace fuzzycsg::bspline
