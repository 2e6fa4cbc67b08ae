#include "fuzzycsg/fit/fit.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <future>
#include <memory>
#include <sstream>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/fit/init.hpp"
#include "fuzzycsg/fit/types.hpp"
#include "fuzzycsg/optim/adam.hpp"
#include "fuzzycsg/optim/schedule.hpp"

namespace fuzzycsg {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

[[noreturn]] void bad_option(const char* field, std::string what) {
  throw OptionError(field, std::move(what));
}

// The sampler draws from its own stream so that changing the model's seed use does not shift
// the training points (and vice versa).
constexpr std::uint64_t kSamplerStream = 0x9e3779b97f4a7c15ULL;
// Re-seeding rounds draw from a stream of the seed and the step, so a resumed run repeats them.
constexpr std::uint64_t kReseedStream = 0xd1b54a32d192ed03ULL;
constexpr std::uint64_t kTypeSearchStream = 0x8cb92ba72f3d8dd7ULL;

std::string save_rng(const Rng& rng) {
  std::ostringstream s;
  s << rng;
  return s.str();
}

Rng load_rng(const std::string& text) {
  Rng rng;
  std::istringstream s(text);
  s >> rng;
  if (!s) throw InputError("checkpoint: state.rng: not a generator state");
  return rng;
}

// Parameter indices of the unified operators' temperatures, which the schedule drives.
std::vector<std::size_t> temperature_indices(const Tree& tree) {
  std::vector<std::size_t> out;
  for (const Node& n : tree.nodes) {
    if (n.kind == NodeKind::kOperator && n.op == OpKind::kUnified && n.temperature) {
      out.push_back(n.temperature->index);
    }
  }
  return out;
}

// The boolean each unified operator currently selects: argmax of c, which for t > 0 is the
// argmax of sin(omega * logits). Indexed like tree.nodes; -1 for nodes that are not unified
// operators.
std::vector<int> operator_types(const Tree& tree, std::span<const double> params) {
  std::vector<int> out(tree.nodes.size(), -1);
  for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
    const Node& n = tree.nodes[k];
    if (n.kind != NodeKind::kOperator || n.op != OpKind::kUnified) continue;
    std::array<double, 4> w{};
    for (int i = 0; i < 4; ++i) w[i] = params[n.unified[i].index];
    if (n.unified_logits) {
      const double omega = n.omega ? params[n.omega->index] : 10.0;
      for (double& x : w) x = std::sin(omega * x);
    }
    out[k] = static_cast<int>(std::max_element(w.begin(), w.end()) - w.begin());
  }
  return out;
}

// Adam over the model's parameters: the fixed ones stay, each is projected into its field's
// range after a step (projected gradient), and with SharpnessParam::kLog the sharpness of every
// free sigmoid step of a leaf is stepped as log s.
optim::Adam model_adam(const Tree& tree, const FitOptions& o) {
  optim::AdamOptions ao;
  ao.beta1 = o.beta1;
  ao.beta2 = o.beta2;
  ao.eps = o.adam_eps;
  optim::Adam adam(tree.params.size(), ao);
  for (std::size_t i = 0; i < tree.params.size(); ++i) {
    adam.set_free(i, !tree.params.at(i).fixed);
    adam.set_range(i, tree.params.at(i).range);
  }
  if (o.sharpness_param == SharpnessParam::kLog) {
    for (const Node& n : tree.nodes) {
      if (n.kind == NodeKind::kPrimitive && n.step.kind == StepKind::kSigmoid && n.step.param &&
          !tree.params[*n.step.param].fixed) {
        adam.set_log(n.step.param->index, true);
      }
    }
  }
  return adam;
}

Tree with_values(Tree tree, std::span<const double> values) {
  tree.params.set_values(values);
  return tree;
}

}  // namespace

std::string_view stop_reason_name(StopReason r) {
  switch (r) {
    case StopReason::kIterations:
      return "iterations";
    case StopReason::kTimeLimit:
      return "time-limit";
    case StopReason::kNonFinite:
      return "non-finite-loss";
  }
  return "?";
}

