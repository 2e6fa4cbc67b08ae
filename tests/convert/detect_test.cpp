#include "fuzzycsg/convert/detect.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "convert/test_meshes.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/triangle_mesh.hpp"
#include "fuzzycsg/target/mesh_file.hpp"

namespace fuzzycsg::convert {
namespace {

using Eigen::Vector3d;
using test_meshes::box_mesh;
using test_meshes::box_with_hole_mesh;
using test_meshes::prism_mesh;
using test_meshes::scaled;
using test_meshes::turned_over;
using test_meshes::uv_sphere_mesh;

const std::filesystem::path kData = FUZZYCSG_TEST_DATA_DIR;
constexpr double kPi = std::numbers::pi;

// ---- Helpers -----------------------------------------------------------------------------

void print(const std::string& name, const std::vector<Surface>& surfaces) {
  std::printf("%s: %zu surfaces\n", name.c_str(), surfaces.size());
  for (const Surface& s : surfaces) {
    std::printf(
        "  %-8s point (%.5g, %.5g, %.5g) direction (%.4f, %.4f, %.4f) radius %.6g minor %.4g "
        "half-angle %.3f deg %s area %.4g rms %.3g axial [%.4g, %.4g] coverage %.3f "
        "triangles %zu\n",
        std::string(surface_kind_name(s.kind)).c_str(), s.point.x(), s.point.y(), s.point.z(),
        s.direction.x(), s.direction.y(), s.direction.z(), s.radius, s.minor_radius,
        s.half_angle * 180 / kPi, s.outward ? "outward" : "inward", s.area, s.rms, s.axial_min,
        s.axial_max, s.angular_coverage, s.triangles.size());
  }
}

std::vector<Surface> detect_and_print(const std::string& name, const TriangleMesh& mesh,
                                      const DetectOptions& options = {}) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<Surface> surfaces = detect_surfaces(mesh, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  print(name + " (" + std::to_string(mesh.triangles.size()) + " triangles, " +
            std::to_string(seconds) + " s)",
        surfaces);
  return surfaces;
}

std::vector<Surface> of_kind(const std::vector<Surface>& surfaces, SurfaceKind kind) {
  std::vector<Surface> out;
  for (const Surface& s : surfaces) {
    if (s.kind == kind) out.push_back(s);
  }
  return out;
}

// The angle between two lines (directions up to sign), in degrees.
double line_angle_deg(const Vector3d& a, const Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * 180 / kPi;
}

// The distance from p to the line through q along d.
double distance_to_line(const Vector3d& p, const Vector3d& q, const Vector3d& d) {
  const Vector3d v = p - q;
  return (v - v.dot(d.normalized()) * d.normalized()).norm();
}

// The plane among `planes` whose normal is nearest n, or nullptr.
const Surface* plane_facing(const std::vector<Surface>& planes, const Vector3d& n) {
  const Surface* best = nullptr;
  for (const Surface& p : planes) {
    if (best == nullptr || p.direction.dot(n) > best->direction.dot(n)) best = &p;
  }
  return best;
}

// Each triangle belongs to at most one surface, and the areas are those of the triangles.
void expect_consistent(const TriangleMesh& mesh, const std::vector<Surface>& surfaces) {
  std::vector<int> owners(mesh.triangles.size(), 0);
  for (const Surface& s : surfaces) {
    double area = 0;
    for (const int t : s.triangles) {
      ASSERT_GE(t, 0);
      ASSERT_LT(t, static_cast<int>(mesh.triangles.size()));
      ++owners[static_cast<std::size_t>(t)];
      const auto& c = mesh.triangles[static_cast<std::size_t>(t)];
      const auto v = [&](int k) {
        const auto& p = mesh.vertices[static_cast<std::size_t>(c[static_cast<std::size_t>(k)])];
        return Vector3d(p[0], p[1], p[2]);
      };
      area += 0.5 * (v(1) - v(0)).cross(v(2) - v(0)).norm();
    }
    EXPECT_NEAR(s.area, area, 1e-9 * std::max(1.0, area));
    EXPECT_TRUE(std::is_sorted(s.triangles.begin(), s.triangles.end()));
    EXPECT_NEAR(s.direction.norm(), 1.0, 1e-9);
  }
  EXPECT_LE(*std::max_element(owners.begin(), owners.end()), 1);
}

// ---- Meshes built here -------------------------------------------------------------------

TEST(DetectSurfaces, BoxIsSixPlanesWithOutwardNormals) {
  const Vector3d lo(-1, 2, 0.5), hi(3, 5, 1.5);
  const TriangleMesh mesh = box_mesh(lo, hi);
  ASSERT_GT(signed_volume(mesh), 0);
  const std::vector<Surface> surfaces = detect_and_print("box", mesh);
  expect_consistent(mesh, surfaces);
  ASSERT_EQ(surfaces.size(), 6u);
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {-1.0, 1.0}) {
      Vector3d n = Vector3d::Zero();
      n[axis] = sign;
      const Surface* p = plane_facing(surfaces, n);
      ASSERT_NE(p, nullptr);
      EXPECT_EQ(p->kind, SurfaceKind::kPlane);
      EXPECT_GT(p->direction.dot(n), 1 - 1e-9);
      // The plane's offset along its normal: the face's coordinate.
      const double face = sign > 0 ? hi[axis] : lo[axis];
      EXPECT_NEAR(p->point.dot(n), sign * face, 1e-9);
      EXPECT_EQ(p->triangles.size(), 2u);
      EXPECT_LT(p->rms, 1e-9);
    }
  }
}

