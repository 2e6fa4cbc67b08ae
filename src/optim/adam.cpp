#include "fuzzycsg/optim/adam.hpp"

#include <algorithm>
#include <cmath>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::optim {

double project(double x, const Range& r) {
  if (x < r.lo || (r.lo_open && x <= r.lo)) {
    x = r.lo_open ? r.lo + std::max(1e-6, std::abs(r.lo) * 1e-6) : r.lo;
  }
  if (x > r.hi || (r.hi_open && x >= r.hi)) {
    x = r.hi_open ? r.hi - std::max(1e-6, std::abs(r.hi) * 1e-6) : r.hi;
  }
  return x;
}

Adam::Adam(std::size_t n, const AdamOptions& options)
    : options_(options), free_(n, 1), log_(n, 0), rate_(n, 1.0), range_(n, Range::any()) {}

void Adam::set_free(std::size_t i, bool free) { free_.at(i) = free ? 1 : 0; }
void Adam::set_rate(std::size_t i, double rate) { rate_.at(i) = rate; }
void Adam::set_log(std::size_t i, bool log) { log_.at(i) = log ? 1 : 0; }
void Adam::set_range(std::size_t i, const Range& range) { range_.at(i) = range; }

void Adam::step(long k, double lr, std::span<const double> grad, const ConstAdamState& from,
                const AdamState& to) const {
  const std::size_t n = size();
  if (grad.size() != n || from.params.size() != n || from.m.size() != n || from.v.size() != n ||
      to.params.size() != n || to.m.size() != n || to.v.size() != n) {
    throw Error("adam: the gradient, parameters and moments must have one entry per parameter");
  }
  const double b1 = options_.beta1, b2 = options_.beta2;
  const double c1 = 1.0 - std::pow(b1, static_cast<double>(k));
  const double c2 = 1.0 - std::pow(b2, static_cast<double>(k));
  for (std::size_t i = 0; i < n; ++i) {
    const double x = from.params[i];
    if (!free_[i] || (options_.skip_non_finite && !std::isfinite(grad[i]))) {
      const double m = from.m[i], v = from.v[i];
      to.params[i] = x;
      to.m[i] = m;
      to.v[i] = v;
      continue;
    }
    // In log coordinates u = log x: dL/du = x dL/dx, and x' = exp(u - du) = x exp(-du).
    const double g = log_[i] ? grad[i] * x : grad[i];
    const double m = b1 * from.m[i] + (1.0 - b1) * g;
    const double v = b2 * from.v[i] + (1.0 - b2) * g * g;
    // (lr * rate) first: with rate 1 that is lr itself, the product the engines formed before
    // they had rates.
    const double update = lr * rate_[i] * (m / c1) / (std::sqrt(v / c2) + options_.eps);
    const double next = log_[i] ? x * std::exp(-update) : x - update;
    to.m[i] = m;
    to.v[i] = v;
    to.params[i] = project(next, range_[i]);
  }
}

void Adam::step(long k, double lr, std::span<const double> grad, const AdamState& state) const {
  step(k, lr, grad, ConstAdamState{state.params, state.m, state.v}, state);
}

}  // namespace fuzzycsg::optim
