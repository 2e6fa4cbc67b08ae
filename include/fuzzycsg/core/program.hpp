#pragma once
// A tree compiled into a flat post-order tape (Liu et al. App. A, after Grasberger et al.):
// every instruction reads the slots of its inputs, which come earlier in the tape, and writes
// its own slot. n-ary unions and intersections are folded left into binary instructions, and a
// spline node into one instruction per child: acc + B_k(p) L_k (the first without acc).
//
// Parameters are mapped to per-instruction *constants* once per call (prepare): rotation
// matrices from Euler angles, the bilinear coefficients (a, b, d) of a unified operator from its
// logits, and so on. The kernel works on constants only; its gradient with respect to the
// constants is pulled back to the parameters once per call (pullback).

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg {

enum class OpCode : std::uint8_t {
  kLeafQuadric3,  // 3D or 2D (z = 0) quadric, no placement, sigmoid step: q0..q9, sharpness
  kLeaf,          // any primitive: theta, [R], [t], [s], [step parameter]
  kBilinear,      // a x + b y + d x y: product-logic booleans and the unified operator B_c
  kLogic,         // intersection / union / difference of another logic family
  kComplement,    // C(x)
  kSplineTerm,    // [left +] B_k(p) right: one term of a spline node (left -1 for the first)
};

enum class LogicOp : std::uint8_t { kIntersection, kUnion, kDifference };

enum class BilinearSource : std::uint8_t {
  kConstant,     // product union / intersection / difference: no parameters
  kBarycentric,  // unified with "c"
  kLogits,       // unified with "logits", temperature, omega
};

struct Instruction {
  OpCode code = OpCode::kLeaf;
  int node = -1;              // the tree node this instruction evaluates (or folds)
  int left = -1, right = -1;  // input slots
  std::uint32_t consts = 0;   // offset of this instruction's constants
  std::uint32_t num_consts = 0;

  // kLeaf, kLeafQuadric3
  int num_theta = 0;
  bool has_rotate = false, has_translate = false, has_scale = false;
  StepKind step = StepKind::kSigmoid;
  int step_n = 0;
  // Offsets within this instruction's constants (kLeaf).
  std::uint32_t rotate_at = 0, translate_at = 0, scale_at = 0, step_at = 0;
  // kLeaf: a sphere or circle placed by a translation alone, with a sigmoid step (radius,
  // centre, sharpness), which the kernel runs on SIMD vectors.
  bool ball = false;

  // kBilinear
  BilinearSource bilinear = BilinearSource::kConstant;
  // kLogic, kComplement
  LogicOp logic_op = LogicOp::kIntersection;
  logic::Family family = logic::Family::kProduct;
  int n = 0;
  logic::Complement complement = logic::Complement::kStandard;

  // kSplineTerm: B_k is the product over the axes of N_{index[a]} of the spline's degree with
  // cells[a] functions (core/bspline.hpp). Constants: per axis the box's min, then per axis
  // the scale (cells - degree) / (max - min) of the normalised parameter.
  int spline_degree = 0;
  std::array<std::int16_t, 3> spline_index{}, spline_cells{};
};

// d loss / d parameter contributed by one instruction (before summing over instructions that
// share the parameter).
struct RefGrad {
  std::uint32_t index = 0;
  double value = 0.0;
};

class Program {
 public:
  // The tree must be valid (validate()).
  static Program compile(const Tree& tree);

  const Tree& tree() const { return tree_; }
  int dim() const { return tree_.dim; }
  std::span<const Instruction> tape() const { return tape_; }
  std::size_t num_params() const { return tree_.params.size(); }
  std::size_t num_consts() const { return num_consts_; }
  // Largest number of adjoint blocks live at once during a backward sweep.
  int max_stack_depth() const { return max_stack_; }
  int num_leaves() const { return num_leaves_; }
  bool has_quadric_fast_path() const { return has_quadric3_; }

  // consts (size num_consts()) from the parameter vector (size num_params()), for the
  // instructions [begin, end) (default: all). Ranges write disjoint constants, so they may run
  // in parallel.
  void prepare(std::span<const double> params, std::span<double> consts, std::size_t begin = 0,
               std::size_t end = static_cast<std::size_t>(-1)) const;
  // grad_params += (d consts / d params)^T grad_consts. Fixed parameters receive nothing.
  void pullback(std::span<const double> params, std::span<const double> grad_consts,
                std::span<double> grad_params) const;
  // The same in two steps: per-instruction contributions for [begin, end) into `out` (size
  // num_ref_grads(); ranges write disjoint entries, so they may run in parallel), then their
  // sum in a fixed order.
  std::size_t num_ref_grads() const { return ref_offsets_.empty() ? 0 : ref_offsets_.back(); }
  void pullback_local(std::span<const double> params, std::span<const double> grad_consts,
                      std::span<RefGrad> out, std::size_t begin, std::size_t end) const;
  void scatter(std::span<const RefGrad> ref_grads, std::span<double> grad_params) const;

 private:
  template <class Sink>
  void pullback_instruction(const Instruction& ins, std::span<const double> params,
                            std::span<const double> grad_consts, Sink& sink) const;
  void count_refs();

  Tree tree_;
  std::vector<std::uint32_t> ref_offsets_;  // per instruction, into the RefGrad list
  std::vector<Instruction> tape_;
  std::size_t num_consts_ = 0;
  int max_stack_ = 0;
  int num_leaves_ = 0;
  bool has_quadric3_ = false;
};

}  // namespace fuzzycsg
