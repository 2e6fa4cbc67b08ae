// The kernel against the double-precision reference: values, gradients (against central
// differences of the reference), tails of partial blocks, losses, determinism across threads.

#include "fuzzycsg/eval/evaluator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg {
namespace {

std::vector<float> random_points(std::size_t n, int dim, std::uint64_t seed, float extent = 1.0f) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-extent, extent);
  std::vector<float> p(n * static_cast<std::size_t>(dim));
  for (float& v : p) v = u(rng);
  return p;
}

std::vector<double> reference_values(const Tree& tree, std::span<const double> params,
                                     const std::vector<float>& points) {
  const std::size_t dim = static_cast<std::size_t>(tree.dim);
  std::vector<double> out(points.size() / dim);
  for (std::size_t i = 0; i < out.size(); ++i) {
    double p[3] = {0, 0, 0};
    for (std::size_t j = 0; j < dim; ++j) p[j] = points[i * dim + j];
    out[i] = reference_occupancy(tree, params, p);
  }
  return out;
}

double reference_mse(const Tree& tree, std::span<const double> params,
                     const std::vector<float>& points, const std::vector<float>& targets) {
  const auto v = reference_values(tree, params, points);
  double s = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) s += (v[i] - targets[i]) * (v[i] - targets[i]);
  return s / static_cast<double>(v.size());
}

// Checks forward values against the reference and the MSE gradient against central
// differences of the reference loss, for every free parameter (or every `stride`-th one).
void check_tree(const Tree& tree, std::size_t n, std::uint64_t seed, std::size_t stride = 1,
                double grad_tol = 2e-3) {
  const Evaluator ev(tree, EvalOptions{2});
  const auto params = tree.params.values();
  const auto points = random_points(n, tree.dim, seed);
  std::vector<float> occ(n);
  ev.forward(params, points, occ);
  const auto ref = reference_values(tree, params, points);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_NEAR(occ[i], ref[i], 2e-5) << "point " << i;
  }

  std::vector<float> targets(n);
  std::mt19937_64 rng(seed + 1);
  for (float& t : targets) t = static_cast<float>(rng() % 2);
  std::vector<double> grad(params.size());
  const double loss = ev.backward(params, points, Loss{Loss::Kind::kMse, targets, {}}, grad);
  EXPECT_NEAR(loss, reference_mse(tree, params, points, targets), 1e-5);

  double scale = 0.0;
  for (double g : grad) scale = std::max(scale, std::abs(g));
  for (std::size_t k = 0; k < params.size(); k += stride) {
    const Parameter& p = tree.params.at(k);
    if (p.fixed) {
      EXPECT_EQ(grad[k], 0.0) << p.name;
      continue;
    }
    const double h = 1e-6 * std::max(1.0, std::abs(params[k]));
    auto plus = params, minus = params;
    plus[k] += h;
    minus[k] -= h;
    const double fd =
        (reference_mse(tree, plus, points, targets) - reference_mse(tree, minus, points, targets)) /
        (2 * h);
    EXPECT_NEAR(grad[k], fd, grad_tol * std::max(1e-2, scale)) << p.name;
  }
}

// The vector-Jacobian product: kSum with signed weights w gives d(sum_i w_i o_i)/dparams and,
// per point, w_i do_i/dp_i, both against central differences of the reference.
void check_vjp(const Tree& tree, std::size_t n, std::uint64_t seed) {
  const Evaluator ev(tree, EvalOptions{2});
  const auto params = tree.params.values();
  const auto points = random_points(n, tree.dim, seed);
  std::vector<float> w(n);
  std::mt19937_64 rng(seed + 3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (float& x : w) x = u(rng);
  const auto weighted = [&](std::span<const double> q) {
    const auto v = reference_values(tree, q, points);
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i) s += w[i] * v[i];
    return s;
  };
  std::vector<double> grad(params.size());
  std::vector<float> occ(n), pgrad(points.size());
  const double loss = ev.backward(params, points, Loss{Loss::Kind::kSum, {}, w}, grad, occ, pgrad);
  EXPECT_NEAR(loss, weighted(params), 1e-4 * static_cast<double>(n));
  double scale = 0.0;
  for (double g : grad) scale = std::max(scale, std::abs(g));
  for (std::size_t k = 0; k < params.size(); ++k) {
    if (tree.params.at(k).fixed) continue;
    const double h = 1e-6 * std::max(1.0, std::abs(params[k]));
    auto plus = params, minus = params;
    plus[k] += h;
    minus[k] -= h;
    EXPECT_NEAR(grad[k], (weighted(plus) - weighted(minus)) / (2 * h), 2e-3 * std::max(1.0, scale))
        << tree.params.at(k).name;
  }
  const auto dim = static_cast<std::size_t>(tree.dim);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < dim; ++j) {
      double p[3] = {0, 0, 0}, m[3] = {0, 0, 0};
      for (std::size_t a = 0; a < dim; ++a) p[a] = m[a] = points[i * dim + a];
      const double h = 1e-6;
      p[j] += h;
      m[j] -= h;
      const double fd =
          w[i] * (reference_occupancy(tree, params, p) - reference_occupancy(tree, params, m)) /
          (2 * h);
      ASSERT_NEAR(pgrad[i * dim + j], fd, 2e-3 * std::max(1.0, std::abs(fd)))
          << "point " << i << " axis " << j;
    }
  }
}

