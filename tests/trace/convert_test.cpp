// Trees of the tracer as fuzzycsg trees: the project's evaluator reproduces the tracer's bitmap.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/convert.hpp"
#include "fuzzycsg/trace/evaluate.hpp"
#include "io/tree_compare.hpp"

namespace fuzzycsg::trace {
namespace {

// Whether the centre (px, py) lies within eps of the boundary of p.
bool near_boundary(const Primitive& p, double px, double py, double eps) {
  const double dx = px - p.x, dy = py - p.y;
  if (p.shape == Shape::kCircle) return std::abs(std::hypot(dx, dy) - p.r) < eps;
  const double t = p.theta * std::numbers::pi / 180.0;
  const double u = std::cos(t) * dx + std::sin(t) * dy, v = -std::sin(t) * dx + std::cos(t) * dy;
  const double f = std::max(std::abs(u) - p.w / 2, std::abs(v) - p.h / 2);
  return std::abs(f) < eps;
}

TEST(TraceConvert, TheProjectEvaluatorReproducesTheMask) {
  Rng rng(41);
  int compared = 0, skipped = 0;
  for (int trial = 0; trial < 25; ++trial) {
    const int width = 16 + static_cast<int>(rng() % 80), height = 16 + static_cast<int>(rng() % 60);
    CsgTree t = random_tree(1 + static_cast<int>(rng() % 10), width, height, rng);
    // Some primitives on the pixel grid exactly (boundaries through pixel centres are skipped).
    for (const int leaf : t.leaves()) {
      if (uniform01(rng) < 0.3) {
        Primitive& p = t.primitive(leaf);
        p.x = std::round(p.x);
        p.y = std::round(p.y);
        p.theta = 90.0 * static_cast<double>(rng() % 4);
        p.w = std::round(p.w);
        p.h = std::round(p.h);
      }
    }
    const Bitmap mask = TreeEvaluator(t, width, height).result();
    const Tree tree = to_tree(t, width, height);
    ASSERT_EQ(tree.dim, 2);
    ASSERT_TRUE(tree.domain);
    EXPECT_EQ(tree.domain->max[0], width);
    EXPECT_EQ(tree.domain->max[1], height);
    EXPECT_EQ(count(tree).primitives, t.primitive_count());
    const std::vector<double> params = tree.params.values();
    const std::vector<int> leaves = t.leaves();
    for (int j = 0; j < height; ++j) {
      for (int i = 0; i < width; ++i) {
        const bool skip = std::any_of(leaves.begin(), leaves.end(), [&](int leaf) {
          return near_boundary(t.primitive(leaf), i + 0.5, j + 0.5, 1e-9);
        });
        if (skip) {
          ++skipped;
          continue;
        }
        // The tree-file convention: x = min0 + (i + 1/2) (max0 - min0) / W, y = max1 - ...
        const double world[2] = {tree.domain->min[0] + (i + 0.5) * width / width,
                                 tree.domain->max[1] - (j + 0.5) * height / height};
        const double o = reference_occupancy(tree, params, world);
        ASSERT_EQ(o, mask.get(i, j) ? 1.0 : 0.0)
            << "trial " << trial << " pixel " << i << ", " << j;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 10000);
  EXPECT_LT(skipped, compared / 20);
}

TEST(TraceConvert, TheFileReadsBackAndTheFastEvaluatorAgrees) {
  Rng rng(42);
  const int width = 64, height = 40;
  const CsgTree t = random_tree(8, width, height, rng);
  const std::string text = io::write_tree_string(to_tree(t, width, height));
  const Tree tree = io::read_tree_string(text, "trace.json");
  EXPECT_EQ(testing::tree_difference(tree, to_tree(t, width, height)), "");
  EXPECT_EQ(io::write_tree_string(io::read_tree_string(io::write_tree_string(tree))),
            io::write_tree_string(tree));
  const Bitmap mask = TreeEvaluator(t, width, height).result();
  std::vector<float> points;
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      points.push_back(static_cast<float>(i + 0.5));
      points.push_back(static_cast<float>(height - j - 0.5));
    }
  }
  std::vector<float> out(points.size() / 2);
  EvalOptions eo;
  eo.threads = 1;
  const Evaluator ev(tree, eo);
  ev.forward(tree.params.values(), points, out);
  // Single precision: count disagreements, which can only sit on boundaries.
  int differ = 0;
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const float o = out[static_cast<std::size_t>(j * width + i)];
      if ((o > 0.5f) != mask.get(i, j)) ++differ;
    }
  }
  EXPECT_LE(differ, 3);
}

}  // namespace
}  // namespace fuzzycsg::trace
