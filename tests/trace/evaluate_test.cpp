// Scan conversion against the point test, incremental against full evaluation, edits, score.
#include <gtest/gtest.h>

#include <cmath>

#include "fuzzycsg/trace/evaluate.hpp"

namespace fuzzycsg::trace {
namespace {

// Primitives anywhere around a width x height bitmap, partly or wholly outside it too.
Primitive wild_primitive(int width, int height, Rng& rng) {
  const auto u = [&](double lo, double hi) { return lo + (hi - lo) * uniform01(rng); };
  Primitive p;
  p.shape = (rng() & 1) ? Shape::kRectangle : Shape::kCircle;
  p.x = u(-0.5 * width, 1.5 * width);
  p.y = u(-0.5 * height, 1.5 * height);
  p.r = u(0.2, 0.6 * width);
  p.w = u(0.2, 1.2 * width);
  p.h = u(0.2, 1.2 * height);
  const double r = uniform01(rng);
  // Some axis-aligned and right angles, and centres on pixel centres and corners.
  p.theta = r < 0.1 ? 0.0 : r < 0.2 ? 90.0 * static_cast<double>(rng() % 4) : u(0, 360);
  if (uniform01(rng) < 0.2) {
    p.x = std::round(p.x) + ((rng() & 1) ? 0.5 : 0.0);
    p.y = std::round(p.y) + ((rng() & 1) ? 0.5 : 0.0);
  }
  return p;
}

Bitmap direct(const Primitive& p, int width, int height) {
  Bitmap b(width, height);
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      if (contains(p, i + 0.5, j + 0.5)) b.set(i, j);
    }
  }
  return b;
}

Bitmap direct(const CsgTree& t, int id, int width, int height) {
  const Node& n = t.node(id);
  if (n.leaf) return direct(n.prim, width, height);
  const Bitmap a = direct(t, n.children[0], width, height);
  const Bitmap b = direct(t, n.children[1], width, height);
  Bitmap out(width, height);
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const bool x = a.get(i, j), y = b.get(i, j);
      out.set(i, j,
              n.op == Op::kUnion          ? (x || y)
              : n.op == Op::kIntersection ? (x && y)
                                          : (x && !y));
    }
  }
  return out;
}

TEST(TraceScan, MatchesThePointTestForRandomPrimitives) {
  Rng rng(7);
  for (int trial = 0; trial < 3000; ++trial) {
    const int width = 1 + static_cast<int>(rng() % 150), height = 1 + static_cast<int>(rng() % 90);
    const Primitive p = wild_primitive(width, height, rng);
    Bitmap b(width, height);
    // Garbage outside the primitive's rows survives; inside them it is cleared.
    const PixelBox box = scan_convert(p, b);
    const Bitmap want = direct(p, width, height);
    ASSERT_EQ(b, want) << "trial " << trial << " shape " << static_cast<int>(p.shape) << " at ("
                       << p.x << ", " << p.y << ") r " << p.r << " w " << p.w << " h " << p.h
                       << " theta " << p.theta;
    for (int j = 0; j < height; ++j) {
      for (int i = 0; i < width; ++i) {
        if (want.get(i, j)) {
          ASSERT_TRUE(i >= box.col0 && i < box.col1 && j >= box.row0 && j < box.row1);
        }
      }
    }
  }
}

TEST(TraceScan, SmallAndExactCases) {
  Bitmap b(8, 8);
  // A circle of radius 1 at a pixel corner covers the 4 pixels around it (their centres are
  // at distance sqrt(0.5)); at a pixel centre, r = 1 covers only that pixel (the 4 neighbours
  // are at distance exactly 1, not inside).
  Primitive c{Shape::kCircle, 4.0, 4.0, 1.0};
  scan_convert(c, b);
  EXPECT_EQ(b.count(), 4);
  c.x = c.y = 4.5;
  scan_convert(c, b);
  EXPECT_EQ(b.count(), 1);
  EXPECT_TRUE(b.get(4, 4));
  // A 4 x 2 rectangle on pixel edges, and the same turned by 90 degrees.
  Primitive r{Shape::kRectangle, 4.0, 4.0, 1.0, 4.0, 2.0, 0.0};
  scan_convert(r, b);
  EXPECT_EQ(b.count(), 8);
  EXPECT_TRUE(b.get(2, 3));
  EXPECT_TRUE(b.get(5, 4));
  EXPECT_FALSE(b.get(6, 4));
  r.theta = 90;
  scan_convert(r, b);
  EXPECT_EQ(b.count(), 8);
  EXPECT_TRUE(b.get(3, 2));
  EXPECT_FALSE(b.get(2, 3));
  // Wholly outside.
  r.x = -50;
  scan_convert(r, b);
  EXPECT_EQ(b.count(), 0);
}