TEST(Evaluator, VectorJacobianProductByParametersAndPoints) {
  FullTreeOptions o;
  o.leaves = 8;
  o.seed = 5;
  o.temperature = 3.0;
  check_vjp(make_full_binary_tree(o), 150, 31);  // quadrics: the vector path
  o.dim = 2;
  o.family = PrimitiveType::kQuadric2;
  check_vjp(make_full_binary_tree(o), 150, 32);
  for (int dim : {2, 3}) {
    for (PrimitiveType t : {PrimitiveType::kSphere, PrimitiveType::kBox, PrimitiveType::kTorus,
                            PrimitiveType::kCircle, PrimitiveType::kRectangle}) {
      if (primitive_info(t).dim != dim) continue;
      FullTreeOptions b;
      b.dim = dim;
      b.leaves = 4;
      b.family = t;
      b.seed = 40 + static_cast<int>(t);
      b.sharpness = 6.0;
      b.temperature = 2.0;
      SCOPED_TRACE(std::string(primitive_info(t).name));
      check_vjp(make_full_binary_tree(b), 100, 33);
    }
  }
}

TEST(Evaluator, QuadricUnifiedTreeMatchesReference) {
  for (int leaves : {1, 2, 8, 32}) {
    FullTreeOptions o;
    o.leaves = leaves;
    o.seed = 7 + leaves;
    o.temperature = 3.0;  // soft operator weights, so every logit has a gradient
    check_tree(make_full_binary_tree(o), 200, 11);
  }
}

TEST(Evaluator, FixedBooleanTreesMatchReference) {
  for (OperatorMode mode : {OperatorMode::kProduct, OperatorMode::kGodel}) {
    FullTreeOptions o;
    o.leaves = 16;
    o.ops = mode;
    o.seed = 3;
    check_tree(make_full_binary_tree(o), 150, 5);
  }
}

TEST(Evaluator, EveryPlacedFamilyMatchesReference) {
  for (PrimitiveType t : {PrimitiveType::kSphere, PrimitiveType::kBox, PrimitiveType::kCylinder,
                          PrimitiveType::kCone, PrimitiveType::kTorus, PrimitiveType::kCapsule,
                          PrimitiveType::kEllipsoid, PrimitiveType::kPlane, PrimitiveType::kMlp}) {
    FullTreeOptions o;
    o.leaves = 4;
    o.family = t;
    o.seed = 100 + static_cast<int>(t);
    o.sharpness = 8.0;
    o.temperature = 2.0;
    SCOPED_TRACE(std::string(primitive_info(t).name));
    check_tree(make_full_binary_tree(o), 120, 21, t == PrimitiveType::kMlp ? 7 : 1);
  }
  for (PrimitiveType t :
       {PrimitiveType::kCircle, PrimitiveType::kRectangle, PrimitiveType::kEllipse,
        PrimitiveType::kHalfPlane, PrimitiveType::kQuadric2}) {
    FullTreeOptions o;
    o.dim = 2;
    o.leaves = 4;
    o.family = t;
    o.seed = 200 + static_cast<int>(t);
    o.sharpness = 8.0;
    o.temperature = 2.0;
    SCOPED_TRACE(std::string(primitive_info(t).name));
    check_tree(make_full_binary_tree(o), 120, 22);
  }
}

// Spheres and circles placed by a translation alone take the kernel's vector path; with a
// rotation, a scale or another step they keep the scalar one. Both against the reference, with
// points on the balls' centres (where the direction of the gradient is undefined and is 0).
TEST(Evaluator, TranslatedBallsTakeTheVectorPath) {
  for (int dim : {2, 3}) {
    FullTreeOptions o;
    o.dim = dim;
    o.leaves = 16;
    o.family = dim == 3 ? PrimitiveType::kSphere : PrimitiveType::kCircle;
    o.seed = 40 + dim;
    o.sharpness = 8.0;
    o.temperature = 2.0;
    const Tree tree = make_full_binary_tree(o);
    int balls = 0;
    const Program prog = Program::compile(tree);
    for (const Instruction& ins : prog.tape()) balls += ins.ball;
    EXPECT_EQ(balls, 16) << dim << "D";
    SCOPED_TRACE(dim);
    check_tree(tree, 300, 31);

    const Evaluator ev(tree, EvalOptions{1});
    const auto params = tree.params.values();
    std::vector<float> centres;
    for (const Node& n : tree.nodes) {
      if (n.kind != NodeKind::kPrimitive) continue;
      for (const ParamRef& t : n.placement.translate) {
        centres.push_back(static_cast<float>(params[t.index]));
      }
    }
    std::vector<double> grad(params.size());
    const std::vector<float> targets(centres.size() / static_cast<std::size_t>(dim), 1.0f);
    const double loss = ev.backward(params, centres, Loss{Loss::Kind::kMse, targets, {}}, grad);
    EXPECT_NEAR(loss, reference_mse(tree, params, centres, targets), 1e-5);
    for (double g : grad) ASSERT_TRUE(std::isfinite(g));
  }

  const Tree scalar = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
    "root": {"op": "union", "children": [
      {"type": "sphere", "radius": 0.3, "translate": [0.1, 0, 0], "sharpness": 6},
      {"type": "sphere", "radius": 0.3, "translate": [0.1, 0, 0], "scale": 1.5, "sharpness": 6},
      {"type": "sphere", "radius": 0.3, "translate": [0.1, 0, 0], "step": "crisp"},
      {"type": "sphere", "radius": 0.3, "sharpness": 6}]}})",
                                           "balls");
  std::vector<bool> fast;
  const Program prog = Program::compile(scalar);
  for (const Instruction& ins : prog.tape()) {
    if (ins.code == OpCode::kLeaf) fast.push_back(ins.ball);
  }
  EXPECT_EQ(fast, (std::vector<bool>{true, false, false, false}));
}

