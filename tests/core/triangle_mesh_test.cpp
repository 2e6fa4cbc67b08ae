#include "fuzzycsg/core/triangle_mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>

namespace fuzzycsg {
namespace {

// The unit cube [0, 1]^3 moved by `offset`, twelve triangles facing out.
TriangleMesh cube(double offset) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k) {
    m.vertices.push_back({offset + (k & 1), offset + ((k >> 1) & 1), offset + ((k >> 2) & 1)});
  }
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

TEST(TriangleMesh, SignedVolumeIsTheEnclosedVolumeWhereverTheMeshIs) {
  EXPECT_DOUBLE_EQ(signed_volume(cube(0)), 1.0);
  EXPECT_NEAR(signed_volume(cube(-3.25)), 1.0, 1e-12);
  TriangleMesh tetrahedron;
  tetrahedron.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tetrahedron.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  EXPECT_DOUBLE_EQ(signed_volume(tetrahedron), 1.0 / 6.0);
  // Turned inside out: the volume changes sign.
  TriangleMesh inward = cube(0.5);
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  EXPECT_NEAR(signed_volume(inward), -1.0, 1e-12);
  EXPECT_EQ(signed_volume(TriangleMesh{}), 0.0);
}

TEST(TriangleMesh, BoundingBoxHoldsEveryVertex) {
  TriangleMesh m = cube(-0.5);
  m.vertices.push_back({7, -9, 0.25});  // used by no triangle, still counted
  const auto [lo, hi] = bounding_box(m);
  EXPECT_EQ(lo, (std::array<double, 3>{-0.5, -9, -0.5}));
  EXPECT_EQ(hi, (std::array<double, 3>{7, 0.5, 0.5}));
  const auto [empty_lo, empty_hi] = bounding_box(TriangleMesh{});
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(std::isinf(empty_lo[k]) && empty_lo[k] > 0);
    EXPECT_TRUE(std::isinf(empty_hi[k]) && empty_hi[k] < 0);
  }
}

}  // namespace
}  // namespace fuzzycsg