TEST(DetectSurfaces, TurnedOverBoxKeepsNormalsOutOfTheSolid) {
  const TriangleMesh mesh = turned_over(box_mesh(Vector3d(0, 0, 0), Vector3d(2, 1, 1)));
  ASSERT_LT(signed_volume(mesh), 0);
  const std::vector<Surface> surfaces = detect_surfaces(mesh);
  ASSERT_EQ(surfaces.size(), 6u);
  const Vector3d centre(1, 0.5, 0.5);
  for (const Surface& s : surfaces) {
    EXPECT_EQ(s.kind, SurfaceKind::kPlane);
    // Out of the solid: from the box's centre towards the face.
    EXPECT_GT((s.point - centre).dot(s.direction), 0.49);
  }
}

TEST(DetectSurfaces, ThirtyGonPrismIsOneCylinderAndTwoPlanes) {
  const Vector3d base(0.3, -0.2, 0.1), axis = Vector3d(1, 2, 2).normalized();
  const double r = 0.8, h = 1.5;
  const TriangleMesh mesh = prism_mesh(30, r, h, base, axis);
  ASSERT_GT(signed_volume(mesh), 0);
  const std::vector<Surface> surfaces = detect_and_print("30-gon prism", mesh);
  expect_consistent(mesh, surfaces);
  ASSERT_EQ(surfaces.size(), 3u);
  const std::vector<Surface> cylinders = of_kind(surfaces, SurfaceKind::kCylinder);
  const std::vector<Surface> planes = of_kind(surfaces, SurfaceKind::kPlane);
  ASSERT_EQ(cylinders.size(), 1u);
  ASSERT_EQ(planes.size(), 2u);
  const Surface& c = cylinders[0];
  EXPECT_NEAR(c.radius, r, 0.02 * r);
  EXPECT_LT(line_angle_deg(c.direction, axis), 1.0);
  EXPECT_LT(distance_to_line(c.point, base, axis), 0.01 * r);
  EXPECT_TRUE(c.outward);
  EXPECT_NEAR(c.angular_coverage, 1.0, 1e-9);
  EXPECT_NEAR(c.axial_max - c.axial_min, h, 1e-6);
  EXPECT_EQ(c.triangles.size(), 60u);
  // The caps: normals along the axis, out of the solid, at heights 0 and h.
  const Surface* top = plane_facing(planes, axis);
  const Surface* bottom = plane_facing(planes, -axis);
  ASSERT_NE(top, bottom);
  EXPECT_GT(top->direction.dot(axis), std::cos(1e-6));
  EXPECT_GT(bottom->direction.dot(-axis), std::cos(1e-6));
  EXPECT_NEAR((top->point - base).dot(axis), h, 1e-9);
  EXPECT_NEAR((bottom->point - base).dot(axis), 0, 1e-9);
}