// Placed extrudes (translated, rotated, scaled; one with an H_n step) go through the kernel's
// scalar leaf path: forward values against the reference, and the gradient of every parameter
// (profile control points, a shared one among them, height, placement, sharpness) against
// central differences of the reference.
TEST(Evaluator, PlacedExtrudeMatchesReference) {
  const Tree tree = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
    "parameters": {"w": 0.35},
    "root": {"op": "union", "children": [
      {"op": "difference", "children": [
        {"type": "extrude",
         "profile": [[-0.5, -0.3], [-0.2, -0.3], [0.2, -0.3], [0.5, -0.3], [0.9, -0.3], [0.9, 0.3],
                     [0.5, {"param": "w"}], [0.1, 0.4], [-0.2, 0.3], [-0.5, 0.3], [-0.9, 0.3],
                     [-0.8, -0.3]],
         "height": 0.5, "translate": [0.1, -0.05, 0.05], "rotate": [20, -30, 40], "scale": 0.9,
         "sharpness": 6},
        {"type": "cylinder", "radius": 0.2, "height": 1.5, "translate": [0.2, 0, 0],
         "sharpness": 6}]},
      {"type": "extrude",
       "profile": [[0, -0.4], [0, -0.1], [0, 0.1], [0, 0.4], [{"param": "w"}, 0.4], [0.4, -0.4]],
       "height": 0.3, "translate": [-0.3, 0.4, -0.3], "rotate": [90, 0, 0],
       "step": {"hn": 3, "range": 0.4}}]}})",
                                         "placed_extrude.json");
  check_tree(tree, 200, 31);
}

// A tree with every operator family, complements, n-ary folds, steps and shared parameters.
constexpr const char* kMixed = R"({
  "format": "fuzzycsg-tree", "version": 1, "dim": 3,
  "parameters": {"r": 0.45},
  "root": {"op": "union", "logic": "yager", "p": 2.5, "children": [
    {"op": "intersection", "logic": "hamacher", "a": 0.3, "children": [
      {"type": "sphere", "radius": {"param": "r"}, "translate": [0.1, 0.0, -0.1], "sharpness": 6},
      {"type": "box", "size": [0.8, 0.6, 0.9], "rotate": [10, 20, 30], "scale": 1.2, "sharpness": 5},
      {"type": "cylinder", "radius": 0.3, "height": 1.1, "step": {"hn": 3, "range": 0.4}}]},
    {"op": "difference", "logic": "dombi", "lambda": 1.5, "complement": {"type": "sugeno", "lambda": 0.5},
     "children": [
      {"type": "torus", "major": 0.5, "minor": 0.15, "translate": [0, 0.2, 0], "sharpness": 7},
      {"type": "sphere", "radius": {"param": "r"}, "translate": [0.4, 0.2, 0], "sharpness": 9}]},
    {"op": "complement", "complement": "cosine", "children": [
      {"op": "union", "logic": "li-tian", "n": 2, "delta": 0.6, "children": [
        {"type": "cone", "radius1": 0.4, "radius2": 0.1, "height": 0.8, "sharpness": 4},
        {"type": "capsule", "radius": 0.2, "height": 0.5, "rotate": [0, 90, 0], "sharpness": 4}]}]},
    {"op": "intersection", "logic": "bezier", "n": 3, "children": [
      {"type": "ellipsoid", "radii": [0.6, 0.4, 0.3], "sharpness": 6},
      {"op": "union", "logic": "li-tian-hat", "n": 3, "delta": 0.7, "children": [
        {"type": "plane", "normal": [0.2, 1.0, 0.1], "offset": 0.1, "sharpness": 5},
        {"type": "quadric", "coefficients": [1, 2, 1, 0.1, 0, 0, 0.2, 0, 0, -0.3]}]}]},
    {"op": "unified", "c": [0.1, 0.5, 0.3, 0.1], "children": [
      {"type": "sphere", "radius": 0.3, "sharpness": {"value": 6, "fixed": true}},
      {"op": "difference", "logic": "einstein", "children": [
        {"type": "box", "size": [0.5, 0.5, 0.5], "sharpness": 5},
        {"op": "intersection", "logic": "weber", "k": 0.5, "children": [
          {"type": "sphere", "radius": 0.35, "sharpness": 5},
          {"op": "union", "logic": "dubois-prade", "k": 0.7, "children": [
            {"type": "sphere", "radius": 0.2, "translate": [0.3, 0, 0], "sharpness": 5},
            {"op": "difference", "logic": "lukasiewicz", "complement": {"type": "yager", "lambda": 2},
             "children": [
              {"type": "sphere", "radius": 0.25, "sharpness": 5},
              {"type": "sphere", "radius": 0.1, "step": "crisp"}]}]}]}]}]}]}
})";

TEST(Evaluator, EveryOperatorFamilyMatchesReference) {
  const Tree tree = io::read_tree_string(kMixed, "mixed");
  check_tree(tree, 300, 31, 1, 3e-3);
}