TEST(TraceEval, FullEvaluationMatchesTheDirectTree) {
  Rng rng(11);
  for (int trial = 0; trial < 60; ++trial) {
    const int width = 20 + static_cast<int>(rng() % 100),
              height = 20 + static_cast<int>(rng() % 70);
    const CsgTree t = random_tree(1 + static_cast<int>(rng() % 12), width, height, rng);
    TreeEvaluator ev(t, width, height);
    ASSERT_EQ(ev.result(), direct(t, t.root(), width, height)) << trial;
    EXPECT_EQ(ev.counters().trees_evaluated, 1u);
    EXPECT_EQ(ev.counters().primitives_scanned, static_cast<std::uint64_t>(t.primitive_count()));
  }
}

TEST(TraceEval, IncrementalEqualsFullAfterRandomEdits) {
  Rng rng(12);
  for (int trial = 0; trial < 20; ++trial) {
    const int width = 30 + static_cast<int>(rng() % 140),
              height = 30 + static_cast<int>(rng() % 100);
    CsgTree t = random_tree(2 + static_cast<int>(rng() % 12), width, height, rng);
    TreeEvaluator inc(t, width, height);
    const std::vector<int> leaves = t.leaves();
    for (int edit = 0; edit < 200; ++edit) {
      const int leaf = leaves[rng() % leaves.size()];
      Primitive p = inc.tree().primitive(leaf);
      switch (rng() % 5) {
        case 0:
          p = wild_primitive(width, height, rng);
          break;
        case 1:
          p.x += uniform01(rng) * 6 - 3;
          p.y += uniform01(rng) * 6 - 3;
          break;
        case 2:
          p.r = std::max(0.3, p.r + uniform01(rng) * 6 - 3);
          p.w = std::max(0.3, p.w + uniform01(rng) * 6 - 3);
          break;
        case 3:
          p.theta += uniform01(rng) * 20 - 10;
          break;
        default:
          p.shape = p.shape == Shape::kCircle ? Shape::kRectangle : Shape::kCircle;
          break;
      }
      inc.update_primitive(leaf, p);
      t.primitive(leaf) = p;
      if (edit % 10 == 0 || edit == 199) {
        const TreeEvaluator full(t, width, height);
        ASSERT_EQ(inc.result(), full.result()) << "trial " << trial << " edit " << edit;
        for (const int n : t.post_order()) ASSERT_EQ(inc.mask(n), full.mask(n));
      }
    }
    EXPECT_EQ(inc.counters().trees_evaluated, 201u);
  }
}

TEST(TraceTree, StructuralEdits) {
  Rng rng(13);
  const int width = 64, height = 48;
  for (int trial = 0; trial < 200; ++trial) {
    CsgTree t = random_tree(1 + static_cast<int>(rng() % 10), width, height, rng);
    const int before = t.primitive_count();
    const std::vector<int> order = t.post_order();
    const int at = order[rng() % order.size()];
    const int at_count = t.primitive_count(at);
    const CsgTree sub = random_tree(1 + static_cast<int>(rng() % 4), width, height, rng);
    switch (rng() % 4) {
      case 0:
        t.replace_subtree(at, sub);
        EXPECT_EQ(t.primitive_count(), before - at_count + sub.primitive_count());
        break;
      case 1:
        if (t.cut_subtree(at)) {
          EXPECT_EQ(t.primitive_count(), before - at_count);
        } else {
          EXPECT_EQ(at, t.root());
        }
        break;
      case 2:
        t.add_subtree(at, (rng() & 1) ? Op::kUnion : Op::kDifference, sub);
        EXPECT_EQ(t.primitive_count(), before + sub.primitive_count());
        break;
      default: {
        const std::vector<int> leaves = t.leaves();
        const int leaf = leaves[rng() % leaves.size()];
        const Shape s = t.primitive(leaf).shape;
        t.toggle_shape(leaf);
        EXPECT_NE(t.primitive(leaf).shape, s);
        break;
      }
    }
    // Parent links agree with child links; the evaluation is that of the compacted tree.
    for (const int n : t.post_order()) {
      const Node& node = t.node(n);
      ASSERT_TRUE(node.alive);
      if (!node.leaf) {
        for (const int c : node.children) ASSERT_EQ(t.node(c).parent, n);
      }
    }
    ASSERT_EQ(t.node(t.root()).parent, -1);
    CsgTree compact = t;
    compact.compact();
    EXPECT_EQ(static_cast<int>(compact.nodes().size()), 2 * compact.primitive_count() - 1);
    EXPECT_EQ(TreeEvaluator(t, width, height).result(),
              TreeEvaluator(compact, width, height).result());
  }
}

