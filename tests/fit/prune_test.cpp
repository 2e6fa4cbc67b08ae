// Snapping unified operators and pruning redundant nodes: argmax and index semantics, equality
// with the unified tree at one-hot weights, the simplifications of App. A on small trees whose
// answer is known, and full binary trees whose pruned output must stay close to the original.
#include "fuzzycsg/fit/prune.hpp"
#include "fuzzycsg/core/snap.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "fit/fit_support.hpp"
#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "io/tree_compare.hpp"

namespace fuzzycsg {
namespace {

using testing::mse;
using testing::occupancy;
using testing::random_points;

Tree tree3(const std::string& root, const std::string& parameters = "") {
  std::string text = R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, )";
  if (!parameters.empty()) text += R"("parameters": )" + parameters + ", ";
  return io::read_tree_string(text + R"("root": )" + root + "}");
}

// Leaves used below: `a` and `b` overlap near the origin, `tiny` is far from both, `huge`
// covers the whole domain, `box` contains `a`.
const std::string kA =
    R"({"name": "a", "type": "sphere", "radius": 0.5, "translate": [-0.2, 0, 0]})";
const std::string kB =
    R"({"name": "b", "type": "box", "size": [0.6, 0.8, 0.7], "translate": [0.3, 0.1, 0]})";
const std::string kC =
    R"({"name": "c", "type": "cylinder", "radius": 0.2, "height": 1.6, "rotate": [0, 90, 0]})";
const std::string kTiny =
    R"({"name": "tiny", "type": "sphere", "radius": 0.02, "translate": [0.9, 0.9, 0.9]})";
const std::string kHuge = R"({"name": "huge", "type": "box", "size": [5, 5, 5]})";
const std::string kBox = R"({"name": "box", "type": "box", "size": [1.5, 1.5, 1.5]})";

std::string op(const std::string& name, const std::string& a, const std::string& b,
               const std::string& extra = "") {
  return R"({"op": ")" + name + "\", " + extra + R"("children": [)" + a + ", " + b + "]}";
}

const std::vector<float>& points() {
  static const std::vector<float> p = random_points(20000, 3, 11);
  return p;
}

Tree pruned(const Tree& tree, PruneReport* report = nullptr) {
  return prune(tree, points(), PruneOptions{1e-3, 2}, report);
}

// ---- snapping

TEST(Snap, OperatorIsTheArgmaxOfTheWeights) {
  const Tree t = tree3(op("union", op("unified", kA, kB, R"("c": [0.1, 0.6, 0.2, 0.1], )"),
                          op("unified", kA, kB, R"("c": [0.4, 0.1, 0.1, 0.4], )")));
  const Node& root = t.node(t.root);
  EXPECT_EQ(snapped_operator(t, root.children[0]), 1);
  EXPECT_EQ(snapped_operator(t, root.children[1]), 0);  // a tie goes to the lowest index
  EXPECT_THROW(snapped_operator(t, t.root), Error);
  EXPECT_THROW(snapped_operator(t, 99), Error);
}

TEST(Snap, LogitsGoThroughTheWeights) {
  const std::array<double, 4> logits{0.02, 0.3, -0.07, 0.12};
  const auto c = logic::unified_weights(logits, 3.0, 10.0);
  const auto expected = static_cast<int>(std::max_element(c.begin(), c.end()) - c.begin());
  // sin(10 x) reorders the logits: the largest logit is not the largest weight.
  ASSERT_NE(expected, 1);
  const Tree t = tree3(op(
      "unified", kA, kB, R"("logits": [0.02, 0.3, -0.07, 0.12], "temperature": 3, "omega": 10, )"));
  EXPECT_EQ(snapped_operator(t, t.root), expected);
}

