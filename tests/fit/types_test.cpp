// The search over unified operators' types: exact proposals, switches that only help, and its
// place in the training loop (counts, resume).

#include "fuzzycsg/fit/types.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
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

TEST(TypeSearch, SwitchesBetweenFreeWeightsOnly) {
  const NotchedBall target;
  FullTreeOptions t;
  t.leaves = 2;
  Tree model = make_full_binary_tree(t);
  std::vector<double> params = model.params.values();
  const std::vector<int> leaves = leaves_in_order(model);
  ASSERT_TRUE(set_leaf_to_ball(model, leaves[0], Ball{{0, 0, 0}, 0.6}, true, 30, params));
  ASSERT_TRUE(set_leaf_to_ball(model, leaves[1], Ball{{0.35, 0, 0}, 0.3}, true, 30, params));
  const Node& root = model.nodes[static_cast<std::size_t>(model.root)];
  set_type(root, 1, params);  // a union, which the search would make x \ y (type 2)
  const std::vector<double> start = params;
  TypeSearchOptions o;
  o.sampling.surface = 0;
  {
    // x \ y fixed: no other type is better than the union, nothing moves.
    model.params[root.unified[2]].fixed = true;
    const Evaluator ev(model, EvalOptions{2});
    Rng rng(3);
    const TypeSearchReport r = search_operator_types(model, ev, target, params, {}, {}, o, rng);
    EXPECT_EQ(r.operators, 1);
    EXPECT_EQ(r.switched, 0);
    EXPECT_EQ(params, start);
    model.params[root.unified[2]].fixed = false;
  }
  {
    // y \ x fixed: the union still becomes x \ y, and the fixed weight keeps its value.
    model.params[root.unified[3]].fixed = true;
    const Evaluator ev(model, EvalOptions{2});
    Rng rng(3);
    const TypeSearchReport r = search_operator_types(model, ev, target, params, {}, {}, o, rng);
    EXPECT_EQ(r.switched, 1);
    EXPECT_EQ(unified_type(root, params), 2);
    EXPECT_EQ(params[root.unified[3].index], start[root.unified[3].index]);
  }
  {
    // Three weights fixed: no switch to make.
    for (int i : {0, 2, 3}) model.params[root.unified[static_cast<std::size_t>(i)]].fixed = true;
    params = start;
    const Evaluator ev(model, EvalOptions{2});
    Rng rng(3);
    const TypeSearchReport r = search_operator_types(model, ev, target, params, {}, {}, o, rng);
    EXPECT_EQ(r.operators, 0);
    EXPECT_EQ(params, start);
  }
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

// A boolean of a fixed tree as N^o(N^l(A) ∩ N^r(B)), N the complement: intersection (0, 0, 0),
// union (1, 1, 1) (A ∪ B = ¬(¬A ∩ ¬B), exactly so in product logic), A \ B (0, 0, 1) and
// B \ A (0, 1, 0) (a difference with its children swapped).
struct Negations {
  bool o, l, r;
};

Negations negations_of(const Node& n, bool swapped) {
  if (n.op == OpKind::kUnion) return {true, true, true};
  if (n.op == OpKind::kIntersection) return {false, false, false};
  return swapped ? Negations{false, true, false} : Negations{false, false, true};
}

// Gives `twin` (a copy of `original`) other operator types below node `i` such that node `i`
// of the twin is the complement of the original's when `complemented`, and the same function
// otherwise: the type's output negation is forced, its input negations are free (drawn from
// `rng`), and what they change is handed down, to a leaf as the negation of its coefficients
// (a quadric's complement: sigmoid(-s q) = 1 - sigmoid(s q)). Returns the operators retyped
// and marks the negated leaves' parameters in `sign` (-1).
// The type indices of a fixed tree's booleans (0 intersection, 1 union, 2 x \ y) for
// structure_bits; its leaves -1.
std::vector<int> fixed_types(const Tree& tree) {
  std::vector<int> out;
  for (const Node& n : tree.nodes) {
    out.push_back(n.kind != NodeKind::kOperator   ? -1
                  : n.op == OpKind::kIntersection ? 0
                  : n.op == OpKind::kUnion        ? 1
                                                  : 2);
  }
  return out;
}

int retype(const Tree& original, Tree& twin, int i, bool complemented, std::mt19937_64& rng,
           std::vector<double>& sign, bool negate_leaves) {
  const Node& n = original.node(i);
  if (n.kind == NodeKind::kPrimitive) {
    if (complemented && negate_leaves) {
      for (ParamRef r : n.intrinsic) {
        twin.params[r].value = -twin.params[r].value;
        sign[r.index] = -1;
      }
    }
    return 0;
  }
  const Negations was = negations_of(n, false);
  const bool o = was.o != complemented;
  Negations now{true, true, true};
  bool swapped = false;
  if (!o) {
    const int pick = static_cast<int>(rng() % 3);  // intersection, A \ B, B \ A
    swapped = pick == 2;
    now = pick == 0 ? Negations{false, false, false} : Negations{false, pick == 2, pick == 1};
  }
  Node& t = twin.nodes.at(static_cast<std::size_t>(i));
  t.op = o ? OpKind::kUnion : (now.l || now.r ? OpKind::kDifference : OpKind::kIntersection);
  int changed = t.op != n.op || swapped ? 1 : 0;
  changed += retype(original, twin, n.children[0], was.l != now.l, rng, sign, negate_leaves);
  changed += retype(original, twin, n.children[1], was.r != now.r, rng, sign, negate_leaves);
  if (swapped) std::swap(t.children[0], t.children[1]);
  return changed;
}

TEST(ProductLogicTwins, StructureBitsAreOutputNegationsAsTheParentSeesThem) {
  FullTreeOptions t;
  t.leaves = 4;
  t.ops = OperatorMode::kProduct;
  Tree tree = make_full_binary_tree(t);
  const int root = tree.root;
  const int left = tree.node(root).children[0], right = tree.node(root).children[1];
  auto bits = [&](OpKind r, OpKind a, OpKind b) {
    tree.nodes[static_cast<std::size_t>(root)].op = r;
    tree.nodes[static_cast<std::size_t>(left)].op = a;
    tree.nodes[static_cast<std::size_t>(right)].op = b;
    const std::vector<int> all = structure_bits(tree, fixed_types(tree));
    return std::vector<int>{all[static_cast<std::size_t>(root)],
                            all[static_cast<std::size_t>(left)],
                            all[static_cast<std::size_t>(right)]};
  };
  using enum OpKind;
  // (a ∩ b) ∪ (c ∩ d) = ¬(¬(a ∩ b) ∩ ¬(c ∩ d)): all three are complemented intersections.
  EXPECT_EQ(bits(kUnion, kIntersection, kIntersection), (std::vector<int>{1, 1, 1}));
  EXPECT_EQ(bits(kIntersection, kIntersection, kIntersection), (std::vector<int>{0, 0, 0}));
  // (a ∩ b) \ (c ∩ d) = (a ∩ b) ∩ ¬(c ∩ d).
  EXPECT_EQ(bits(kDifference, kIntersection, kIntersection), (std::vector<int>{0, 0, 1}));
  // (a ∪ b) \ (c \ d) = ¬(¬a ∩ ¬b) ∩ ¬(c ∩ ¬d).
  EXPECT_EQ(bits(kDifference, kUnion, kDifference), (std::vector<int>{0, 1, 1}));
  // (a \ b) ∪ (c ∪ d) = ¬(¬(a ∩ ¬b) ∩ (¬c ∩ ¬d)): the inner union, complemented by the root's,
  // is an intersection.
  EXPECT_EQ(bits(kUnion, kDifference, kUnion), (std::vector<int>{1, 1, 0}));
  const std::vector<int> all = structure_bits(tree, fixed_types(tree));
  for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
    if (tree.nodes[k].kind == NodeKind::kPrimitive) {
      EXPECT_EQ(all[k], -1);
    }
  }
}

