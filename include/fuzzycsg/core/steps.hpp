#pragma once
// Occupancy maps ("steps"): functions taking an implicit value to a membership in [0, 1].
//
// The tree's convention is f negative inside, so the occupancy of a leaf is step(-f):
//   sigmoid:  o = 1 / (1 + exp(s f))            (TREE_FORMAT; Liu et al. App. A eq. 20)
//   crisp:    o = H_0(-f)                         (1 inside, 0 outside, 1/2 on the surface)
//   hn:       o = H_n(n (-f) / R) = H_{n,R}(-f)   (Li & Tian eq. 2-3)
// and Li & Tian's logistic H_inf(x) = 1 / (1 + exp(-alpha x)) (eq. 1).

#include "fuzzycsg/core/logic.hpp"

namespace fuzzycsg::steps {

// Heaviside H_0 with H_0(0) = 1/2.
template <class T>
T heaviside(T x);
// Li & Tian's H_n (eq. 2), n >= 0: C^{n-1}, piecewise polynomial, 0 for x <= -n, 1 for x >= n.
template <class T>
T hn(int n, T x);
template <class T>
logic::Grad1<T> hn_grad(int n, T x);  // dx only
// H_{n,R}(x) = H_n(n x / R) (eq. 3); dp = d/dR.
template <class T>
T hn_range(int n, T x, T range);
template <class T>
logic::Grad1<T> hn_range_grad(int n, T x, T range);
// Logistic H_inf(x) = 1 / (1 + exp(-alpha x)); dp = d/dalpha.
template <class T>
T logistic(T x, T alpha);
template <class T>
logic::Grad1<T> logistic_grad(T x, T alpha);

}  // namespace fuzzycsg::steps

#include "fuzzycsg/core/steps_inl.hpp"  // IWYU pragma: export