TEST(Evaluator, PartialBlocksAndEmptyInput) {
  FullTreeOptions o;
  o.leaves = 4;
  const Tree tree = make_full_binary_tree(o);
  const Evaluator ev(tree);
  const auto params = tree.params.values();
  for (std::size_t n : {0u, 1u, 63u, 64u, 65u, 1000u}) {
    const auto points = random_points(n, 3, n);
    std::vector<float> occ(n, -1.0f);
    ev.forward(params, points, occ);
    const auto ref = reference_values(tree, params, points);
    for (std::size_t i = 0; i < n; ++i) ASSERT_NEAR(occ[i], ref[i], 2e-5) << n << ":" << i;
    std::vector<double> grad(params.size());
    std::vector<float> occ2(n);
    const double sum = ev.backward(params, points, Loss{}, grad, occ2);
    double ref_sum = 0.0;
    for (double v : ref) ref_sum += v;
    EXPECT_NEAR(sum, ref_sum, 1e-4 * std::max(1.0, ref_sum));
    EXPECT_EQ(occ, occ2);
  }
}

// Sharp primitives far from their surface: sigmoids of 87..104 are subnormal floats (below
// 1.2e-38), and so are products of small occupancies in the booleans. The kernel flushes them to
// 0 (arithmetic on subnormals made training steps several times slower): every value is 0 or a
// normal float, and the caller's floating-point mode is left as it was.
TEST(Evaluator, NoSubnormalOccupancies) {
  const Tree tree = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
    "root": {"op": "intersection", "children": [
      {"type": "sphere", "radius": 0.1, "sharpness": 100},
      {"type": "sphere", "radius": 0.1, "sharpness": 100}]}})",
                                         "sharp");
  const Evaluator ev(tree, EvalOptions{2});
  // Points along x from 0.5 to 1.2: s * (|p| - r) runs over 40..110, so the intersection's
  // product exp(-2 s (|p| - r)) passes through the whole subnormal range, and so does one
  // sigmoid near 88.
  std::vector<float> points;
  for (int i = 0; i < 4096; ++i) {
    points.insert(points.end(), {0.5f + 0.7f * static_cast<float>(i) / 4096.0f, 0.0f, 0.0f});
  }
  std::vector<float> occ(4096);
  ev.forward(tree.params.values(), points, occ);
  int zeros = 0;
  for (float v : occ) {
    EXPECT_TRUE(v == 0.0f || std::fpclassify(v) == FP_NORMAL) << v;
    zeros += v == 0.0f ? 1 : 0;
  }
  EXPECT_GT(zeros, 0);
  // The caller's mode is restored: subnormal arithmetic still works here.
  volatile float tiny = 1e-30f;
  volatile float product = tiny * 1e-10f;
  EXPECT_EQ(std::fpclassify(product), FP_SUBNORMAL);
}

TEST(Evaluator, WeightedMse) {
  FullTreeOptions o;
  o.leaves = 8;
  const Tree tree = make_full_binary_tree(o);
  const Evaluator ev(tree);
  const auto params = tree.params.values();
  const std::size_t n = 500;
  const auto points = random_points(n, 3, 4);
  std::vector<float> targets(n), weights(n);
  for (std::size_t i = 0; i < n; ++i) {
    targets[i] = static_cast<float>(i % 2);
    weights[i] = static_cast<float>(i % 5);
  }
  std::vector<double> grad(params.size()), grad_dup(params.size());
  const double loss = ev.backward(params, points, Loss{Loss::Kind::kMse, targets, weights}, grad);
  const auto ref = reference_values(tree, params, points);
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    num += weights[i] * (ref[i] - targets[i]) * (ref[i] - targets[i]);
    den += weights[i];
  }
  EXPECT_NEAR(loss, num / den, 1e-6);
  // Integer weights are the same as repeating points.
  std::vector<float> dup_points, dup_targets;
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < static_cast<int>(weights[i]); ++k) {
      dup_points.insert(dup_points.end(), points.begin() + 3 * i, points.begin() + 3 * i + 3);
      dup_targets.push_back(targets[i]);
    }
  }
  const double loss_dup =
      ev.backward(params, dup_points, Loss{Loss::Kind::kMse, dup_targets, {}}, grad_dup);
  EXPECT_NEAR(loss, loss_dup, 1e-6);
  for (std::size_t k = 0; k < grad.size(); ++k) EXPECT_NEAR(grad[k], grad_dup[k], 1e-5);
}

TEST(Evaluator, IdenticalForEveryThreadCount) {
  FullTreeOptions o;
  o.leaves = 64;
  o.seed = 9;
  const Tree tree = make_full_binary_tree(o);
  const auto params = tree.params.values();
  const std::size_t n = 20000;
  const auto points = random_points(n, 3, 12);
  std::vector<float> targets(n);
  for (std::size_t i = 0; i < n; ++i) targets[i] = static_cast<float>((i * 7) % 3 == 0);
  std::vector<double> first;
  double first_loss = 0.0;
  for (int threads : {1, 2, 3, 4, 2}) {
    const Evaluator ev(tree, EvalOptions{threads});
    std::vector<double> grad(params.size());
    const double loss = ev.backward(params, points, Loss{Loss::Kind::kMse, targets, {}}, grad);
    if (first.empty()) {
      first = grad;
      first_loss = loss;
      continue;
    }
    EXPECT_EQ(loss, first_loss) << threads << " threads";
    EXPECT_EQ(grad, first) << threads << " threads";
  }
}

