// Initialisation from the target and re-seeding of dead leaves.

#include "fuzzycsg/fit/init.hpp"
#include "fuzzycsg/core/snap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "fit/fit_support.hpp"
#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "fuzzycsg/fit/prune.hpp"
#include "fuzzycsg/fit/report.hpp"

namespace fuzzycsg {
namespace {

using testing::BallTarget;

// A tree of one leaf of `family` (sigmoid step), parameters zero.
Tree single_leaf(PrimitiveType family, int dim) {
  FullTreeOptions t;
  t.dim = dim;
  t.leaves = 1;
  t.family = family;
  return make_full_binary_tree(t);
}

double occupancy_at(const Tree& tree, std::vector<float> point) {
  return testing::occupancy(tree, point)[0];
}

double distance(const Ball& b, const std::vector<double>& c, int dim) {
  double s = 0;
  for (int a = 0; a < dim; ++a) s += (b.center[a] - c[a]) * (b.center[a] - c[a]);
  return std::sqrt(s);
}

TEST(BoundaryDistance, ApproximatesTheDistanceToTheSphere) {
  const BallTarget target(3, {0.1, 0, 0}, 0.5);
  Rng rng(1);
  const BoundaryDistance d(target, 50000, rng);
  EXPECT_EQ(d.dim(), 3);
  const float centre[3] = {0.1f, 0, 0}, off[3] = {0.4f, 0, 0}, outside[3] = {0.1f, 0.9f, 0};
  EXPECT_NEAR(d(centre), 0.5, 1e-6);  // every sample is 0.5 away
  EXPECT_NEAR(d(off), 0.2, 0.02);
  EXPECT_NEAR(d(outside), 0.4, 0.02);
  const std::size_t i = d.nearest(off);
  EXPECT_GT(d.normal(i)[0], 0.95);  // the nearest sample is at +x, its normal points out
  EXPECT_NEAR(d.point(i)[0], 0.6, 0.03);
}

TEST(CoverWithBalls, LargestBallFirstAndAllInside) {
  const std::vector<double> c{0.1, -0.2, 0.05};
  const BallTarget target(3, c, 0.6);
  Rng rng(2);
  const BoundaryDistance d(target, 50000, rng);
  const std::vector<Ball> balls = cover_with_balls(target, d, 16, rng, 5000);
  ASSERT_EQ(balls.size(), 16u);
  // The first is about the target itself; every ball stays inside it (up to the sampling).
  EXPECT_GT(balls[0].radius, 0.5);
  EXPECT_LT(distance(balls[0], c, 3), 0.1);
  for (const Ball& b : balls) EXPECT_LE(distance(b, c, 3) + b.radius, 0.6 + 0.03);
  // Later balls fill in what the first leaves out: their centres lie outside it.
  EXPECT_GT(distance(balls[1], {balls[0].center[0], balls[0].center[1], balls[0].center[2]}, 3),
            balls[0].radius - 1e-9);
}

TEST(CoverWithBalls, ThinTargetsStillGiveTheCount) {
  const BallTarget target(2, {0.5, 0.5}, 0.1);  // 0.8% of the square
  Rng rng(3);
  const BoundaryDistance d(target, 20000, rng);
  const std::vector<Ball> balls = cover_with_balls(target, d, 64, rng, 2000);
  EXPECT_EQ(balls.size(), 64u);
  for (const Ball& b : balls) EXPECT_LE(distance(b, {0.5, 0.5}, 2), 0.1);
}

TEST(OrderForTree, HalvesAreClusters) {
  std::vector<Ball> balls;
  for (int i = 0; i < 8; ++i) {
    Ball b;
    b.center = {(i % 2 ? 0.5 : -0.5) + 0.01 * i, 0.02 * i, 0};
    b.radius = 0.1;
    balls.push_back(b);
  }
  order_for_tree(balls, 3);
  for (int i = 0; i < 4; ++i) EXPECT_LT(balls[static_cast<std::size_t>(i)].center[0], 0);
  for (int i = 4; i < 8; ++i) EXPECT_GT(balls[static_cast<std::size_t>(i)].center[0], 0);
}

TEST(SetLeafToBall, QuadricIsTheBallOrItsComplement) {
  Tree t = single_leaf(PrimitiveType::kQuadric3, 3);
  Ball b;
  b.center = {0.2, -0.1, 0.3};
  b.radius = 0.25;
  std::vector<double> p = t.params.values();
  ASSERT_TRUE(set_leaf_to_ball(t, t.root, b, true, 20.0, p));
  t.params.set_values(p);
  // o(x) = 1 / (1 + exp(s (|x - c|^2 - r^2))) with s = slope / 2r: slope 20 across the sphere.
  const auto expected = [&](double dist, bool inside) {
    const double f = (dist * dist - b.radius * b.radius) * (inside ? 1 : -1);
    return 1.0 / (1.0 + std::exp(20.0 / (2 * b.radius) * f));
  };
  EXPECT_NEAR(occupancy_at(t, {0.2f, -0.1f, 0.3f}), expected(0, true), 1e-5);
  EXPECT_GT(occupancy_at(t, {0.2f, -0.1f, 0.3f}), 0.9);
  EXPECT_NEAR(occupancy_at(t, {0.45f, -0.1f, 0.3f}), 0.5, 1e-3);  // on the sphere
  EXPECT_NEAR(occupancy_at(t, {0.35f, -0.1f, 0.3f}), expected(0.15, true), 1e-5);
  EXPECT_LT(occupancy_at(t, {0.8f, -0.1f, 0.3f}), 1e-4);
  ASSERT_TRUE(set_leaf_to_ball(t, t.root, b, false, 20.0, p));
  t.params.set_values(p);
  EXPECT_NEAR(occupancy_at(t, {0.2f, -0.1f, 0.3f}), expected(0, false), 1e-5);
  EXPECT_LT(occupancy_at(t, {0.2f, -0.1f, 0.3f}), 0.1);
  EXPECT_GT(occupancy_at(t, {0.8f, -0.1f, 0.3f}), 0.99);
}

TEST(SetLeafToBall, DistanceFamiliesFitInsideTheBall) {
  Ball b;
  b.center = {0.1, 0.2, -0.3};
  b.radius = 0.3;
  for (PrimitiveType f : {PrimitiveType::kSphere, PrimitiveType::kBox, PrimitiveType::kCylinder,
                          PrimitiveType::kEllipsoid}) {
    Tree t = single_leaf(f, 3);
    std::vector<double> p = t.params.values();
    ASSERT_TRUE(set_leaf_to_ball(t, t.root, b, true, 50.0, p)) << primitive_info(f).name;
    EXPECT_FALSE(set_leaf_to_ball(t, t.root, b, false, 50.0, p)) << primitive_info(f).name;
    t.params.set_values(p);
    EXPECT_GT(occupancy_at(t, {0.1f, 0.2f, -0.3f}), 0.99) << primitive_info(f).name;
    EXPECT_LT(occupancy_at(t, {0.1f, 0.2f + 0.35f, -0.3f}), 0.2) << primitive_info(f).name;
  }
  Tree plane = single_leaf(PrimitiveType::kPlane, 3);
  std::vector<double> p = plane.params.values();
  EXPECT_FALSE(set_leaf_to_ball(plane, plane.root, b, true, 50.0, p));
  EXPECT_EQ(p, plane.params.values());
}

TEST(SetLeafThroughPoint, PassesThroughThePointAlongTheNormal) {
  for (int dim : {2, 3}) {
    Tree t = single_leaf(dim == 3 ? PrimitiveType::kQuadric3 : PrimitiveType::kQuadric2, dim);
    std::vector<double> p = t.params.values();
    const float point[3] = {0.3f, -0.2f, 0.1f};
    const float normal[3] = {0.6f, 0.8f, 0.0f};
    Rng rng(4);
    ASSERT_TRUE(set_leaf_through_point(t, t.root, point, normal, 0.5, 3.0, rng, p));
    t.params.set_values(p);
    std::vector<float> at(point, point + dim), in(at), out(at);
    for (int a = 0; a < dim; ++a) {
      in[static_cast<std::size_t>(a)] -= 0.01f * normal[a];
      out[static_cast<std::size_t>(a)] += 0.01f * normal[a];
    }
    EXPECT_NEAR(occupancy_at(t, at), 0.5, 1e-5) << dim;
    // |grad f| = 1 and sharpness 3: the occupancy changes by about 3 * 0.01 / 4 each way.
    EXPECT_NEAR(occupancy_at(t, in) - 0.5, 0.0075, 0.001) << dim;
    EXPECT_NEAR(occupancy_at(t, out) - 0.5, -0.0075, 0.001) << dim;
  }
}

TEST(SetLeafConstant, QuadricsEmptyOrFull) {
  Tree t = single_leaf(PrimitiveType::kQuadric3, 3);
  const std::vector<float> pts = testing::random_points(1000, 3, 5);
  for (bool full : {false, true}) {
    std::vector<double> p = t.params.values();
    ASSERT_TRUE(set_leaf_constant(t, t.root, full, p));
    Tree c = t;
    c.params.set_values(p);
    for (float o : testing::occupancy(c, pts)) EXPECT_NEAR(o, full ? 1.0 : 0.0, 1e-6);
  }
  Tree s = single_leaf(PrimitiveType::kSphere, 3);
  std::vector<double> p = s.params.values();
  EXPECT_FALSE(set_leaf_constant(s, s.root, true, p));
  ASSERT_TRUE(set_leaf_constant(s, s.root, false, p));
  s.params.set_values(p);
  for (float o : testing::occupancy(s, pts)) EXPECT_LT(o, 1e-6);
}

TEST(InitialiseFromTarget, StartsAsAUnionOfBallsCloseToTheTarget) {
  const BallTarget target(3, {0.1, 0.0, -0.1}, 0.55);
  FitOptions o;
  o.prims = 16;
  Tree random = make_initial_model(o, 3);
  Tree balls = random;
  TargetInitOptions io;
  io.candidates = 4000;
  io.boundary_samples = 20000;
  EXPECT_EQ(initialise_from_target(balls, target, io), 16);
  const std::vector<float> pts = testing::random_points(20000, 3, 6);
  std::vector<float> truth(pts.size() / 3);
  target.occupancy(pts, truth);
  const double mse_random = testing::mse(testing::occupancy(random, pts), truth);
  const double mse_balls = testing::mse(testing::occupancy(balls, pts), truth);
  EXPECT_LT(mse_balls, 0.2 * mse_random);
  EXPECT_LT(mse_balls, 0.02);
  // Every operator selects union, with weight about 0.9 at the starting temperature.
  for (std::size_t i = 0; i < balls.nodes.size(); ++i) {
    const Node& n = balls.nodes[i];
    if (n.kind != NodeKind::kOperator) continue;
    EXPECT_EQ(snapped_operator(balls, static_cast<int>(i)), 1);
  }
  // Fixed booleans become unions.
  o.ops = OperatorMode::kGodel;
  Tree godel = make_initial_model(o, 3);
  initialise_from_target(godel, target, io);
  for (const Node& n : godel.nodes) {
    if (n.kind == NodeKind::kOperator) {
      EXPECT_EQ(n.op, OpKind::kUnion);
    }
  }
}

TEST(InitialiseOnSurface, EveryQuadricTouchesTheTarget) {
  const BallTarget target(3, {0, 0, 0}, 0.5);
  FitOptions o;
  o.prims = 8;
  Tree t = make_initial_model(o, 3);
  SurfaceInitOptions so;
  EXPECT_EQ(initialise_on_surface(t, target, so), 8);
  // Each leaf alone: its 0.5 level set passes through a point of the sphere (some sample of
  // the sphere has occupancy within 0.01 of 0.5: with sharpness 1 and |grad f| = 1 there, the
  // samples' spacing of about 0.01 moves it by about 0.003).
  Rng rng(7);
  std::vector<float> sphere, normals;
  target.sample_boundary(20000, rng, sphere, normals);
  // How close to 0.5 a leaf's occupancy comes on the sphere, the leaf alone.
  const auto closest_to_half = [&](const Tree& tree, int leaf) {
    Tree one = single_leaf(PrimitiveType::kQuadric3, 3);
    std::vector<double> p = one.params.values();
    const Node& n = tree.node(leaf);
    for (std::size_t k = 0; k < n.intrinsic.size(); ++k) {
      p[one.node(one.root).intrinsic[k].index] = tree.params[n.intrinsic[k]].value;
    }
    one.params.set_values(p);
    double closest = 1;
    for (float v : testing::occupancy(one, sphere)) {
      closest = std::min(closest, std::abs(static_cast<double>(v) - 0.5));
    }
    return closest;
  };
  for (int leaf : leaves_in_order(t)) EXPECT_LT(closest_to_half(t, leaf), 0.01);
  // Random quadrics miss the sphere far more: the same test fails for most of them.
  const Tree random = make_initial_model(o, 3);
  int touching = 0;
  for (int leaf : leaves_in_order(random)) touching += closest_to_half(random, leaf) < 0.01 ? 1 : 0;
  EXPECT_LT(touching, 8);
}

// A union of two leaves: one a ball inside the target, one far away (dead).
Tree two_leaves_one_dead() {
  FullTreeOptions t;
  t.dim = 3;
  t.leaves = 2;
  t.temperature = 1000;
  Tree tree = make_full_binary_tree(t);
  std::vector<double> p = tree.params.values();
  const std::vector<int> leaves = leaves_in_order(tree);
  Ball b;
  b.center = {-0.3, 0, 0};
  b.radius = 0.25;
  set_leaf_to_ball(tree, leaves[0], b, true, 30.0, p);
  set_leaf_constant(tree, leaves[1], false, p);
  const Node& op = tree.node(tree.root);
  for (int k = 0; k < 4; ++k) p[op.unified[static_cast<std::size_t>(k)].index] = 0.0;
  p[op.unified[1].index] = std::asin(1.0) / 10.0;  // union
  tree.params.set_values(p);
  return tree;
}

// The ball both re-seeding targets below contain.
Ball left_ball() {
  Ball b;
  b.center = {-0.3, 0, 0};
  b.radius = 0.25;
  return b;
}

// One re-seeding round on `model` with `params`, every Adam moment 0.5 (v is returned).
ReseedReport reseed_once(const Tree& model, const Target& target, std::vector<double>& params,
                         std::vector<double>& v, std::uint64_t seed, const ReseedOptions& ro = {}) {
  const Evaluator ev(model, EvalOptions{2});
  std::vector<double> m(params.size(), 0.5);
  v.assign(params.size(), 0.5);
  Rng rng(seed);
  const BoundaryDistance d(target, 20000, rng);
  return reseed_dead_leaves(model, ev, target, d, params, m, v, ro, rng);
}

TEST(Reseed, MovesADeadLeafToWhatTheModelMisses) {
  // The target: balls at x = -0.3 and x = +0.4. The model has the first; its second leaf is
  // empty.
  class TwoBalls : public Target {
   public:
    int dim() const override { return 3; }
    std::string describe() const override { return "two balls"; }
    std::string kind() const override { return "test"; }
    void occupancy(std::span<const float> pts, std::span<float> out) const override {
      a_.occupancy(pts, out);
      std::vector<float> o2(out.size());
      b_.occupancy(pts, o2);
      for (std::size_t i = 0; i < out.size(); ++i) out[i] = std::max(out[i], o2[i]);
    }
    void sample_boundary(std::size_t n, Rng& rng, std::vector<float>& p,
                         std::vector<float>& nrm) const override {
      a_.sample_boundary(n - n / 2, rng, p, nrm);
      std::vector<float> p2, n2;
      b_.sample_boundary(n / 2, rng, p2, n2);
      p.insert(p.end(), p2.begin(), p2.end());
      nrm.insert(nrm.end(), n2.begin(), n2.end());
    }

   private:
    BallTarget a_{3, {-0.3, 0, 0}, 0.25}, b_{3, {0.4, 0, 0}, 0.2};
  } target;

  const Tree model = two_leaves_one_dead();
  std::vector<double> params = model.params.values(), v;
  ReseedOptions ro;
  ro.slope = 30.0;
  const ReseedReport rep = reseed_once(model, target, params, v, 8, ro);
  EXPECT_EQ(rep.dead, 1);
  EXPECT_EQ(rep.moved, 1);
  EXPECT_LT(rep.loss_after, 0.5 * rep.loss_before);

  // The moved leaf's Adam moments are reset, the other's kept.
  const std::vector<int> leaves = leaves_in_order(model);
  for (std::size_t k : leaf_parameters(model.node(leaves[1]))) EXPECT_EQ(v[k], 0.0);
  for (std::size_t k : leaf_parameters(model.node(leaves[0]))) EXPECT_EQ(v[k], 0.5);
  // On independent points the model now covers the second ball too.
  Tree after = model;
  after.params.set_values(params);
  const std::vector<float> pts = testing::random_points(20000, 3, 9);
  std::vector<float> truth(pts.size() / 3);
  target.occupancy(pts, truth);
  EXPECT_LT(testing::mse(testing::occupancy(after, pts), truth),
            0.5 * testing::mse(testing::occupancy(model, pts), truth));
}

TEST(Reseed, SkipsMaskedLeaves) {
  // An intersection of an empty leaf with a ball at the target: the ball is masked (emptying
  // or filling it changes nothing), the empty leaf is not (filling it gives the ball).
  const BallTarget target(3, {-0.3, 0, 0}, 0.25);
  Tree model = two_leaves_one_dead();
  std::vector<double> params = model.params.values(), v;
  const std::vector<int> leaves = leaves_in_order(model);
  set_leaf_constant(model, leaves[0], false, params);
  set_leaf_to_ball(model, leaves[1], left_ball(), true, 30.0, params);
  const Node& op = model.node(model.root);
  for (int k = 0; k < 4; ++k) params[op.unified[static_cast<std::size_t>(k)].index] = 0.0;
  params[op.unified[0].index] = std::asin(1.0) / 10.0;  // intersection
  model.params.set_values(params);
  const ReseedReport rep = reseed_once(model, target, params, v, 11);
  EXPECT_EQ(rep.dead, 2);
  EXPECT_EQ(rep.tried, 1);
  EXPECT_EQ(rep.moved, 1);
  EXPECT_LT(rep.loss_after, 0.5 * rep.loss_before);
  for (std::size_t k : leaf_parameters(model.node(leaves[1]))) {
    EXPECT_EQ(params[k], model.params.at(k).value);
  }
}

TEST(Reseed, LeavesLiveLeavesAlone) {
  const BallTarget target(3, {-0.3, 0, 0}, 0.25);
  Tree model = two_leaves_one_dead();
  // Make the second leaf the same ball as the first, slightly larger: removing either changes
  // the union a little but no move can lower the loss much.
  std::vector<double> params = model.params.values(), v;
  const std::vector<int> leaves = leaves_in_order(model);
  set_leaf_to_ball(model, leaves[1], left_ball(), true, 30.0, params);
  model.params.set_values(params);
  ReseedOptions ro;
  ro.threshold = 1e-9;  // nothing is that redundant once the sigmoids overlap
  const std::vector<double> before = params;
  const ReseedReport rep = reseed_once(model, target, params, v, 10, ro);
  EXPECT_EQ(rep.dead, 0);
  EXPECT_EQ(rep.moved, 0);
  EXPECT_EQ(params, before);
}

TEST(LearningRate, CosineFromLrToLrTimesEnd) {
  FitOptions o;
  o.iters = 1000;
  o.lr = 2e-3;
  EXPECT_DOUBLE_EQ(lr_at(o, 500), 2e-3);  // constant by default
  o.lr_schedule = LrSchedule::kCosine;
  o.lr_end = 0.1;
  EXPECT_DOUBLE_EQ(lr_at(o, 0), 2e-3);
  EXPECT_NEAR(lr_at(o, 500), 2e-3 * 0.55, 1e-15);
  EXPECT_NEAR(lr_at(o, 1000), 2e-4, 1e-15);
  EXPECT_LT(lr_at(o, 700), lr_at(o, 600));
}

TEST(Fit, TargetInitialisationAndReseedingResumeBitIdentically) {
  const BallTarget target(3, {0.1, 0, 0}, 0.5);
  FitOptions o;
  o.prims = 8;
  o.iters = 240;
  o.batch = 256;
  o.threads = 2;
  o.measure = false;
  o.prune_points = 4096;
  o.init = InitMode::kSurface;
  o.reseed_every = 40;
  o.reseed_until = 1.0;
  o.lr_schedule = LrSchedule::kCosine;
  o.op_init = OperatorInit::kBalanced;
  o.op_types = OperatorTypes::kUnionIntersection;
  const FitResult full = fit(target, o);
  EXPECT_EQ(full.initialised_leaves, 8);

  TrainState at100;
  FitHooks hooks;
  hooks.checkpoint_every = 100;
  hooks.checkpoint = [&](const Tree&, const TrainState& st) {
    if (st.step == 100) at100 = st;
  };
  (void)fit(target, o, hooks);
  ASSERT_EQ(at100.step, 100);
  // Through the checkpoint file format.
  Checkpoint ck;
  ck.target = "ball";
  ck.dim = 3;
  ck.options = o;
  ck.state = at100;
  const Checkpoint back = read_checkpoint(
      testing::write_temp("fuzzycsg_init_checkpoint.json", checkpoint_to_string(ck)));
  EXPECT_EQ(back.options.init, InitMode::kSurface);
  EXPECT_EQ(back.options.reseed_every, 40);
  EXPECT_EQ(back.options.lr_schedule, LrSchedule::kCosine);
  EXPECT_EQ(back.options.op_init, OperatorInit::kBalanced);
  EXPECT_EQ(back.options.op_types, OperatorTypes::kUnionIntersection);
  EXPECT_EQ(back.state.reseeded, at100.reseeded);
  const FitResult resumed = fit(target, back.options, {}, &back.state);
  EXPECT_EQ(resumed.trained.params.values(), full.trained.params.values());
  EXPECT_EQ(resumed.reseeded, full.reseeded);
  EXPECT_EQ(resumed.operators_changed, full.operators_changed);
}

TEST(FitOptionsValidation, NewFlagsAreChecked) {
  const auto message = [](const FitOptions& o) { return testing::validation_message(o, 3); };
  FitOptions o;
  o.lr_end = 0;
  EXPECT_NE(message(o).find("lr_end: "), std::string::npos);
  o = {};
  o.reseed_every = -1;
  EXPECT_NE(message(o).find("reseed_every: "), std::string::npos);
  o = {};
  o.reseed_until = 1.5;
  EXPECT_NE(message(o).find("reseed_until: "), std::string::npos);
  o = {};
  o.init_slope = -1;
  EXPECT_NE(message(o).find("init_slope: "), std::string::npos);
}

}  // namespace
}  // namespace fuzzycsg
