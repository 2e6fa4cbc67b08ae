// OpenSCAD import: fragments as OpenSCAD counts them, the checked model (kinds, placements
// multiplied through nested multmatrix, triangle counts), messages, and the model as a tree.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/scad/openscad_csg.hpp"

namespace fuzzycsg::scad {
namespace {

TEST(OpenscadImport, FragmentsAsOpenscadCountsThem) {
  EXPECT_EQ(openscad_fragments(10, 0, 2, 12), 30);
  EXPECT_EQ(openscad_fragments(25, 100, 2, 12), 100);
  EXPECT_EQ(openscad_fragments(0.5, 0, 2, 12), 5);
  EXPECT_EQ(openscad_fragments(3, 0, 2, 12), 10);  // 2 pi 3 / 2 = 9.42
  EXPECT_EQ(openscad_fragments(1e-9, 0, 2, 12), 3);
  EXPECT_EQ(openscad_fragments(5, 2, 2, 12), 3);
  // Saturated, never an overflowing conversion.
  EXPECT_EQ(openscad_fragments(1, 1e300, 2, 12), std::numeric_limits<int>::max());
  EXPECT_EQ(openscad_fragments(1e300, 0, 1e-300, 1e-300), std::numeric_limits<int>::max());
}

constexpr const char* kModel = R"(
group() {
  multmatrix([[1, 0, 0, 10], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {
    multmatrix([[2, 0, 0, 0], [0, 2, 0, 0], [0, 0, 2, 5], [0, 0, 0, 1]]) {
      sphere($fn = 8, r = 1);
    }
  }
  difference() {
    cube(size = [1, 2, 3], center = true);
    cylinder($fn = 6, h = 4, r1 = 0.5, r2 = 0.25, center = true);
    %cube(size = 9);
  }
}
)";

TEST(OpenscadImport, TheModelIsResolved) {
  const CsgModel m = parse_csg(kModel, "m.csg");
  ASSERT_EQ(m.items.size(), 1u);
  const CsgItem& group = m.items[0];
  EXPECT_EQ(group.kind, CsgItem::Kind::kUnion);
  EXPECT_EQ(group.name, "group");
  ASSERT_EQ(group.children.size(), 2u);
  const CsgItem& sphere = group.children[0].children[0].children[0];
  EXPECT_EQ(sphere.kind, CsgItem::Kind::kPrimitive);
  EXPECT_EQ(sphere.line, 5);
  EXPECT_EQ(sphere.primitive.kind, CsgPrimitive::Kind::kSphere);
  EXPECT_EQ(sphere.primitive.fragments, 8);
  // The outer translation times the inner scale and lift: x = 2 x' + 10, z = 2 z' + 5.
  EXPECT_EQ(sphere.matrix[0], 2);
  EXPECT_EQ(sphere.matrix[3], 10);
  EXPECT_EQ(sphere.matrix[11], 5);
  // 2 caps of 6 triangles and 2 * 8 * 3 between its 4 rings.
  EXPECT_EQ(sphere.triangle_count(), 60u);
  const CsgItem& diff = group.children[1];
  EXPECT_EQ(diff.kind, CsgItem::Kind::kDifference);
  ASSERT_EQ(diff.children.size(), 2u);  // the % cube is removed
  EXPECT_EQ(diff.children[1].primitive.r2, 0.25);
  EXPECT_EQ(diff.children[0].triangle_count(), 12u);
  try {
    fail_at(m, diff, "a problem");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "m.csg: line 8: difference: a problem");
  }
}

TEST(OpenscadImport, TheModelAsATree) {
  const CsgTree t = csg_tree(parse_csg(kModel, "m.csg"));
  ASSERT_EQ(t.tree.nodes.size(), 5u);  // union(sphere, difference(box, cone))
  const Node& sphere = t.tree.node(1);
  EXPECT_EQ(sphere.shape.type, PrimitiveType::kSphere);
  EXPECT_EQ(sphere.name, "sphere line 5");
  EXPECT_EQ(t.tree.params[sphere.intrinsic[0]].value, 2);  // r 1 scaled by 2
  EXPECT_EQ(t.tree.params[sphere.placement.translate[2]].value, 5);
  EXPECT_EQ(t.tree.node(4).shape.type, PrimitiveType::kCone);
  EXPECT_EQ(t.fragments, (std::map<int, int>{{1, 8}, {4, 6}}));
  EXPECT_EQ(t.tree.params.at(0).name, "root.children[0].radius");
}

TEST(OpenscadImport, RefusalsNameTheLine) {
  const auto error = [](const std::string& text) {
    try {
      csg_tree(parse_csg(text, "e.csg"));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error("cube(1);\nlinear_extrude(height = 1) square(1);"),
            "e.csg: line 2: unsupported node 'linear_extrude' (cube, sphere, cylinder, "
            "multmatrix, union, difference, intersection, group)");
  EXPECT_EQ(error("sphere($fn = 5000, r = 1);"),
            "e.csg: line 1: sphere: $fn, $fa, $fs: 5000 fragments, at most 4096");
  EXPECT_EQ(error("multmatrix([[1, 1, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) cube(1);"),
            "e.csg: line 1: cube: its placement shears it, which a tree's translate, rotate and "
            "size cannot express");
  EXPECT_EQ(error("%cube(1);"), "e.csg: no primitives");
}

}  // namespace
}  // namespace fuzzycsg::scad