void validate(const FitOptions& o, int dim) {
  if (o.prims < 1 || o.prims > (1 << 16) || !std::has_single_bit(static_cast<unsigned>(o.prims))) {
    bad_option("prims", fmt::format("must be a power of two in [1, 65536] (got {})", o.prims));
  }
  for (PrimitiveType f : o.families) {
    const PrimitiveInfo& info = primitive_info(f);
    if (info.dim != dim) {
      bad_option("families", fmt::format("{} is a {}D primitive but the target is {}D", info.name,
                                         info.dim, dim));
    }
    if (f == PrimitiveType::kPolygon || f == PrimitiveType::kExtrude) {
      bad_option("families", fmt::format("{} cannot be fitted", info.name));
    }
  }
  if (!(o.init_range > 0) || !std::isfinite(o.init_range)) {
    bad_option("init_range", fmt::format("must be > 0 (got {})", o.init_range));
  }
  if (!(o.init_slope >= 0) || !std::isfinite(o.init_slope)) {
    bad_option("init_slope", fmt::format("must be >= 0 (got {})", o.init_slope));
  }
  if (!(o.temperature > 0) || !std::isfinite(o.temperature)) {
    bad_option("temperature", fmt::format("must be > 0 (got {})", o.temperature));
  }
  if (!(o.temperature_start > 0) || !std::isfinite(o.temperature_start)) {
    bad_option("temperature_start", fmt::format("must be > 0 (got {})", o.temperature_start));
  }
  if (!(o.temperature_ramp >= 0 && o.temperature_ramp <= 1)) {
    bad_option("temperature_ramp", fmt::format("must be in [0, 1] (got {})", o.temperature_ramp));
  }
  if (!std::isfinite(o.omega) || o.omega == 0) {
    bad_option("omega", fmt::format("must be finite and non-zero (got {})", o.omega));
  }
  if (o.iters < 0) bad_option("iters", fmt::format("must be >= 0 (got {})", o.iters));
  if (o.batch < 1 || o.batch > (1 << 24)) {
    bad_option("batch", fmt::format("must be in [1, 16777216] (got {})", o.batch));
  }
  if (o.pool != 0 && (o.pool < static_cast<std::size_t>(o.batch) || o.pool > (1u << 26))) {
    bad_option("pool", fmt::format("must be 0 or in [batch, 67108864] (got {})", o.pool));
  }
  if (o.resample_every < 1) {
    bad_option("resample_every", fmt::format("must be >= 1 (got {})", o.resample_every));
  }
  if (!(o.lr > 0) || !std::isfinite(o.lr))
    bad_option("lr", fmt::format("must be > 0 (got {})", o.lr));
  if (!(o.beta1 >= 0 && o.beta1 < 1)) {
    bad_option("beta1", fmt::format("must be in [0, 1) (got {})", o.beta1));
  }
  if (!(o.beta2 >= 0 && o.beta2 < 1)) {
    bad_option("beta2", fmt::format("must be in [0, 1) (got {})", o.beta2));
  }
  if (!(o.adam_eps > 0) || !std::isfinite(o.adam_eps)) {
    bad_option("adam_eps", fmt::format("must be > 0 (got {})", o.adam_eps));
  }
  const SamplingOptions& s = o.sampling;
  if (!(s.surface >= 0 && s.near >= 0 && s.surface + s.near <= 1 + 1e-12)) {
    bad_option("sampling",
               fmt::format("fractions must be >= 0 with surface + near <= 1 (got {}, {})",
                           s.surface, s.near));
  }
  if (!(s.near_distance >= 0) || !std::isfinite(s.near_distance)) {
    bad_option("sampling.near_distance", fmt::format("must be >= 0 (got {})", s.near_distance));
  }
  if (o.threads < 0) bad_option("threads", fmt::format("must be >= 0 (got {})", o.threads));
  if (!(o.time_limit >= 0) || !std::isfinite(o.time_limit)) {
    bad_option("time_limit", fmt::format("must be >= 0 (got {})", o.time_limit));
  }
  if (!(o.prune_threshold >= 0) || !std::isfinite(o.prune_threshold)) {
    bad_option("prune_threshold", fmt::format("must be >= 0 (got {})", o.prune_threshold));
  }
  if (!(o.lr_end > 0 && o.lr_end <= 1)) {
    bad_option("lr_end", fmt::format("must be in (0, 1] (got {})", o.lr_end));
  }
  if (o.reseed_every < 0) {
    bad_option("reseed_every", fmt::format("must be >= 0 (got {})", o.reseed_every));
  }
  if (!(o.reseed_until >= 0 && o.reseed_until <= 1)) {
    bad_option("reseed_until", fmt::format("must be in [0, 1] (got {})", o.reseed_until));
  }
  if (o.type_search_every < 0) {
    bad_option("type_search_every", fmt::format("must be >= 0 (got {})", o.type_search_every));
  }
  if (!(o.type_search_from >= 0 && o.type_search_from <= 1)) {
    bad_option("type_search_from", fmt::format("must be in [0, 1] (got {})", o.type_search_from));
  }
  if (!(o.type_search_until >= 0 && o.type_search_until <= 1)) {
    bad_option("type_search_until", fmt::format("must be in [0, 1] (got {})", o.type_search_until));
  }
  if (o.type_search_switches < 1) {
    bad_option("type_search_switches",
               fmt::format("must be >= 1 (got {})", o.type_search_switches));
  }
  if (o.type_search_points < 1 || o.type_search_points > (1u << 24)) {
    bad_option("type_search_points",
               fmt::format("must be in [1, 16777216] (got {})", o.type_search_points));
  }
  if (o.prune_points < 1) bad_option("prune_points", "must be >= 1");
  if (o.prune_max_primitives < 0) {
    bad_option("prune_max_primitives",
               fmt::format("must be >= 0 (0: no limit; got {})", o.prune_max_primitives));
  }
  if (o.metrics.points < 1) bad_option("metrics.points", "must be >= 1");
}