TEST(DetectSurfaces, HexagonalPrismIsEightPlanes) {
  const TriangleMesh mesh = prism_mesh(6, 1.0, 0.7, Vector3d(0, 0, 0), Vector3d(0, 0, 1));
  const std::vector<Surface> surfaces = detect_and_print("hexagonal prism", mesh);
  expect_consistent(mesh, surfaces);
  ASSERT_EQ(surfaces.size(), 8u);
  for (const Surface& s : surfaces) EXPECT_EQ(s.kind, SurfaceKind::kPlane);
  // The six sides: 60 degrees apart, at the apothem cos(30) from the axis.
  for (int i = 0; i < 6; ++i) {
    const double a = 2 * kPi * (i + 0.5) / 6;
    const Vector3d n(std::cos(a), std::sin(a), 0);
    const Surface* p = plane_facing(surfaces, n);
    EXPECT_GT(p->direction.dot(n), 1 - 1e-9);
    EXPECT_NEAR(p->point.dot(n), std::cos(kPi / 6), 1e-9);
  }
}

TEST(DetectSurfaces, SmallHexagonalPrismInALargeSceneIsStillPlanes) {
  // The prism's facets are within the distance tolerance of a cylinder here (the box beside it
  // makes the scene large); they are 60 degrees apart, so they are planes.
  TriangleMesh mesh = prism_mesh(6, 5.0, 5.0, Vector3d(0, 0, 0), Vector3d(0, 0, 1));
  const TriangleMesh box = box_mesh(Vector3d(150, 150, 0), Vector3d(200, 200, 50));
  const int offset = static_cast<int>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), box.vertices.begin(), box.vertices.end());
  for (auto t : box.triangles)
    mesh.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  DetectOptions options;
  options.min_area = 0.0005;
  const std::vector<Surface> surfaces =
      detect_and_print("small hexagonal prism, big box", mesh, options);
  EXPECT_TRUE(of_kind(surfaces, SurfaceKind::kCylinder).empty());
  EXPECT_TRUE(of_kind(surfaces, SurfaceKind::kSphere).empty());
  EXPECT_TRUE(of_kind(surfaces, SurfaceKind::kCone).empty());
  EXPECT_TRUE(of_kind(surfaces, SurfaceKind::kTorus).empty());
  // The box's six faces and the prism's eight, less one: both stand on z = 0, one plane.
  EXPECT_EQ(of_kind(surfaces, SurfaceKind::kPlane).size(), 6u + 8u - 1u);
}

TEST(DetectSurfaces, UvSphereIsOneSphere) {
  const Vector3d centre(2, -1, 0.5);
  const double r = 3;
  const TriangleMesh mesh = uv_sphere_mesh(centre, r, 18, 36);
  ASSERT_GT(signed_volume(mesh), 0);
  const std::vector<Surface> surfaces = detect_and_print("UV sphere", mesh);
  expect_consistent(mesh, surfaces);
  ASSERT_EQ(surfaces.size(), 1u);
  const Surface& s = surfaces[0];
  EXPECT_EQ(s.kind, SurfaceKind::kSphere);
  EXPECT_NEAR(s.radius, r, 0.01 * r);
  EXPECT_LT((s.point - centre).norm(), 0.01 * r);
  EXPECT_TRUE(s.outward);
  EXPECT_EQ(s.triangles.size(), mesh.triangles.size());
}

TEST(DetectSurfaces, BoxWithCylindricalHoleHasAnInwardCylinder) {
  const double a = 2, r = 0.9, h = 1.2;
  const TriangleMesh mesh = box_with_hole_mesh(a, r, h);
  ASSERT_GT(signed_volume(mesh), 0);
  const std::vector<Surface> surfaces = detect_and_print("box with a hole", mesh);
  expect_consistent(mesh, surfaces);
  ASSERT_EQ(surfaces.size(), 7u);
  const std::vector<Surface> cylinders = of_kind(surfaces, SurfaceKind::kCylinder);
  ASSERT_EQ(cylinders.size(), 1u);
  const Surface& hole = cylinders[0];
  EXPECT_FALSE(hole.outward);
  EXPECT_NEAR(hole.radius, r, 0.02 * r);
  EXPECT_LT(line_angle_deg(hole.direction, Vector3d::UnitZ()), 1.0);
  EXPECT_LT(distance_to_line(hole.point, Vector3d::Zero(), Vector3d::UnitZ()), 0.01 * r);
  EXPECT_NEAR(hole.angular_coverage, 1.0, 1e-9);
  EXPECT_EQ(of_kind(surfaces, SurfaceKind::kPlane).size(), 6u);
}

