// Intersection edges between primitives: single triangle pairs, and the closed loop where two
// overlapping cubes' surfaces cross, of known length.
#include <gtest/gtest.h>

#include <cmath>

#include "fuzzycsg/diffcsg/edges.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::diffcsg {
namespace {

double length(const IntersectionEdge& e) {
  const double dx = e.p[0] - e.q[0], dy = e.p[1] - e.q[1], dz = e.p[2] - e.q[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

TEST(DiffcsgEdges, TrianglePairs) {
  Vec3 p, q;
  // A triangle in z = 0 and one in x = 0.2 through it.
  ASSERT_TRUE(triangle_intersection({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, -1, -1}, {0.2, 2, -1},
                                    {0.2, 0.5, 1}, p, q));
  EXPECT_NEAR(p[0], 0.2, 1e-12);
  EXPECT_NEAR(q[0], 0.2, 1e-12);
  EXPECT_NEAR(p[2], 0, 1e-12);
  EXPECT_NEAR(q[2], 0, 1e-12);
  // The shared segment is x = 0.2, z = 0, y from 0 to 0.8 (the first triangle's hypotenuse).
  EXPECT_NEAR(std::abs(p[1] - q[1]), 0.8, 1e-12);
  // Apart, and coplanar.
  EXPECT_FALSE(triangle_intersection({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1},
                                     {0, 1, 1}, p, q));
  EXPECT_FALSE(triangle_intersection({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.1, 0.1, 0}, {0.5, 0.1, 0},
                                     {0.1, 0.5, 0}, p, q));
}

TEST(DiffcsgEdges, TwoOverlappingCubesCrossAlongAHexagonOfLengthThree) {
  const Tree tree = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
      "root": {"op": "union", "children": [{"type": "box", "size": [1, 1, 1]},
        {"type": "box", "size": [1, 1, 1], "translate": [0.5, 0.5, 0.5]}]}})");
  const Scene scene = scene_from_tree(tree, "cubes");
  const std::vector<IntersectionEdge> edges = intersection_edges(scene);
  double total = 0;
  for (const IntersectionEdge& e : edges) {
    EXPECT_EQ(e.primitive_a, 0);
    EXPECT_EQ(e.primitive_b, 1);
    total += length(e);
    // Every point of the loop is on both cubes' surfaces: one coordinate is 0.5 (the first
    // cube's face) or 0 (the second's), the others in [0, 0.5].
    for (const Vec3& v : {e.p, e.q}) {
      for (int k = 0; k < 3; ++k) {
        EXPECT_GE(v[static_cast<std::size_t>(k)], -1e-12);
        EXPECT_LE(v[static_cast<std::size_t>(k)], 0.5 + 1e-12);
      }
    }
  }
  EXPECT_NEAR(total, 3.0, 1e-9);
  // Apart, no edges.
  const Tree apart = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
      "root": {"op": "union", "children": [{"type": "box", "size": [1, 1, 1]},
        {"type": "sphere", "radius": 0.4, "translate": [2, 0, 0]}]}})");
  EXPECT_TRUE(intersection_edges(scene_from_tree(apart, "apart")).empty());
}

TEST(DiffcsgEdges, ASphereThroughACubeFaceCrossesAlongACircle) {
  // The ball of radius 0.6 centred on the face x = 0.5: the crossing is near the circle of
  // radius 0.6 in that face (the ball's mesh is inscribed, so a little shorter).
  const Tree tree = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
      "root": {"op": "difference", "children": [{"type": "box", "size": [2, 2, 2]},
        {"type": "sphere", "radius": 0.6, "translate": [1, 0, 0]}]}})");
  const std::vector<IntersectionEdge> edges = intersection_edges(scene_from_tree(tree, "cavity"));
  double total = 0;
  for (const IntersectionEdge& e : edges) {
    total += length(e);
    EXPECT_NEAR(e.p[0], 1.0, 1e-9);
    EXPECT_NEAR(e.q[0], 1.0, 1e-9);
  }
  const double circle = 2 * 3.14159265358979323846 * 0.6;
  EXPECT_GT(total, 0.95 * circle);
  EXPECT_LT(total, circle);
}

}  // namespace
}  // namespace fuzzycsg::diffcsg
