// convert on pictures: the tracer's crisp tree of circles and rectangles, refined and tidied.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "fuzzycsg/convert/convert.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::convert {
namespace {

const std::filesystem::path kGlyphP =
    std::filesystem::path(FUZZYCSG_TEST_DATA_DIR) / "glyphs/DejaVuSans-Bold_U0050_P.png";

ConvertOptions picture_options() {
  ConvertOptions o;
  o.threads = 2;
  o.metrics.points = 200'000;
  return o;
}

TEST(ConvertPicture, GlyphIsAFewCrispCirclesAndRectangles) {
  const ConvertResult r = convert(kGlyphP.string(), picture_options());
  EXPECT_EQ(r.tree.dim, 2);
  EXPECT_GE(r.metrics.iou, 0.97);
  EXPECT_GE(r.primitives, 2);
  EXPECT_LE(r.primitives, 8);
  ASSERT_TRUE(r.chamfer.has_value());
  EXPECT_LT(*r.chamfer, 1.0);  // pixels
  const std::vector<double> params = r.tree.params.values();
  for (const Node& n : r.tree.nodes) {
    if (n.kind != NodeKind::kPrimitive) {
      EXPECT_TRUE(n.op == OpKind::kUnion || n.op == OpKind::kIntersection ||
                  n.op == OpKind::kDifference);
      continue;
    }
    EXPECT_TRUE(n.shape.type == PrimitiveType::kCircle ||
                n.shape.type == PrimitiveType::kRectangle);
    EXPECT_EQ(n.step.kind, StepKind::kCrisp);
    // Tidied: every number a multiple of a hundredth of a pixel (or degree).
    for (const ParamRef p : n.intrinsic) {
      EXPECT_NEAR(params[p.index] * 100, std::round(params[p.index] * 100), 1e-6);
    }
  }
  // The same seed and threads: the same tree.
  const ConvertResult again = convert(kGlyphP.string(), picture_options());
  EXPECT_EQ(io::write_tree_string(again.tree), io::write_tree_string(r.tree));
}

TEST(ConvertPicture, MaxPrimitivesIsHeld) {
  ConvertOptions o = picture_options();
  o.max_primitives = 2;
  const ConvertResult r = convert(kGlyphP.string(), o);
  EXPECT_LE(r.primitives, 2);
  EXPECT_GE(r.primitives, 1);
}

}  // namespace
}  // namespace fuzzycsg::convert
