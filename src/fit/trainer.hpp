#pragma once
// The training loop of fit() (fuzzycsg/fit/fit.hpp), one method per stage of a step, so that
// fit() reads as the loop it is:
//
//   while (steps_left() && !out_of_time()) {
//     sample_batch(); set_temperature(); loss = loss_and_gradient();
//     if (rollback_if_non_finite(loss)) break;
//     keep_rollback_point(); step(); reseed(); search_types();
//     record_curves(loss); checkpoint(); report_progress();
//   }
//   finish();  // the final state, then snap, prune and metrics
//
// The stages run in this order and no other: the sampler's generator, the re-seeding and the
// type search draw from their own streams, and a resumed run repeats an interrupted one only
// when every stage sees the state the previous one left.

#include <chrono>
#include <cstddef>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "fuzzycsg/fit/init.hpp"
#include "fuzzycsg/optim/adam.hpp"

namespace fuzzycsg::fit_detail {

class Trainer {
 public:
  // The model of `options` (validated by the caller), started from the target when
  // options.init says so, and the state of `resume` or a fresh one.
  Trainer(const Target& target, const FitOptions& options, const FitHooks& hooks,
          const TrainState* resume);
  // The pool drawn ahead holds references to the trainer's generator.
  Trainer(const Trainer&) = delete;
  Trainer& operator=(const Trainer&) = delete;

  bool steps_left() const { return st_.step < o_.iters; }
  // Whether the time limit has been reached (the stop reason is then kTimeLimit).
  bool out_of_time();
  // This step's batch: the next `batch` points of the pool, cycling; a new pool every
  // `resample_every` steps, the one after it drawn meanwhile on another thread.
  void sample_batch();
  // The unified operators' temperature for this step (the schedule, not Adam, sets it).
  void set_temperature();
  // The mean squared error on the batch, with its gradient.
  double loss_and_gradient();
  // A NaN or infinite loss or gradient stops training, back at the state at the start of the
  // last step whose loss was finite: true then.
  bool rollback_if_non_finite(double loss);
  // This step's start, as the state a later non-finite step rolls back to.
  void keep_rollback_point();
  // One Adam step, and the step count.
  void step();
  // Dead leaves moved onto the target's surface, when due.
  void reseed();
  // The unified operators' types searched, when due.
  void search_types();
  // The loss into the loss curve (a point every iters / 1000 steps) and the progress mean.
  void record_curves(double loss);
  // The state to the checkpoint hook, when due.
  void checkpoint();
  // Progress to the progress hook, when due.
  void report_progress();
  // After the loop: the last curve point, report and checkpoint, the trained tree, and unless
  // training failed, the snapped and pruned trees and their metrics. Called once.
  FitResult finish();

 private:
  using Clock = std::chrono::steady_clock;

  double seconds() const;  // training time, this run's and the resumed one's
  void report(bool final);
  void draw_pool();
  void close_training();
  void count_operator_changes();
  void snap_and_prune();
  void measure_results();

  const Target& target_;
  const FitOptions& o_;
  const FitHooks& hooks_;
  const bool resumed_;
  const int dim_;
  FitResult result_;
  Tree model_;
  const Evaluator ev_;
  const std::vector<double> initial_;  // the parameters the model started with
  TrainState st_;
  optim::Adam adam_;
  std::vector<std::size_t> temperatures_;  // parameter indices the schedule drives
  std::size_t pool_size_ = 0, batch_ = 0;
  long curve_every_ = 1;

  Rng rng_;  // the sampler's; declared before next_pool_, whose draw uses it
  SampleSet pool_;
  std::future<SampleSet> next_pool_;  // drawn ahead; holds rng_ meanwhile
  std::string next_rng_;              // the generator's state before it

  // A non-finite loss rolls back to the state at the start of the last step whose loss was
  // finite. Adam writes the new parameters and moments here and they are swapped in, so that
  // this holds that state without copies.
  struct RollbackPoint {
    std::vector<double> params, m, v;
    long pool_step = -1;
    std::string rng_at_resample;
    std::size_t curve_size = 0;
    double loss_sum = 0;
    long loss_count = 0;
    long reseeded = 0;
    long switched = 0;
    bool valid = false;  // a step of this run had a finite loss
  } prev_;

  std::vector<double> grad_;
  std::vector<float> points_, labels_;
  std::unique_ptr<BoundaryDistance> distance_;  // when re-seeding is on
  long reseed_last_ = 0, type_search_first_ = 0, type_search_last_ = 0;

  Clock::time_point start_, last_report_;
  double seconds_before_ = 0;  // training time of the run resumed
  long steps_at_report_ = 0;
  double report_loss_sum_ = 0;
  long report_loss_count_ = 0;
};

}  // namespace fuzzycsg::fit_detail