TEST(Snap, EachIndexBecomesItsProductBoolean) {
  const std::array<OpKind, 4> kinds{OpKind::kIntersection, OpKind::kUnion, OpKind::kDifference,
                                    OpKind::kDifference};
  for (int k = 0; k < 4; ++k) {
    std::string c = "[";
    for (int j = 0; j < 4; ++j) c += std::string(j ? ", " : "") + (j == k ? "1" : "0");
    const Tree t = tree3(op("unified", kA, kB, "\"c\": " + c + "], "));
    const Tree s = snap_operators(t);
    validate(s, "snapped");
    const Node& root = s.node(s.root);
    EXPECT_EQ(root.op, kinds[static_cast<std::size_t>(k)]) << k;
    EXPECT_EQ(root.logic.family, logic::Family::kProduct);
    EXPECT_EQ(root.complement.kind, logic::Complement::kStandard);
    EXPECT_TRUE(root.unified.empty());
    // Index 3 is "right minus left": the children are swapped.
    EXPECT_EQ(s.node(root.children[0]).name, k == 3 ? "b" : "a") << k;
    EXPECT_EQ(s.node(root.children[1]).name, k == 3 ? "a" : "b") << k;
    // The weights are gone; the leaves' parameters (radius, translate, sharpness; size,
    // translate, sharpness) remain, named by their new paths.
    EXPECT_EQ(s.params.size(), 5u + 7u) << k;
    EXPECT_EQ(s.params.find("root.c[0]"), std::nullopt);
    const auto radius =
        s.params.find(k == 3 ? "root.children[1].radius" : "root.children[0].radius");
    ASSERT_TRUE(radius.has_value()) << k;
    EXPECT_EQ(s.params[*radius].value, 0.5);
    // At a one-hot c the snapped operator is the unified one.
    const auto p = random_points(5000, 3, 5);
    const auto before = occupancy(t, p), after = occupancy(s, p);
    for (std::size_t i = 0; i < before.size(); ++i) ASSERT_NEAR(before[i], after[i], 1e-6) << k;
  }
}

TEST(Snap, OtherNodesAreUnchanged) {
  const std::string a =
      R"({"type": "sphere", "radius": {"value": 0.4, "fixed": true}, "step": "crisp"})";
  const std::string b = R"({"type": "box", "size": [0.3, {"param": "s"}, 0.5], "sharpness": 20})";
  const std::string keep = R"({"op": "complement", "complement": {"type": "sugeno", "lambda": 0.5},
                              "children": [)" +
                           kC + "]}";
  const Tree t = tree3(op("union", op("unified", a, b, R"("c": [0.1, 0.2, 0.3, 0.4], )"), keep,
                          R"("logic": "godel", )"),
                       R"({"s": {"value": 0.7, "fixed": true}})");
  const Tree expected = tree3(op("union", op("difference", b, a), keep, R"("logic": "godel", )"),
                              R"({"s": {"value": 0.7, "fixed": true}})");
  const Tree s = snap_operators(t);
  EXPECT_EQ(testing::tree_difference(s, expected), "");
}

TEST(Snap, SnappedTreeEqualsTheUnifiedTreeAtOneHotWeights) {
  FullTreeOptions o;
  o.leaves = 16;
  o.family = PrimitiveType::kSphere;
  o.seed = 3;
  Tree t = make_full_binary_tree(o);
  // sin(omega x) = +-1 at x = +-pi / (2 omega): at t = 1000 the softmax underflows to exactly
  // one-hot in double precision, as it does for a trained tree whose weights have saturated.
  std::mt19937_64 rng(9);
  std::vector<int> chosen(t.nodes.size(), -1);
  const double x = std::numbers::pi / (2.0 * o.omega);
  for (std::size_t i = 0; i < t.nodes.size(); ++i) {
    const Node& n = t.nodes[i];
    if (n.op != OpKind::kUnified || n.kind != NodeKind::kOperator) continue;
    chosen[i] = static_cast<int>(rng() % 4);
    std::array<double, 4> logits{};
    for (std::size_t j = 0; j < 4; ++j) {
      logits[j] = static_cast<int>(j) == chosen[i] ? x : -x;
      t.params[n.unified[j]].value = logits[j];
    }
    const auto c = logic::unified_weights(logits, o.temperature, o.omega);
    for (std::size_t j = 0; j < 4; ++j) {
      ASSERT_EQ(c[j], static_cast<int>(j) == chosen[i] ? 1.0 : 0.0);
    }
  }
  int operators = 0;
  for (std::size_t i = 0; i < t.nodes.size(); ++i) {
    if (chosen[i] < 0) continue;
    ++operators;
    EXPECT_EQ(snapped_operator(t, static_cast<int>(i)), chosen[i]);
  }
  ASSERT_EQ(operators, 15);
  const Tree s = snap_operators(t);
  validate(s, "snapped");
  EXPECT_EQ(count(s).operators, 15);
  EXPECT_EQ(count(s).primitives, 16);
  // Four logits, temperature and omega per operator are dropped.
  EXPECT_EQ(s.params.size(), t.params.size() - 6u * 15u);
  const auto p = random_points(20000, 3, 4);
  const auto before = occupancy(t, p), after = occupancy(s, p);
  for (std::size_t i = 0; i < before.size(); ++i) ASSERT_NEAR(before[i], after[i], 1e-6) << i;
}