// Why optimising the types gains little with quadrics (docs/results.md, Fig. 12): a quadric's
// complement is a quadric, so in product logic many type assignments are one function with
// some leaves' coefficients negated — and, Adam being odd in each parameter, one training run.
// The 4^(P-1) type assignments of a tree's P - 1 booleans give at most 2^(P-1) families of
// functions: a node contributes one bit (whether its parent sees an intersection or the
// complement of one), and the rest of its type moves into the leaves below.
// Retypes a 32-quadric tree of fixed `ops` booleans four ways with the same structure bits and
// checks that each twin is the same function, with the same loss and a gradient equal up to
// the sign of the negated leaves' coefficients.
void expect_quadric_twins(OperatorMode ops) {
  FullTreeOptions t;
  t.leaves = 32;
  t.ops = ops;
  t.seed = 5;
  const Tree original = make_full_binary_tree(t);
  const std::vector<float> points = testing::random_points(4096, 3, 11);
  std::vector<float> labels(4096);
  testing::BallTarget(3, {0.1, 0, 0}, 0.5).occupancy(points, labels);

  const Evaluator ev(original, EvalOptions{2});
  std::vector<double> grad(ev.num_params());
  std::vector<float> occ(4096);
  Loss loss;
  loss.kind = Loss::Kind::kMse;
  loss.targets = labels;
  const double value = ev.backward(original.params.values(), points, loss, grad, occ);

  for (std::uint64_t seed = 0; seed < 4; ++seed) {
    Tree twin = original;
    std::mt19937_64 rng(seed);
    std::vector<double> sign(original.params.size(), 1.0);
    const int changed = retype(original, twin, original.root, false, rng, sign, true);
    EXPECT_GE(changed, 8) << "seed " << seed;  // a real variation of the types
    EXPECT_EQ(structure_bits(twin, fixed_types(twin)),
              structure_bits(original, fixed_types(original)))
        << "seed " << seed;
    const Evaluator tev(twin, EvalOptions{2});
    std::vector<double> tgrad(tev.num_params());
    std::vector<float> tocc(4096);
    const double tvalue = tev.backward(twin.params.values(), points, loss, tgrad, tocc);
    EXPECT_NEAR(tvalue, value, 1e-6 * value) << "seed " << seed;
    float worst = 0;
    for (std::size_t k = 0; k < occ.size(); ++k)
      worst = std::max(worst, std::abs(tocc[k] - occ[k]));
    EXPECT_LT(worst, 1e-5f) << "seed " << seed;
    // dL/dθ of the twin is ±dL/dθ of the original: Adam's steps are the same up to sign.
    for (std::size_t k = 0; k < grad.size(); ++k) {
      EXPECT_NEAR(tgrad[k], sign[k] * grad[k], 1e-5 * std::abs(grad[k]) + 1e-9)
          << "seed " << seed << ", " << original.params.at(k).name;
    }
  }
}

