// The steps after RANSAC (src/convert/detect_refine.cpp) on candidates given by hand: what they
// make of candidates RANSAC could have proposed.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <vector>

#include "convert/detect_internal.hpp"
#include "convert/surface_fit.hpp"
#include "convert/test_meshes.hpp"
#include "fuzzycsg/convert/detect.hpp"
#include "fuzzycsg/target/mesh_file.hpp"

namespace fuzzycsg::convert::detail {
namespace {

using Eigen::Vector3d;

Tolerances tolerances(const PreparedMesh& m) {
  Tolerances tol;
  tol.distance = 0.005 * m.diagonal;
  tol.normal_angle = 25 * std::numbers::pi / 180;
  tol.cos_normal = std::cos(tol.normal_angle);
  tol.facet_half_angle = 20 * std::numbers::pi / 180;
  tol.min_area = 0.002 * m.total_area;
  return tol;
}

Candidate plane_candidate(const PreparedMesh& m, std::vector<int> triangles) {
  Candidate c;
  c.surface.kind = SurfaceKind::kPlane;
  c.surface.point = m.centroids[static_cast<std::size_t>(triangles[0])];
  c.surface.direction = m.normals[static_cast<std::size_t>(triangles[0])];
  for (const int t : triangles) c.area += m.areas[static_cast<std::size_t>(t)];
  c.triangles = std::move(triangles);
  return c;
}

// A 30-gon prism whose every facet came as a plane, and a cylinder that holds a few facets: the
// facet planes are the cylinder's, and go.
TEST(RefineCandidates, FacetPlanesGoToTheCylinder) {
  const TriangleMesh mesh =
      test_meshes::prism_mesh(30, 1.0, 2.0, Vector3d(0, 0, 0), Vector3d(0, 0, 1));
  const PreparedMesh m = prepare_mesh(mesh);
  const Tolerances tol = tolerances(m);
  std::vector<Candidate> candidates;
  // prism_mesh's triangles come four per side: two of the side, then bottom and top.
  std::vector<int> bottom, top;
  for (int i = 0; i < 30; ++i) {
    candidates.push_back(plane_candidate(m, {4 * i, 4 * i + 1}));
    bottom.push_back(4 * i + 2);
    top.push_back(4 * i + 3);
  }
  candidates.push_back(plane_candidate(m, bottom));
  candidates.push_back(plane_candidate(m, top));
  Candidate cylinder;
  cylinder.surface.kind = SurfaceKind::kCylinder;
  cylinder.surface.point = Vector3d(0.01, -0.02, 0);
  cylinder.surface.direction = Vector3d(0.01, 0, 1).normalized();
  cylinder.surface.radius = 0.97;
  cylinder.triangles = {0, 1, 4, 5, 8, 9};
  for (const int t : cylinder.triangles) cylinder.area += m.areas[static_cast<std::size_t>(t)];
  candidates.push_back(cylinder);

  const std::vector<Candidate> out = refine_candidates(m, candidates, tol);
  ASSERT_EQ(out.size(), 3u);
  int cylinders = 0;
  for (const Candidate& c : out) {
    if (c.surface.kind != SurfaceKind::kCylinder) {
      EXPECT_EQ(c.surface.kind, SurfaceKind::kPlane);
      EXPECT_EQ(c.triangles.size(), 30u);
      continue;
    }
    ++cylinders;
    EXPECT_EQ(c.triangles.size(), 60u);
    EXPECT_NEAR(c.surface.radius, 1.0, 1e-6);
    EXPECT_GT(std::abs(c.surface.direction.z()), 1 - 1e-9);
    EXPECT_TRUE(c.surface.outward);
  }
  EXPECT_EQ(cylinders, 1);
}

// The same prism with only its caps proposed: the sides, which nothing explains, are grown into
// planar regions, one per facet, each too small to be a surface of its own (the smallest surface
// is 3% of the area here, a side facet 2.2%).
TEST(RefineCandidates, UnexplainedFacetsBelowTheSmallestSurfaceStayUnexplained) {
  const TriangleMesh mesh =
      test_meshes::prism_mesh(30, 1.0, 2.0, Vector3d(0, 0, 0), Vector3d(0, 0, 1));
  const PreparedMesh m = prepare_mesh(mesh);
  Tolerances tol = tolerances(m);
  tol.min_area = 0.03 * m.total_area;
  std::vector<int> bottom, top;
  for (int i = 0; i < 30; ++i) {
    bottom.push_back(4 * i + 2);
    top.push_back(4 * i + 3);
  }
  const std::vector<Candidate> out =
      refine_candidates(m, {plane_candidate(m, bottom), plane_candidate(m, top)}, tol);
  ASSERT_EQ(out.size(), 2u);
  for (const Candidate& c : out) EXPECT_EQ(c.triangles.size(), 30u);
}

// A hexagonal prism's sides handed over as one cylinder (its facets within the distance
// tolerance, as in a large scene): the facets are 60 degrees apart, so the cylinder goes and the
// sides come back as six planes.
TEST(RefineCandidates, CoarseFacetsAreNotACylinder) {
  const TriangleMesh mesh =
      test_meshes::prism_mesh(6, 1.0, 2.0, Vector3d(0, 0, 0), Vector3d(0, 0, 1));
  const PreparedMesh m = prepare_mesh(mesh);
  Tolerances tol = tolerances(m);
  tol.distance = 0.2;  // more than the sagitta of the facets, 1 - cos(30 deg) = 0.134
  tol.normal_angle = 35 * std::numbers::pi / 180;
  tol.cos_normal = std::cos(tol.normal_angle);
  Candidate cylinder;
  cylinder.surface.kind = SurfaceKind::kCylinder;
  cylinder.surface.point = Vector3d(0, 0, 0);
  cylinder.surface.direction = Vector3d(0, 0, 1);
  cylinder.surface.radius = 0.95;
  for (int i = 0; i < 6; ++i) {
    cylinder.triangles.push_back(4 * i);
    cylinder.triangles.push_back(4 * i + 1);
  }
  for (const int t : cylinder.triangles) cylinder.area += m.areas[static_cast<std::size_t>(t)];
  // The cylinder alone explains the sides.
  Surface check = cylinder.surface;
  EXPECT_LT(explain_cost(m, check, 0, tol), std::numeric_limits<double>::infinity());
  const std::vector<Candidate> out = refine_candidates(m, {cylinder}, tol);
  int planes = 0;
  for (const Candidate& c : out) {
    EXPECT_EQ(c.surface.kind, SurfaceKind::kPlane);
    planes += c.surface.kind == SurfaceKind::kPlane;
  }
  EXPECT_EQ(planes, 8);
}

// cgal_cross, a plus-shaped plate: the four end faces of its arms lie within the tolerances of
// one cylinder around z (through their corners), which also meets its normals within the normal
// angle. Handed over as that cylinder, they are four planes all the same: four separate flat
// faces are no cylinder.
TEST(RefineCandidates, SeparateFlatFacesAreNotACylinder) {
  const TriangleMesh mesh =
      read_mesh_file(std::filesystem::path(FUZZYCSG_TEST_DATA_DIR) / "meshes/cad/cgal_cross.off");
  const PreparedMesh m = prepare_mesh(mesh);
  const Tolerances tol = tolerances(m);
  Candidate cylinder;
  cylinder.surface.kind = SurfaceKind::kCylinder;
  cylinder.surface.point = Vector3d(0, 0, 0);
  cylinder.surface.direction = Vector3d(0, 0, 1);
  cylinder.surface.radius = std::hypot(0.5, 0.1);
  for (const int t : m.valid) {
    const Vector3d& c = m.centroids[static_cast<std::size_t>(t)];
    if (std::max(std::abs(c.x()), std::abs(c.y())) > 0.49) {
      cylinder.triangles.push_back(t);
      cylinder.area += m.areas[static_cast<std::size_t>(t)];
    }
  }
  ASSERT_EQ(cylinder.triangles.size(), 8u);
  for (const int t : cylinder.triangles) {
    EXPECT_LT(explain_cost(m, cylinder.surface, t, tol), std::numeric_limits<double>::infinity());
  }
  const std::vector<Candidate> out = refine_candidates(m, {cylinder}, tol);
  EXPECT_EQ(out.size(), 10u);
  for (const Candidate& c : out) EXPECT_EQ(c.surface.kind, SurfaceKind::kPlane);
}

// Two halves of one sphere proposed separately are merged into one.
TEST(RefineCandidates, HalvesOfOneSphereMerge) {
  const TriangleMesh mesh = test_meshes::uv_sphere_mesh(Vector3d(1, 2, 3), 2.0, 12, 24);
  const PreparedMesh m = prepare_mesh(mesh);
  const Tolerances tol = tolerances(m);
  Candidate a, b;
  a.surface.kind = b.surface.kind = SurfaceKind::kSphere;
  a.surface.point = Vector3d(1.02, 2, 3);
  b.surface.point = Vector3d(1, 1.97, 3.01);
  a.surface.radius = 1.98;
  b.surface.radius = 2.01;
  for (const int t : m.valid) {
    Candidate& half = m.centroids[static_cast<std::size_t>(t)].x() < 1 ? a : b;
    half.triangles.push_back(t);
    half.area += m.areas[static_cast<std::size_t>(t)];
  }
  const std::vector<Candidate> out = refine_candidates(m, {a, b}, tol);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].surface.kind, SurfaceKind::kSphere);
  EXPECT_EQ(out[0].triangles.size(), mesh.triangles.size());
  EXPECT_LT((out[0].surface.point - Vector3d(1, 2, 3)).norm(), 1e-3);
}