// ---- pruning small trees with known answers

TEST(Prune, UnionWithATinyFarSphereIsTheSphere) {
  PruneReport report;
  const Tree t = tree3(op("union", kA, kTiny));
  const Tree p = pruned(t, &report);
  EXPECT_EQ(testing::tree_difference(p, tree3(kA)), "");
  EXPECT_EQ(report.primitives_before, 2);
  EXPECT_EQ(report.operators_before, 1);
  EXPECT_EQ(report.primitives_after, 1);
  EXPECT_EQ(report.operators_after, 0);
}

TEST(Prune, IntersectionWithAContainingBoxIsTheInnerShape) {
  EXPECT_EQ(testing::tree_difference(pruned(tree3(op("intersection", kA, kBox))), tree3(kA)), "");
  // Order does not matter, nor whether the box covers the whole domain (then it is "full").
  EXPECT_EQ(testing::tree_difference(pruned(tree3(op("intersection", kHuge, kA))), tree3(kA)), "");
}

TEST(Prune, DifferenceWithAFarSubtrahendIsTheMinuend) {
  EXPECT_EQ(testing::tree_difference(pruned(tree3(op("difference", kA, kTiny))), tree3(kA)), "");
}

// A tree that amounts to a constant becomes a crisp plane that is exactly that constant.
void expect_constant(const Tree& tree, std::span<const float> at, float value) {
  const Tree p = prune(tree, at, PruneOptions{1e-3, 2});
  ASSERT_EQ(p.nodes.size(), 1u);
  const Node& leaf = p.node(p.root);
  EXPECT_EQ(leaf.shape.type, tree.dim == 3 ? PrimitiveType::kPlane : PrimitiveType::kHalfPlane);
  EXPECT_EQ(leaf.step.kind, StepKind::kCrisp);
  for (float o : occupancy(p, at)) ASSERT_EQ(o, value);
  // Also beyond the points, over the domain.
  for (float o : occupancy(p, random_points(1000, tree.dim, 8))) ASSERT_EQ(o, value);
}

TEST(Prune, ConstantTreesBecomeExactConstants) {
  // a \ huge is empty, and so is the tiny sphere: their union is empty.
  expect_constant(tree3(op("union", op("difference", kA, kHuge), kTiny)), points(), 0.0f);
  expect_constant(tree3(op("union", kA, kHuge)), points(), 1.0f);
  // Points beyond the domain are covered too.
  std::vector<float> wide = points();
  for (float& v : wide) v *= 3.0f;
  expect_constant(tree3(op("union", kA, R"({"type": "box", "size": [20, 20, 20]})")), wide, 1.0f);
}