TEST(Evaluator, RejectsMismatchedSizes) {
  FullTreeOptions o;
  o.leaves = 2;
  const Tree tree = make_full_binary_tree(o);
  const Evaluator ev(tree);
  auto params = tree.params.values();
  std::vector<float> points(9), out(3), bad_out(2);
  EXPECT_THROW(ev.forward(params, points, bad_out), InputError);
  std::vector<float> odd_points(8);
  EXPECT_THROW(ev.forward(params, odd_points, out), InputError);
  std::vector<double> short_params(params.begin(), params.end() - 1);
  EXPECT_THROW(ev.forward(short_params, points, out), InputError);
  std::vector<double> grad(params.size());
  std::vector<float> targets(2);
  EXPECT_THROW(ev.backward(params, points, Loss{Loss::Kind::kMse, targets, {}}, grad), InputError);
  std::vector<float> t3(3), zero_w(3, 0.0f);
  EXPECT_THROW(ev.backward(params, points, Loss{Loss::Kind::kMse, t3, zero_w}, grad), InputError);
}

TEST(Evaluator, RejectsInvalidTreesBuiltInCode) {
  FullTreeOptions o;
  o.leaves = 2;
  Tree tree = make_full_binary_tree(o);
  tree.nodes[static_cast<std::size_t>(tree.root)].children.pop_back();
  EXPECT_THROW(Evaluator{tree}, InputError);
  Tree empty;
  EXPECT_THROW(Evaluator{empty}, InputError);
}

TEST(Program, PostOrderTapeWithFoldedNaryNodes) {
  const Tree tree = io::read_tree_string(kMixed, "mixed");
  const Program prog = Program::compile(tree);
  int leaves = 0;
  for (std::size_t k = 0; k < prog.tape().size(); ++k) {
    const Instruction& ins = prog.tape()[k];
    if (ins.left >= 0) {
      EXPECT_LT(ins.left, static_cast<int>(k));
    }
    if (ins.right >= 0) {
      EXPECT_LT(ins.right, static_cast<int>(k));
      EXPECT_LT(ins.left, ins.right);
    }
    leaves += (ins.code == OpCode::kLeaf || ins.code == OpCode::kLeafQuadric3);
  }
  EXPECT_EQ(leaves, count(tree).primitives);
  // A binary fold of k children takes k - 1 instructions; the root union has 5 children.
  EXPECT_EQ(prog.tape().size(),
            static_cast<std::size_t>(2 * count(tree).primitives - 1 + 1 /* complement */));
}

}  // namespace
}  // namespace fuzzycsg

namespace fuzzycsg {
namespace {

// Every example tree of the repository, kernel against reference.
TEST(Evaluator, ExamplesMatchReference) {
  const std::filesystem::path dir = std::filesystem::path(FUZZYCSG_SOURCE_DIR) / "examples";
  int seen = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    check_tree(io::read_tree_file(entry.path()), 150, 41, 1, 3e-3);
    ++seen;
  }
  EXPECT_GE(seen, 5);
}

}  // namespace
}  // namespace fuzzycsg

