#include "fuzzycsg/eval/evaluator.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <thread>

#include "eval/flush_denormals.hpp"
#include "eval/kernel.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/limits.hpp"

namespace fuzzycsg {

namespace kernel {

Scratch::Scratch(std::size_t tape_size, std::size_t stack_depth, std::size_t max_theta)
    : values(hwy::AllocateAligned<float>(tape_size * kBlock)),
      stack(hwy::AllocateAligned<float>((stack_depth + 1) * kBlock)),
      points(hwy::AllocateAligned<float>(3 * kBlock)),
      monomials(hwy::AllocateAligned<float>(9 * kBlock)),
      dtheta(hwy::AllocateAligned<float>(std::max<std::size_t>(max_theta, 1))),
      residual(hwy::AllocateAligned<float>(2 * kBlock)),
      point_grad(hwy::AllocateAligned<float>(3 * kBlock)) {}

}  // namespace kernel

namespace {

// Chunks are fixed by the number of points alone, so the order of every floating-point sum
// (and so every result) does not depend on the thread count or on scheduling.
constexpr std::size_t kMaxChunks = 32;
constexpr std::size_t kMinBlocksPerChunk = 2;
// Instructions per task when preparing constants and pulling gradients back to parameters.
constexpr std::size_t kInstructionGrain = 256;

struct Chunking {
  std::size_t blocks = 0, chunks = 0;
  std::size_t begin(std::size_t c, std::size_t n) const {
    return std::min(n, (c * blocks / chunks) * kernel::kBlock);
  }
};

Chunking chunking(std::size_t n) {
  Chunking c;
  c.blocks = (n + kernel::kBlock - 1) / kernel::kBlock;
  c.chunks = std::clamp<std::size_t>(c.blocks / kMinBlocksPerChunk, 1, kMaxChunks);
  return c;
}

[[noreturn]] void bad_argument(const std::string& what) { throw InputError(what); }

// The compile step trusts its input; a tree built in code is checked here first.
Program compile_valid(const Tree& tree) {
  validate(tree, "Evaluator");
  return Program::compile(tree);
}

}  // namespace

struct Evaluator::Impl {
  Program program;
  std::vector<const PrimitiveShape*> shapes;
  std::size_t max_theta = 1;
  int threads = 1;
  bool flush = true;
  mutable tbb::task_arena arena;
  mutable tbb::enumerable_thread_specific<std::unique_ptr<kernel::Scratch>> scratch;

  Impl(const Tree& tree, EvalOptions options)
      : program(compile_valid(tree)),
        threads(thread_count(options.threads)),
        flush(options.flush_subnormals),
        arena(threads) {
    const auto tape = program.tape();
    shapes.resize(tape.size(), nullptr);
    for (std::size_t k = 0; k < tape.size(); ++k) {
      if (tape[k].code == OpCode::kLeaf || tape[k].code == OpCode::kLeafQuadric3) {
        shapes[k] = &program.tree().node(tape[k].node).shape;
        max_theta = std::max(max_theta, static_cast<std::size_t>(tape[k].num_theta));
      }
    }
  }

  kernel::Scratch& local_scratch() const {
    auto& s = scratch.local();
    if (!s) {
      s = std::make_unique<kernel::Scratch>(
          program.tape().size(), static_cast<std::size_t>(program.max_stack_depth()), max_theta);
    }
    return *s;
  }

  std::vector<float> constants(std::span<const double> params) const {
    if (params.size() != program.num_params()) {
      bad_argument("Evaluator: params has " + std::to_string(params.size()) +
                   " entries, expected " + std::to_string(program.num_params()));
    }
    std::vector<double> c(program.num_consts());
    const std::size_t tape = program.tape().size();
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tape, kInstructionGrain),
                        [&](const auto& r) { program.prepare(params, c, r.begin(), r.end()); });
    });
    return {c.begin(), c.end()};
  }

  std::size_t point_count(std::span<const float> points, const char* fn) const {
    const auto dim = static_cast<std::size_t>(program.dim());
    if (points.size() % dim != 0) {
      bad_argument(std::string("Evaluator::") + fn + ": points has " +
                   std::to_string(points.size()) + " floats, not a multiple of dim " +
                   std::to_string(dim));
    }
    return points.size() / dim;
  }

  // The loss's targets, weights and scale into `a`, checked.
  void set_loss(kernel::Args& a, const Loss& loss, std::size_t n, const char* fn) const {
    a.loss_kind = loss.kind;
    const std::string where = std::string("Evaluator::") + fn + ": ";
    if (loss.kind == Loss::Kind::kSum) {
      if (loss.weights.empty()) return;
      if (loss.weights.size() != n) {
        bad_argument(where + "weights has " + std::to_string(loss.weights.size()) +
                     " entries, expected " + std::to_string(n) + " (one per point)");
      }
      for (float w : loss.weights) {
        if (!std::isfinite(w)) bad_argument(where + "weights must be finite");
      }
      a.weights = loss.weights.data();
      return;
    }
    if (loss.targets.size() != n) {
      bad_argument(where + "targets has " + std::to_string(loss.targets.size()) +
                   " entries, expected " + std::to_string(n) + " (one per point)");
    }
    a.targets = loss.targets.data();
    double wsum = static_cast<double>(n);
    if (!loss.weights.empty()) {
      if (loss.weights.size() != n) {
        bad_argument(where + "weights has " + std::to_string(loss.weights.size()) +
                     " entries, expected " + std::to_string(n) + " (one per point)");
      }
      wsum = 0.0;
      for (float w : loss.weights) {
        if (!(w >= 0.0f) || !std::isfinite(w)) {
          bad_argument(where + "weights must be finite and >= 0");
        }
        wsum += w;
      }
      a.weights = loss.weights.data();
    }
    if (!(wsum > 0.0)) bad_argument(where + "the weights sum to 0");
    a.loss_scale = 1.0 / wsum;
  }

  kernel::Args args(const std::vector<float>& consts, std::span<const float> points) const {
    kernel::Args a;
    a.tape = program.tape();
    a.shapes = shapes.data();
    a.consts = consts.data();
    a.dim = program.dim();
    a.has_quadric3 = program.has_quadric_fast_path();
    a.points = points.data();
    return a;
  }
};