TEST(ProductLogicTwins, QuadricTreesWithOtherTypesAreTheSameFunction) {
  expect_quadric_twins(OperatorMode::kProduct);

  FullTreeOptions t;
  t.leaves = 32;
  t.ops = OperatorMode::kProduct;
  t.seed = 5;
  const std::vector<float> points = testing::random_points(4096, 3, 11);
  // Balls have no complement among balls: the same retyping is another function.
  t.family = PrimitiveType::kSphere;
  const Tree balls = make_full_binary_tree(t);
  Tree twin = balls;
  std::mt19937_64 rng(0);
  std::vector<double> sign(balls.params.size(), 1.0);
  ASSERT_GE(retype(balls, twin, balls.root, false, rng, sign, false), 8);
  EXPECT_GT(testing::mse(testing::occupancy(twin, points), testing::occupancy(balls, points)),
            1e-3);
}

// Gödel logic satisfies De Morgan's laws exactly with the standard complement too
// (1 - min(x, y) = max(1 - x, 1 - y)), so the same twins exist among Gödel trees of quadrics:
// the fixed Gödel baseline of Fig. 12 is no more constrained by its random types than product's.
TEST(GodelLogicTwins, QuadricTreesWithOtherTypesAreTheSameFunction) {
  expect_quadric_twins(OperatorMode::kGodel);
}

TEST(TypeSearch, OptionsAreValidated) {
  FitOptions o;
  o.type_search_every = -1;
  EXPECT_NE(testing::validation_message(o, 3).find("type_search_every: "), std::string::npos);
  o = {};
  o.type_search_until = 1.5;
  EXPECT_NE(testing::validation_message(o, 3).find("type_search_until: "), std::string::npos);
  o = {};
  o.type_search_points = 0;
  EXPECT_NE(testing::validation_message(o, 3).find("type_search_points: "), std::string::npos);
}

}  // namespace
}  // namespace fuzzycsg