TEST(Prune, TwoDimensionalTrees) {
  const auto tree2 = [](const std::string& root) {
    return io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2, "root": )" +
                                root + "}");
  };
  const std::string circle = R"({"type": "circle", "radius": 0.5})";
  const std::string far = R"({"type": "circle", "radius": 0.01, "translate": [0.95, -0.95]})";
  const std::string square = R"({"type": "rectangle", "size": [4, 4]})";
  const auto p2 = random_points(20000, 2, 12);
  EXPECT_EQ(testing::tree_difference(prune(tree2(op("union", far, circle)), p2), tree2(circle)),
            "");
  expect_constant(tree2(op("difference", circle, square)), p2, 0.0f);
}

TEST(Prune, FullMinusAShapeIsItsComplement) {
  const std::string sugeno = R"("complement": {"type": "sugeno", "lambda": 0.5}, )";
  const Tree t = tree3(op("intersection", kB, op("difference", kHuge, kA, sugeno)));
  const Tree expected = tree3(op("intersection", kB,
                                 R"({"op": "complement", "complement": {"type": "sugeno",
                                     "lambda": 0.5}, "children": [)" +
                                     kA + "]}"));
  const Tree p = pruned(t);
  EXPECT_EQ(testing::tree_difference(p, expected), "");
  EXPECT_LT(mse(occupancy(p, points()), occupancy(t, points())), 1e-3);
}

TEST(Prune, ATreeWithoutRedundancyIsUnchanged) {
  const Tree t = tree3(op("difference", op("union", kA, kB), kC));
  PruneReport report;
  EXPECT_EQ(testing::tree_difference(pruned(t, &report), t), "");
  EXPECT_EQ(report.primitives_after, 3);
  EXPECT_EQ(report.operators_after, 2);
  // So is one whose operators are of other families and arities.
  const Tree g = tree3(R"({"op": "union", "logic": "godel", "children": [)" + kA + ", " + kB +
                       ", " + kC + "]}");
  EXPECT_EQ(testing::tree_difference(pruned(g), g), "");
}

TEST(Prune, OtherFamiliesAndArities) {
  // A Gödel union of three drops the tiny sphere and keeps a union of two.
  const Tree g = tree3(R"({"op": "union", "logic": "godel", "children": [)" + kA + ", " + kTiny +
                       ", " + kB + "]}");
  EXPECT_EQ(
      testing::tree_difference(pruned(g), tree3(op("union", kA, kB, R"("logic": "godel", )"))), "");
  // A child inside another adds nothing to a union: it is dropped, the other two stay.
  const std::string inner = R"({"type": "sphere", "radius": 0.3, "translate": [-0.2, 0, 0]})";
  const Tree n = tree3(R"({"op": "union", "logic": "godel", "children": [)" + kA + ", " + inner +
                       ", " + kB + "]}");
  EXPECT_EQ(
      testing::tree_difference(pruned(n), tree3(op("union", kA, kB, R"("logic": "godel", )"))), "");
  // The complement of an empty shape is full, and full is the identity of an intersection.
  const Tree c =
      tree3(op("intersection", kA,
               R"({"op": "complement", "complement": "cosine", "children": [)" + kTiny + "]}",
               R"("logic": "yager", "p": 3, )"));
  EXPECT_EQ(testing::tree_difference(pruned(c), tree3(kA)), "");
}

TEST(Prune, KeepsValuesFixedFlagsAndSharedParameters) {
  const std::string a = R"({"type": "sphere", "radius": {"param": "r"}, "translate": [{"value":
      -0.2, "fixed": true}, 0, 0], "sharpness": {"param": "s"}})";
  const std::string tiny = R"({"type": "sphere", "radius": {"param": "r_tiny"}, "translate":
      [0.9, 0.9, 0.9], "sharpness": {"param": "s"}})";
  const Tree t = tree3(op("union", tiny, a),
                       R"({"r": {"value": 0.5, "fixed": true}, "r_tiny": 0.02, "s": 40})");
  const Tree p = pruned(t);
  validate(p, "pruned");
  ASSERT_EQ(p.nodes.size(), 1u);
  // The shared parameters the survivor uses stay shared; the one only the tiny sphere used goes.
  ASSERT_EQ(p.params.size(), 5u);
  const auto r = p.params.find("r"), s = p.params.find("s");
  const auto x = p.params.find("root.translate[0]"), y = p.params.find("root.translate[1]");
  ASSERT_TRUE(r && s && x && y);
  EXPECT_EQ(p.params.find("r_tiny"), std::nullopt);
  EXPECT_TRUE(p.params[*r].shared && p.params[*r].fixed);
  EXPECT_EQ(p.params[*r].value, 0.5);
  EXPECT_TRUE(p.params[*s].shared && !p.params[*s].fixed);
  EXPECT_EQ(p.params[*s].value, 40.0);
  EXPECT_TRUE(p.params[*x].fixed && !p.params[*x].shared);
  EXPECT_EQ(p.params[*x].value, -0.2);
  EXPECT_FALSE(p.params[*y].fixed);
  EXPECT_EQ(p.node(p.root).intrinsic[0], *r);
}

