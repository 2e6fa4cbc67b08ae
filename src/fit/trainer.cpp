#include "fit/trainer.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <utility>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/snap.hpp"
#include "fuzzycsg/fit/types.hpp"

namespace fuzzycsg::fit_detail {

namespace {

// The sampler draws from its own stream so that changing the model's seed use does not shift
// the training points (and vice versa).
constexpr std::uint64_t kSamplerStream = 0x9e3779b97f4a7c15ULL;
// Re-seeding rounds draw from a stream of the seed and the step, so a resumed run repeats them.
constexpr std::uint64_t kReseedStream = 0xd1b54a32d192ed03ULL;
constexpr std::uint64_t kTypeSearchStream = 0x8cb92ba72f3d8dd7ULL;

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

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

// The initial model, started from the target when the options say so (the leaves so started
// into `initialised_leaves`).
Tree started_model(const Target& target, const FitOptions& o, int dim, int& initialised_leaves) {
  Tree model = make_initial_model(o, dim);
  if (o.init == InitMode::kBalls) {
    TargetInitOptions io;
    io.temperature = temperature_at(o, 0);
    io.seed = o.seed;
    if (o.init_slope > 0) io.slope = o.init_slope;
    initialised_leaves = initialise_from_target(model, target, io);
  } else if (o.init == InitMode::kSurface) {
    SurfaceInitOptions so;
    so.seed = o.seed;
    so.curvature = o.init_range;
    if (o.init_slope > 0) so.slope = o.init_slope;
    initialised_leaves = initialise_on_surface(model, target, so);
  }
  return model;
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

Tree with_values(Tree tree, std::span<const double> values) {
  tree.params.set_values(values);
  return tree;
}

// The step at which a fraction of the run falls.
long step_at(double fraction, long iters) {
  return static_cast<long>(fraction * static_cast<double>(iters));
}

}  // namespace

Trainer::Trainer(const Target& target, const FitOptions& options, const FitHooks& hooks,
                 const TrainState* resume)
    : target_(target),
      o_(options),
      hooks_(hooks),
      resumed_(resume != nullptr),
      dim_(target.dim()),
      model_(started_model(target, options, dim_, result_.initialised_leaves)),
      ev_(model_, EvalOptions{options.threads}),
      initial_(model_.params.values()),
      adam_(model_adam(model_, options)) {
  const std::size_t n = model_.params.size();
  if (resume) {
    st_ = *resume;
    if (st_.params.size() != n || st_.m.size() != n || st_.v.size() != n) {
      throw InputError(
          fmt::format("checkpoint: state.params: {} values, but the model has {} parameters",
                      st_.params.size(), n));
    }
  } else {
    st_.params = initial_;
    st_.m.assign(n, 0.0);
    st_.v.assign(n, 0.0);
  }
  temperatures_ = temperature_indices(model_);
  pool_size_ = o_.pool ? o_.pool : static_cast<std::size_t>(o_.batch);
  batch_ = static_cast<std::size_t>(o_.batch);
  curve_every_ = std::max(1L, o_.iters / 1000);

  rng_ = Rng(o_.seed ^ kSamplerStream);
  if (resume && st_.pool_step >= 0) {
    // Redraw the pool the interrupted run was using: same generator state, same points.
    rng_ = load_rng(st_.rng_at_resample);
    pool_ = draw_samples(target_, pool_size_, o_.sampling, rng_);
  }
  prev_.params.resize(n);
  prev_.m.resize(n);
  prev_.v.resize(n);

  grad_.resize(n);
  points_.resize(batch_ * static_cast<std::size_t>(dim_));
  labels_.resize(batch_);
  reseed_last_ = step_at(o_.reseed_until, o_.iters);
  if (o_.reseed_every > 0 && o_.reseed_every < reseed_last_) {
    Rng drng(o_.seed ^ kReseedStream);
    distance_ = std::make_unique<BoundaryDistance>(target_, 50000, drng);
  }
  type_search_first_ = step_at(o_.type_search_from, o_.iters);
  type_search_last_ = step_at(o_.type_search_until, o_.iters);
  start_ = Clock::now();
  seconds_before_ = st_.seconds;
  last_report_ = start_;
  steps_at_report_ = st_.step;
  result_.stop = StopReason::kIterations;
}

double Trainer::seconds() const { return seconds_before_ + seconds_since(start_); }

bool Trainer::out_of_time() {
  st_.seconds = seconds();
  if (o_.time_limit > 0 && st_.seconds >= o_.time_limit) {
    result_.stop = StopReason::kTimeLimit;
    return true;
  }
  return false;
}

void Trainer::draw_pool() {
  st_.pool_step = st_.step;
  if (next_pool_.valid()) {
    st_.rng_at_resample = std::move(next_rng_);
    pool_ = next_pool_.get();
  } else {
    st_.rng_at_resample = save_rng(rng_);
    pool_ = draw_samples(target_, pool_size_, o_.sampling, rng_);
  }
  // The next pool is drawn on another thread while these steps run (the generator is used by
  // nothing else), so that sampling leaves the critical path; the same points in the same
  // order as drawing it when it is needed.
  if (st_.step + o_.resample_every < o_.iters) {
    next_rng_ = save_rng(rng_);
    next_pool_ = std::async(std::launch::async, [this] {
      return draw_samples(target_, pool_size_, o_.sampling, rng_);
    });
  }
}

void Trainer::sample_batch() {
  if (st_.pool_step < 0 || st_.step - st_.pool_step >= o_.resample_every) draw_pool();
  const std::size_t dim = static_cast<std::size_t>(dim_);
  const std::size_t offset =
      (static_cast<std::size_t>(st_.step - st_.pool_step) * batch_) % pool_size_;
  for (std::size_t i = 0; i < batch_; ++i) {
    const std::size_t j = (offset + i) % pool_size_;
    labels_[i] = pool_.occupancy[j];
    for (std::size_t d = 0; d < dim; ++d) points_[i * dim + d] = pool_.points[j * dim + d];
  }
}

void Trainer::set_temperature() {
  const double t = temperature_at(o_, st_.step);
  for (std::size_t i : temperatures_) st_.params[i] = t;
}

double Trainer::loss_and_gradient() {
  Loss loss;
  loss.kind = Loss::Kind::kMse;
  loss.targets = labels_;
  return ev_.backward(st_.params, points_, loss, grad_);
}

bool Trainer::rollback_if_non_finite(double loss) {
  bool finite = std::isfinite(loss);
  for (std::size_t i = 0; finite && i < grad_.size(); ++i) finite = std::isfinite(grad_[i]);
  if (finite) return false;
  result_.stop = StopReason::kNonFinite;
  result_.nonfinite_step = st_.step + 1;
  if (prev_.valid) {
    std::swap(st_.params, prev_.params);
    std::swap(st_.m, prev_.m);
    std::swap(st_.v, prev_.v);
    --st_.step;
    st_.pool_step = prev_.pool_step;
    st_.rng_at_resample = prev_.rng_at_resample;
    st_.curve.resize(prev_.curve_size);
    st_.loss_sum = prev_.loss_sum;
    st_.loss_count = prev_.loss_count;
    st_.reseeded = prev_.reseeded;
    st_.switched = prev_.switched;
  }
  return true;
}

void Trainer::keep_rollback_point() {
  // The parameters and moments are kept by step(); the generator's state only changes with
  // the pool.
  if (!prev_.valid || prev_.pool_step != st_.pool_step) {
    prev_.rng_at_resample = st_.rng_at_resample;
  }
  prev_.pool_step = st_.pool_step;
  prev_.curve_size = st_.curve.size();
  prev_.loss_sum = st_.loss_sum;
  prev_.loss_count = st_.loss_count;
  prev_.reseeded = st_.reseeded;
  prev_.switched = st_.switched;
  prev_.valid = true;
}

void Trainer::step() {
  // Into prev_, then swapped in: prev_ keeps the parameters and moments this step started from.
  adam_.step(st_.step + 1, lr_at(o_, st_.step), grad_,
             optim::ConstAdamState{st_.params, st_.m, st_.v},
             optim::AdamState{prev_.params, prev_.m, prev_.v});
  std::swap(st_.params, prev_.params);
  std::swap(st_.m, prev_.m);
  std::swap(st_.v, prev_.v);
  ++st_.step;
}

void Trainer::reseed() {
  if (!distance_ || st_.step % o_.reseed_every != 0 || st_.step >= reseed_last_) return;
  Rng rng(o_.seed ^ kReseedStream ^ (static_cast<std::uint64_t>(st_.step) * 0x9e3779b97f4a7c15ULL));
  ReseedOptions ro;
  if (o_.init_slope > 0) ro.slope = o_.init_slope;
  ro.threshold = o_.prune_threshold;
  ro.near_distance = o_.sampling.near_distance;
  const ReseedReport rep =
      reseed_dead_leaves(model_, ev_, target_, *distance_, st_.params, st_.m, st_.v, ro, rng);
  st_.reseeded += rep.moved;
}

void Trainer::search_types() {
  if (o_.type_search_every <= 0 || st_.step % o_.type_search_every != 0 ||
      st_.step < type_search_first_ || st_.step >= type_search_last_) {
    return;
  }
  Rng rng(o_.seed ^ kTypeSearchStream ^
          (static_cast<std::uint64_t>(st_.step) * 0x9e3779b97f4a7c15ULL));
  TypeSearchOptions to;
  to.points = o_.type_search_points;
  to.max_switches = o_.type_search_switches;
  to.sampling = o_.sampling;
  const TypeSearchReport rep =
      search_operator_types(model_, ev_, target_, st_.params, st_.m, st_.v, to, rng);
  st_.switched += rep.switched;
  ++result_.type_searches;
}

void Trainer::record_curves(double loss) {
  st_.loss_sum += loss;
  ++st_.loss_count;
  report_loss_sum_ += loss;
  ++report_loss_count_;
  if (st_.step % curve_every_ == 0 || st_.step == o_.iters) {
    st_.seconds = seconds();
    st_.curve.push_back(
        {st_.step, st_.loss_sum / static_cast<double>(st_.loss_count), st_.seconds});
    st_.loss_sum = 0;
    st_.loss_count = 0;
  }
}

void Trainer::checkpoint() {
  if (hooks_.checkpoint && hooks_.checkpoint_every > 0 && st_.step % hooks_.checkpoint_every == 0) {
    st_.seconds = seconds();
    hooks_.checkpoint(model_, st_);
  }
}

void Trainer::report_progress() {
  if (hooks_.progress && seconds_since(last_report_) >= hooks_.progress_seconds) report(false);
}

void Trainer::report(bool final) {
  if (!hooks_.progress) return;
  const double dt = seconds_since(last_report_);
  Progress p;
  p.step = st_.step;
  p.iters = o_.iters;
  p.loss = report_loss_count_ ? report_loss_sum_ / static_cast<double>(report_loss_count_)
                              : (st_.curve.empty() ? 0.0 : st_.curve.back().loss);
  p.steps_per_second = dt > 0 ? static_cast<double>(st_.step - steps_at_report_) / dt : 0.0;
  p.seconds = st_.seconds;
  p.temperature = temperature_at(o_, st_.step);
  p.final = final;
  hooks_.progress(p);
  last_report_ = Clock::now();
  steps_at_report_ = st_.step;
  report_loss_sum_ = 0;
  report_loss_count_ = 0;
}

FitResult Trainer::finish() {
  close_training();
  if (result_.stop != StopReason::kNonFinite) {
    snap_and_prune();
    if (o_.measure) measure_results();
  }
  return std::move(result_);
}

void Trainer::close_training() {
  st_.seconds = seconds();
  if (st_.loss_count > 0) {
    st_.curve.push_back(
        {st_.step, st_.loss_sum / static_cast<double>(st_.loss_count), st_.seconds});
    st_.loss_sum = 0;
    st_.loss_count = 0;
  }
  // The temperature the parameters were last trained at (the final one unless stopped early).
  for (std::size_t i : temperatures_)
    st_.params[i] = temperature_at(o_, std::max(0L, st_.step - 1));
  report(true);
  result_.last_good_step = st_.step;
  result_.train_seconds = st_.seconds;
  // A first step without a finite loss leaves no state worth keeping (a resumed one is kept).
  const bool nothing_good = result_.stop == StopReason::kNonFinite && !prev_.valid && !resumed_;
  if (hooks_.checkpoint && !nothing_good) hooks_.checkpoint(model_, st_);

  result_.trained = with_values(model_, st_.params);
  count_operator_changes();
  result_.reseeded = st_.reseeded;
  result_.type_switches = st_.switched;
  result_.state = std::move(st_);
}

void Trainer::count_operator_changes() {
  const std::vector<int> before = operator_types(model_, initial_);
  const std::vector<int> after = operator_types(model_, st_.params);
  const std::vector<int> bits_before = structure_bits(model_, before);
  const std::vector<int> bits_after = structure_bits(model_, after);
  for (std::size_t i = 0; i < before.size(); ++i) {
    if (before[i] < 0) continue;
    ++result_.operators_total;
    result_.operators_changed += before[i] != after[i] ? 1 : 0;
    result_.operators_restructured += bits_before[i] != bits_after[i] ? 1 : 0;
  }
}

void Trainer::snap_and_prune() {
  const Clock::time_point t0 = Clock::now();
  result_.snapped = snap_operators(result_.trained);
  Rng prune_rng(o_.seed ^ (kSamplerStream * 3));
  const std::vector<float> prune_points = uniform_points(dim_, o_.prune_points, prune_rng);
  PruneOptions po;
  po.threshold = o_.prune_threshold;
  po.threads = o_.threads;
  po.max_primitives = o_.prune_max_primitives;
  result_.pruned = prune(result_.snapped, prune_points, po, &result_.prune);
  result_.prune_seconds = seconds_since(t0);
}

void Trainer::measure_results() {
  const Clock::time_point t0 = Clock::now();
  MetricsOptions mo = o_.metrics;
  mo.threads = o_.threads;
  result_.metrics_trained = measure(result_.trained, result_.trained.params.values(), target_, mo);
  result_.metrics_pruned = measure(result_.pruned, result_.pruned.params.values(), target_, mo);
  result_.metrics_seconds = seconds_since(t0);
}

}  // namespace fuzzycsg::fit_detail
