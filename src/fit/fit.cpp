#include "fuzzycsg/fit/fit.hpp"

#include <fmt/core.h>

#include <bit>
#include <cmath>

#include "fit/trainer.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/optim/schedule.hpp"

namespace fuzzycsg {

namespace {

[[noreturn]] void bad_option(const char* field, std::string what) {
  throw OptionError(field, std::move(what));
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
  validate(o, target.dim());
  fit_detail::Trainer trainer(target, o, hooks, resume);
  while (trainer.steps_left() && !trainer.out_of_time()) {
    trainer.sample_batch();
    trainer.set_temperature();
    const double loss = trainer.loss_and_gradient();
    if (trainer.rollback_if_non_finite(loss)) break;
    trainer.keep_rollback_point();
    trainer.step();
    trainer.reseed();
    trainer.search_types();
    trainer.record_curves(loss);
    trainer.checkpoint();
    trainer.report_progress();
  }
  return trainer.finish();
}

}  // namespace fuzzycsg