// A cone proposed for a cylinder (half-angle near zero) is re-classified as the cylinder.
TEST(RefineCandidates, NarrowConeIsACylinder) {
  const TriangleMesh mesh =
      test_meshes::prism_mesh(40, 1.0, 3.0, Vector3d(0, 0, 0), Vector3d(0, 1, 0));
  const PreparedMesh m = prepare_mesh(mesh);
  const Tolerances tol = tolerances(m);
  Candidate cone;
  cone.surface.kind = SurfaceKind::kCone;
  cone.surface.point = Vector3d(0, -200, 0);
  cone.surface.direction = Vector3d(0, 1, 0);
  cone.surface.half_angle = std::atan(1.0 / 201.5);
  for (int i = 0; i < 40; ++i) {
    cone.triangles.push_back(4 * i);
    cone.triangles.push_back(4 * i + 1);
  }
  for (const int t : cone.triangles) cone.area += m.areas[static_cast<std::size_t>(t)];
  const std::vector<Candidate> out = refine_candidates(m, {cone}, tol);
  int cylinders = 0;
  for (const Candidate& c : out) {
    EXPECT_NE(c.surface.kind, SurfaceKind::kCone);
    if (c.surface.kind != SurfaceKind::kCylinder) continue;
    ++cylinders;
    EXPECT_NEAR(c.surface.radius, 1.0, 1e-6);
  }
  EXPECT_EQ(cylinders, 1);
}