TEST(DetectSurfaces, SameSeedSameSurfaces) {
  const TriangleMesh mesh = read_mesh_file(kData / "scad/Old/example001.ref.off");
  DetectOptions options;
  options.seed = 7;
  const std::vector<Surface> first = detect_surfaces(mesh, options);
  const std::vector<Surface> second = detect_surfaces(mesh, options);
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].kind, second[i].kind);
    EXPECT_EQ(first[i].point, second[i].point);
    EXPECT_EQ(first[i].direction, second[i].direction);
    EXPECT_EQ(first[i].radius, second[i].radius);
    EXPECT_EQ(first[i].outward, second[i].outward);
    EXPECT_EQ(first[i].rms, second[i].rms);
    EXPECT_EQ(first[i].triangles, second[i].triangles);
  }
}

TEST(DetectSurfaces, ScaleDoesNotChangeTheResult) {
  const TriangleMesh mesh = box_with_hole_mesh(2, 0.9, 1.2);
  for (const double factor : {1e-3, 1e3}) {
    const std::vector<Surface> surfaces =
        detect_surfaces(scaled(mesh, factor, Vector3d(5 * factor, 0, -factor)));
    ASSERT_EQ(surfaces.size(), 7u) << "scale " << factor;
    const std::vector<Surface> cylinders = of_kind(surfaces, SurfaceKind::kCylinder);
    ASSERT_EQ(cylinders.size(), 1u) << "scale " << factor;
    EXPECT_NEAR(cylinders[0].radius / factor, 0.9, 0.02 * 0.9);
  }
}

TEST(DetectSurfaces, BadInputThrowsInputError) {
  EXPECT_THROW(detect_surfaces(TriangleMesh{}), InputError);
  TriangleMesh flat;
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 1}};
  flat.triangles = {{0, 1, 2}, {3, 3, 3}};
  EXPECT_THROW(detect_surfaces(flat), InputError);
  TriangleMesh out_of_range = box_mesh(Vector3d(0, 0, 0), Vector3d(1, 1, 1));
  out_of_range.triangles[3][1] = 8;
  EXPECT_THROW(detect_surfaces(out_of_range), InputError);
  TriangleMesh not_finite = box_mesh(Vector3d(0, 0, 0), Vector3d(1, 1, 1));
  not_finite.vertices[2][0] = std::nan("");
  EXPECT_THROW(detect_surfaces(not_finite), InputError);
  try {
    detect_surfaces(flat);
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  DetectOptions bad;
  bad.epsilon = 0;
  EXPECT_THROW(detect_surfaces(box_mesh(Vector3d(0, 0, 0), Vector3d(1, 1, 1)), bad), OptionError);
}

// ---- Meshes of the test data -------------------------------------------------------------