namespace fuzzycsg {
namespace {

// ---- The fuzzy spline node

// A spline tree of random leaves: `cells` per axis of degree `degree` over a box smaller than the
// domain (so that a good share of the points in [-1, 1] lie outside it and are clamped), leaves
// of several families with placement, and in 3D one child that is itself a union.
std::string spline_tree_text(int dim, std::vector<int> cells, int degree, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.6, 0.6), r(0.15, 0.6), s(4.0, 12.0);
  const auto num = [](double v) { return std::to_string(v); };
  int total = 1;
  std::string cells_text;
  for (std::size_t a = 0; a < cells.size(); ++a) {
    total *= cells[a];
    cells_text += (a ? ", " : "") + std::to_string(cells[a]);
  }
  std::string children;
  for (int k = 0; k < total; ++k) {
    std::string t =
        "[" + num(u(rng)) + ", " + num(u(rng)) + (dim == 3 ? ", " + num(u(rng)) : "") + "]";
    std::string leaf;
    if (dim == 2) {
      leaf = k % 3 == 0 ? R"({"type": "rectangle", "size": [)" + num(r(rng)) + ", " + num(r(rng)) +
                              R"(], "rotate": )" + num(60 * u(rng)) + ", "
             : k % 3 == 1
                 ? R"({"type": "ellipse", "radii": [)" + num(r(rng)) + ", " + num(r(rng)) + "], "
                 : R"({"type": "circle", "radius": )" + num(r(rng)) + ", ";
    } else {
      leaf = k % 3 == 0 ? R"({"type": "box", "size": [)" + num(r(rng)) + ", " + num(r(rng)) + ", " +
                              num(r(rng)) + "], "
             : k % 3 == 1
                 ? R"({"type": "quadric", "coefficients": [1, 2, 1.5, 0.1, 0, 0.2, 0, 0.1, 0, )" +
                       num(-r(rng)) + "], "
                 : R"({"type": "sphere", "radius": )" + num(r(rng)) + ", ";
    }
    leaf += R"("translate": )" + t + R"(, "sharpness": )" + num(s(rng)) + "}";
    if (dim == 3 && k == 1) {
      leaf = R"({"op": "union", "children": [)" + leaf +
             R"(, {"type": "sphere", "radius": 0.3, "sharpness": 6}]})";
    }
    children += (k ? ",\n" : "") + leaf;
  }
  const std::string box = dim == 2 ? R"({"min": [-0.7, -0.5], "max": [0.6, 0.8]})"
                                   : R"({"min": [-0.7, -0.5, -0.6], "max": [0.6, 0.8, 0.5]})";
  return R"({"format": "fuzzycsg-tree", "version": 1, "dim": )" + std::to_string(dim) +
         R"(, "root": {"op": "spline", "cells": [)" + cells_text + R"(], "degree": )" +
         std::to_string(degree) + R"(, "box": )" + box + R"(, "children": [)" + children + "]}}";
}

// Forward values against the reference and gradients with respect to every child parameter
// against central differences, for degrees 1..3 in 2D and 3D.
TEST(Spline, KernelMatchesReferenceAndGradients) {
  for (int degree = 1; degree <= 3; ++degree) {
    SCOPED_TRACE("degree " + std::to_string(degree));
    check_tree(io::read_tree_string(spline_tree_text(2, {degree + 1, degree + 3}, degree, degree),
                                    "spline 2D"),
               150, 51);
    check_tree(io::read_tree_string(
                   spline_tree_text(3, {degree + 1, 2 + degree, degree + 1}, degree, 10 + degree),
                   "spline 3D"),
               130, 52, degree == 3 ? 3 : 1);
  }
}

// A spline inside a union and below a complement, and a unified node among its children: the
// adjoint stack and the fold of a spline's terms within other nodes.
TEST(Spline, NestedInOtherOperators) {
  const Tree tree = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
    "root": {"op": "union", "logic": "yager", "p": 2, "children": [
      {"type": "circle", "radius": 0.3, "translate": [0.5, 0.5], "sharpness": 8},
      {"op": "complement", "children": [
        {"op": "spline", "cells": [2, 3], "degree": 1, "children": [
          {"type": "circle", "radius": 0.4, "sharpness": 7},
          {"op": "unified", "logits": [0.1, 0.3, -0.2, 0.05], "temperature": 3, "children": [
            {"type": "circle", "radius": 0.5, "translate": [0.2, 0], "sharpness": 6},
            {"type": "rectangle", "size": [0.6, 0.3], "sharpness": 9}]},
          {"type": "ellipse", "radii": [0.5, 0.3], "sharpness": 5},
          {"op": "spline", "cells": [3, 3], "degree": 2, "box": {"min": [-0.5, -0.5], "max": [0.5, 0.5]},
           "children": [
            {"type": "circle", "radius": 0.1, "sharpness": 10}, {"type": "circle", "radius": 0.2, "sharpness": 10},
            {"type": "circle", "radius": 0.3, "sharpness": 10}, {"type": "circle", "radius": 0.4, "sharpness": 10},
            {"type": "circle", "radius": 0.5, "sharpness": 10}, {"type": "circle", "radius": 0.6, "sharpness": 10},
            {"type": "circle", "radius": 0.7, "sharpness": 10}, {"type": "circle", "radius": 0.8, "sharpness": 10},
            {"type": "circle", "radius": 0.9, "sharpness": 10}]},
          {"type": "half-plane", "normal": [1, 1], "offset": 0.1, "sharpness": 4},
          {"type": "quadric", "coefficients": [1, 1, 0, 0, 0, -0.3]}]}]},
      {"type": "rectangle", "size": [0.3, 0.3], "translate": [-0.6, 0.6], "sharpness": 8}]}})",
                                         "nested");
  check_tree(tree, 200, 53);
  // One term per child: a spline of k children takes k instructions, the first without acc.
  const Program prog = Program::compile(tree);
  int terms = 0, first_terms = 0;
  for (const Instruction& ins : prog.tape()) {
    if (ins.code != OpCode::kSplineTerm) continue;
    ++terms;
    first_terms += ins.left < 0 ? 1 : 0;
    EXPECT_GE(ins.right, 0);
  }
  EXPECT_EQ(terms, 6 + 9);
  EXPECT_EQ(first_terms, 2);
}

// By hand: cells [3, 2], degree 1 over the box [0, 2] x [0, 1]: hats along x at 0, 1, 2 and
// the linear pair (1 - y, y) along y; the children are circles at different centres.
TEST(Spline, HandComputedBilinearBlend) {
  const double cx[6] = {0.0, 1.0, 2.0, 0.0, 1.0, 2.0}, cy[6] = {0.0, 0.0, 0.0, 1.0, 1.0, 1.0};
  const double radius[6] = {0.3, 0.5, 0.4, 0.6, 0.2, 0.7};
  std::string children;
  for (int k = 0; k < 6; ++k) {
    children += (k ? ", " : "") + std::string(R"({"type": "circle", "radius": )") +
                std::to_string(radius[k]) + R"(, "translate": [)" + std::to_string(cx[k]) + ", " +
                std::to_string(cy[k]) + R"(], "sharpness": 5})";
  }
  const Tree tree = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2, "domain": {"min": [-1, -1], "max": [3, 2]},
          "root": {"op": "spline", "cells": [3, 2], "degree": 1,
                   "box": {"min": [0, 0], "max": [2, 1]}, "children": [)" +
          children + "]}}",
      "hand");
  const auto hand = [&](double x, double y) {
    const double xc = std::clamp(x, 0.0, 2.0), yc = std::clamp(y, 0.0, 1.0);
    const double nx[3] = {std::max(0.0, 1 - xc), std::max(0.0, 1 - std::abs(xc - 1)),
                          std::max(0.0, xc - 1)};
    const double ny[2] = {1 - yc, yc};
    double f = 0.0;
    for (int k = 0; k < 6; ++k) {
      const double d = std::hypot(x - cx[k], y - cy[k]) - radius[k];
      f += nx[k % 3] * ny[k / 3] / (1.0 + std::exp(5.0 * d));
    }
    return f;
  };
  const std::vector<std::array<float, 2>> at = {{0.25f, 0.5f}, {1.0f, 0.0f}, {1.7f, 0.9f},
                                                {0.0f, 0.0f},  {2.0f, 1.0f}, {-0.8f, 0.3f},
                                                {2.6f, -0.7f}, {0.5f, 1.8f}};
  std::vector<float> points;
  for (const auto& p : at) points.insert(points.end(), p.begin(), p.end());
  std::vector<float> occ(at.size());
  const Evaluator ev(tree);
  ev.forward(tree.params.values(), points, occ);
  for (std::size_t i = 0; i < at.size(); ++i) {
    const double p[2] = {at[i][0], at[i][1]};
    EXPECT_NEAR(reference_occupancy(tree, tree.params.values(), p), hand(p[0], p[1]), 1e-14) << i;
    EXPECT_NEAR(occ[i], hand(p[0], p[1]), 2e-6) << i;
  }
}