Evaluator::Evaluator(const Tree& tree, EvalOptions options)
    : impl_(std::make_unique<Impl>(tree, options)) {}
Evaluator::~Evaluator() = default;
Evaluator::Evaluator(Evaluator&&) noexcept = default;
Evaluator& Evaluator::operator=(Evaluator&&) noexcept = default;

const Program& Evaluator::program() const { return impl_->program; }
int Evaluator::dim() const { return impl_->program.dim(); }
std::size_t Evaluator::num_params() const { return impl_->program.num_params(); }

void Evaluator::forward(std::span<const double> params, std::span<const float> points,
                        std::span<float> out) const {
  check_cancelled();
  const Impl& im = *impl_;
  const std::size_t n = im.point_count(points, "forward");
  if (out.size() != n) {
    bad_argument("Evaluator::forward: out has " + std::to_string(out.size()) +
                 " entries, expected " + std::to_string(n) + " (one per point)");
  }
  if (n == 0) return;
  const auto consts = im.constants(params);
  kernel::Args a = im.args(consts, points);
  a.occupancy = out.data();
  const Chunking ch = chunking(n);
  im.arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ch.chunks, 1), [&](const auto& r) {
      kernel::Scratch& s = im.local_scratch();
      const eval_detail::FlushDenormals ftz(im.flush);
      for (std::size_t c = r.begin(); c != r.end(); ++c) {
        kernel::run(a, ch.begin(c, n), ch.begin(c + 1, n), s, nullptr, nullptr);
      }
    });
  });
}

double Evaluator::backward(std::span<const double> params, std::span<const float> points,
                           const Loss& loss, std::span<double> grad, std::span<float> occupancy,
                           std::span<float> point_grad) const {
  check_cancelled();
  const Impl& im = *impl_;
  const std::size_t n = im.point_count(points, "backward");
  if (grad.size() != im.program.num_params()) {
    bad_argument("Evaluator::backward: grad has " + std::to_string(grad.size()) +
                 " entries, expected " + std::to_string(im.program.num_params()));
  }
  if (!occupancy.empty() && occupancy.size() != n) {
    bad_argument("Evaluator::backward: occupancy has " + std::to_string(occupancy.size()) +
                 " entries, expected " + std::to_string(n));
  }
  if (!point_grad.empty()) {
    if (point_grad.size() != points.size()) {
      bad_argument("Evaluator::backward: point_grad has " + std::to_string(point_grad.size()) +
                   " entries, expected " + std::to_string(points.size()) + " (as points)");
    }
    for (const Instruction& ins : im.program.tape()) {
      if (ins.code == OpCode::kSplineTerm) {
        bad_argument(
            "Evaluator::backward: the gradient by the points is not computed through "
            "spline nodes");
      }
    }
  }
  std::fill(grad.begin(), grad.end(), 0.0);
  const auto consts = im.constants(params);
  kernel::Args a = im.args(consts, points);
  a.occupancy = occupancy.empty() ? nullptr : occupancy.data();
  a.point_grad = point_grad.empty() ? nullptr : point_grad.data();
  im.set_loss(a, loss, n, "backward");
  if (n == 0) return 0.0;

  const Chunking ch = chunking(n);
  const std::size_t nc = im.program.num_consts();
  std::vector<double> chunk_grad(ch.chunks * nc, 0.0);
  std::vector<double> chunk_loss(ch.chunks, 0.0);
  im.arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ch.chunks, 1), [&](const auto& r) {
      kernel::Scratch& s = im.local_scratch();
      const eval_detail::FlushDenormals ftz(im.flush);
      for (std::size_t c = r.begin(); c != r.end(); ++c) {
        kernel::run(a, ch.begin(c, n), ch.begin(c + 1, n), s, chunk_grad.data() + c * nc,
                    &chunk_loss[c]);
      }
    });
  });
  // Reduction over chunks in chunk order (per constant, so it may run in parallel), then the
  // pullback to parameters: per-instruction contributions in parallel, summed in tape order.
  std::vector<double> grad_consts(nc);
  std::vector<RefGrad> ref_grads(im.program.num_ref_grads());
  const std::size_t tape = im.program.tape().size();
  im.arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nc, 4096), [&](const auto& r) {
      for (std::size_t k = r.begin(); k != r.end(); ++k) {
        double sum = chunk_grad[k];
        for (std::size_t c = 1; c < ch.chunks; ++c) sum += chunk_grad[c * nc + k];
        grad_consts[k] = sum;
      }
    });
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, tape, kInstructionGrain), [&](const auto& r) {
          im.program.pullback_local(params, grad_consts, ref_grads, r.begin(), r.end());
        });
  });
  im.program.scatter(ref_grads, grad);
  double total = 0.0;
  for (double l : chunk_loss) total += l;
  return loss.kind == Loss::Kind::kMse ? total * a.loss_scale : total;
}