// A plane explains a very flat cylinder: the cylinder is re-classified as the plane.
TEST(RefineCandidates, HugeCylinderOverAFaceIsAPlane) {
  const TriangleMesh mesh = test_meshes::box_mesh(Vector3d(0, 0, 0), Vector3d(1, 1, 1));
  const PreparedMesh m = prepare_mesh(mesh);
  const Tolerances tol = tolerances(m);
  Candidate cylinder;
  cylinder.surface.kind = SurfaceKind::kCylinder;
  cylinder.surface.point = Vector3d(0.5, 0.5, 1 - 500);
  cylinder.surface.direction = Vector3d(1, 0, 0);
  cylinder.surface.radius = 500;
  for (int t = 0; t < 12; ++t) {
    if (m.normals[static_cast<std::size_t>(t)].z() > 0.5) cylinder.triangles.push_back(t);
  }
  for (const int t : cylinder.triangles) cylinder.area += m.areas[static_cast<std::size_t>(t)];
  ASSERT_EQ(cylinder.triangles.size(), 2u);
  const std::vector<Candidate> out = refine_candidates(m, {cylinder}, tol);
  ASSERT_EQ(out.size(), 6u);
  for (const Candidate& c : out) EXPECT_EQ(c.surface.kind, SurfaceKind::kPlane);
}

}  // namespace
}  // namespace fuzzycsg::convert::detail