// A spline of identical children is that child (the weights sum to 1), in the kernel too.
TEST(Spline, IdenticalChildrenGiveTheChild) {
  std::string children;
  for (int k = 0; k < 16; ++k) {
    children +=
        (k ? ", " : "") +
        std::string(
            R"({"type": "circle", "radius": 0.45, "translate": [0.1, -0.2], "sharpness": 9})");
  }
  const Tree tree = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2, "root": {"op": "spline", "cells": [4, 4],
          "degree": 3, "box": {"min": [-0.5, -0.4], "max": [0.3, 0.9]}, "children": [)" +
          children + "]}}",
      "same");
  const Tree one = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
          "root": {"type": "circle", "radius": 0.45, "translate": [0.1, -0.2], "sharpness": 9}})",
      "one");
  const auto points = random_points(1000, 2, 54);
  std::vector<float> a(1000), b(1000);
  Evaluator(tree).forward(tree.params.values(), points, a);
  Evaluator(one).forward(one.params.values(), points, b);
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(a[i], b[i], 1e-6) << i;
}

// Gradient descent on the children's parameters through the spline: a few steps of plain
// gradient descent on the MSE to another spline's occupancy lower the loss.
TEST(Spline, TrainsThroughTheNode) {
  const Tree tree = io::read_tree_string(spline_tree_text(2, {3, 3}, 2, 61), "model");
  const Tree target = io::read_tree_string(spline_tree_text(2, {3, 3}, 2, 62), "target");
  const auto points = random_points(4000, 2, 63);
  std::vector<float> targets(4000);
  Evaluator(target).forward(target.params.values(), points, targets);
  const Evaluator ev(tree);
  std::vector<double> params = tree.params.values(), grad(params.size());
  const Loss loss{Loss::Kind::kMse, targets, {}};
  const double start = ev.backward(params, points, loss, grad);
  double last = start;
  for (int step = 0; step < 20; ++step) {
    last = ev.backward(params, points, loss, grad);
    for (std::size_t k = 0; k < params.size(); ++k) {
      const Parameter& p = tree.params.at(k);
      params[k] -= 0.5 * grad[k];
      // Keep sizes and sharpness positive.
      if (!p.range.contains(params[k])) params[k] = std::max(params[k], 0.05);
    }
  }
  EXPECT_TRUE(std::isfinite(last));
  EXPECT_LT(last, 0.9 * start);
}

}  // namespace
}  // namespace fuzzycsg

namespace fuzzycsg {
namespace {

// Tree nodes that are operators, in index order.
std::vector<int> operator_nodes(const Tree& tree) {
  std::vector<int> out;
  for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
    if (tree.nodes[k].kind == NodeKind::kOperator) out.push_back(static_cast<int>(k));
  }
  return out;
}

std::array<double, 3> abd(const std::array<double, 4>& c) {
  return {c[1] + c[2], c[1] + c[3], c[0] - c[1] - c[2] - c[3]};
}

TEST(EditLossChanges, SwappedUnifiedWeightsAreExact) {
  // Soft weights (t = 3), so a swap of any two entries changes the operator; the predicted
  // change of the MSE must be the one the double-precision reference measures after the swap.
  FullTreeOptions o;
  o.leaves = 16;
  o.seed = 21;
  o.temperature = 3.0;
  const Tree tree = make_full_binary_tree(o);
  const Evaluator ev(tree, EvalOptions{2});
  const auto params = tree.params.values();
  const std::size_t n = 700;  // partial last block
  const auto points = random_points(n, 3, 5);
  std::vector<float> targets(n);
  for (std::size_t i = 0; i < n; ++i) targets[i] = points[3 * i] * points[3 * i + 1] > 0 ? 1 : 0;
  const double base = reference_mse(tree, params, points, targets);

  std::vector<BilinearEdit> edits;
  std::vector<std::vector<double>> swapped;
  for (int k : operator_nodes(tree)) {
    const Node& node = tree.nodes[static_cast<std::size_t>(k)];
    std::array<double, 4> l{};
    for (int i = 0; i < 4; ++i) l[i] = params[node.unified[i].index];
    const auto c = logic::unified_weights(l, 3.0, 10.0);
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        auto s = c;
        std::swap(s[i], s[j]);
        const auto a = abd(c), b = abd(s);
        edits.push_back({k, {b[0] - a[0], b[1] - a[1], b[2] - a[2]}});
        auto p = params;
        std::swap(p[node.unified[i].index], p[node.unified[j].index]);
        swapped.push_back(p);
      }
    }
  }
  std::vector<double> changes(edits.size());
  const double loss =
      ev.edit_loss_changes(params, points, Loss{Loss::Kind::kMse, targets, {}}, edits, changes);
  EXPECT_NEAR(loss, base, 1e-5);
  int moved = 0;
  for (std::size_t e = 0; e < edits.size(); ++e) {
    const double truth = reference_mse(tree, swapped[e], points, targets) - base;
    EXPECT_NEAR(changes[e], truth, 2e-5 + 1e-3 * std::abs(truth)) << "edit " << e;
    moved += std::abs(truth) > 1e-4 ? 1 : 0;
  }
  EXPECT_GT(moved, static_cast<int>(edits.size()) / 2);  // the swaps do change the loss
}

