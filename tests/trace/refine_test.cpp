// Trees of the tracer read back from the project's trees, and refinement by fuzzy gradient
// descent: never worse, and better where the crisp local optimizer is stuck.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/convert.hpp"
#include "fuzzycsg/trace/evaluate.hpp"
#include "fuzzycsg/trace/optimize.hpp"
#include "fuzzycsg/trace/refine.hpp"

namespace fuzzycsg::trace {
namespace {

// Adam steps on a glyph: fewer under the sanitizers, where the evaluator is ten times slower.
#if defined(__SANITIZE_ADDRESS__)
constexpr int kGlyphSteps = 30;
#else
constexpr int kGlyphSteps = 150;
#endif

Bitmap glyph(const char* name) {
  return read_bitmap(std::filesystem::path(FUZZYCSG_TEST_DATA_DIR) / "glyphs" / name);
}

double crisp_score(const CsgTree& t, const Bitmap& target, double k = 25.0) {
  return score(TreeEvaluator(t, target.width(), target.height()).result(), target,
               t.primitive_count(), k)
      .total();
}

// Structure and shapes equal (the fields that define each primitive) within eps.
void expect_same(const CsgTree& a, const CsgTree& b, double eps) {
  const std::vector<int> pa = a.post_order(), pb = b.post_order();
  ASSERT_EQ(pa.size(), pb.size());
  for (std::size_t i = 0; i < pa.size(); ++i) {
    const Node& x = a.node(pa[i]);
    const Node& y = b.node(pb[i]);
    ASSERT_EQ(x.leaf, y.leaf) << "node " << i;
    if (!x.leaf) {
      EXPECT_EQ(x.op, y.op) << "node " << i;
      continue;
    }
    const Primitive &p = x.prim, &q = y.prim;
    ASSERT_EQ(p.shape, q.shape) << "node " << i;
    EXPECT_NEAR(p.x, q.x, eps);
    EXPECT_NEAR(p.y, q.y, eps);
    if (p.shape == Shape::kCircle) {
      EXPECT_NEAR(p.r, q.r, eps);
    } else {
      EXPECT_NEAR(p.w, q.w, eps);
      EXPECT_NEAR(p.h, q.h, eps);
      EXPECT_NEAR(p.theta, q.theta, eps);
    }
  }
}

TEST(TraceFromTree, RoundTripsEveryPrimitiveAndOperator) {
  Rng rng(51);
  for (int trial = 0; trial < 40; ++trial) {
    const int width = 8 + static_cast<int>(rng() % 200), height = 8 + static_cast<int>(rng() % 150);
    const CsgTree t = random_tree(1 + static_cast<int>(rng() % 12), width, height, rng);
    for (const double sharpness : {0.0, 3.0}) {
      const Tree tree = to_tree(t, width, height, sharpness);
      const CsgTree back = from_tree(tree, width, height);
      expect_same(t, back, 1e-9);
      EXPECT_EQ(back.leaves().size(), t.leaves().size());
    }
  }
}

TEST(TraceFromTree, SoftLeavesHaveAFixedSharpness) {
  CsgTree t;
  t.add_op(Op::kDifference, t.add_leaf({Shape::kRectangle, 20, 20, 1, 30, 10, 15}),
           t.add_leaf({Shape::kCircle, 25, 22, 6}));
  const Tree tree = to_tree(t, 40, 40, 2.5);
  int sharpness = 0;
  for (const fuzzycsg::Node& n : tree.nodes) {
    if (n.kind != NodeKind::kPrimitive) continue;
    ASSERT_EQ(n.step.kind, StepKind::kSigmoid);
    ASSERT_TRUE(n.step.param);
    EXPECT_TRUE(tree.params[*n.step.param].fixed);
    EXPECT_EQ(tree.params[*n.step.param].value, 2.5);
    ++sharpness;
  }
  EXPECT_EQ(sharpness, 2);
  // Positions, sizes and the angle are free: 2 + 1 for the circle, 2 + 2 + 1 for the rectangle.
  EXPECT_EQ(count(tree).free_parameters, 8);
  EXPECT_THROW(to_tree(t, 40, 40, -1), InputError);
}

TEST(TraceFromTree, ReadsWiderOperatorsAndScales) {
  const Tree tree = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
    "root": {"op": "union", "logic": "godel", "children": [
      {"type": "circle", "radius": 2, "translate": [10, 30], "scale": 1.5},
      {"type": "rectangle", "size": [4, 6], "translate": [20, 25], "rotate": 30},
      {"type": "circle", "radius": 3, "translate": [5, 5], "step": "crisp"}]}})",
                                         "test");
  const CsgTree t = from_tree(tree, 40, 40);
  ASSERT_EQ(t.primitive_count(), 3);
  const Node& root = t.node(t.root());
  ASSERT_FALSE(root.leaf);
  EXPECT_EQ(root.op, Op::kUnion);
  EXPECT_FALSE(t.node(root.children[0]).leaf);  // (a u b) u c
  const std::vector<int> leaves = t.leaves();
  EXPECT_DOUBLE_EQ(t.primitive(leaves[0]).r, 3.0);
  EXPECT_DOUBLE_EQ(t.primitive(leaves[0]).y, 10.0);
  EXPECT_EQ(t.primitive(leaves[1]).shape, Shape::kRectangle);
  EXPECT_DOUBLE_EQ(t.primitive(leaves[1]).theta, -30.0);
  EXPECT_DOUBLE_EQ(t.primitive(leaves[2]).x, 5.0);
}