// example001: sphere(r = 25) minus three cylinders (r = 12.5) along x, y and z.
TEST(DetectSurfaces, Example001IsASphereAndThreeHoles) {
  const TriangleMesh mesh = read_mesh_file(kData / "scad/Old/example001.ref.off");
  const std::vector<Surface> surfaces = detect_and_print("example001", mesh);
  expect_consistent(mesh, surfaces);
  ASSERT_EQ(surfaces.size(), 4u);
  const std::vector<Surface> spheres = of_kind(surfaces, SurfaceKind::kSphere);
  ASSERT_EQ(spheres.size(), 1u);
  EXPECT_NEAR(spheres[0].radius, 25, 0.02 * 25);
  EXPECT_LT(spheres[0].point.norm(), 0.25);
  EXPECT_TRUE(spheres[0].outward);
  const std::vector<Surface> cylinders = of_kind(surfaces, SurfaceKind::kCylinder);
  ASSERT_EQ(cylinders.size(), 3u);
  for (int axis = 0; axis < 3; ++axis) {
    const Vector3d e = Vector3d::Unit(axis);
    int found = 0;
    for (const Surface& c : cylinders) {
      if (line_angle_deg(c.direction, e) > 1) continue;
      ++found;
      EXPECT_NEAR(c.radius, 12.5, 0.02 * 12.5);
      EXPECT_FALSE(c.outward);
      EXPECT_LT(distance_to_line(Vector3d::Zero(), c.point, c.direction), 0.125);
      EXPECT_NEAR(c.angular_coverage, 1.0, 1e-9);
    }
    EXPECT_EQ(found, 1) << "axis " << axis;
  }
}

// example004: cube(30, center = true) minus sphere(r = 20).
TEST(DetectSurfaces, Example004IsSixPlanesAndASphericalCavity) {
  const TriangleMesh mesh = read_mesh_file(kData / "scad/Old/example004.ref.off");
  const std::vector<Surface> surfaces = detect_and_print("example004", mesh);
  expect_consistent(mesh, surfaces);
  ASSERT_EQ(surfaces.size(), 7u);
  const std::vector<Surface> spheres = of_kind(surfaces, SurfaceKind::kSphere);
  ASSERT_EQ(spheres.size(), 1u);
  EXPECT_NEAR(spheres[0].radius, 20, 0.02 * 20);
  EXPECT_LT(spheres[0].point.norm(), 0.2);
  EXPECT_FALSE(spheres[0].outward);
  const std::vector<Surface> planes = of_kind(surfaces, SurfaceKind::kPlane);
  ASSERT_EQ(planes.size(), 6u);
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {-1.0, 1.0}) {
      const Vector3d n = sign * Vector3d::Unit(axis);
      const Surface* p = plane_facing(planes, n);
      EXPECT_GT(p->direction.dot(n), std::cos(0.1 * kPi / 180));
      EXPECT_NEAR(p->point.dot(n), 15, 1e-6);
    }
  }
}

// example003: a cube (30) with three bars (40 x 15 x 15) minus three bars (50 x 10 x 10): 24
// planes, faces at 15, 20, 7.5 (out of the solid) and 5 (into the tunnels) on each axis.
TEST(DetectSurfaces, Example003IsTwentyFourPlanes) {
  const TriangleMesh mesh = read_mesh_file(kData / "scad/Old/example003.ref.off");
  const std::vector<Surface> surfaces = detect_and_print("example003", mesh);
  expect_consistent(mesh, surfaces);
  ASSERT_EQ(surfaces.size(), 24u);
  std::vector<double> offsets;
  for (const Surface& s : surfaces) {
    ASSERT_EQ(s.kind, SurfaceKind::kPlane);
    Eigen::Index axis = 0;
    EXPECT_GT(s.direction.cwiseAbs().maxCoeff(&axis), 1 - 1e-9);
    offsets.push_back(std::round(s.point[axis] * s.direction[axis] * 2) / 2);
  }
  std::sort(offsets.begin(), offsets.end());
  const std::vector<double> expected = {-5, -5, -5, -5, -5, -5, 7.5, 7.5, 7.5, 7.5, 7.5, 7.5,
                                        15, 15, 15, 15, 15, 15, 20,  20,  20,  20,  20,  20};
  EXPECT_EQ(offsets, expected);
}