TEST(EditLossChanges, ProductBooleanChangedTypeIsExactAndWeighted) {
  FullTreeOptions o;
  o.leaves = 8;
  o.ops = OperatorMode::kProduct;
  o.seed = 4;
  const Tree tree = make_full_binary_tree(o);
  const Evaluator ev(tree, EvalOptions{3});
  const auto params = tree.params.values();
  const std::size_t n = 300;
  const auto points = random_points(n, 3, 8);
  std::vector<float> targets(n), weights(n);
  for (std::size_t i = 0; i < n; ++i) {
    targets[i] = points[3 * i + 2] > 0.1f ? 1 : 0;
    weights[i] = 0.5f + static_cast<float>(i % 3);
  }
  auto weighted_mse = [&](const Tree& t) {
    const auto v = reference_values(t, t.params.values(), points);
    double s = 0, w = 0;
    for (std::size_t i = 0; i < n; ++i) {
      s += weights[i] * (v[i] - targets[i]) * (v[i] - targets[i]);
      w += weights[i];
    }
    return s / w;
  };
  const double base = weighted_mse(tree);
  // (a, b, d) of product logic: x y, x + y - x y, x - x y.
  auto constants = [](OpKind op) -> std::array<double, 3> {
    return op == OpKind::kIntersection ? std::array<double, 3>{0, 0, 1}
           : op == OpKind::kUnion      ? std::array<double, 3>{1, 1, -1}
                                       : std::array<double, 3>{1, 0, -1};
  };
  std::vector<BilinearEdit> edits;
  std::vector<double> truth;
  for (int k : operator_nodes(tree)) {
    const OpKind now = tree.nodes[static_cast<std::size_t>(k)].op;
    for (OpKind op : {OpKind::kIntersection, OpKind::kUnion, OpKind::kDifference}) {
      if (op == now) continue;
      const auto a = constants(now), b = constants(op);
      edits.push_back({k, {b[0] - a[0], b[1] - a[1], b[2] - a[2]}});
      Tree changed = tree;
      changed.nodes[static_cast<std::size_t>(k)].op = op;
      truth.push_back(weighted_mse(changed) - base);
    }
  }
  std::vector<double> changes(edits.size());
  ev.edit_loss_changes(params, points, Loss{Loss::Kind::kMse, targets, weights}, edits, changes);
  for (std::size_t e = 0; e < edits.size(); ++e) {
    EXPECT_NEAR(changes[e], truth[e], 2e-5 + 1e-3 * std::abs(truth[e])) << "edit " << e;
  }
  // The same answer with any number of threads, and edits in any order.
  const Evaluator one(tree, EvalOptions{1});
  std::vector<BilinearEdit> reversed(edits.rbegin(), edits.rend());
  std::vector<double> again(edits.size());
  one.edit_loss_changes(params, points, Loss{Loss::Kind::kMse, targets, weights}, reversed, again);
  for (std::size_t e = 0; e < edits.size(); ++e) {
    EXPECT_EQ(again[edits.size() - 1 - e], changes[e]);
  }
}

TEST(EditLossChanges, RejectsWhatItCannotEdit) {
  FullTreeOptions o;
  o.leaves = 4;
  o.ops = OperatorMode::kGodel;
  const Tree godel = make_full_binary_tree(o);
  const Evaluator ev(godel);
  const auto params = godel.params.values();
  const auto points = random_points(10, 3, 1);
  std::vector<float> targets(10);
  std::vector<double> changes(1);
  const Loss mse{Loss::Kind::kMse, targets, {}};
  const std::vector<BilinearEdit> op{{operator_nodes(godel)[0], {1, 0, 0}}};
  EXPECT_THROW(ev.edit_loss_changes(params, points, mse, op, changes), InputError);  // min/max
  const std::vector<BilinearEdit> leaf{{0, {1, 0, 0}}};
  EXPECT_THROW(ev.edit_loss_changes(params, points, mse, leaf, changes), InputError);
  const std::vector<BilinearEdit> outside{{999, {1, 0, 0}}};
  EXPECT_THROW(ev.edit_loss_changes(params, points, mse, outside, changes), InputError);
  o.ops = OperatorMode::kUnified;
  const Tree unified = make_full_binary_tree(o);
  const Evaluator eu(unified);
  const std::vector<BilinearEdit> ok{{operator_nodes(unified)[0], {1, 0, 0}}};
  EXPECT_THROW(eu.edit_loss_changes(unified.params.values(), points, Loss{}, ok, changes),
               InputError);  // not the MSE
  std::vector<double> two(2);
  EXPECT_THROW(eu.edit_loss_changes(unified.params.values(), points, mse, ok, two), InputError);
}

}  // namespace
}  // namespace fuzzycsg
