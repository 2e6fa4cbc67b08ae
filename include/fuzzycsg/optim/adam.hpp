#pragma once
// Adam (Kingma & Ba 2015) with bias correction, as torch.optim.Adam computes it, shared by the
// engines that descend gradients: fit (inverse CSG), trace's refinement and diffcsg's.
//
// Each parameter has its own settings: whether it moves at all, a multiplier of the learning
// rate, whether it is stepped as its logarithm, and the range it is projected back into after
// a step. The moments are not held here: the engines keep them beside their parameters (fit
// checkpoints them, re-seeding and the type search edit them), and a step reads one set of
// parameters and moments and writes another, or the same one.
//
// The arithmetic is that of the engines' own loops before they shared it, operation for
// operation, so that their results stay bit-identical:
//   m' = b1 m + (1 - b1) g,   v' = b2 v + (1 - b2) g g,
//   u  = lr rate (m' / c1) / (sqrt(v' / c2) + eps),   c1 = 1 - b1^k, c2 = 1 - b2^k,
//   x' = project(x - u)                (x' = project(x exp(-u)) in log coordinates).

#include <cstddef>
#include <span>
#include <vector>

#include "fuzzycsg/core/schema.hpp"

namespace fuzzycsg::optim {

struct AdamOptions {
  double beta1 = 0.9, beta2 = 0.999, eps = 1e-8;
  // A parameter whose gradient is NaN or infinite keeps its value and moments for the step
  // (trace's refinement) instead of carrying the NaN into both (fit stops at such a gradient
  // before stepping; diffcsg steps whatever it gets).
  bool skip_non_finite = false;
};

// Parameters and their first and second moments, one entry each per parameter.
struct AdamState {
  std::span<double> params, m, v;
};
struct ConstAdamState {
  std::span<const double> params, m, v;
};

// x kept inside r: a closed bound is clamped to, an open one is kept a small relative distance
// inside (1e-6, or 1e-6 of the bound when that is larger). NaN stays NaN.
double project(double x, const Range& r);

class Adam {
 public:
  // `n` parameters, all free, rate 1, stepped directly, in Range::any().
  explicit Adam(std::size_t n, const AdamOptions& options = {});

  std::size_t size() const { return free_.size(); }
  const AdamOptions& options() const { return options_; }

  // A parameter that is not free is copied through a step unchanged, moments included.
  void set_free(std::size_t i, bool free);
  // The multiplier of the learning rate (0: the value stays, the moments still follow the
  // gradient).
  void set_rate(std::size_t i, double rate);
  // Stepped as u = log x (x > 0): dL/du = x dL/dx and x' = x exp(-du), so that x stays
  // positive and moves by about a factor exp(lr) a step whatever its size.
  void set_log(std::size_t i, bool log);
  void set_range(std::size_t i, const Range& range);

  // Step `k` (counted from 1: the bias correction's exponent) with learning rate `lr`, from
  // `from` into `to`. `to` may be `from` (a step in place) or hold other vectors of the same
  // size; each entry is read before it is written.
  void step(long k, double lr, std::span<const double> grad, const ConstAdamState& from,
            const AdamState& to) const;
  void step(long k, double lr, std::span<const double> grad, const AdamState& state) const;

 private:
  AdamOptions options_;
  std::vector<char> free_, log_;
  std::vector<double> rate_;
  std::vector<Range> range_;
};

}  // namespace fuzzycsg::optim