TEST(Prune, RejectsUnifiedOperatorsAndBadPoints) {
  const Tree u = tree3(op("unified", kA, kB, R"("c": [1, 0, 0, 0], )"));
  EXPECT_THROW(pruned(u), Error);
  const Tree t = tree3(op("union", kA, kB));
  EXPECT_THROW(prune(t, std::vector<float>(7)), InputError);
  EXPECT_THROW(prune(t, std::vector<float>()), InputError);
  EXPECT_THROW(prune(t, points(), PruneOptions{-1.0, 1}), InputError);
  EXPECT_THROW(prune(t, points(), PruneOptions{1e-3, 1, -1}), InputError);
}

// ---- pruning to a number of primitives

// Radii of the spheres of a pruned tree, sorted.
std::vector<double> sphere_radii(const Tree& t) {
  std::vector<double> out;
  for (const Node& n : t.nodes) {
    if (n.kind == NodeKind::kPrimitive) out.push_back(t.params[n.intrinsic[0]].value);
  }
  std::ranges::sort(out);
  return out;
}

// ((s1 | s2) | (s3 | s4)) of four disjoint spheres: kept to k primitives, the k largest stay,
// whether the unions are product logic (edits judged by one sweep) or Gödel's (edits evaluated
// one by one).
TEST(PruneToSize, KeepsTheLargestOfDisjointSpheres) {
  const auto sphere = [](double r, double x) {
    return R"({"type": "sphere", "radius": )" + std::to_string(r) + R"(, "translate": [)" +
           std::to_string(x) + R"(, 0, 0], "sharpness": 200})";
  };
  for (const std::string logic : {"", R"("logic": "godel", )"}) {
    const Tree t = tree3(op("union", op("union", sphere(0.2, -0.7), sphere(0.12, -0.2), logic),
                            op("union", sphere(0.15, 0.2), sphere(0.25, 0.65), logic), logic));
    for (int k = 1; k <= 4; ++k) {
      PruneReport report;
      const Tree p = prune(t, points(), PruneOptions{1e-6, 2, k}, &report);
      validate(p, "pruned");
      std::vector<double> want = {0.12, 0.15, 0.2, 0.25};
      want.erase(want.begin(), want.end() - k);
      EXPECT_EQ(sphere_radii(p), want) << "k = " << k << (logic.empty() ? "" : ", Godel");
      EXPECT_EQ(report.primitives_after, k);
    }
  }
}

// A subtracted part goes with what it was cut from: of (a \ b) | c, at one primitive the
// closest tree is c alone or a alone, never b.
TEST(PruneToSize, NeverKeepsOnlyASubtrahend) {
  const Tree t = tree3(op("union", op("difference", kA, kC), kB));
  const Tree p = prune(t, points(), PruneOptions{1e-6, 2, 1});
  ASSERT_EQ(count(p).primitives, 1);
  EXPECT_NE(p.node(p.root).shape.type, PrimitiveType::kCylinder);
}