TEST(TraceFromTree, RefusesWhatTheTracerCannotHold) {
  const auto read = [](const std::string& root, int dim = 2) {
    return io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": )" +
                                    std::to_string(dim) + R"(, "root": )" + root + "}",
                                "test");
  };
  EXPECT_THROW(from_tree(read(R"({"type": "ellipse", "radii": [1, 2]})"), 10, 10), InputError);
  EXPECT_THROW(
      from_tree(read(R"({"op": "complement", "children": [{"type": "circle", "radius": 1}]})"), 10,
                10),
      InputError);
  EXPECT_THROW(from_tree(read(R"({"type": "sphere", "radius": 1})", 3), 10, 10), InputError);
  try {
    from_tree(read(R"({"op": "union", "children": [{"type": "circle", "radius": 1},
                       {"type": "half-plane", "normal": [1, 0], "offset": 0}]})"),
              10, 10);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("root.children[1]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("half-plane"), std::string::npos) << e.what();
  }
}

TEST(TraceRefine, NeverMakesTheCrispScoreWorse) {
  Rng rng(52);
  const int n = 64;
  CsgTree shape;
  shape.add_op(Op::kDifference, shape.add_leaf({Shape::kRectangle, 30, 34, 1, 36, 20, 20}),
               shape.add_leaf({Shape::kCircle, 40, 30, 7}));
  const Bitmap target = TreeEvaluator(shape, n, n).result();
  RefineOptions o;
  o.iterations = 40;
  o.threads = 1;
  for (int trial = 0; trial < 5; ++trial) {
    const CsgTree t = random_tree(norm_count(4, 2, rng), n, n, rng);
    const RefineResult r = refine(t, target, o);
    EXPECT_DOUBLE_EQ(r.before.total(), crisp_score(t, target));
    EXPECT_LE(r.after.total(), r.before.total());
    EXPECT_DOUBLE_EQ(r.after.total(), crisp_score(r.tree, target));
    EXPECT_EQ(r.improved, r.after.total() < r.before.total());
    EXPECT_EQ(r.iterations, 40);
    EXPECT_EQ(r.loss.size(), 40u);
    if (!r.improved) expect_same(r.tree, t, 0);
  }
  // No steps: the input back.
  o.iterations = 0;
  const CsgTree t = random_tree(3, n, n, rng);
  const RefineResult r = refine(t, target, o);
  EXPECT_FALSE(r.improved);
  expect_same(r.tree, t, 0);
  o.iterations = -1;
  EXPECT_THROW(refine(t, target, o), InputError);
}