TEST(TraceTree, RandomTreesFollowThePaperRanges) {
  Rng rng(14);
  const int width = 128, height = 96;
  int rectangles = 0, total = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const CsgTree t = random_tree(norm_count(10.0, 2.0, rng), width, height, rng);
    for (const int leaf : t.leaves()) {
      const Primitive& p = t.primitive(leaf);
      ++total;
      rectangles += p.shape == Shape::kRectangle;
      EXPECT_GE(p.x, width / 4.0);
      EXPECT_LE(p.x, 3 * width / 4.0);
      EXPECT_GE(p.y, height / 4.0);
      EXPECT_LE(p.y, 3 * height / 4.0);
      EXPECT_GE(p.r, 1.0);
      EXPECT_LE(p.r, 48.0);
      EXPECT_GE(p.w, 1.0);
      EXPECT_LE(p.w, 64.0);
      EXPECT_GE(p.h, 1.0);
      EXPECT_LE(p.h, 48.0);
      EXPECT_GE(p.theta, 0.0);
      EXPECT_LT(p.theta, 360.0);
    }
  }
  EXPECT_NEAR(static_cast<double>(rectangles) / total, 0.5, 0.05);
  EXPECT_NEAR(static_cast<double>(total) / 200, 10.0, 0.5);
  // Same seed, same tree.
  Rng a(99), b(99);
  const CsgTree ta = random_tree(7, width, height, a), tb = random_tree(7, width, height, b);
  EXPECT_EQ(TreeEvaluator(ta, width, height).result(), TreeEvaluator(tb, width, height).result());
}

TEST(TraceScore, HandMadeCases) {
  Bitmap target(10, 10), tree(10, 10);
  for (int j = 2; j < 6; ++j) target.set_span(j, 2, 6);  // 16 pixels
  EXPECT_EQ(score(tree, target, 0).uncovered, 16);
  EXPECT_EQ(score(tree, target, 0).excess, 0);
  EXPECT_DOUBLE_EQ(score(tree, target, 2).total(), 16 + 50);
  for (int j = 3; j < 7; ++j) tree.set_span(j, 3, 7);  // overlaps 9 pixels
  const Score s = score(tree, target, 1, 10.0);
  EXPECT_EQ(s.excess, 7);
  EXPECT_EQ(s.uncovered, 7);
  EXPECT_DOUBLE_EQ(s.total(), 24.0);
  const Score same = score(target, target, 1);
  EXPECT_EQ(same.mismatch(), 0);
  EXPECT_DOUBLE_EQ(same.total(), 25.0);
  // Local counts and centroids.
  const LocalMismatch lm = local_mismatch(tree, target, PixelBox{0, 0, 10, 10});
  EXPECT_EQ(lm.excess, 7);
  EXPECT_EQ(lm.uncovered, 7);
  const LocalMismatch corner = local_mismatch(tree, target, PixelBox{0, 0, 3, 3});
  EXPECT_EQ(corner.excess, 0);
  EXPECT_EQ(corner.uncovered, 1);
  EXPECT_DOUBLE_EQ(corner.uncovered_x, 2.5);
  EXPECT_DOUBLE_EQ(corner.uncovered_y, 2.5);
}

TEST(TraceScore, WideBitmapsAcrossWords) {
  Bitmap target(200, 3), tree(200, 3);
  target.set_span(1, 60, 140);
  tree.set_span(1, 100, 190);
  const Score s = score(tree, target, 0);
  EXPECT_EQ(s.excess, 50);
  EXPECT_EQ(s.uncovered, 40);
  const LocalMismatch lm = local_mismatch(tree, target, PixelBox{62, 0, 130, 3});
  EXPECT_EQ(lm.uncovered, 38);
  EXPECT_EQ(lm.excess, 0);
  EXPECT_DOUBLE_EQ(lm.uncovered_x, (62 + 99) / 2.0 + 0.5);
}

}  // namespace
}  // namespace fuzzycsg::trace