// Random full trees: the limit is met, the result is a valid binary tree that reads back, and a
// limit the threshold already meets changes nothing.
TEST(PruneToSize, FullTreesMeetTheLimit) {
  FullTreeOptions o;
  o.leaves = 32;
  o.seed = 3;
  for (OperatorMode ops : {OperatorMode::kProduct, OperatorMode::kGodel}) {
    o.ops = ops;
    const Tree t = make_full_binary_tree(o);
    const std::vector<float> pts = random_points(16384, 3, 5);
    const Tree plain = prune(t, pts, PruneOptions{1e-3, 2});
    const int kept = count(plain).primitives;
    ASSERT_GT(kept, 8);
    EXPECT_EQ(testing::tree_difference(prune(t, pts, PruneOptions{1e-3, 2, kept}), plain), "");
    for (int k : {kept - 1, 8, 3, 1}) {
      const Tree p = prune(t, pts, PruneOptions{1e-3, 2, k});
      validate(p, "pruned");
      const TreeCounts c = count(p);
      EXPECT_LE(c.primitives, k);
      EXPECT_GE(c.primitives, 1);
      EXPECT_EQ(testing::tree_difference(io::read_tree_string(io::write_tree_string(p)), p), "");
    }
  }
}

// ---- full binary trees

struct FullCase {
  PrimitiveType family;
  OperatorMode ops;
  std::uint64_t seed;
  bool all_unions;  // replace every operator by a union
};

class PruneFullTree : public ::testing::TestWithParam<FullCase> {};

TEST_P(PruneFullTree, StaysCloseToTheOriginalWithFewerNodes) {
  FullTreeOptions o;
  o.leaves = 64;
  o.family = GetParam().family;
  o.ops = GetParam().ops;
  o.seed = GetParam().seed;
  Tree t = make_full_binary_tree(o);
  for (Node& n : t.nodes) {
    if (GetParam().all_unions && n.kind == NodeKind::kOperator) n.op = OpKind::kUnion;
  }
  const double threshold = 1e-3;
  PruneReport report;
  const Tree p = prune(t, random_points(65536, 3, 1), PruneOptions{threshold, 2}, &report);
  validate(p, "pruned");

  const TreeCounts before = count(t), after = count(p);
  EXPECT_EQ(report.primitives_before, before.primitives);
  EXPECT_EQ(report.operators_before, before.operators);
  EXPECT_EQ(report.primitives_after, after.primitives);
  EXPECT_EQ(report.operators_after, after.operators);
  EXPECT_EQ(after.operators + 1, after.primitives);  // still a binary tree
  EXPECT_LT(after.primitives, before.primitives);
  if (GetParam().all_unions) {
    EXPECT_GT(after.primitives, 1);
  }
  EXPECT_EQ(p.nodes.size(), static_cast<std::size_t>(after.primitives + after.operators));

  // Fresh points. Each removal is within the threshold of the node it replaces, but the
  // changes of many removals in different places add up: the union of 64 boxes loses 26 of
  // them at 4.4 times the threshold in all.
  const auto fresh = random_points(100000, 3, 2);
  const double e = mse(occupancy(p, fresh), occupancy(t, fresh));
  EXPECT_LT(e, 5 * threshold) << after.primitives << " primitives left";

  // The written tree reads back identically and is valid.
  const Tree back = io::read_tree_string(io::write_tree_string(p));
  EXPECT_EQ(testing::tree_difference(back, p), "");
}

// Random operators over quadrics (fuzzy everywhere at sharpness 1) leave part of the tree;
// over spheres they mostly cancel out to an empty tree; a union of spheres keeps those not
// inside others.
INSTANTIATE_TEST_SUITE_P(
    Trees, PruneFullTree,
    ::testing::Values(FullCase{PrimitiveType::kQuadric3, OperatorMode::kProduct, 1, false},
                      FullCase{PrimitiveType::kQuadric3, OperatorMode::kGodel, 1, false},
                      FullCase{PrimitiveType::kSphere, OperatorMode::kProduct, 2, false},
                      FullCase{PrimitiveType::kSphere, OperatorMode::kProduct, 3, true},
                      FullCase{PrimitiveType::kBox, OperatorMode::kGodel, 4, true}));

}  // namespace
}  // namespace fuzzycsg
