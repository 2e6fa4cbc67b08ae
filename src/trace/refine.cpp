#include "fuzzycsg/trace/refine.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <span>
#include <string_view>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/limits.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/optim/adam.hpp"
#include "fuzzycsg/optim/schedule.hpp"
#include "fuzzycsg/trace/convert.hpp"

namespace fuzzycsg::trace {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();

[[noreturn]] void bad(std::string_view field, double v, std::string_view what) {
  throw OptionError(std::string(field), fmt::format("must be {} (got {})", what, v));
}

bool finite_positive(double v) { return v > 0 && std::isfinite(v); }

// The shape-defining fields of `from` into `to` (the others, such as a circle's unused w, h and
// theta, stay).
void copy_shape(const Primitive& from, Primitive& to) {
  to.x = from.x;
  to.y = from.y;
  if (to.shape == Shape::kCircle) {
    to.r = from.r;
  } else {
    to.w = from.w;
    to.h = from.h;
    to.theta = from.theta;
  }
}

}  // namespace

void validate(const RefineOptions& o) {
  if (o.iterations < 0) bad("iterations", o.iterations, ">= 0");
  if (o.batch < 0) bad("batch", o.batch, ">= 0");
  if (!finite_positive(o.lr)) bad("lr", o.lr, "> 0");
  if (!(o.lr_end > 0 && o.lr_end <= 1)) bad("lr_end", o.lr_end, "in (0, 1]");
  if (!(o.angle_lr >= 0) || !std::isfinite(o.angle_lr)) bad("angle_lr", o.angle_lr, ">= 0");
  if (!(o.beta1 >= 0 && o.beta1 < 1)) bad("beta1", o.beta1, "in [0, 1)");
  if (!(o.beta2 >= 0 && o.beta2 < 1)) bad("beta2", o.beta2, "in [0, 1)");
  if (!finite_positive(o.adam_eps)) bad("adam_eps", o.adam_eps, "> 0");
  if (!finite_positive(o.sharpness_start)) bad("sharpness_start", o.sharpness_start, "> 0");
  if (!finite_positive(o.sharpness_end)) bad("sharpness_end", o.sharpness_end, "> 0");
  if (!finite_positive(o.min_size)) bad("min_size", o.min_size, "> 0");
  if (o.check_every < 1) bad("check_every", o.check_every, ">= 1");
  if (!(o.k >= 0) || !std::isfinite(o.k)) bad("k", o.k, ">= 0");
  check_threads(o.threads);
  if (!(o.time_limit >= 0) || !std::isfinite(o.time_limit)) {
    bad("time_limit", o.time_limit, ">= 0");
  }
}