// CSG.scad: cube(15) with sphere(10): their union at x = -24 and difference at x = 24, their
// intersection at 0. The faces y = +-7.5 and z = +-7.5 of the three cubes are one plane each.
TEST(DetectSurfaces, CsgExampleHasThreeSpheresAndTenPlanes) {
  const TriangleMesh mesh = read_mesh_file(kData / "scad/Basics/CSG.ref.off");
  const std::vector<Surface> surfaces = detect_and_print("CSG", mesh);
  expect_consistent(mesh, surfaces);
  const std::vector<Surface> spheres = of_kind(surfaces, SurfaceKind::kSphere);
  ASSERT_EQ(spheres.size(), 3u);
  for (const Surface& s : spheres) {
    EXPECT_NEAR(s.radius, 10, 0.02 * 10);
    EXPECT_NEAR(s.point.y(), 0, 0.1);
    EXPECT_NEAR(s.point.z(), 0, 0.1);
    const double x = s.point.x();
    EXPECT_TRUE(std::abs(x + 24) < 0.1 || std::abs(x) < 0.1 || std::abs(x - 24) < 0.1) << x;
    // Only the difference's sphere is a cavity.
    EXPECT_EQ(s.outward, x < 12);
  }
  EXPECT_EQ(of_kind(surfaces, SurfaceKind::kPlane).size(), 10u);
  EXPECT_EQ(surfaces.size(), 13u);
}

// logo.scad: sphere(d = 50) minus three cylinders (d = 25), $fn = 100.
TEST(DetectSurfaces, LogoIsASphereAndThreeHoles) {
  const TriangleMesh mesh = read_mesh_file(kData / "scad/Basics/logo.ref.off");
  const std::vector<Surface> surfaces = detect_and_print("logo", mesh);
  expect_consistent(mesh, surfaces);
  ASSERT_EQ(surfaces.size(), 4u);
  ASSERT_EQ(of_kind(surfaces, SurfaceKind::kSphere).size(), 1u);
  EXPECT_NEAR(of_kind(surfaces, SurfaceKind::kSphere)[0].radius, 25, 0.01 * 25);
  const std::vector<Surface> cylinders = of_kind(surfaces, SurfaceKind::kCylinder);
  ASSERT_EQ(cylinders.size(), 3u);
  for (const Surface& c : cylinders) {
    EXPECT_NEAR(c.radius, 12.5, 0.01 * 12.5);
    EXPECT_FALSE(c.outward);
  }
}

// cgal_pipe: a tube along y (outer radius 0.311, inner 0.1706, 40 sides, from y = -0.5 to 0.5).
TEST(DetectSurfaces, CgalPipeIsTwoCylindersAndTwoPlanes) {
  const TriangleMesh mesh = read_mesh_file(kData / "meshes/cad/cgal_pipe.off");
  const std::vector<Surface> surfaces = detect_and_print("cgal_pipe", mesh);
  expect_consistent(mesh, surfaces);
  ASSERT_EQ(surfaces.size(), 4u);
  const std::vector<Surface> cylinders = of_kind(surfaces, SurfaceKind::kCylinder);
  ASSERT_EQ(cylinders.size(), 2u);
  const Surface& outer = cylinders[0].radius > cylinders[1].radius ? cylinders[0] : cylinders[1];
  const Surface& inner = cylinders[0].radius > cylinders[1].radius ? cylinders[1] : cylinders[0];
  EXPECT_NEAR(outer.radius, 0.311, 0.003);
  EXPECT_TRUE(outer.outward);
  EXPECT_NEAR(inner.radius, 0.1706, 0.002);
  EXPECT_FALSE(inner.outward);
  for (const Surface* c : {&outer, &inner}) {
    EXPECT_LT(line_angle_deg(c->direction, Vector3d::UnitY()), 1.0);
    EXPECT_NEAR(c->axial_min, -0.5, 1e-3);
    EXPECT_NEAR(c->axial_max, 0.5, 1e-3);
  }
  const std::vector<Surface> planes = of_kind(surfaces, SurfaceKind::kPlane);
  ASSERT_EQ(planes.size(), 2u);
  for (const Surface& p : planes) {
    EXPECT_GT(std::abs(p.direction.y()), 1 - 1e-9);
    EXPECT_NEAR(p.point.y() * p.direction.y(), 0.5, 1e-6);
  }
}

