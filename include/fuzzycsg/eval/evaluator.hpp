#pragma once
// The hot kernel: occupancy of a compiled tree at a batch of points, and the reverse-mode
// gradient of a loss with respect to every parameter of the tree.
//
// Points are processed in blocks of kBlock (structure of arrays) so that the per-node values of
// one block stay in cache; the tape is walked once forward and once backward per block. Blocks
// are grouped into fixed chunks, each with its own gradient accumulator, summed in chunk order:
// results are identical for any thread count (and bit-identical run to run).

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fuzzycsg/core/program.hpp"
#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg {

struct EvalOptions {
  int threads = 0;  // 0: all hardware threads
  // Subnormal floats (below 1.2e-38: saturated sigmoids of sharp primitives far from their
  // surface, and their products) are flushed to zero inside the kernel, which keeps the
  // arithmetic off the processor's slow path; off only to measure what that buys
  // (bench/subnormal_bench).
  bool flush_subnormals = true;
};

// What backward() differentiates.
struct Loss {
  enum class Kind {
    kSum,  // sum_i o_i
    kMse,  // sum_i w_i (o_i - t_i)^2 / sum_i w_i   (w_i = 1 when no weights)
  };
  Kind kind = Kind::kSum;
  std::span<const float> targets;  // kMse: one per point
  std::span<const float> weights;  // kMse, optional: one per point
};

class Evaluator {
 public:
  explicit Evaluator(const Tree& tree, EvalOptions options = {});
  ~Evaluator();
  Evaluator(Evaluator&&) noexcept;
  Evaluator& operator=(Evaluator&&) noexcept;

  const Program& program() const;
  int dim() const;
  std::size_t num_params() const;

  // Occupancy at N points (row-major N x dim) with the parameter vector `params` (the tree's
  // parameter table order). out.size() == N.
  void forward(std::span<const double> params, std::span<const float> points,
               std::span<float> out) const;

  // Loss value, and grad (size num_params()) = dLoss/dparams. Fixed parameters get 0.
  // When `occupancy` is non-empty it receives the forward values too.
  double backward(std::span<const double> params, std::span<const float> points, const Loss& loss,
                  std::span<double> grad, std::span<float> occupancy = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Double-precision scalar evaluation of the tree at one point, straight from the IR by
// recursion: slow, simple, and the reference the kernel is tested against (its gradients
// against central differences of this function).
double reference_occupancy(const Tree& tree, std::span<const double> params, const double* point);

}  // namespace fuzzycsg
