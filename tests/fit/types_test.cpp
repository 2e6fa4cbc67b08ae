// The search over unified operators' types: exact proposals, switches that only help, and its
// place in the training loop (counts, resume).

#include "fuzzycsg/fit/types.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "fit/fit_support.hpp"
#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "fuzzycsg/fit/init.hpp"
#include "fuzzycsg/fit/report.hpp"

namespace fuzzycsg {
namespace {

// A ball of radius 0.6 at the origin less a ball of radius 0.3 at (0.35, 0, 0).
class NotchedBall : public testing::BallTarget {
 public:
  NotchedBall() : BallTarget(3, {0, 0, 0}, 0.6) {}
  void occupancy(std::span<const float> p, std::span<float> out) const override {
    for (std::size_t i = 0; i < out.size(); ++i) {
      const double x = p[3 * i], y = p[3 * i + 1], z = p[3 * i + 2];
      const bool big = x * x + y * y + z * z < 0.36;
      const bool small = (x - 0.35) * (x - 0.35) + y * y + z * z < 0.09;
      out[i] = big && !small ? 1.0f : 0.0f;
    }
  }
};

// Logits whose largest sin(10 l) is that of `type`.
void set_type(const Node& node, int type, std::span<double> params) {
  for (int i = 0; i < 4; ++i) {
    params[node.unified[i].index] = i == type ? std::numbers::pi / 20 : -0.05;
  }
}

TEST(TypeSearch, SwapDeltaIsTheChangeOfTheBilinearConstants) {
  // Union (c1) becoming x \ y (c2): (a, b, d) goes from (1, 1, -1) to (1, 0, -1).
  const auto d = swap_delta({0, 1, 0, 0}, 1, 2);
  EXPECT_DOUBLE_EQ(d[0], 0);
  EXPECT_DOUBLE_EQ(d[1], -1);
  EXPECT_DOUBLE_EQ(d[2], 0);
  // Swapping a soft c's entries permutes them: intersection and y \ x weights trade places.
  const auto s = swap_delta({0.4, 0.3, 0.2, 0.1}, 0, 3);
  // before (0.5, 0.4, -0.2), after (0.5, 0.7, -0.8)
  EXPECT_NEAR(s[0], 0.0, 1e-12);
  EXPECT_NEAR(s[1], 0.3, 1e-12);
  EXPECT_NEAR(s[2], -0.6, 1e-12);
}

TEST(TypeSearch, FindsTheDifferenceThatAUnionMisses) {
  const NotchedBall target;
  FullTreeOptions t;
  t.leaves = 2;
  t.seed = 1;
  const Tree model = make_full_binary_tree(t);
  std::vector<double> params = model.params.values();
  const std::vector<int> leaves = leaves_in_order(model);
  ASSERT_TRUE(set_leaf_to_ball(model, leaves[0], Ball{{0, 0, 0}, 0.6}, true, 30, params));
  ASSERT_TRUE(set_leaf_to_ball(model, leaves[1], Ball{{0.35, 0, 0}, 0.3}, true, 30, params));
  const Node& root = model.nodes[static_cast<std::size_t>(model.root)];
  ASSERT_EQ(root.children[0], leaves[0]);
  set_type(root, 1, params);  // union: the notch is filled
  ASSERT_EQ(unified_type(root, params), 1);
  std::vector<double> m(params.size()), v(params.size());
  for (std::size_t i = 0; i < m.size(); ++i) {
    m[i] = static_cast<double>(i);
    v[i] = 2.0 * static_cast<double>(i);
  }

  const Evaluator ev(model, EvalOptions{2});
  TypeSearchOptions o;
  // Points on the surface cost about 1/4 each whatever the operator: leave them out, so that
  // the loss measures the fit.
  o.sampling.surface = 0;
  Rng rng(3);
  const TypeSearchReport r = search_operator_types(model, ev, target, params, m, v, o, rng);
  EXPECT_EQ(r.operators, 1);
  EXPECT_GE(r.proposed, 1);
  EXPECT_EQ(r.switched, 1);
  EXPECT_EQ(unified_type(root, params), 2);  // big ball less small ball
  EXPECT_LT(r.loss_after, 0.7 * r.loss_before);
  // The Adam moments moved with the logits.
  const std::size_t u = root.unified[1].index, d = root.unified[2].index;
  EXPECT_EQ(m[u], static_cast<double>(d));
  EXPECT_EQ(m[d], static_cast<double>(u));
  EXPECT_EQ(v[d], 2.0 * static_cast<double>(u));

  // Already right: nothing to switch, nothing changes.
  const std::vector<double> before = params;
  Rng rng2(4);
  const TypeSearchReport again = search_operator_types(model, ev, target, params, {}, {}, o, rng2);
  EXPECT_EQ(again.switched, 0);
  EXPECT_EQ(params, before);
}

TEST(TypeSearch, LeavesFixedWeightsAlone) {
  const NotchedBall target;
  FullTreeOptions t;
  t.leaves = 2;
  Tree model = make_full_binary_tree(t);
  std::vector<double> params = model.params.values();
  const std::vector<int> leaves = leaves_in_order(model);
  ASSERT_TRUE(set_leaf_to_ball(model, leaves[0], Ball{{0, 0, 0}, 0.6}, true, 30, params));
  ASSERT_TRUE(set_leaf_to_ball(model, leaves[1], Ball{{0.35, 0, 0}, 0.3}, true, 30, params));
  const Node& root = model.nodes[static_cast<std::size_t>(model.root)];
  set_type(root, 1, params);  // a union, which the search would make a difference
  model.params[root.unified[3]].fixed = true;
  const std::vector<double> before = params;
  const Evaluator ev(model, EvalOptions{2});
  TypeSearchOptions o;
  o.sampling.surface = 0;
  Rng rng(3);
  const TypeSearchReport r = search_operator_types(model, ev, target, params, {}, {}, o, rng);
  EXPECT_EQ(r.operators, 0);
  EXPECT_EQ(r.switched, 0);
  EXPECT_EQ(params, before);
}

TEST(TypeSearch, NeverWorseOnTheJudgingSampleAndCountsAgree) {
  const testing::BallTarget target(3, {0.1, 0, 0}, 0.5);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    FullTreeOptions t;
    t.leaves = 32;
    t.seed = seed;
    const Tree model = make_full_binary_tree(t);
    std::vector<double> params = model.params.values();
    const std::vector<double> initial = params;
    const Evaluator ev(model, EvalOptions{2});
    TypeSearchOptions o;
    o.points = 4096;
    Rng rng(seed);
    const TypeSearchReport r = search_operator_types(model, ev, target, params, {}, {}, o, rng);
    EXPECT_EQ(r.operators, 31);
    EXPECT_LE(r.loss_after, r.loss_before);
    int changed = 0;
    for (const Node& n : model.nodes) {
      if (n.kind == NodeKind::kOperator) {
        changed += unified_type(n, params) != unified_type(n, initial) ? 1 : 0;
      }
    }
    EXPECT_LE(changed, r.switched);
    if (r.switched > 0) {
      EXPECT_LT(r.loss_after, r.loss_before);
    } else {
      EXPECT_EQ(params, initial);
    }
  }
}

FitOptions search_options() {
  FitOptions o;
  o.prims = 32;
  o.iters = 300;
  o.batch = 256;
  o.lr = 1e-2;
  o.threads = 2;
  o.measure = false;
  o.prune_points = 4096;
  o.temperature_ramp = 0;  // t = 1000: only the search changes types
  o.type_search_every = 50;
  o.type_search_points = 2048;
  return o;
}

TEST(TypeSearch, RunsInTheTrainingLoopAndCountsItsSwitches) {
  const NotchedBall target;
  FitOptions o = search_options();
  const FitResult r = fit(target, o);
  // Steps 50, 100, ..., 250 (before 0.9 of 300).
  EXPECT_EQ(r.type_searches, 5);
  EXPECT_GT(r.type_switches, 0);
  EXPECT_GE(r.type_switches, r.operators_changed);
  o.type_search_every = 0;
  const FitResult plain = fit(target, o);
  EXPECT_EQ(plain.type_searches, 0);
  EXPECT_EQ(plain.operators_changed, 0);  // saturated softmax
  EXPECT_GT(r.operators_changed, 0);
}

TEST(TypeSearch, ResumeIsBitIdentical) {
  const NotchedBall target;
  const FitOptions o = search_options();
  const FitResult full = fit(target, o);
  std::string saved;
  FitHooks hooks;
  hooks.checkpoint_every = 120;
  hooks.checkpoint = [&](const Tree&, const TrainState& st) {
    if (st.step == 120) {
      Checkpoint ck;
      ck.target = "notched ball";
      ck.dim = 3;
      ck.options = o;
      ck.state = st;
      saved = checkpoint_to_string(ck);
    }
  };
  (void)fit(target, o, hooks);
  ASSERT_FALSE(saved.empty());
  const Checkpoint ck =
      read_checkpoint(testing::write_temp("fuzzycsg_types_checkpoint.json", saved));
  EXPECT_EQ(ck.options.type_search_every, 50);
  EXPECT_EQ(ck.options.type_search_points, 2048u);
  const FitResult resumed = fit(target, ck.options, {}, &ck.state);
  EXPECT_EQ(resumed.trained.params.values(), full.trained.params.values());
  EXPECT_EQ(resumed.type_switches, full.type_switches);
}

TEST(TypeSearch, OptionsAreValidated) {
  FitOptions o;
  o.type_search_every = -1;
  EXPECT_NE(testing::validation_message(o, 3).find("--type-search-every"), std::string::npos);
  o = {};
  o.type_search_until = 1.5;
  EXPECT_NE(testing::validation_message(o, 3).find("--type-search-until"), std::string::npos);
  o = {};
  o.type_search_points = 0;
  EXPECT_NE(testing::validation_message(o, 3).find("--type-search-points"), std::string::npos);
}

}  // namespace
}  // namespace fuzzycsg