// cgal_u: a plate (z = +-0.0804) with drafted sides (5 degrees) and a round cut-out, open on one
// side: planes and one cylinder, the cut-out, facing its axis.
TEST(DetectSurfaces, CgalUIsPlanesAndAHole) {
  const TriangleMesh mesh = read_mesh_file(kData / "meshes/cad/cgal_u.off");
  const std::vector<Surface> surfaces = detect_and_print("cgal_u", mesh);
  expect_consistent(mesh, surfaces);
  const std::vector<Surface> cylinders = of_kind(surfaces, SurfaceKind::kCylinder);
  ASSERT_EQ(cylinders.size(), 1u);
  EXPECT_FALSE(cylinders[0].outward);
  EXPECT_LT(line_angle_deg(cylinders[0].direction, Vector3d::UnitZ()), 1.0);
  EXPECT_NEAR(cylinders[0].radius, 0.186, 0.004);
  EXPECT_GT(cylinders[0].angular_coverage, 0.6);
  EXPECT_LT(cylinders[0].angular_coverage, 0.95);
  const std::vector<Surface> planes = of_kind(surfaces, SurfaceKind::kPlane);
  EXPECT_EQ(planes.size() + 1, surfaces.size());
  ASSERT_GE(planes.size(), 2u);
  // The two largest: the plate's faces.
  EXPECT_GT(std::abs(planes[0].direction.z()), 1 - 1e-9);
  EXPECT_GT(std::abs(planes[1].direction.z()), 1 - 1e-9);
  EXPECT_LT(planes[0].direction.z() * planes[1].direction.z(), 0);
  // Every triangle is explained.
  std::size_t explained = 0;
  for (const Surface& s : surfaces) explained += s.triangles.size();
  EXPECT_EQ(explained, mesh.triangles.size());
}

// cgal_cross: a plus-shaped plate (arms 0.2 wide, 1 across, 0.2 thick). The four end faces of
// its arms lie within the tolerances of one cylinder around z (through their corners, 0.51 from
// the axis); they are four planes all the same, like the rest.
TEST(DetectSurfaces, CgalCrossIsTenPlanes) {
  const TriangleMesh mesh = read_mesh_file(kData / "meshes/cad/cgal_cross.off");
  const std::vector<Surface> surfaces = detect_and_print("cgal_cross", mesh);
  expect_consistent(mesh, surfaces);
  ASSERT_EQ(surfaces.size(), 10u);
  std::vector<double> offsets;
  for (const Surface& s : surfaces) {
    ASSERT_EQ(s.kind, SurfaceKind::kPlane);
    Eigen::Index axis = 0;
    EXPECT_GT(s.direction.cwiseAbs().maxCoeff(&axis), 1 - 1e-9);
    offsets.push_back(std::round(s.point[axis] * s.direction[axis] * 10) / 10);
  }
  std::sort(offsets.begin(), offsets.end());
  // Top and bottom (0.1), the arms' sides (0.1, each plane two faces), the arms' ends (0.5).
  const std::vector<double> expected = {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.5, 0.5, 0.5, 0.5};
  EXPECT_EQ(offsets, expected);
}

// cgal_couplingdown: a coupling with holes and 45-degree chamfers; the chamfers are cones.
TEST(DetectSurfaces, CgalCouplingChamfersAreCones) {
  const TriangleMesh mesh = read_mesh_file(kData / "meshes/cad/cgal_couplingdown.off");
  const std::vector<Surface> surfaces = detect_and_print("cgal_couplingdown", mesh);
  expect_consistent(mesh, surfaces);
  const std::vector<Surface> cones = of_kind(surfaces, SurfaceKind::kCone);
  ASSERT_GE(cones.size(), 2u);
  for (const Surface& c : cones) {
    EXPECT_NEAR(c.half_angle, kPi / 4, 0.5 * kPi / 180);
    EXPECT_LT(line_angle_deg(c.direction, Vector3d::UnitZ()), 1.0);
  }
  EXPECT_TRUE(of_kind(surfaces, SurfaceKind::kSphere).empty());
  EXPECT_TRUE(of_kind(surfaces, SurfaceKind::kTorus).empty());
  const std::vector<Surface> cylinders = of_kind(surfaces, SurfaceKind::kCylinder);
  ASSERT_FALSE(cylinders.empty());
  // The largest cylinder: the body, radius 0.5.
  EXPECT_NEAR(cylinders[0].radius, 0.5, 0.005);
  EXPECT_TRUE(cylinders[0].outward);
}

}  // namespace
}  // namespace fuzzycsg::convert
