// The local optimizer brings perturbed primitives back onto their targets, and prunes.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "fuzzycsg/trace/optimize.hpp"

namespace fuzzycsg::trace {
namespace {

Bitmap render(const CsgTree& t, int width, int height) {
  return TreeEvaluator(t, width, height).result();
}

struct Case {
  const char* name;
  Primitive target, start;
};

TEST(TraceOptimize, PerturbedPrimitivesReturnToTheTarget) {
  const int n = 96;
  const std::vector<Case> cases = {
      {"rectangle shifted",
       {Shape::kRectangle, 48, 40, 1, 40, 24, 0},
       {Shape::kRectangle, 55, 46, 1, 40, 24, 0}},
      {"rectangle resized",
       {Shape::kRectangle, 48, 40, 1, 40, 24, 0},
       {Shape::kRectangle, 48, 40, 1, 30, 34, 0}},
      {"rectangle rotated",
       {Shape::kRectangle, 48, 48, 1, 50, 20, 30},
       {Shape::kRectangle, 48, 48, 1, 50, 20, 22}},
      {"rectangle all three",
       {Shape::kRectangle, 50, 45, 1, 44, 26, 15},
       {Shape::kRectangle, 44, 50, 1, 36, 30, 8}},
      {"circle shifted and resized", {Shape::kCircle, 45, 50, 25}, {Shape::kCircle, 53, 43, 18}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Bitmap target = render(CsgTree(c.target), n, n);
    TreeEvaluator ev(CsgTree(c.start), n, n);
    const Score before = score(ev.result(), target, 1);
    const LocalResult r = optimize_locally(ev, target);
    EXPECT_LT(r.score.total(), before.total());
    EXPECT_EQ(r.score.primitives, 1);
    const Primitive& p = ev.tree().primitive(ev.tree().root());
    // Within a few pixels (1% of the shape's area for the circle's sub-pixel placement).
    EXPECT_LE(r.score.mismatch(), std::max<std::int64_t>(6, target.count() / 100))
        << "from " << before.mismatch() << " to (" << p.x << ", " << p.y << ") r " << p.r << " w "
        << p.w << " h " << p.h << " theta " << p.theta << " after " << r.iterations;
    EXPECT_EQ(r.score.mismatch(), score(ev.result(), target, 1).mismatch());
    EXPECT_GT(ev.counters().trees_evaluated, 1u);
  }
}

TEST(TraceOptimize, TwoPrimitivesAndADifference) {
  // An L shape as a rectangle less a rectangle, started off by a few pixels.
  const int n = 80;
  CsgTree target;
  {
    const int a = target.add_leaf({Shape::kRectangle, 40, 40, 1, 40, 40, 0});
    const int b = target.add_leaf({Shape::kRectangle, 50, 30, 1, 20, 20, 0});
    target.add_op(Op::kDifference, a, b);
  }
  CsgTree start;
  {
    const int a = start.add_leaf({Shape::kRectangle, 43, 38, 1, 36, 42, 0});
    // The subtracted rectangle overhangs the other's corner, as it may in a solution (an
    // overhang does not count); it must come down to the notch's inner edges.
    const int b = start.add_leaf({Shape::kRectangle, 53, 27, 1, 24, 22, 0});
    start.add_op(Op::kDifference, a, b);
  }
  const Bitmap t = render(target, n, n);
  TreeEvaluator ev(start, n, n);
  const Score before = score(ev.result(), t, 2);
  const LocalResult r = optimize_locally(ev, t);
  EXPECT_EQ(r.score.primitives, 2);
  EXPECT_LT(r.score.mismatch(), before.mismatch() / 4);
  std::string where;
  for (const int leaf : ev.tree().leaves()) {
    const Primitive& p = ev.tree().primitive(leaf);
    where += " (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ") " + std::to_string(p.w) +
             " x " + std::to_string(p.h) + " at " + std::to_string(p.theta);
  }
  EXPECT_LE(r.score.mismatch(), 20) << where;
}

TEST(TraceOptimize, PrunesPrimitivesThatDoNotContribute) {
  const int n = 64;
  CsgTree t;
  const int a = t.add_leaf({Shape::kCircle, 32, 32, 15});
  const int b = t.add_leaf({Shape::kCircle, 32, 32, 5});  // inside a: contributes nothing
  t.add_op(Op::kUnion, a, b);
  const Bitmap target = render(CsgTree(Primitive{Shape::kCircle, 32, 32, 15}), n, n);
  TreeEvaluator ev(t, n, n);
  LocalOptions o;
  o.max_iterations = 0;  // pruning only
  const LocalResult r = optimize_locally(ev, target, o);
  EXPECT_EQ(r.pruned, 1);
  EXPECT_EQ(r.score.primitives, 1);
  EXPECT_EQ(r.score.mismatch(), 0);
  EXPECT_DOUBLE_EQ(r.score.total(), 25.0);
}

TEST(TraceOptimize, NeverWorsensARandomTree) {
  Rng rng(31);
  const int n = 64;
  const Bitmap target = render(CsgTree(Primitive{Shape::kRectangle, 30, 34, 1, 30, 18, 20}), n, n);
  for (int trial = 0; trial < 5; ++trial) {
    TreeEvaluator ev(random_tree(norm_count(5, 2, rng), n, n, rng), n, n);
    const Score before = score(ev.result(), target, ev.tree().primitive_count());
    const LocalResult r = optimize_locally(ev, target);
    EXPECT_LE(r.score.total(), before.total());
    EXPECT_LE(r.score.mismatch(), before.mismatch());
  }
}

TEST(TraceOptimize, LowersTheScoreOfRandomTreesOnAGlyph) {
  const Bitmap target = read_bitmap(std::filesystem::path(FUZZYCSG_TEST_DATA_DIR) / "glyphs" /
                                    "DejaVuSans-Bold_U0050_P.png");
  Rng rng(32);
  for (int trial = 0; trial < 3; ++trial) {
    TreeEvaluator ev(random_tree(norm_count(10, 2, rng), target.width(), target.height(), rng),
                     target.width(), target.height());
    const Score before = score(ev.result(), target, ev.tree().primitive_count());
    const LocalResult r = optimize_locally(ev, target);
    EXPECT_LT(r.score.total(), before.total());
    EXPECT_EQ(r.score.primitives, ev.tree().primitive_count());
    EXPECT_EQ(r.score.mismatch(), score(ev.result(), target, 0).mismatch());
    // The evaluator's bitmap is that of its tree.
    EXPECT_EQ(ev.result(), TreeEvaluator(ev.tree(), target.width(), target.height()).result());
  }
}

}  // namespace
}  // namespace fuzzycsg::trace