TEST(TraceRefine, KeepsTheInputsNodeIds) {
  // A tree with an unused slot (an edit's leftover): the result has the same nodes, only the
  // primitives' shapes moved; a circle's unused rectangle fields stay.
  const int n = 48;
  const Bitmap target =
      TreeEvaluator(CsgTree(Primitive{Shape::kRectangle, 24, 22, 1, 20, 14, 10}), n, n).result();
  CsgTree t;
  const int a = t.add_leaf({Shape::kRectangle, 26, 24, 1, 18, 12, 4});
  const int b = t.add_leaf({Shape::kCircle, 10, 10, 3, 7, 9, 33});
  const int c = t.add_leaf({Shape::kCircle, 40, 40, 2});
  t.add_op(Op::kUnion, t.add_op(Op::kUnion, a, b), c);
  ASSERT_TRUE(t.cut_subtree(c));
  RefineOptions o;
  o.iterations = 40;
  o.threads = 1;
  const RefineResult r = refine(t, target, o);
  ASSERT_TRUE(r.improved);
  ASSERT_EQ(r.tree.nodes().size(), t.nodes().size());
  EXPECT_EQ(r.tree.root(), t.root());
  EXPECT_EQ(r.tree.leaves(), t.leaves());
  EXPECT_FALSE(r.tree.node(c).alive);
  const Primitive& circle = r.tree.primitive(b);
  EXPECT_EQ(circle.w, 7);
  EXPECT_EQ(circle.h, 9);
  EXPECT_EQ(circle.theta, 33);
  EXPECT_LT(r.after.mismatch(), r.before.mismatch());
}

// A good tree for a glyph: the best of a few random trees, locally optimized.
CsgTree good_tree(const Bitmap& target, int tries) {
  CsgTree best;
  double best_score = 0;
  for (int seed = 1; seed <= tries; ++seed) {
    Rng rng(static_cast<std::uint64_t>(seed));
    TreeEvaluator ev(random_tree(norm_count(10, 2, rng), target.width(), target.height(), rng),
                     target.width(), target.height());
    const LocalResult r = optimize_locally(ev, target);
    if (best.empty() || r.score.total() < best_score) {
      best = ev.tree();
      best_score = r.score.total();
    }
  }
  best.compact();
  return best;
}

// The glyph P and a good tree for it, made once for the tests below.
struct GlyphP {
  Bitmap target = glyph("DejaVuSans-Bold_U0050_P.png");
  CsgTree good = good_tree(target, 3);
};
const GlyphP& glyph_p() {
  static const GlyphP g;
  return g;
}

TEST(TraceRefine, BringsAShiftedGlyphTreeBack) {
  const Bitmap& target = glyph_p().target;
  const CsgTree& good = glyph_p().good;
  CsgTree shifted = good;
  for (const int leaf : shifted.leaves()) {
    shifted.primitive(leaf).x += 2.5;
    shifted.primitive(leaf).y -= 2.0;
  }
  RefineOptions o;
  o.iterations = kGlyphSteps;
  const RefineResult r = refine(shifted, target, o);
  EXPECT_TRUE(r.improved);
  EXPECT_LT(r.after.total(), r.before.total());
  // Most of the way back: the shift costs more than the good tree's whole mismatch.
  EXPECT_LT(r.after.mismatch() - crisp_score(good, target, 0),
            (r.before.mismatch() - crisp_score(good, target, 0)) / 2)
      << "good " << crisp_score(good, target, 0) << ", shifted " << r.before.mismatch()
      << ", refined " << r.after.mismatch();
  EXPECT_EQ(r.after.primitives, good.primitive_count());
}

TEST(TraceRefine, ImprovesWhereTheLocalOptimizerIsStuck) {
  // The local optimizer's result is a fixed point of the local optimizer: it moves one
  // coordinate of one primitive at a time by fixed steps and needs each step to improve.
  // Gradient descent moves every parameter at once, by any amount.
  const Bitmap& target = glyph_p().target;
  const CsgTree& good = glyph_p().good;
  TreeEvaluator ev(good, target.width(), target.height());
  LocalOptions lo;
  lo.prune = false;
  const LocalResult again = optimize_locally(ev, target, lo);
  ASSERT_EQ(again.score.total(), crisp_score(good, target));  // stuck
  RefineOptions o;
  o.iterations = kGlyphSteps;
  const RefineResult r = refine(good, target, o);
  EXPECT_TRUE(r.improved);
  EXPECT_LT(r.after.total(), r.before.total());
}

}  // namespace
}  // namespace fuzzycsg::trace