Tree make_initial_model(const FitOptions& o, int dim) {
  FullTreeOptions t;
  t.dim = dim;
  t.leaves = o.prims;
  t.family = dim == 3 ? PrimitiveType::kQuadric3 : PrimitiveType::kQuadric2;
  t.families = o.families;
  t.ops = o.ops;
  t.op_init = o.op_init;
  t.op_types = o.op_types;
  t.init_range = o.init_range;
  t.seed = o.seed;
  t.temperature = o.temperature;
  t.omega = o.omega;
  return make_full_binary_tree(t);
}

double temperature_at(const FitOptions& o, long step) {
  return optim::geometric_ramp(o.temperature_start, o.temperature,
                               o.temperature_ramp * static_cast<double>(o.iters), step);
}

double lr_at(const FitOptions& o, long step) {
  if (o.lr_schedule == LrSchedule::kConstant || o.iters <= 0) return o.lr;
  return optim::cosine_lr(o.lr, o.lr_end, static_cast<double>(step) / static_cast<double>(o.iters));
}

FitResult fit(const Target& target, const FitOptions& o, const FitHooks& hooks,
              const TrainState* resume) {
  const int dim = target.dim();
  validate(o, dim);
  Tree model = make_initial_model(o, dim);
  FitResult result;
  if (o.init == InitMode::kBalls) {
    TargetInitOptions io;
    io.temperature = temperature_at(o, 0);
    io.seed = o.seed;
    if (o.init_slope > 0) io.slope = o.init_slope;
    result.initialised_leaves = initialise_from_target(model, target, io);
  } else if (o.init == InitMode::kSurface) {
    SurfaceInitOptions so;
    so.seed = o.seed;
    so.curvature = o.init_range;
    if (o.init_slope > 0) so.slope = o.init_slope;
    result.initialised_leaves = initialise_on_surface(model, target, so);
  }
  const Evaluator ev(model, EvalOptions{o.threads});
  const std::size_t n = model.params.size();
  const std::vector<double> initial = model.params.values();

  TrainState st;
  if (resume) {
    st = *resume;
    if (st.params.size() != n || st.m.size() != n || st.v.size() != n) {
      throw InputError(
          fmt::format("checkpoint: state.params: {} values, but the model has {} parameters",
                      st.params.size(), n));
    }
  } else {
    st.params = initial;
    st.m.assign(n, 0.0);
    st.v.assign(n, 0.0);
  }

  const optim::Adam adam = model_adam(model, o);
  const std::vector<std::size_t> temps = temperature_indices(model);
  const std::size_t pool_size = o.pool ? o.pool : static_cast<std::size_t>(o.batch);
  const std::size_t batch = static_cast<std::size_t>(o.batch);
  const long curve_every = std::max(1L, o.iters / 1000);

  Rng rng(o.seed ^ kSamplerStream);
  SampleSet pool;
  std::future<SampleSet> next_pool;  // drawn ahead (see the training loop); holds `rng` meanwhile
  std::string next_rng;              // the generator's state before it
  if (resume && st.pool_step >= 0) {
    // Redraw the pool the interrupted run was using: same generator state, same points.
    rng = load_rng(st.rng_at_resample);
    pool = draw_samples(target, pool_size, o.sampling, rng);
  }

  // A non-finite loss rolls back to the state at the start of the last step whose loss was
  // finite. Adam writes the new parameters and moments into `prev` and swaps them in, so that
  // `prev` holds that state without copies.
  struct {
    std::vector<double> params, m, v;
    long pool_step = -1;
    std::string rng_at_resample;
    std::size_t curve_size = 0;
    double loss_sum = 0;
    long loss_count = 0;
    long reseeded = 0;
    long switched = 0;
    bool valid = false;  // a step of this run had a finite loss
  } prev;
  prev.params.resize(n);
  prev.m.resize(n);
  prev.v.resize(n);

  std::vector<double> grad(n);
  std::vector<float> points(batch * static_cast<std::size_t>(dim));
  std::vector<float> labels(batch);
  std::unique_ptr<BoundaryDistance> distance;
  const long reseed_last = static_cast<long>(o.reseed_until * static_cast<double>(o.iters));
  if (o.reseed_every > 0 && o.reseed_every < reseed_last) {
    Rng drng(o.seed ^ kReseedStream);
    distance = std::make_unique<BoundaryDistance>(target, 50000, drng);
  }
  const long type_search_first =
      static_cast<long>(o.type_search_from * static_cast<double>(o.iters));
  const long type_search_last =
      static_cast<long>(o.type_search_until * static_cast<double>(o.iters));
  const Clock::time_point start = Clock::now();
  const double seconds_before = st.seconds;
  Clock::time_point last_report = start;
  long steps_at_report = st.step;
  double report_loss_sum = 0;
  long report_loss_count = 0;

  auto report = [&](bool final) {
    if (!hooks.progress) return;
    const double dt = seconds_since(last_report);
    Progress p;
    p.step = st.step;
    p.iters = o.iters;
    p.loss = report_loss_count ? report_loss_sum / static_cast<double>(report_loss_count)
                               : (st.curve.empty() ? 0.0 : st.curve.back().loss);
    p.steps_per_second = dt > 0 ? static_cast<double>(st.step - steps_at_report) / dt : 0.0;
    p.seconds = st.seconds;
    p.temperature = temperature_at(o, st.step);
    p.final = final;
    hooks.progress(p);
    last_report = Clock::now();
    steps_at_report = st.step;
    report_loss_sum = 0;
    report_loss_count = 0;
  };

  result.stop = StopReason::kIterations;
  while (st.step < o.iters) {
    st.seconds = seconds_before + seconds_since(start);
    if (o.time_limit > 0 && st.seconds >= o.time_limit) {
      result.stop = StopReason::kTimeLimit;
      break;
    }
    if (st.pool_step < 0 || st.step - st.pool_step >= o.resample_every) {
      st.pool_step = st.step;
      if (next_pool.valid()) {
        st.rng_at_resample = std::move(next_rng);
        pool = next_pool.get();
      } else {
        st.rng_at_resample = save_rng(rng);
        pool = draw_samples(target, pool_size, o.sampling, rng);
      }
      // The next pool is drawn on another thread while these steps run (the generator is used
      // by nothing else), so that sampling leaves the critical path; the same points in the
      // same order as drawing it when it is needed.
      if (st.step + o.resample_every < o.iters) {
        next_rng = save_rng(rng);
        next_pool = std::async(std::launch::async, [&target, &o, &rng, pool_size] {
          return draw_samples(target, pool_size, o.sampling, rng);
        });
      }
    }
    // The batch: the next `batch` points of the pool, cycling.
    const std::size_t offset =
        (static_cast<std::size_t>(st.step - st.pool_step) * batch) % pool_size;
    for (std::size_t i = 0; i < batch; ++i) {
      const std::size_t j = (offset + i) % pool_size;
      labels[i] = pool.occupancy[j];
      for (int d = 0; d < dim; ++d) {
        points[i * static_cast<std::size_t>(dim) + static_cast<std::size_t>(d)] =
            pool.points[j * static_cast<std::size_t>(dim) + static_cast<std::size_t>(d)];
      }
    }
    const double t = temperature_at(o, st.step);
    for (std::size_t i : temps) st.params[i] = t;

    Loss loss_spec;
    loss_spec.kind = Loss::Kind::kMse;
    loss_spec.targets = labels;
    const double loss = ev.backward(st.params, points, loss_spec, grad);
    bool finite = std::isfinite(loss);
    for (std::size_t i = 0; finite && i < n; ++i) finite = std::isfinite(grad[i]);
    if (!finite) {
      result.stop = StopReason::kNonFinite;
      result.nonfinite_step = st.step + 1;
      if (prev.valid) {
        std::swap(st.params, prev.params);
        std::swap(st.m, prev.m);
        std::swap(st.v, prev.v);
        --st.step;
        st.pool_step = prev.pool_step;
        st.rng_at_resample = prev.rng_at_resample;
        st.curve.resize(prev.curve_size);
        st.loss_sum = prev.loss_sum;
        st.loss_count = prev.loss_count;
        st.reseeded = prev.reseeded;
        st.switched = prev.switched;
      }
      break;
    }
    if (!prev.valid || prev.pool_step != st.pool_step) prev.rng_at_resample = st.rng_at_resample;
    prev.pool_step = st.pool_step;
    prev.curve_size = st.curve.size();
    prev.loss_sum = st.loss_sum;
    prev.loss_count = st.loss_count;
    prev.reseeded = st.reseeded;
    prev.switched = st.switched;
    prev.valid = true;

    // Adam into `prev`.
    adam.step(st.step + 1, lr_at(o, st.step), grad, optim::ConstAdamState{st.params, st.m, st.v},
              optim::AdamState{prev.params, prev.m, prev.v});
    std::swap(st.params, prev.params);
    std::swap(st.m, prev.m);
    std::swap(st.v, prev.v);

    ++st.step;
    if (distance && st.step % o.reseed_every == 0 && st.step < reseed_last) {
      Rng rrng(o.seed ^ kReseedStream ^
               (static_cast<std::uint64_t>(st.step) * 0x9e3779b97f4a7c15ULL));
      ReseedOptions ro;
      if (o.init_slope > 0) ro.slope = o.init_slope;
      ro.threshold = o.prune_threshold;
      ro.near_distance = o.sampling.near_distance;
      const ReseedReport rep =
          reseed_dead_leaves(model, ev, target, *distance, st.params, st.m, st.v, ro, rrng);

      st.reseeded += rep.moved;
    }
    if (o.type_search_every > 0 && st.step % o.type_search_every == 0 &&
        st.step >= type_search_first && st.step < type_search_last) {
      Rng trng(o.seed ^ kTypeSearchStream ^
               (static_cast<std::uint64_t>(st.step) * 0x9e3779b97f4a7c15ULL));
      TypeSearchOptions to;
      to.points = o.type_search_points;
      to.max_switches = o.type_search_switches;
      to.sampling = o.sampling;
      const TypeSearchReport rep =
          search_operator_types(model, ev, target, st.params, st.m, st.v, to, trng);
      st.switched += rep.switched;
      ++result.type_searches;
    }
    st.loss_sum += loss;
    ++st.loss_count;
    report_loss_sum += loss;
    ++report_loss_count;
    if (st.step % curve_every == 0 || st.step == o.iters) {
      st.seconds = seconds_before + seconds_since(start);
      st.curve.push_back({st.step, st.loss_sum / static_cast<double>(st.loss_count), st.seconds});
      st.loss_sum = 0;
      st.loss_count = 0;
    }
    if (hooks.checkpoint && hooks.checkpoint_every > 0 && st.step % hooks.checkpoint_every == 0) {
      st.seconds = seconds_before + seconds_since(start);
      hooks.checkpoint(model, st);
    }
    if (hooks.progress && seconds_since(last_report) >= hooks.progress_seconds) report(false);
  }
  st.seconds = seconds_before + seconds_since(start);
  if (st.loss_count > 0) {
    st.curve.push_back({st.step, st.loss_sum / static_cast<double>(st.loss_count), st.seconds});
    st.loss_sum = 0;
    st.loss_count = 0;
  }
  // The temperature the parameters were last trained at (the final one unless stopped early).
  for (std::size_t i : temps) st.params[i] = temperature_at(o, std::max(0L, st.step - 1));
  report(true);
  result.last_good_step = st.step;
  result.train_seconds = st.seconds;
  // A first step without a finite loss leaves no state worth keeping (a resumed one is kept).
  const bool nothing_good = result.stop == StopReason::kNonFinite && !prev.valid && !resume;
  if (hooks.checkpoint && !nothing_good) hooks.checkpoint(model, st);

  result.trained = with_values(model, st.params);
  {
    const std::vector<int> before = operator_types(model, initial);
    const std::vector<int> after = operator_types(model, st.params);
    const std::vector<int> bits_before = structure_bits(model, before);
    const std::vector<int> bits_after = structure_bits(model, after);
    for (std::size_t i = 0; i < before.size(); ++i) {
      if (before[i] < 0) continue;
      ++result.operators_total;
      result.operators_changed += before[i] != after[i] ? 1 : 0;
      result.operators_restructured += bits_before[i] != bits_after[i] ? 1 : 0;
    }
  }
  result.reseeded = st.reseeded;
  result.type_switches = st.switched;
  result.state = std::move(st);
  if (result.stop == StopReason::kNonFinite) return result;

  Clock::time_point t0 = Clock::now();
  result.snapped = snap_operators(result.trained);
  Rng prune_rng(o.seed ^ (kSamplerStream * 3));
  const std::vector<float> prune_points = uniform_points(dim, o.prune_points, prune_rng);
  PruneOptions po;
  po.threshold = o.prune_threshold;
  po.threads = o.threads;
  po.max_primitives = o.prune_max_primitives;
  result.pruned = prune(result.snapped, prune_points, po, &result.prune);
  result.prune_seconds = seconds_since(t0);

  if (o.measure) {
    t0 = Clock::now();
    MetricsOptions mo = o.metrics;
    mo.threads = o.threads;
    result.metrics_trained = measure(result.trained, result.trained.params.values(), target, mo);
    result.metrics_pruned = measure(result.pruned, result.pruned.params.values(), target, mo);
    result.metrics_seconds = seconds_since(t0);
  }
  return result;
}

}  // namespace fuzzycsg
