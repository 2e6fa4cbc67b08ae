#pragma once
// The hot kernel: occupancy of a compiled tree at a batch of points, and the reverse-mode
// gradient of a loss with respect to every parameter of the tree.
//
// Points are processed in blocks of kBlock (structure of arrays) so that the per-node values of
// one block stay in cache; the tape is walked once forward and once backward per block. Blocks
// are grouped into fixed chunks, each with its own gradient accumulator, summed in chunk order:
// results are identical for any thread count (and bit-identical run to run).

#include <array>
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
    kSum,  // sum_i w_i o_i   (w_i = 1 when no weights; any finite w_i: a vector-Jacobian product)
    kMse,  // sum_i w_i (o_i - t_i)^2 / sum_i w_i   (w_i = 1 when no weights)
  };
  Kind kind = Kind::kSum;
  std::span<const float> targets;  // kMse: one per point
  std::span<const float> weights;  // optional: one per point (kMse: >= 0)
};

// A change of one bilinear operator's constants: the operator z = a x + b y + d x y of tree
// node `node` (a unified operator B_c, or a boolean of product logic) becoming
// (a + da) x + (b + db) y + (d + dd) x y. For B_c, a = c1 + c2, b = c1 + c3 and
// d = c0 - c1 - c2 - c3 (core/logic.hpp), so a change of c is a change of (a, b, d).
struct BilinearEdit {
  int node = -1;
  std::array<double, 3> delta{};  // (da, db, dd)
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
  // When `occupancy` is non-empty it receives the forward values too. When `point_grad` is
  // non-empty (as many entries as `points`) it receives dLoss/dpoints, row-major N x dim (not for
  // trees with spline nodes: InputError).
  double backward(std::span<const double> params, std::span<const float> points, const Loss& loss,
                  std::span<double> grad, std::span<float> occupancy = {},
                  std::span<float> point_grad = {}) const;

  // The loss (kMse only) at the points, and in `changes` (one per edit) how much it would
  // change if that edit alone were made, everything else as in `params`. One forward sweep and
  // one reverse sweep of d root / d value, without the leaves' gradients, serve every edit:
  // the change of the loss is sum_i w_i (2 e_i g_i dv_i + (g_i dv_i)^2) / sum_i w_i, with e the
  // residual, dv the change of the operator's value and g the derivative of the root with
  // respect to that value. The result is exact when every instruction between the operator and
  // the root is bilinear, a standard complement or a spline term (the root is then affine in
  // the operator's value): for trees of unified operators and product logic. Through other
  // logic families it is the first-order estimate. Each node must be an operator that
  // compiles to one bilinear instruction (a binary unified or product-logic boolean).
  double edit_loss_changes(std::span<const double> params, std::span<const float> points,
                           const Loss& loss, std::span<const BilinearEdit> edits,
                           std::span<double> changes) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Double-precision scalar evaluation of the tree at one point, straight from the IR by
// recursion: slow, simple, and the reference the kernel is tested against (its gradients
// against central differences of this function).
double reference_occupancy(const Tree& tree, std::span<const double> params, const double* point);

}  // namespace fuzzycsg