RefineResult refine(const CsgTree& input, const Bitmap& target, const RefineOptions& o) {
  validate(o);
  if (input.empty()) throw InputError("refine: empty tree");
  if (target.empty()) throw InputError("refine: empty target");
  const auto start = Clock::now();
  const int width = target.width(), height = target.height();
  const int primitives = input.primitive_count();
  const std::vector<int> leaves = input.leaves();

  RefineResult result;
  result.tree = input;
  result.before = score(TreeEvaluator(input, width, height).result(), target, primitives, o.k);
  result.after = result.before;

  // The crisp tree of a parameter vector, with the input's node ids.
  Tree model = to_tree(input, width, height, o.sharpness_start);
  const auto crisp = [&](std::span<const double> params) {
    model.params.set_values(params);
    const CsgTree read = from_tree(model, width, height);
    const std::vector<int> read_leaves = read.leaves();
    CsgTree out = input;
    for (std::size_t i = 0; i < leaves.size(); ++i) {
      copy_shape(read.primitive(read_leaves[i]), out.primitive(leaves[i]));
    }
    return out;
  };

  // Which parameters move, with what learning rate multiplier and lower bound; the sharpness
  // entries follow the schedule. A parameter whose gradient is not finite sits the step out,
  // value and moments.
  const std::size_t n = model.params.size();
  optim::AdamOptions adam_options;
  adam_options.beta1 = o.beta1;
  adam_options.beta2 = o.beta2;
  adam_options.eps = o.adam_eps;
  adam_options.skip_non_finite = true;
  optim::Adam adam(n, adam_options);
  std::vector<std::size_t> sharpness;
  for (const fuzzycsg::Node& node : model.nodes) {
    if (node.kind != NodeKind::kPrimitive) continue;
    if (node.step.param) sharpness.push_back(node.step.param->index);
    for (const ParamRef r : node.intrinsic) {
      adam.set_range(r.index, Range::closed(o.min_size, kInf));
    }
    for (const ParamRef r : node.placement.rotate) adam.set_rate(r.index, o.angle_lr);
  }
  for (std::size_t i = 0; i < n; ++i) adam.set_free(i, !model.params.at(i).fixed);

  // Every pixel centre, (i + 1/2, H - j - 1/2), and the target there.
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::vector<float> points(2 * pixels), targets(pixels);
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * static_cast<std::size_t>(width) +
                            static_cast<std::size_t>(i);
      points[2 * p] = static_cast<float>(i + 0.5);
      points[2 * p + 1] = static_cast<float>(height - j - 0.5);
      targets[p] = target.get(i, j) ? 1.0f : 0.0f;
    }
  }
  const bool sampled = o.batch > 0 && static_cast<std::size_t>(o.batch) < pixels;
  const std::size_t batch = sampled ? static_cast<std::size_t>(o.batch) : pixels;
  std::vector<float> batch_points(sampled ? 2 * batch : 0), batch_targets(sampled ? batch : 0);
  Rng rng(o.seed);

  EvalOptions eval_options;
  eval_options.threads = o.threads;
  const Evaluator evaluator(model, eval_options);

  std::vector<double> params = model.params.values(), grad(n, 0.0), m(n, 0.0), v(n, 0.0);
  double best = result.before.total();
  const int iters = o.iterations;
  result.loss.reserve(static_cast<std::size_t>(iters));
  const auto check = [&](int step) {
    const CsgTree t = crisp(params);
    const Score s = score(TreeEvaluator(t, width, height).result(), target, primitives, o.k);
    if (s.total() < best) {
      best = s.total();
      result.tree = t;
      result.after = s;
      result.best_iteration = step;
    }
  };
  for (int step = 0; step < iters; ++step) {
    check_cancelled();
    if (o.time_limit > 0 &&
        std::chrono::duration<double>(Clock::now() - start).count() > o.time_limit) {
      break;
    }
    const double f = iters > 1 ? static_cast<double>(step) / (iters - 1) : 1.0;
    const double s = optim::geometric(o.sharpness_start, o.sharpness_end, f);
    for (const std::size_t i : sharpness) params[i] = s;
    const double lr = optim::cosine_lr(o.lr, o.lr_end, f);

    Loss loss;
    loss.kind = Loss::Kind::kMse;
    double value = 0;
    if (sampled) {
      for (std::size_t b = 0; b < batch; ++b) {
        const std::size_t p =
            static_cast<std::size_t>(uniform01(rng) * static_cast<double>(pixels));
        batch_points[2 * b] = points[2 * p];
        batch_points[2 * b + 1] = points[2 * p + 1];
        batch_targets[b] = targets[p];
      }
      loss.targets = batch_targets;
      value = evaluator.backward(params, batch_points, loss, grad);
    } else {
      loss.targets = targets;
      value = evaluator.backward(params, points, loss, grad);
    }
    if (!std::isfinite(value)) break;
    result.loss.push_back(value);

    adam.step(step + 1, lr, grad, optim::AdamState{params, m, v});
    result.iterations = step + 1;
    if ((step + 1) % o.check_every == 0 || step + 1 == iters) check(step + 1);
  }
  if (result.iterations % o.check_every != 0 && result.iterations != iters) {
    check(result.iterations);
  }
  result.improved = result.after.total() < result.before.total();
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace fuzzycsg::trace
