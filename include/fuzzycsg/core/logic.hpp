#pragma once
// Fuzzy logic on soft occupancy: t-norms, t-conorms, complements, the Bézier operators and
// Li & Tian's shape-preserving operators (Li & Tian 2008), and the unified operator B_c of
// Liu et al. 2024 (eq. 12, 21). Every function is pure, templated on the scalar type (float,
// double) and has a companion *_grad returning the first derivatives.
//
// Inputs x, y are memberships in [0, 1]. `p` is the family's one continuous parameter
// (Yager p, Hamacher a, Dombi lambda, Dubois-Prade k, Weber k, Li-Tian delta; ignored
// otherwise) and `n` its integer degree (Bézier n, Li-Tian n; ignored otherwise).

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>

namespace fuzzycsg::logic {

enum class Family {
  kProduct,      // xy
  kGodel,        // min(x, y)
  kLukasiewicz,  // max(0, x + y - 1)
  kYager,        // max(0, 1 - ((1-x)^p + (1-y)^p)^(1/p)), p > 0
  kEinstein,     // xy / (2 - (x + y - xy))
  kHamacher,     // xy / (a + (1-a)(x + y - xy)), a >= 0
  kDombi,        // 1 / (1 + ((1/x - 1)^l + (1/y - 1)^l)^(1/l)), l > 0
  kDuboisPrade,  // xy / max(x, y, k), k in (0, 1]
  kWeber,        // max(0, (x + y + kxy - 1) / (1 + k)), k > -1
  kBezier,       // Li & Tian eq. 4, degree n >= 1
  kLiTian,       // Li & Tian eq. 20, the shape-preserving AND_{n,delta} (*)
  kLiTianHat,    // Li & Tian eq. 21-25, hat-AND_{n,delta} (*)
  // (*) with the Coons corner term corrected so that the identity and dominance laws hold for
  //     every delta > 0 (see logic_inl.hpp, impl::coons_min).
};

enum class Complement {
  kStandard,  // 1 - x
  kSugeno,    // (1 - x) / (1 + lambda x), lambda > -1
  kYager,     // (1 - x^lambda)^(1/lambda), lambda > 0
  kCosine,    // (1 + cos(pi x)) / 2
};

// Name used in tree files ("product", "godel", "lukasiewicz", "yager", "einstein", "hamacher",
// "dombi", "dubois-prade", "weber", "bezier", "li-tian", "li-tian-hat").
std::string_view family_name(Family f);
std::optional<Family> family_from_name(std::string_view name);
// True for the families that satisfy the four t-norm axioms (all but kBezier, kLiTian,
// kLiTianHat, which Li & Tian only prove boundary/commutativity properties for).
bool is_tnorm(Family f);
// Does the family use `p` / `n`? Name of the tree-file field for p ("p", "a", "lambda", "k",
// "delta"); empty when unused.
bool uses_p(Family f);
bool uses_n(Family f);
std::string_view p_field_name(Family f);

std::string_view complement_name(Complement c);  // "standard", "sugeno", "yager", "cosine"
std::optional<Complement> complement_from_name(std::string_view name);
bool complement_uses_lambda(Complement c);

// Value and partial derivatives of a binary operator.
template <class T>
struct Grad2 {
  T v{}, dx{}, dy{}, dp{};  // dp: derivative wrt the continuous parameter (0 if none)
};
template <class T>
struct Grad1 {
  T v{}, dx{}, dp{};
};

// Intersection (t-norm or Li-Tian AND), union via De Morgan with the standard complement
// S(x, y) = 1 - T(1 - x, 1 - y), difference x \ y = T(x, C(y)).
template <class T>
T tnorm(Family f, T x, T y, T p, int n);
template <class T>
Grad2<T> tnorm_grad(Family f, T x, T y, T p, int n);
template <class T>
T tconorm(Family f, T x, T y, T p, int n);
template <class T>
Grad2<T> tconorm_grad(Family f, T x, T y, T p, int n);

template <class T>
T complement(Complement c, T x, T lambda);
template <class T>
Grad1<T> complement_grad(Complement c, T x, T lambda);  // dp = d/dlambda

template <class T>
T difference(Family f, Complement c, T x, T y, T p, int n, T lambda);
template <class T>
struct DifferenceGrad {
  T v{}, dx{}, dy{}, dp{}, dlambda{};
};
template <class T>
DifferenceGrad<T> difference_grad(Family f, Complement c, T x, T y, T p, int n, T lambda);

// Block forms over contiguous arrays (structure of arrays), out[i] = op(x[i], y[i]).
void tnorm_block(Family f, std::span<const float> x, std::span<const float> y, std::span<float> out,
                 float p, int n);
void tconorm_block(Family f, std::span<const float> x, std::span<const float> y,
                   std::span<float> out, float p, int n);

// ---- Li & Tian building blocks (all with derivatives wrt x and, where present, delta) ----
// Bézier operator B_n (eq. 4).
template <class T>
T bezier(int n, T x, T y);
template <class T>
Grad2<T> bezier_grad(int n, T x, T y);
// Upper smooth absolute value |x|_n (eq. 8) and |x|_{n,delta} (eq. 9).
template <class T>
T upper_abs(int n, T x);
template <class T>
Grad1<T> upper_abs_grad(int n, T x);
template <class T>
T upper_abs(int n, T x, T delta);
template <class T>
Grad1<T> upper_abs_grad(int n, T x, T delta);  // dp = d/ddelta
// Lower smooth absolute value hat|x|_n (eq. 10) and hat|x|_{n,delta} (eq. 11).
template <class T>
T lower_abs(int n, T x);
template <class T>
Grad1<T> lower_abs_grad(int n, T x);
template <class T>
T lower_abs(int n, T x, T delta);
template <class T>
Grad1<T> lower_abs_grad(int n, T x, T delta);
// Smooth minima min_{n,delta} (eq. 12, from the upper abs) and hat-min_{n,delta} (eq. 13).
template <class T>
T smooth_min(int n, T x, T y, T delta);
template <class T>
Grad2<T> smooth_min_grad(int n, T x, T y, T delta);
template <class T>
T smooth_min_hat(int n, T x, T y, T delta);
template <class T>
Grad2<T> smooth_min_hat_grad(int n, T x, T y, T delta);
// Shape-preserving operators AND_{n,delta} (eq. 14-20) and hat-AND_{n,delta} (eq. 21-25).
template <class T>
T li_tian_and(int n, T x, T y, T delta);
template <class T>
Grad2<T> li_tian_and_grad(int n, T x, T y, T delta);
template <class T>
T li_tian_hat_and(int n, T x, T y, T delta);
template <class T>
Grad2<T> li_tian_hat_and_grad(int n, T x, T y, T delta);

// ---- The unified operator of Liu et al. 2024 ----
// B_c(x, y) = (c1 + c2) x + (c1 + c3) y + (c0 - c1 - c2 - c3) x y   (eq. 12)
// c0 intersection, c1 union, c2 x \ y, c3 y \ x.
template <class T>
T unified(const std::array<T, 4>& c, T x, T y);
template <class T>
struct UnifiedGrad {
  T v{}, dx{}, dy{};
  std::array<T, 4> dc{};
};
template <class T>
UnifiedGrad<T> unified_grad(const std::array<T, 4>& c, T x, T y);

// c = softmax(sin(omega * logits) * t)   (eq. 21)
std::array<double, 4> unified_weights(const std::array<double, 4>& logits, double t, double omega);
// Vector-Jacobian product of unified_weights: given g = dL/dc, returns dL/dlogits and, through
// the optional outputs, dL/dt and dL/domega.
std::array<double, 4> unified_weights_vjp(const std::array<double, 4>& logits, double t,
                                          double omega, const std::array<double, 4>& g,
                                          double* dt = nullptr, double* domega = nullptr);

}  // namespace fuzzycsg::logic

#include "fuzzycsg/core/logic_inl.hpp"  // IWYU pragma: export
