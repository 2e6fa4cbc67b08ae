#include "fuzzycsg/core/program.hpp"

#include <algorithm>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/placement.hpp"

namespace fuzzycsg {

namespace {

// Where the 2D quadric's coefficients (x², y², xy, x, y, 1) sit among the 3D quadric's
// (x², y², z², xy, yz, zx, x, y, z, 1).
constexpr int kQuadric2Slots[6] = {0, 1, 3, 6, 7, 9};

bool is_product_standard(const Node& n) {
  return n.logic.family == logic::Family::kProduct &&
         (n.op != OpKind::kDifference || n.complement.kind == logic::Complement::kStandard);
}

double value_or(std::span<const double> params, const std::optional<ParamRef>& r, double dflt) {
  return r ? params[r->index] : dflt;
}

}  // namespace

Program Program::compile(const Tree& tree) {
  Program prog;
  prog.tree_ = tree;
  const int dim = tree.dim;
  std::uint32_t next_const = 0;
  int leaves = 0;

  auto emit_leaf = [&](int node_index) {
    const Node& node = tree.node(node_index);
    Instruction ins;
    ins.node = node_index;
    ins.num_theta = static_cast<int>(node.intrinsic.size());
    ins.step = node.step.kind;
    ins.step_n = node.step.n;
    ins.consts = next_const;
    // The 2D quadric runs on the 3D fast path with z = 0 (its six coefficients placed among the
    // ten, the others 0).
    if ((node.shape.type == PrimitiveType::kQuadric3 ||
         node.shape.type == PrimitiveType::kQuadric2) &&
        node.placement.empty() && node.step.kind == StepKind::kSigmoid) {
      ins.code = OpCode::kLeafQuadric3;
      ins.num_consts = 11;
      prog.has_quadric3_ = true;
    } else {
      ins.code = OpCode::kLeaf;
      std::uint32_t k = static_cast<std::uint32_t>(ins.num_theta);
      ins.has_rotate = !node.placement.rotate.empty();
      ins.has_translate = !node.placement.translate.empty();
      ins.has_scale = node.placement.scale.has_value();
      ins.rotate_at = k;
      if (ins.has_rotate) k += static_cast<std::uint32_t>(dim * dim);
      ins.translate_at = k;
      if (ins.has_translate) k += static_cast<std::uint32_t>(dim);
      ins.scale_at = k;
      if (ins.has_scale) k += 1;
      ins.step_at = k;
      if (node.step.kind != StepKind::kCrisp) k += 1;
      ins.num_consts = k;
      ins.ball = (node.shape.type == PrimitiveType::kSphere ||
                  node.shape.type == PrimitiveType::kCircle) &&
                 ins.has_translate && !ins.has_rotate && !ins.has_scale &&
                 node.step.kind == StepKind::kSigmoid;
      // The kernel's ball path reads radius, centre, sharpness at these offsets.
      FUZZYCSG_ASSERT(!ins.ball || (ins.num_theta == 1 && ins.translate_at == 1 &&
                                    ins.step_at == 1 + static_cast<std::uint32_t>(dim)));
    }
    next_const += ins.num_consts;
    ++leaves;
    prog.tape_.push_back(ins);
    return static_cast<int>(prog.tape_.size()) - 1;
  };

  auto emit_op = [&](int node_index, int left, int right) {
    const Node& node = tree.node(node_index);
    Instruction ins;
    ins.node = node_index;
    ins.left = left;
    ins.right = right;
    ins.consts = next_const;
    if (node.op == OpKind::kComplement) {
      ins.code = OpCode::kComplement;
      ins.complement = node.complement.kind;
      ins.num_consts = 1;
    } else if (node.op == OpKind::kUnified) {
      ins.code = OpCode::kBilinear;
      ins.bilinear = node.unified_logits ? BilinearSource::kLogits : BilinearSource::kBarycentric;
      ins.num_consts = 3;
    } else if (is_product_standard(node)) {
      ins.code = OpCode::kBilinear;
      ins.bilinear = BilinearSource::kConstant;
      ins.logic_op = node.op == OpKind::kUnion          ? LogicOp::kUnion
                     : node.op == OpKind::kIntersection ? LogicOp::kIntersection
                                                        : LogicOp::kDifference;
      ins.num_consts = 3;
    } else {
      ins.code = OpCode::kLogic;
      ins.logic_op = node.op == OpKind::kUnion          ? LogicOp::kUnion
                     : node.op == OpKind::kIntersection ? LogicOp::kIntersection
                                                        : LogicOp::kDifference;
      ins.family = node.logic.family;
      ins.n = node.logic.n;
      ins.complement = node.complement.kind;
      ins.num_consts = 2;
    }
    next_const += ins.num_consts;
    prog.tape_.push_back(ins);
    return static_cast<int>(prog.tape_.size()) - 1;
  };

  // Term k of a spline node: acc + B_k(p) y (acc < 0: the first term, B_k(p) y).
  auto emit_spline_term = [&](int node_index, std::size_t k, int acc, int y) {
    const Node& node = tree.node(node_index);
    Instruction ins;
    ins.code = OpCode::kSplineTerm;
    ins.node = node_index;
    ins.left = acc;
    ins.right = y;
    ins.consts = next_const;
    ins.num_consts = static_cast<std::uint32_t>(2 * dim);
    ins.spline_degree = node.spline_degree;
    std::size_t rest = k;
    for (int a = 0; a < dim; ++a) {
      const auto cells = static_cast<std::size_t>(node.spline_cells[static_cast<std::size_t>(a)]);
      ins.spline_cells[a] = static_cast<std::int16_t>(cells);
      ins.spline_index[a] = static_cast<std::int16_t>(rest % cells);
      rest /= cells;
    }
    next_const += ins.num_consts;
    prog.tape_.push_back(ins);
    return static_cast<int>(prog.tape_.size()) - 1;
  };

  // Iterative post-order walk (trees can be deeper than the call stack allows).
  struct Frame {
    int node;
    std::size_t next_child = 0;
    int acc = -1;  // slot of the left fold so far
  };
  std::vector<Frame> stack;
  stack.push_back({tree.root});
  int result = -1;
  while (!stack.empty()) {
    Frame& f = stack.back();
    const Node& node = tree.node(f.node);
    int done_slot = -1;
    if (node.kind == NodeKind::kPrimitive) {
      done_slot = emit_leaf(f.node);
    } else if (f.next_child < node.children.size()) {
      const int child = node.children[f.next_child++];
      stack.push_back({child});
      continue;
    } else {
      done_slot = node.op == OpKind::kComplement ? emit_op(f.node, f.acc, -1) : f.acc;
    }
    stack.pop_back();
    if (stack.empty()) {
      result = done_slot;
      break;
    }
    Frame& parent = stack.back();
    const Node& pnode = tree.node(parent.node);
    if (pnode.op == OpKind::kSpline) {
      parent.acc = emit_spline_term(parent.node, parent.next_child - 1, parent.acc, done_slot);
    } else if (parent.acc < 0 || pnode.op == OpKind::kComplement) {
      parent.acc = done_slot;
    } else {
      parent.acc = emit_op(parent.node, parent.acc, done_slot);
    }
  }
  FUZZYCSG_ASSERT(result == static_cast<int>(prog.tape_.size()) - 1);
  (void)result;
  prog.num_consts_ = next_const;
  prog.num_leaves_ = leaves;

  // Adjoint stack depth of the reverse sweep: each instruction pops one block and pushes one
  // per input.
  int depth = 1, max_depth = 1;
  for (auto it = prog.tape_.rbegin(); it != prog.tape_.rend(); ++it) {
    depth -= 1;
    depth += (it->left >= 0) + (it->right >= 0);
    max_depth = std::max(max_depth, depth);
  }
  prog.max_stack_ = max_depth;
  prog.count_refs();
  return prog;
}

void Program::prepare(std::span<const double> params, std::span<double> consts, std::size_t begin,
                      std::size_t end) const {
  FUZZYCSG_ASSERT(params.size() == num_params() && consts.size() == num_consts_);
  const int dim = tree_.dim;
  end = std::min(end, tape_.size());
  for (std::size_t k = begin; k < end; ++k) {
    const Instruction& ins = tape_[k];
    const Node& node = tree_.node(ins.node);
    double* c = consts.data() + ins.consts;
    switch (ins.code) {
      case OpCode::kLeafQuadric3:
        if (node.shape.type == PrimitiveType::kQuadric2) {
          std::fill(c, c + 10, 0.0);
          for (int i = 0; i < 6; ++i) c[kQuadric2Slots[i]] = params[node.intrinsic[i].index];
        } else {
          for (int i = 0; i < 10; ++i) c[i] = params[node.intrinsic[i].index];
        }
        c[10] = params[node.step.param->index];
        break;
      case OpCode::kLeaf: {
        for (int i = 0; i < ins.num_theta; ++i) c[i] = params[node.intrinsic[i].index];
        const auto& pl = node.placement;
        if (ins.has_rotate) {
          if (dim == 3) {
            const auto r = placement::rotation_3d(
                params[pl.rotate[0].index], params[pl.rotate[1].index], params[pl.rotate[2].index]);
            std::copy(r.begin(), r.end(), c + ins.rotate_at);
          } else {
            const auto r = placement::rotation_2d(params[pl.rotate[0].index]);
            std::copy(r.begin(), r.end(), c + ins.rotate_at);
          }
        }
        if (ins.has_translate) {
          for (int i = 0; i < dim; ++i) c[ins.translate_at + i] = params[pl.translate[i].index];
        }
        if (ins.has_scale) c[ins.scale_at] = params[pl.scale->index];
        if (ins.step != StepKind::kCrisp) c[ins.step_at] = params[node.step.param->index];
        break;
      }
      case OpCode::kBilinear: {
        std::array<double, 4> w{};
        switch (ins.bilinear) {
          case BilinearSource::kConstant:
            w = ins.logic_op == LogicOp::kIntersection ? std::array<double, 4>{1, 0, 0, 0}
                : ins.logic_op == LogicOp::kUnion      ? std::array<double, 4>{0, 1, 0, 0}
                                                       : std::array<double, 4>{0, 0, 1, 0};
            break;
          case BilinearSource::kBarycentric:
            for (int i = 0; i < 4; ++i) w[i] = params[node.unified[i].index];
            break;
          case BilinearSource::kLogits: {
            std::array<double, 4> l{};
            for (int i = 0; i < 4; ++i) l[i] = params[node.unified[i].index];
            w = logic::unified_weights(l, value_or(params, node.temperature, 1000.0),
                                       value_or(params, node.omega, 10.0));
            break;
          }
        }
        c[0] = w[1] + w[2];
        c[1] = w[1] + w[3];
        c[2] = w[0] - w[1] - w[2] - w[3];
        break;
      }
      case OpCode::kLogic:
        c[0] = value_or(params, node.logic.p, 0.0);
        c[1] = value_or(params, node.complement.lambda, 0.0);
        break;
      case OpCode::kComplement:
        c[0] = value_or(params, node.complement.lambda, 0.0);
        break;
      case OpCode::kSplineTerm: {
        const Domain box = tree_.spline_box(node);
        for (int a = 0; a < dim; ++a) {
          c[a] = box.min[a];
          c[dim + a] = (ins.spline_cells[a] - ins.spline_degree) / (box.max[a] - box.min[a]);
        }
        break;
      }
    }
  }
}

template <class Sink>
void Program::pullback_instruction(const Instruction& ins, std::span<const double> params,
                                   std::span<const double> grad_consts, Sink& sink) const {
  const int dim = tree_.dim;
  {
    const Node& node = tree_.node(ins.node);
    const double* g = grad_consts.data() + ins.consts;
    switch (ins.code) {
      case OpCode::kLeafQuadric3:
        if (node.shape.type == PrimitiveType::kQuadric2) {
          for (int i = 0; i < 6; ++i) sink(node.intrinsic[i], g[kQuadric2Slots[i]]);
        } else {
          for (int i = 0; i < 10; ++i) sink(node.intrinsic[i], g[i]);
        }
        sink(node.step.param, g[10]);
        break;
      case OpCode::kLeaf: {
        for (int i = 0; i < ins.num_theta; ++i) sink(node.intrinsic[i], g[i]);
        const auto& pl = node.placement;
        if (ins.has_rotate) {
          if (dim == 3) {
            std::array<double, 9> gr{};
            std::copy(g + ins.rotate_at, g + ins.rotate_at + 9, gr.begin());
            const auto ga =
                placement::rotation_3d_vjp(params[pl.rotate[0].index], params[pl.rotate[1].index],
                                           params[pl.rotate[2].index], gr);
            for (int i = 0; i < 3; ++i) sink(pl.rotate[i], ga[i]);
          } else {
            std::array<double, 4> gr{};
            std::copy(g + ins.rotate_at, g + ins.rotate_at + 4, gr.begin());
            sink(pl.rotate[0], placement::rotation_2d_vjp(params[pl.rotate[0].index], gr));
          }
        }
        if (ins.has_translate) {
          for (int i = 0; i < dim; ++i) sink(pl.translate[i], g[ins.translate_at + i]);
        }
        if (ins.has_scale) sink(pl.scale, g[ins.scale_at]);
        if (ins.step != StepKind::kCrisp) sink(node.step.param, g[ins.step_at]);
        break;
      }
      case OpCode::kBilinear: {
        if (ins.bilinear == BilinearSource::kConstant) break;
        // a = c1 + c2, b = c1 + c3, d = c0 - c1 - c2 - c3
        const std::array<double, 4> gw{g[2], g[0] + g[1] - g[2], g[0] - g[2], g[1] - g[2]};
        if (ins.bilinear == BilinearSource::kBarycentric) {
          for (int i = 0; i < 4; ++i) sink(node.unified[i], gw[i]);
        } else {
          std::array<double, 4> l{};
          for (int i = 0; i < 4; ++i) l[i] = params[node.unified[i].index];
          double gt = 0.0, gomega = 0.0;
          const bool free_t = node.temperature && !tree_.params[*node.temperature].fixed;
          const bool free_omega = node.omega && !tree_.params[*node.omega].fixed;
          const auto gl = logic::unified_weights_vjp(
              l, value_or(params, node.temperature, 1000.0), value_or(params, node.omega, 10.0), gw,
              free_t ? &gt : nullptr, free_omega ? &gomega : nullptr);
          for (int i = 0; i < 4; ++i) sink(node.unified[i], gl[i]);
          sink(node.temperature, gt);
          sink(node.omega, gomega);
        }
        break;
      }
      case OpCode::kLogic:
        sink(node.logic.p, g[0]);
        sink(node.complement.lambda, g[1]);
        break;
      case OpCode::kComplement:
        sink(node.complement.lambda, g[0]);
        break;
      case OpCode::kSplineTerm:
        break;  // the basis depends on the point only
    }
  }
}

namespace {

// Where pullback_instruction sends d loss / d parameter: counted, recorded, or added.
struct CountSink {
  std::uint32_t n = 0;
  void operator()(ParamRef, double) { ++n; }
  void operator()(const std::optional<ParamRef>& r, double) { n += r ? 1 : 0; }
};
struct RecordSink {
  RefGrad* out;
  void operator()(ParamRef r, double g) { *out++ = {r.index, g}; }
  void operator()(const std::optional<ParamRef>& r, double g) {
    if (r) (*this)(*r, g);
  }
};

}  // namespace

void Program::count_refs() {
  ref_offsets_.assign(tape_.size() + 1, 0);
  const std::vector<double> params(num_params(), 0.0);
  const std::vector<double> g(num_consts_, 0.0);
  for (std::size_t k = 0; k < tape_.size(); ++k) {
    CountSink c;
    pullback_instruction(tape_[k], params, g, c);
    ref_offsets_[k + 1] = ref_offsets_[k] + c.n;
  }
}

void Program::pullback_local(std::span<const double> params, std::span<const double> grad_consts,
                             std::span<RefGrad> out, std::size_t begin, std::size_t end) const {
  FUZZYCSG_ASSERT(out.size() == num_ref_grads() && end <= tape_.size());
  for (std::size_t k = begin; k < end; ++k) {
    RecordSink r{out.data() + ref_offsets_[k]};
    pullback_instruction(tape_[k], params, grad_consts, r);
    FUZZYCSG_ASSERT(r.out == out.data() + ref_offsets_[k + 1]);
  }
}

void Program::scatter(std::span<const RefGrad> ref_grads, std::span<double> grad) const {
  for (const RefGrad& rg : ref_grads) {
    if (!tree_.params.at(rg.index).fixed) grad[rg.index] += rg.value;
  }
}

void Program::pullback(std::span<const double> params, std::span<const double> grad_consts,
                       std::span<double> grad) const {
  FUZZYCSG_ASSERT(params.size() == num_params() && grad.size() == num_params());
  std::vector<RefGrad> rg(num_ref_grads());
  pullback_local(params, grad_consts, rg, 0, tape_.size());
  scatter(rg, grad);
}

}  // namespace fuzzycsg
