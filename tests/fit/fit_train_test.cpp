// Training loop of inverse CSG: schedule, Adam, determinism, checkpoints and resume, stopping.

#include <gtest/gtest.h>
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "fit/fit_support.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "fuzzycsg/fit/plot.hpp"
#include "fuzzycsg/fit/report.hpp"

namespace fuzzycsg {
namespace {

// Labels every point NaN: a loss that becomes non-finite at the first step.
class NanTarget : public testing::BallTarget {
 public:
  NanTarget() : BallTarget(3, {0, 0, 0}, 0.5) {}
  void occupancy(std::span<const float>, std::span<float> out) const override {
    std::fill(out.begin(), out.end(), std::numeric_limits<float>::quiet_NaN());
  }
};

FitOptions small_options() {
  FitOptions o;
  o.prims = 4;
  o.iters = 300;
  o.batch = 256;
  o.lr = 1e-2;
  o.threads = 2;
  o.measure = false;
  o.prune_points = 4096;
  return o;
}

TEST(Temperature, RampsGeometricallyThenHolds) {
  FitOptions o;
  o.iters = 1000;
  o.temperature = 1000;
  o.temperature_start = 1;
  o.temperature_ramp = 0.5;
  EXPECT_DOUBLE_EQ(temperature_at(o, 0), 1.0);
  EXPECT_NEAR(temperature_at(o, 250), std::sqrt(1000.0), 1e-9);
  EXPECT_DOUBLE_EQ(temperature_at(o, 500), 1000.0);
  EXPECT_DOUBLE_EQ(temperature_at(o, 999), 1000.0);
  o.temperature_ramp = 0;
  EXPECT_DOUBLE_EQ(temperature_at(o, 0), 1000.0);
}

TEST(FitOptionsValidation, NamesTheFlag) {
  const auto message = [](const FitOptions& o) { return testing::validation_message(o, 3); };
  FitOptions o;
  o.prims = 48;
  EXPECT_NE(message(o).find("prims: "), std::string::npos);
  o = {};
  o.lr = -1;
  EXPECT_NE(message(o).find("lr: "), std::string::npos);
  o = {};
  o.batch = 0;
  EXPECT_NE(message(o).find("batch: "), std::string::npos);
  o = {};
  o.temperature_ramp = 2;
  EXPECT_NE(message(o).find("temperature_ramp: "), std::string::npos);
  o = {};
  o.families = {PrimitiveType::kCircle};
  EXPECT_NE(message(o).find("families: "), std::string::npos);
  o = {};
  o.pool = 10;  // smaller than the batch
  EXPECT_NE(message(o).find("pool: "), std::string::npos);
  o = {};
  o.prune_max_primitives = -1;
  EXPECT_NE(message(o).find("prune_max_primitives: "), std::string::npos);
  EXPECT_EQ(message(FitOptions{}), "");
}

TEST(Fit, LossFallsAndOperatorsAreCounted) {
  const testing::BallTarget target(3, {0, 0, 0}, 0.5);
  FitOptions o = small_options();
  // Points exactly on the surface carry a loss of about 1/4 each whatever the fit (the soft
  // occupancy is 1/2 there): leave them out so that the training loss measures the fit.
  o.sampling.surface = 0.0;
  const FitResult r = fit(target, o);
  ASSERT_EQ(r.stop, StopReason::kIterations);
  EXPECT_EQ(r.state.step, o.iters);
  ASSERT_GE(r.state.curve.size(), 2u);
  EXPECT_LT(r.state.curve.back().loss, 0.5 * r.state.curve.front().loss);
  EXPECT_EQ(r.operators_total, 3);
  EXPECT_GE(r.operators_changed, 0);
  EXPECT_LE(r.operators_changed, 3);
  // The trained tree evaluates at the final temperature.
  for (const Node& n : r.trained.nodes) {
    if (n.kind == NodeKind::kOperator) {
      EXPECT_DOUBLE_EQ(r.trained.params[*n.temperature].value, o.temperature);
    }
  }
  // Fixed parameters (temperature, omega) are not trained; every other one moved.
  const Tree initial = make_initial_model(o, 3);
  int moved = 0, fixed_moved = 0;
  for (std::size_t i = 0; i < initial.params.size(); ++i) {
    const bool changed = initial.params.at(i).value != r.trained.params.at(i).value;
    if (initial.params.at(i).fixed) {
      fixed_moved += changed && initial.params.at(i).name.find("temperature") == std::string::npos;
    } else {
      moved += changed;
    }
  }
  EXPECT_EQ(fixed_moved, 0);
  EXPECT_GT(moved, 40);
}

// --prune-max-primitives bounds the pruned tree and leaves the trained one as it was.
TEST(Fit, PruneMaxPrimitivesBoundsThePrunedTree) {
  const testing::BallTarget target(3, {0, 0, 0}, 0.5);
  FitOptions o = small_options();
  o.prims = 8;
  o.prune_threshold = 0;  // only what is exactly redundant goes at the threshold
  const FitResult free = fit(target, o);
  ASSERT_EQ(free.stop, StopReason::kIterations);
  ASSERT_GT(count(free.pruned).primitives, 2);
  o.prune_max_primitives = 2;
  const FitResult bounded = fit(target, o);
  ASSERT_EQ(bounded.stop, StopReason::kIterations);
  EXPECT_EQ(bounded.trained.params.values(), free.trained.params.values());
  EXPECT_LE(count(bounded.pruned).primitives, 2);
  EXPECT_GE(count(bounded.pruned).primitives, 1);
  EXPECT_EQ(bounded.prune.primitives_after, count(bounded.pruned).primitives);
  EXPECT_EQ(bounded.prune.primitives_before, free.prune.primitives_before);
}

// The sharpness of each leaf's sigmoid step, indexed by leaf.
std::vector<double> sharpnesses(const Tree& t) {
  std::vector<double> out;
  for (const Node& n : t.nodes) {
    if (n.kind == NodeKind::kPrimitive) out.push_back(t.params[*n.step.param].value);
  }
  return out;
}

TEST(Fit, LogSharpnessStepsTheLogarithm) {
  const testing::BallTarget target(3, {0, 0, 0}, 0.5);
  FitOptions o = small_options();
  o.iters = 1;
  const Tree initial = make_initial_model(o, 3);
  const FitResult linear = fit(target, o);
  o.sharpness_param = SharpnessParam::kLog;
  const FitResult log = fit(target, o);
  // Adam's first step moves every coordinate by lr (times g / (|g| + eps)): s by lr when
  // stepped directly, log s by lr when stepped as its logarithm.
  const std::vector<double> s0 = sharpnesses(initial), s1 = sharpnesses(linear.trained),
                            s2 = sharpnesses(log.trained);
  ASSERT_EQ(s0.size(), 4u);
  for (std::size_t i = 0; i < s0.size(); ++i) {
    EXPECT_NEAR(std::abs(s1[i] - s0[i]), o.lr, 1e-3 * o.lr) << i;
    EXPECT_NEAR(std::abs(std::log(s2[i] / s0[i])), o.lr, 1e-3 * o.lr) << i;
    EXPECT_EQ(s1[i] > s0[i], s2[i] > s0[i]) << i;  // the same direction
  }
  // Nothing else differs.
  int same = 0;
  for (std::size_t i = 0; i < initial.params.size(); ++i) {
    if (initial.params.at(i).name.ends_with(".sharpness")) continue;
    EXPECT_EQ(linear.trained.params.at(i).value, log.trained.params.at(i).value)
        << initial.params.at(i).name;
    ++same;
  }
  EXPECT_GT(same, 40);
}

TEST(Fit, LogSharpnessSharpensPastWhatLinearStepsCanReach) {
  const testing::BallTarget target(3, {0, 0, 0}, 0.5);
  FitOptions o = small_options();
  o.iters = 600;
  o.sampling.surface = 0.0;  // as LossFallsAndOperatorsAreCounted: the loss measures the fit
  const double start = std::ranges::max(sharpnesses(make_initial_model(o, 3)));
  const FitResult linear = fit(target, o);
  o.sharpness_param = SharpnessParam::kLog;
  const FitResult log = fit(target, o);
  // Stepped directly, no sharpness can pass start + lr * iters; as log s, some leaf does.
  const double bound = start + o.lr * static_cast<double>(o.iters);
  EXPECT_LE(std::ranges::max(sharpnesses(linear.trained)), bound);
  EXPECT_GT(std::ranges::max(sharpnesses(log.trained)), 2 * bound);
  EXPECT_LT(log.state.curve.back().loss, linear.state.curve.back().loss);
}

TEST(Fit, SameSeedSameResultAnyThreads) {
  const testing::BallTarget target(2, {0.1, 0}, 0.6);
  FitOptions o = small_options();
  o.iters = 120;
  o.threads = 1;
  const FitResult a = fit(target, o);
  o.threads = 2;
  const FitResult b = fit(target, o);
  EXPECT_EQ(a.trained.params.values(), b.trained.params.values());
  o.seed = 7;
  const FitResult c = fit(target, o);
  EXPECT_NE(a.trained.params.values(), c.trained.params.values());
}

TEST(Fit, ResumeFromACheckpointIsBitIdentical) {
  const testing::BallTarget target(3, {0, 0, 0}, 0.5);
  FitOptions o = small_options();
  o.iters = 200;
  o.pool = 1024;  // several batches per pool: the resumed run must redraw the same pool
  o.resample_every = 30;
  const FitResult full = fit(target, o);

  std::string saved;
  FitHooks hooks;
  hooks.checkpoint_every = 70;
  hooks.checkpoint = [&](const Tree&, const TrainState& st) {
    if (st.step == 70) {
      Checkpoint ck;
      ck.target = "ball";
      ck.dim = 3;
      ck.options = o;
      ck.state = st;
      saved = checkpoint_to_string(ck);
    }
  };
  FitOptions interrupted = o;
  interrupted.iters = 200;
  (void)fit(target, interrupted, hooks);
  ASSERT_FALSE(saved.empty());

  const Checkpoint ck = read_checkpoint(testing::write_temp("fuzzycsg_checkpoint.json", saved));
  EXPECT_EQ(ck.state.step, 70);
  EXPECT_EQ(ck.options.pool, 1024u);
  const FitResult resumed = fit(target, ck.options, {}, &ck.state);
  EXPECT_EQ(resumed.state.step, 200);
  EXPECT_EQ(resumed.trained.params.values(), full.trained.params.values());
}

TEST(Fit, StopsOnANonFiniteLossKeepingTheLastGoodState) {
  const NanTarget target;
  FitOptions o = small_options();
  const FitResult r = fit(target, o);
  EXPECT_EQ(r.stop, StopReason::kNonFinite);
  EXPECT_EQ(r.state.step, 0);
  for (double v : r.trained.params.values()) EXPECT_TRUE(std::isfinite(v));
}

TEST(Fit, TimeLimitStopsEarly) {
  const testing::BallTarget target(3, {0, 0, 0}, 0.5);
  FitOptions o = small_options();
  o.iters = 100'000'000;
  o.time_limit = 0.3;
  const FitResult r = fit(target, o);
  EXPECT_EQ(r.stop, StopReason::kTimeLimit);
  EXPECT_LT(r.state.step, o.iters);
  EXPECT_GT(r.state.step, 0);
  EXPECT_LT(r.train_seconds, 5.0);
}

TEST(Fit, MixedFamiliesCycleOverTheLeaves) {
  FitOptions o = small_options();
  o.prims = 8;
  o.families = {PrimitiveType::kQuadric3, PrimitiveType::kSphere, PrimitiveType::kBox};
  const Tree t = make_initial_model(o, 3);
  std::vector<PrimitiveType> leaves;
  for (const Node& n : t.nodes) {
    if (n.kind == NodeKind::kPrimitive) leaves.push_back(n.shape.type);
  }
  ASSERT_EQ(leaves.size(), 8u);
  for (std::size_t i = 0; i < leaves.size(); ++i) EXPECT_EQ(leaves[i], o.families[i % 3]);
}

TEST(Checkpoint, MalformedFilesNameTheField) {
  const std::string name = "fuzzycsg_bad_checkpoint.json";
  const auto message = [&](const std::string& text) {
    const std::string path = testing::write_temp(name, text);
    try {
      (void)read_checkpoint(path);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("{").find("not a checkpoint"), std::string::npos);
  EXPECT_NE(message("{\"format\":\"x\"}").find("format"), std::string::npos);
  Checkpoint ck;
  ck.target = "t.obj";
  ck.state.params = {1, 2};
  ck.state.m = {0, 0};
  ck.state.v = {0, 0};
  std::string good = checkpoint_to_string(ck);
  EXPECT_EQ(message(good), "");
  std::string bad = good;
  bad.replace(bad.find("\"adam_m\""), 8, "\"adam_x\"");
  EXPECT_NE(message(bad).find("state.adam_m: missing"), std::string::npos);
  EXPECT_NE(message("").find(name), std::string::npos);
}

TEST(Plot, LossCurveIsAPngWithTheCurve) {
  std::vector<LossPoint> curve;
  for (int i = 1; i <= 100; ++i) curve.push_back({i * 10L, 0.5 * std::exp(-0.03 * i), 0.0});
  const std::string png = loss_curve_png(curve, "test", 400, 300);
  int w = 0, h = 0, c = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()),
                                            static_cast<int>(png.size()), &w, &h, &c, 3);
  ASSERT_NE(px, nullptr);
  EXPECT_EQ(w, 400);
  EXPECT_EQ(h, 300);
  int blue = 0, black = 0;
  for (int i = 0; i < w * h; ++i) {
    const unsigned char* p = px + 3 * i;
    blue += (p[0] == 31 && p[1] == 119 && p[2] == 180);
    black += (p[0] == 0 && p[1] == 0 && p[2] == 0);
  }
  stbi_image_free(px);
  EXPECT_GT(blue, 300);   // the curve
  EXPECT_GT(black, 500);  // axes and text
}

}  // namespace
}  // namespace fuzzycsg
