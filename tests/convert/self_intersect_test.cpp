// Meshes that cross themselves are told from those that only touch along their edges.
#include "convert/self_intersect.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "convert/test_meshes.hpp"
#include "fuzzycsg/target/mesh_file.hpp"

namespace fuzzycsg::convert {
namespace {

const std::filesystem::path kCadMeshes =
    std::filesystem::path(FUZZYCSG_TEST_DATA_DIR) / "meshes/cad";

// Two closed shells, one after the other in the vertex and triangle lists.
TriangleMesh both(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m = a;
  const int base = static_cast<int>(a.vertices.size());
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  return m;
}

TEST(ConvertSelfIntersection, OverlappingShellsCrossAndSeparateOnesDoNot) {
  const TriangleMesh a = box_mesh({0, 0, 0}, {2, 2, 2});
  EXPECT_EQ(crossing_triangle_pairs(a), 0u);
  const auto overlapping = crossing_triangle_pairs(both(a, box_mesh({1, 1, 1}, {3, 3, 3})));
  ASSERT_TRUE(overlapping.has_value());
  EXPECT_GT(*overlapping, 0u);
  EXPECT_EQ(crossing_triangle_pairs(both(a, box_mesh({3, 0, 0}, {4, 1, 1}))), 0u);
}

TEST(ConvertSelfIntersection, TheSuitesCadMeshesDoNotCrossThemselves) {
  for (const char* name :
       {"cgal_P.off", "cgal_corner.off", "cgal_couplingdown.off", "cgal_cross.off",
        "cgal_fandisk.off", "cgal_hole.off", "cgal_pinion.off", "cgal_pipe.off", "cgal_u.off"}) {
    const TriangleMesh mesh = read_mesh_file(kCadMeshes / name);
    const auto crossing = crossing_triangle_pairs(mesh);
    ASSERT_TRUE(crossing.has_value()) << name;
    EXPECT_EQ(*crossing, 0u) << name;
  }
}

}  // namespace
}  // namespace fuzzycsg::convert
