#include "convert/refine.hpp"

#include <algorithm>
#include <random>

#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/optim/adam.hpp"
#include "fuzzycsg/optim/schedule.hpp"

namespace fuzzycsg::convert {

RefineResult refine_fuzzy(const Tree& tree, const Target& target, const RefineOptions& options) {
  RefineResult result;
  result.tree = tree;
  const std::size_t n = tree.params.size();
  std::vector<double> params = tree.params.values();

  optim::Adam adam(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Parameter& p = tree.params.at(i);
    adam.set_free(i, !p.fixed);
    adam.set_range(i, p.range);
  }
  std::vector<std::size_t> sharpness;
  for (const Node& node : tree.nodes) {
    if (node.kind == NodeKind::kPrimitive) {
      for (const ParamRef r : node.placement.rotate) adam.set_rate(r.index, options.rotation_rate);
      if (node.step.kind == StepKind::kSigmoid && node.step.param) {
        sharpness.push_back(node.step.param->index);
        adam.set_free(node.step.param->index, false);
      }
    } else if (node.op == OpKind::kUnified) {
      for (const ParamRef r : node.unified) adam.set_rate(r.index, options.logit_rate);
    }
  }

  Rng rng(options.seed);
  SamplingOptions sampling;
  sampling.surface = 0.3;
  sampling.near = 0.5;
  sampling.near_distance = options.near_distance;
  const SampleSet pool =
      draw_samples(target, std::max<std::size_t>(options.pool, 1), sampling, rng);
  const std::size_t batch =
      std::min<std::size_t>(static_cast<std::size_t>(std::max(options.batch, 1)), pool.size());

  const Evaluator evaluator(tree, EvalOptions{options.threads});
  std::vector<double> grad(n), m(n, 0.0), v(n, 0.0);
  const int steps = std::max(options.steps, 1);
  const int tenth = std::max(1, steps / 10);
  double first = 0, last = 0;
  std::size_t offset = 0;
  for (int k = 0; k < steps; ++k) {
    if (options.deadline && std::chrono::steady_clock::now() > *options.deadline) {
      result.stopped = true;
      break;
    }
    const double f = steps > 1 ? static_cast<double>(k) / (steps - 1) : 1.0;
    const double s = optim::geometric(options.sharpness_start, options.sharpness_end, f);
    for (const std::size_t i : sharpness) params[i] = s;
    if (offset + batch > pool.size()) offset = 0;
    const std::span<const float> points(pool.points.data() + 3 * offset, 3 * batch);
    Loss loss;
    loss.kind = Loss::Kind::kMse;
    loss.targets = std::span<const float>(pool.occupancy.data() + offset, batch);
    offset += batch;
    const double value = evaluator.backward(params, points, loss, grad);
    if (k < tenth) first += value / tenth;
    if (k >= steps - tenth) last += value / tenth;
    const double lr = optim::cosine_lr(options.lr, options.lr_end, f);
    adam.step(k + 1, lr, grad, optim::AdamState{params, m, v});
  }
  result.tree.params.set_values(params);
  result.loss_first = first;
  result.loss_last = last;
  return result;
}

}  // namespace fuzzycsg::convert
