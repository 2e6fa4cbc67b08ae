#pragma once
// The fit module: inverse CSG by gradient descent (Liu et al. 2024). This header is its main
// one (fit, FitOptions, FitResult); the others:
//   init.hpp          starting points that look at the target, and re-seeding.
//   types.hpp         the search over the types of unified operators.
//   prune.hpp         prune: redundant nodes removed after snapping.
//   report.hpp        report.json and the checkpoint a fit resumes from.
//   option_names.hpp  the names of the settings chosen from a list.
//   plot.hpp          the loss curve and occupancy pictures.
//
// Inverse CSG by gradient descent (Liu et al. 2024, §5.2 and App. A): a full binary tree of
// P primitives with unified boolean operators B_c is fitted to a target's crisp occupancy by
// Adam on the mean squared error, then snapped to crisp booleans and pruned.
//
// One deliberate departure from the letter of App. A, on by default: the temperature t of
// c = softmax(sin(ω c̃) t) rises geometrically from `temperature_start` to `temperature` over
// the first `temperature_ramp` fraction of the steps. At t = 1000 from the first step the
// softmax is saturated, dL/dc̃ is ~0 for almost every operator, and the operator types chosen
// by the random initialisation never change; with the ramp they are optimised, as the paper
// intends. `temperature_ramp = 0` is the authors' release (t constant).

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/fit/prune.hpp"
#include "fuzzycsg/target/metrics.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg {

// How the model's parameters start: U[-init_range, init_range] (App. A), or from the target
// (fuzzycsg/fit/init.hpp): a union of balls covering it, or quadrics through its surface.
enum class InitMode { kRandom, kBalls, kSurface };
// The learning rate over the steps: constant (App. A), or a cosine from lr down to lr * lr_end.
enum class LrSchedule { kConstant, kCosine };
// What Adam steps for the sharpness s of a leaf's sigmoid step: s itself (App. A and the
// authors' release), or log s. Adam moves a parameter by about lr a step, so a sharpness
// stepped directly grows by at most lr a step (1 + 20 after 20,000 steps at lr 1e-3) and the
// occupancy stays soft across the surface; stepped as log s it grows by up to a factor
// exp(lr) a step, as fast at 50 as at 5. The tree keeps s; only the optimiser's coordinate
// (and its Adam moments) differ.
enum class SharpnessParam { kLinear, kLog };

struct FitOptions {
  // --- model
  int prims = 64;                       // leaves of the full binary tree, a power of two
  std::vector<PrimitiveType> families;  // leaf i is families[i % size]; empty: quadric of dim
  OperatorMode ops = OperatorMode::kUnified;
  OperatorInit op_init = OperatorInit::kUniform;  // unified operators' logits (builders.hpp)
  OperatorTypes op_types = OperatorTypes::kAll;   // the types they can take (builders.hpp)
  InitMode init = InitMode::kRandom;
  double init_range = 0.5;  // parameters ~ U[-init_range, init_range] (App. A)
  // kBalls, kSurface: the occupancy's slope across the leaves' surfaces at the start (0: 20 for
  // balls, 1 — the quadrics' default sharpness — for surface patches).
  double init_slope = 0.0;
  double temperature = 1000.0;  // t (the final value when ramped)
  double temperature_start = 10.0;
  double temperature_ramp = 0.3;  // fraction of `iters` over which t rises; 0: constant t
  double omega = 10.0;
  std::uint64_t seed = 0;

  // --- optimisation
  long iters = 10000;
  int batch = 1024;
  std::size_t pool = 0;     // points drawn at each resampling (0: batch); steps cycle through it
  int resample_every = 10;  // steps between resamplings
  double lr = 1e-3, beta1 = 0.9, beta2 = 0.999, adam_eps = 1e-8;
  LrSchedule lr_schedule = LrSchedule::kConstant;
  double lr_end = 0.05;  // kCosine: the final learning rate as a fraction of lr
  SharpnessParam sharpness_param = SharpnessParam::kLinear;
  // Re-seeding of dead leaves (fuzzycsg/fit/init.hpp) every `reseed_every` steps (0: never)
  // during the first `reseed_until` fraction of the steps.
  long reseed_every = 0;
  double reseed_until = 0.5;
  // Search over the unified operators' types (fuzzycsg/fit/types.hpp) every
  // `type_search_every` steps (0: never) from the `type_search_from` fraction of the steps to
  // the `type_search_until` fraction, on two fresh samples of `type_search_points` points each.
  long type_search_every = 0;
  double type_search_from = 0.0;
  double type_search_until = 0.9;
  std::size_t type_search_points = 8192;
  int type_search_switches = 32;  // switches made together in one round of a search
  SamplingOptions sampling;
  int threads = 0;
  double time_limit = 0;  // seconds of training, 0: none