double Evaluator::edit_loss_changes(std::span<const double> params, std::span<const float> points,
                                    const Loss& loss, std::span<const BilinearEdit> edits,
                                    std::span<double> changes) const {
  const Impl& im = *impl_;
  const std::size_t n = im.point_count(points, "edit_loss_changes");
  if (loss.kind != Loss::Kind::kMse) {
    bad_argument("Evaluator::edit_loss_changes: the loss must be the MSE");
  }
  if (changes.size() != edits.size()) {
    bad_argument("Evaluator::edit_loss_changes: changes has " + std::to_string(changes.size()) +
                 " entries, expected " + std::to_string(edits.size()) + " (one per edit)");
  }
  const auto tape = im.program.tape();
  // The one bilinear instruction of each edited node.
  std::vector<int> instruction_of(im.program.tree().nodes.size(), -1);
  for (std::size_t k = 0; k < tape.size(); ++k) {
    const int node = tape[k].node;
    if (node < 0 || tape[k].code == OpCode::kLeaf || tape[k].code == OpCode::kLeafQuadric3) {
      continue;
    }
    const bool one = instruction_of[static_cast<std::size_t>(node)] == -1;
    instruction_of[static_cast<std::size_t>(node)] =
        one && tape[k].code == OpCode::kBilinear ? static_cast<int>(k) : -2;
  }
  std::vector<std::size_t> order(edits.size());
  std::vector<int> ins_of_edit(edits.size());
  for (std::size_t e = 0; e < edits.size(); ++e) {
    const int node = edits[e].node;
    const int k = node >= 0 && static_cast<std::size_t>(node) < instruction_of.size()
                      ? instruction_of[static_cast<std::size_t>(node)]
                      : -2;
    if (k < 0) {
      bad_argument("Evaluator::edit_loss_changes: node " + std::to_string(node) +
                   " is not a binary unified or product-logic operator");
    }
    ins_of_edit[e] = k;
    order[e] = e;
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return ins_of_edit[x] < ins_of_edit[y]; });
  std::vector<std::int32_t> first(tape.size(), -1), count(tape.size(), 0);
  std::vector<float> delta(3 * edits.size());
  for (std::size_t j = 0; j < order.size(); ++j) {
    const std::size_t e = order[j];
    const auto k = static_cast<std::size_t>(ins_of_edit[e]);
    if (first[k] < 0) first[k] = static_cast<std::int32_t>(j);
    ++count[k];
    for (int c = 0; c < 3; ++c) delta[3 * j + c] = static_cast<float>(edits[e].delta[c]);
  }

  const auto consts = im.constants(params);
  kernel::Args a = im.args(consts, points);
  im.set_loss(a, loss, n, "edit_loss_changes");
  a.edit_first = first.data();
  a.edit_count = count.data();
  a.edit_delta = delta.data();
  std::fill(changes.begin(), changes.end(), 0.0);
  if (n == 0) return 0.0;

  const Chunking ch = chunking(n);
  const std::size_t ne = edits.size();
  std::vector<double> chunk_out(ch.chunks * ne, 0.0);
  std::vector<double> chunk_loss(ch.chunks, 0.0);
  im.arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ch.chunks, 1), [&](const auto& r) {
      kernel::Scratch& s = im.local_scratch();
      const eval_detail::FlushDenormals ftz(im.flush);
      // Instructions other than leaves and bilinear ones still accumulate their gradients.
      std::vector<double> scratch_grad(im.program.num_consts());
      for (std::size_t c = r.begin(); c != r.end(); ++c) {
        kernel::Args ac = a;
        ac.edit_out = chunk_out.data() + c * ne;
        kernel::run(ac, ch.begin(c, n), ch.begin(c + 1, n), s, scratch_grad.data(), &chunk_loss[c]);
      }
    });
  });
  for (std::size_t j = 0; j < ne; ++j) {
    double sum = 0.0;
    for (std::size_t c = 0; c < ch.chunks; ++c) sum += chunk_out[c * ne + j];
    changes[order[j]] = sum * a.loss_scale;
  }
  double total = 0.0;
  for (double l : chunk_loss) total += l;
  return total * a.loss_scale;
}

}  // namespace fuzzycsg
