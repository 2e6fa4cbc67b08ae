#pragma once
// Private interface between the evaluator and its SIMD kernel.

#include <cstddef>
#include <cstdint>
#include <span>

#include <hwy/aligned_allocator.h>

#include "fuzzycsg/core/program.hpp"
#include "fuzzycsg/eval/evaluator.hpp"

namespace fuzzycsg::kernel {

// Points per block. Per-node values of one block (tape size x kBlock floats) stay in L2 for
// trees of a few thousand nodes.
inline constexpr std::size_t kBlock = 64;

struct Args {
  std::span<const Instruction> tape;
  const PrimitiveShape* const* shapes = nullptr;  // per instruction; null for operators
  const float* consts = nullptr;
  int dim = 3;
  bool has_quadric3 = false;
  const float* points = nullptr;  // N x dim
  float* occupancy = nullptr;     // optional output, N
  Loss::Kind loss_kind = Loss::Kind::kSum;
  const float* targets = nullptr;
  const float* weights = nullptr;
  double loss_scale = 1.0;      // 1 / sum of weights for kMse
  float* point_grad = nullptr;  // optional output, N x dim: d loss / d point

  // Edit mode (edit_first non-null; kMse only): instead of the gradient, the change of the
  // loss sum if one bilinear instruction's constants (a, b, d) changed by an edit's deltas,
  // for every edit. Per instruction: the first of its edits (-1: none) and their count; per
  // edit: 3 deltas; edit_out (per edit) receives the sums of w (2 e g dv + (g dv)^2) over the
  // points, with e the residual, g = d root / d value and dv the change of the value.
  const std::int32_t* edit_first = nullptr;
  const std::int32_t* edit_count = nullptr;
  const float* edit_delta = nullptr;
  double* edit_out = nullptr;
};

// Per-thread scratch memory, allocated once per evaluator and thread.
struct Scratch {
  hwy::AlignedFreeUniquePtr<float[]> values;      // tape size x kBlock
  hwy::AlignedFreeUniquePtr<float[]> stack;       // (max stack depth + 1) x kBlock
  hwy::AlignedFreeUniquePtr<float[]> points;      // 3 x kBlock
  hwy::AlignedFreeUniquePtr<float[]> monomials;   // 9 x kBlock
  hwy::AlignedFreeUniquePtr<float[]> dtheta;      // largest intrinsic parameter count
  hwy::AlignedFreeUniquePtr<float[]> residual;    // edit mode: w e, then w, per point (2 x kBlock)
  hwy::AlignedFreeUniquePtr<float[]> point_grad;  // d loss / d point of the block (3 x kBlock)

  Scratch(std::size_t tape_size, std::size_t stack_depth, std::size_t max_theta);
};

// Evaluates points [begin, end). With grad non-null, also runs the reverse sweep and adds the
// gradient wrt the constants into grad (double, num_consts) and the loss into *loss. In edit
// mode grad must be non-null (scratch for instructions that accumulate anyway) and receives
// nothing useful; the edits' sums go to args.edit_out.
void run(const Args& args, std::size_t begin, std::size_t end, Scratch& scratch, double* grad,
         double* loss);

// Name of the SIMD target the kernel dispatches to ("AVX3", "AVX2", ...).
const char* target_name();

}  // namespace fuzzycsg::kernel