  // --- after training
  double prune_threshold = 1e-3;
  std::size_t prune_points = 65536;  // uniform points on which redundancy is judged
  // After threshold pruning, at most this many primitives are kept (0: no limit): the greedy
  // reduction of PruneOptions::max_primitives.
  int prune_max_primitives = 0;
  MetricsOptions metrics;
  bool measure = true;
};

// Throws InputError naming the flag (as the program spells it) when a setting is out of range.
void validate(const FitOptions& options, int dim);

// A point of the loss curve: the mean training loss over the steps since the previous point.
struct LossPoint {
  long step = 0;  // steps done
  double loss = 0;
  double seconds = 0;  // training time when recorded
};

// The state that a checkpoint holds: enough to continue bit-identically.
struct TrainState {
  long step = 0;
  std::vector<double> params;   // the tree's parameter table order
  std::vector<double> m, v;     // Adam moments
  std::string rng_at_resample;  // the sampler's state before the current pool was drawn
  long pool_step = -1;          // step at which the current pool was drawn
  std::vector<LossPoint> curve;
  double loss_sum = 0;  // since the last curve point
  long loss_count = 0;
  double seconds = 0;  // training time so far
  long reseeded = 0;   // leaves moved by re-seeding so far
  long switched = 0;   // operator types changed by the type search so far
};

struct Progress {
  long step = 0, iters = 0;
  double loss = 0;  // recent mean
  double steps_per_second = 0;
  double seconds = 0;  // elapsed training time
  double temperature = 0;
  bool final = false;  // the last call
};

struct FitHooks {
  std::function<void(const Progress&)> progress;  // called about every `progress_seconds`
  double progress_seconds = 0.5;
  // Called every `checkpoint_every` steps (and at the end, except after a fresh run's first
  // step fails) with the state to persist.
  std::function<void(const Tree& model, const TrainState&)> checkpoint;
  long checkpoint_every = 0;  // 0: never
};

enum class StopReason { kIterations, kTimeLimit, kNonFinite };
std::string_view stop_reason_name(StopReason r);

struct FitResult {
  Tree trained;      // final parameters (unified operators at the final temperature)
  Tree snapped;      // operators snapped to crisp booleans
  Tree pruned;       // snapped and pruned
  TrainState state;  // the final training state
  StopReason stop = StopReason::kIterations;
  // kNonFinite: the step (counted from 1) whose loss or gradient was NaN or infinite, and the
  // state kept in `trained`, `state` and the last checkpoint: that at the start of the last
  // step whose loss was finite (last_good_step = nonfinite_step - 2), or the start of the run
  // when its first step failed (no checkpoint then, unless resumed).
  long nonfinite_step = 0;
  long last_good_step = 0;
  int operators_changed = 0;  // unified operators whose argmax type differs from the start
  int operators_total = 0;
  // Unified operators whose structure bit differs from the start: whether the parent sees an
  // intersection or the complement of one (structure_bits, fit/types.hpp). With leaves whose
  // family holds their complements (quadrics, conics, planes), a type change that keeps every
  // bit is a negation of leaves, not another structure.
  int operators_restructured = 0;
  long reseeded = 0;           // leaves moved by re-seeding
  long type_switches = 0;      // operator types changed by the type search
  int type_searches = 0;       // searches run by this call
  int initialised_leaves = 0;  // InitMode::kBalls: leaves started as balls
  PruneReport prune;
  std::optional<Metrics> metrics_trained, metrics_pruned;
  double train_seconds = 0, prune_seconds = 0, metrics_seconds = 0;
};

// The initial model for a target of dimension `dim`, drawn at random (InitMode::kRandom; fit()
// then starts it from the target when options.init says so).
Tree make_initial_model(const FitOptions& options, int dim);

// Temperature at a step (see the header comment).
double temperature_at(const FitOptions& options, long step);

// Learning rate at a step.
double lr_at(const FitOptions& options, long step);

// Runs the fit. `resume` continues from a checkpoint of the same model and options.
FitResult fit(const Target& target, const FitOptions& options, const FitHooks& hooks = {},
              const TrainState* resume = nullptr);

}  // namespace fuzzycsg
