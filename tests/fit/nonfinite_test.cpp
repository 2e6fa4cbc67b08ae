// A loss that becomes NaN: fit stops and rolls back to the state at the start of the last step
// whose loss was finite, which resumes bit-identically.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

#include "fit/fit_support.hpp"
#include "fuzzycsg/fit/fit.hpp"

namespace fuzzycsg {
namespace {

// The disc of fit_support, whose labels turn NaN from the `first_bad`-th call of occupancy()
// on (counted from 0; each drawing of training points makes one call).
class TurnsNanTarget : public testing::BallTarget {
 public:
  explicit TurnsNanTarget(int first_bad) : BallTarget(2, {0.1, 0}, 0.5), first_bad_(first_bad) {}
  void occupancy(std::span<const float> points, std::span<float> out) const override {
    BallTarget::occupancy(points, out);
    if (calls_++ >= first_bad_) {
      std::fill(out.begin(), out.end(), std::numeric_limits<float>::quiet_NaN());
    }
  }

 private:
  int first_bad_;
  mutable std::atomic<int> calls_{0};
};

FitOptions fit_options(long iters) {
  FitOptions o;
  o.prims = 4;
  o.iters = iters;
  o.batch = 128;
  o.resample_every = 1;    // one drawing per step
  o.temperature_ramp = 0;  // the same schedule whatever `iters`
  o.lr = 1e-2;
  o.threads = 2;
  o.measure = false;
  o.prune_points = 1024;
  return o;
}

TEST(NonFinite, RollsBackToTheLastStepWithAFiniteLoss) {
  const TurnsNanTarget bad(7);  // the 8th step's labels are NaN
  std::vector<long> saved_steps;
  TrainState last_saved;
  FitHooks hooks;
  hooks.checkpoint_every = 7;  // a periodic checkpoint of the state that fails next
  hooks.checkpoint = [&](const Tree&, const TrainState& st) {
    saved_steps.push_back(st.step);
    last_saved = st;
  };
  const FitResult r = fit(bad, fit_options(300), hooks);
  EXPECT_EQ(r.stop, StopReason::kNonFinite);
  EXPECT_EQ(r.nonfinite_step, 8);
  EXPECT_EQ(r.last_good_step, 6);
  EXPECT_EQ(r.state.step, 6);
  EXPECT_EQ(saved_steps, (std::vector<long>{7, 6}));  // the final checkpoint replaces step 7's
  EXPECT_EQ(last_saved.params, r.state.params);

  // The same as six steps on the target that never fails: parameters, moments, loss curve.
  const testing::BallTarget good(2, {0.1, 0}, 0.5);
  const FitResult six = fit(good, fit_options(6));
  EXPECT_EQ(r.state.params, six.state.params);
  EXPECT_EQ(r.state.m, six.state.m);
  EXPECT_EQ(r.state.v, six.state.v);
  ASSERT_EQ(r.state.curve.size(), six.state.curve.size());
  for (std::size_t i = 0; i < r.state.curve.size(); ++i) {
    EXPECT_EQ(r.state.curve[i].step, six.state.curve[i].step);
    EXPECT_EQ(r.state.curve[i].loss, six.state.curve[i].loss);
  }
  EXPECT_EQ(r.trained.params.values(), six.trained.params.values());

  // Resumed on the good target, it continues as an uninterrupted run.
  const FitResult resumed = fit(good, fit_options(20), {}, &r.state);
  const FitResult straight = fit(good, fit_options(20));
  EXPECT_EQ(resumed.state.step, 20);
  EXPECT_EQ(resumed.trained.params.values(), straight.trained.params.values());
}

TEST(NonFinite, AFirstStepThatFailsKeepsNothing) {
  const TurnsNanTarget bad(0);
  int saves = 0;
  FitHooks hooks;
  hooks.checkpoint_every = 1;
  hooks.checkpoint = [&](const Tree&, const TrainState&) { ++saves; };
  const FitResult r = fit(bad, fit_options(50), hooks);
  EXPECT_EQ(r.stop, StopReason::kNonFinite);
  EXPECT_EQ(r.nonfinite_step, 1);
  EXPECT_EQ(r.last_good_step, 0);
  EXPECT_EQ(saves, 0);
  EXPECT_EQ(r.state.params, make_initial_model(fit_options(50), 2).params.values());
}

TEST(NonFinite, AResumedRunThatFailsAtOnceKeepsItsStart) {
  const testing::BallTarget good(2, {0.1, 0}, 0.5);
  const FitResult start = fit(good, fit_options(5));
  const TurnsNanTarget bad(0);  // the pool redrawn on resuming is NaN
  std::vector<long> saved_steps;
  FitHooks hooks;
  hooks.checkpoint = [&](const Tree&, const TrainState& st) { saved_steps.push_back(st.step); };
  const FitResult r = fit(bad, fit_options(50), hooks, &start.state);
  EXPECT_EQ(r.stop, StopReason::kNonFinite);
  EXPECT_EQ(r.nonfinite_step, 6);
  EXPECT_EQ(r.last_good_step, 5);
  EXPECT_EQ(saved_steps, (std::vector<long>{5}));
  EXPECT_EQ(r.state.params, start.state.params);
}

}  // namespace
}  // namespace fuzzycsg
