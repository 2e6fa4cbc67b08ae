// Mesh targets: the four formats, normalisation, inside/outside against exact volumes computed
// here without assimp or Embree, boundary samples on the surface with outward normals, open
// meshes, and bad files.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/mesh_file.hpp"
#include "fuzzycsg/target/target.hpp"
#include "mesh_support.hpp"
#include "test_support.hpp"

namespace fuzzycsg::test {
namespace {

using namespace std::string_literals;

Vec3 at(const std::vector<float>& v, std::size_t i) {
  return {v[i * 3], v[i * 3 + 1], v[i * 3 + 2]};
}

// Checks every label of a box target against the box |x_i| <= half[i], except at points within
// 1e-4 of its faces; the grid points include the faces' planes and the box's axes.
void expect_exact_box(const Target& target, const Vec3& half) {
  std::vector<float> points;
  for (int i = 0; i <= 40; ++i) {
    for (int j = 0; j <= 40; ++j) {
      for (int k = 0; k <= 40; ++k) {
        points.insert(points.end(), {-1 + i / 20.0f, -1 + j / 20.0f, -1 + k / 20.0f});
      }
    }
  }
  Rng rng(7);
  const std::vector<float> random = uniform_points(3, 20000, rng);
  points.insert(points.end(), random.begin(), random.end());
  std::vector<float> occ(points.size() / 3);
  target.occupancy(points, occ);
  int checked = 0;
  for (std::size_t p = 0; p < occ.size(); ++p) {
    const Vec3 x = at(points, p);
    double gap = 1e9;  // distance to the nearest face plane
    bool inside = true;
    for (int i = 0; i < 3; ++i) {
      gap = std::min(gap, std::abs(std::abs(x[i]) - half[i]));
      inside = inside && std::abs(x[i]) < half[i];
    }
    if (gap < 1e-4) continue;
    ++checked;
    ASSERT_EQ(occ[p], inside ? 1.0f : 0.0f) << "at " << x[0] << " " << x[1] << " " << x[2];
  }
  EXPECT_GT(checked, 70000);
}

// Boundary samples of a box: on its faces, normals the faces' outward axes, spread over the
// faces in proportion to their areas and uniformly within each.
void expect_box_boundary(const Target& target, const Vec3& half) {
  Rng rng(3);
  std::vector<float> points, normals;
  const std::size_t n = 20000;
  target.sample_boundary(n, rng, points, normals);
  ASSERT_EQ(points.size(), n * 3);
  ASSERT_EQ(normals.size(), n * 3);
  std::array<int, 3> per_axis{};
  std::array<int, 16> cells{};  // where on its face each sample lies, 4 x 4 cells per face
  for (std::size_t s = 0; s < n; ++s) {
    const Vec3 p = at(points, s), nrm = at(normals, s);
    int axis = -1;
    for (int i = 0; i < 3; ++i) {
      if (std::abs(nrm[i]) > 0.5) axis = i;
    }
    ASSERT_GE(axis, 0);
    ++per_axis[axis];
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const auto cell = [&](int i) {
      return std::clamp(static_cast<int>((p[i] / half[i] + 1) * 2), 0, 3);
    };
    ++cells[cell(u) * 4 + cell(v)];
    EXPECT_NEAR(p[axis], nrm[axis] > 0 ? half[axis] : -half[axis], 1e-6);
    EXPECT_NEAR(std::abs(nrm[axis]), 1.0, 1e-6);
    for (int i = 0; i < 3; ++i) EXPECT_LE(std::abs(p[i]), half[i] + 1e-6);
  }
  // Face pair normal to axis i has area 8 * half[j] * half[k].
  const double areas[3] = {half[1] * half[2], half[0] * half[2], half[0] * half[1]};
  const double total = areas[0] + areas[1] + areas[2];
  for (int i = 0; i < 3; ++i) {
    const double p = areas[i] / total;
    EXPECT_NEAR(per_axis[i] / static_cast<double>(n), p, tolerance(p, n)) << "axis " << i;
  }
  // Uniform within the faces too (each face is two triangles).
  for (int c = 0; c < 16; ++c) {
    EXPECT_NEAR(cells[c] / static_cast<double>(n), 1.0 / 16, tolerance(1.0 / 16, n)) << c;
  }
}

TEST(MeshTarget, BoxInEveryFormat) {
  TempDir dir;
  // Extents 4 x 1 x 0.5, off the origin: normalised to half-extents 0.8, 0.2, 0.1 about it.
  const PolyMesh mesh = box({-1, 0, 2}, {3, 1, 2.5});
  const Vec3 half = {0.8, 0.2, 0.1};
  const std::vector<std::pair<std::string, std::string>> files = {
      {"box.obj", to_obj(mesh)},
      {"box.off", to_off(mesh)},
      {"box.ply", to_ply(mesh)},
      {"box_ascii.stl", to_stl_ascii(mesh)},
      {"box_binary.stl", to_stl_binary(mesh)},
      {"BOX.OBJ", to_obj(mesh)}};
  for (const auto& [name, bytes] : files) {
    SCOPED_TRACE(name);
    const auto target = load_target(dir.write(name, bytes));
    EXPECT_EQ(target->kind(), "mesh");
    EXPECT_EQ(target->dim(), 3);
    EXPECT_EQ(target->describe(), "mesh " + name + ": 12 triangles");
    expect_exact_box(*target, half);
    expect_box_boundary(*target, half);
    const std::size_t n = 200000;
    const double exact = 0.8 * 0.2 * 0.1;  // the box's share of [-1, 1]^3
    EXPECT_NEAR(inside_fraction(*target, n, 11), exact, tolerance(exact, n));
  }
}

TEST(MeshTarget, InwardFacingTrianglesGetOutwardNormals) {
  TempDir dir;
  const auto target =
      load_target(dir.write("inverted.off", to_off(reversed(box({0, 0, 0}, {2, 1, 1})))));
  expect_exact_box(*target, {0.8, 0.4, 0.4});
  expect_box_boundary(*target, {0.8, 0.4, 0.4});
}

TEST(MeshTarget, Padding) {
  TempDir dir;
  const std::string path = dir.write("box.ply", to_ply(box({-1, -2, -3}, {1, 2, 3})));
  for (double padding : {0.0, 0.2, 0.5}) {
    const double s = (1 - padding) / 3;  // the largest half-extent, 3, becomes 1 - padding
    const auto target = load_target(path, TargetOptions{padding, 256, 0});
    expect_exact_box(*target, {s, 2 * s, 3 * s});
  }
  EXPECT_EQ(load_error(path, TargetOptions{1.0, 256, 0}),
            path + ": padding must be in [0, 1) (got 1)");
  EXPECT_EQ(load_error(path, TargetOptions{-0.1, 256, 0}),
            path + ": padding must be in [0, 1) (got -0.1)");
  EXPECT_EQ(load_error(path, TargetOptions{0.2, 256, -1}),
            path + ": threads must be >= 0 (got -1)");
}

TEST(MeshTarget, SeveralObjectsInOneFile) {
  TempDir dir;
  // Two unit cubes 2 apart along x; assimp makes one mesh per object.
  const PolyMesh a = box({0, 0, 0}, {1, 1, 1}), b = box({2, 0, 0}, {3, 1, 1});
  std::string obj = "o first\n" + to_obj(a) + "o second\n";
  for (const auto& p : b.vertices)
    obj += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) +
           "\n";
  for (const auto& f : b.faces) {
    obj += "f";
    for (int i : f) obj += " " + std::to_string(i + 9);
    obj += "\n";
  }
  const auto target = load_target(dir.write("two.obj", obj));
  EXPECT_EQ(target->describe(), "mesh two.obj: 24 triangles");
  // Normalised: x in [-0.8, 0.8], the cubes 1.6 / 3 wide, so each fills (1.6 / 3)^3 / 8.
  const double exact = 2 * std::pow(1.6 / 3, 3) / 8;
  const std::size_t n = 200000;
  EXPECT_NEAR(inside_fraction(*target, n, 5), exact, tolerance(exact, n));
  std::vector<float> occ(3);
  target->occupancy(std::vector<float>{-0.5f, 0, 0, 0, 0, 0, 0.5f, 0, 0}, occ);
  EXPECT_EQ(occ, (std::vector<float>{1, 0, 1}));
}

TEST(MeshTarget, SphereAgainstExactAndAnalyticVolume) {
  TempDir dir;
  const PolyMesh sphere = icosphere(4, 2.0);  // 5120 triangles
  const auto target = load_target(dir.write("sphere.obj", to_obj(sphere)));
  EXPECT_EQ(target->describe(), "mesh sphere.obj: 5120 triangles");
  const PolyMesh normal = normalised(sphere, 0.2);
  const double polyhedron = volume(normal) / 8, ball = 4.0 / 3.0 * M_PI * 0.512 / 8;
  ASSERT_GT(polyhedron, 0.99 * ball);
  const std::size_t n = 400000;
  const double fraction = inside_fraction(*target, n, 2);
  EXPECT_NEAR(fraction, polyhedron, tolerance(polyhedron, n));
  EXPECT_NEAR(fraction, ball, tolerance(ball, n, 0.01 * ball));

  Rng rng(9);
  std::vector<float> points, normals;
  target->sample_boundary(300, rng, points, normals);
  for (std::size_t s = 0; s < 300; ++s) {
    const Vec3 p = at(points, s), nrm = at(normals, s);
    EXPECT_LT(distance_to_mesh(p, normal), 1e-6);
    EXPECT_NEAR(norm(nrm), 1.0, 1e-6);
    EXPECT_GT(dot(nrm, p) / norm(p), 0.99);  // radial, outward
    EXPECT_GT(norm(p), 0.8 * 0.99);
  }
}

// Each CAD mesh of tests/data: the inside fraction of uniform points against the exact
// volume of the polygon mesh read here, and the describe() line.
TEST(MeshTarget, CadMeshes) {
  const std::map<std::string, int> triangles = {
      {"cgal_P.off", 52},        {"cgal_corner.off", 28},     {"cgal_couplingdown.off", 3714},
      {"cgal_cross.off", 76},    {"cgal_fandisk.off", 12946}, {"cgal_hole.off", 40},
      {"cgal_pinion.off", 1300}, {"cgal_pipe.off", 320},      {"cgal_u.off", 168}};
  for (const auto& [name, count] : triangles) {
    SCOPED_TRACE(name);
    const std::string path = data_file("meshes/cad/" + name);
    const auto target = load_target(path);
    EXPECT_EQ(target->describe(), "mesh " + name + ": " + std::to_string(count) + " triangles");
    const double exact = volume(normalised(read_off(path), 0.2)) / 8;
    const std::size_t n = 400000;
    EXPECT_NEAR(inside_fraction(*target, n, 17), exact, tolerance(exact, n));
  }
}

// A CAD part read from OBJ (the coupling, genus 9, with thin walls between its holes): its
// largest half-extent after normalisation, the inside fraction, boundary samples on the surface
// with outward normals, and speed.
TEST(MeshTarget, ObjCoupling) {
  const std::string path = data_file("meshes/cad/cgal_couplingdown.obj");
  const PolyMesh mesh = normalised(read_obj(path), 0.2);
  const auto t0 = std::chrono::steady_clock::now();
  const auto target = load_target(path, TargetOptions{0.2, 256, 2});
  const auto t1 = std::chrono::steady_clock::now();
  Rng rng(1);
  const std::vector<float> uniform = uniform_points(3, 100000, rng);
  std::vector<float> occ(100000);
  target->occupancy(uniform, occ);
  const auto t2 = std::chrono::steady_clock::now();
  const double load_s = std::chrono::duration<double>(t1 - t0).count();
  const double label_s = std::chrono::duration<double>(t2 - t1).count();
  std::printf("cgal_couplingdown.obj on 2 threads: load %.3f s, 100000 labels %.3f s\n", load_s,
              label_s);
#if !defined(__SANITIZE_ADDRESS__)
  EXPECT_LT(load_s + label_s, 1.0);
#endif

  double inside = 0;
  for (float o : occ) inside += o;
  const double exact = volume(mesh) / 8;
  EXPECT_NEAR(inside / 100000, exact, tolerance(exact, 100000));

  std::vector<float> points, normals;
  target->sample_boundary(20000, rng, points, normals);
  float extent = 0;
  for (float x : points) extent = std::max(extent, std::abs(x));
  EXPECT_NEAR(extent, 0.8f, 2e-3);  // samples come near the extreme faces
  EXPECT_LE(extent, 0.8f + 1e-6f);
  Vec3 lo, hi;
  bounding_box(mesh, lo, hi);
  double max_half = 0;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(lo[i], -hi[i], 1e-9);  // centred
    max_half = std::max(max_half, hi[i]);
  }
  EXPECT_NEAR(max_half, 0.8, 1e-12);

  for (std::size_t s = 0; s < 200; ++s) EXPECT_LT(distance_to_mesh(at(points, s), mesh), 1e-5);
  // Normals: a step along the normal leaves the solid, a step against it enters it, at almost
  // every sample (not at those within the step of an edge or of a thin part).
  std::vector<float> probes;
  const float eps = 1e-3f;
  for (std::size_t s = 0; s < 20000; ++s) {
    for (float sign : {1.0f, -1.0f}) {
      for (int i = 0; i < 3; ++i)
        probes.push_back(points[s * 3 + i] + sign * eps * normals[s * 3 + i]);
    }
  }
  std::vector<float> labels(probes.size() / 3);
  target->occupancy(probes, labels);
  int good = 0;
  for (std::size_t s = 0; s < 20000; ++s)
    good += labels[2 * s] == 0.0f && labels[2 * s + 1] == 1.0f;
  EXPECT_GT(good, 0.97 * 20000);
}

TEST(MeshTarget, FandiskSamplesOnSurfaceWithOutwardNormals) {
  const std::string path = data_file("meshes/cad/cgal_fandisk.off");
  const PolyMesh mesh = normalised(read_off(path), 0.2);
  const auto target = load_target(path);
  Rng rng(4);
  std::vector<float> points, normals;
  target->sample_boundary(10000, rng, points, normals);
  for (std::size_t s = 0; s < 300; ++s) EXPECT_LT(distance_to_mesh(at(points, s), mesh), 1e-5);
  std::vector<float> probes;
  for (std::size_t s = 0; s < 10000; ++s) {
    for (float sign : {1.0f, -1.0f}) {
      for (int i = 0; i < 3; ++i)
        probes.push_back(points[s * 3 + i] + sign * 1e-3f * normals[s * 3 + i]);
    }
  }
  std::vector<float> labels(probes.size() / 3);
  target->occupancy(probes, labels);
  int good = 0;
  for (std::size_t s = 0; s < 10000; ++s)
    good += labels[2 * s] == 0.0f && labels[2 * s + 1] == 1.0f;
  EXPECT_GT(good, 0.97 * 10000);
}

TEST(MeshTarget, SamplingIsDeterministic) {
  const auto target =
      load_target(data_file("meshes/cad/cgal_pinion.off"), TargetOptions{0.2, 256, 2});
  const auto same =
      load_target(data_file("meshes/cad/cgal_pinion.off"), TargetOptions{0.2, 256, 1});
  Rng a(42), b(42), c(43);
  std::vector<float> pa, na, pb, nb, pc, nc;
  target->sample_boundary(1000, a, pa, na);
  same->sample_boundary(1000, b, pb, nb);
  target->sample_boundary(1000, c, pc, nc);
  EXPECT_EQ(pa, pb);
  EXPECT_EQ(na, nb);
  EXPECT_NE(pa, pc);
  std::vector<float> oa(1000), ob(1000);
  target->occupancy(pa, oa);
  same->occupancy(pa, ob);
  EXPECT_EQ(oa, ob);
}

// Small holes: an icosphere without one of its 5120 triangles loads, and its inside fraction
// is that of the closed sphere (the rays through the hole are outvoted).
TEST(MeshTarget, SmallHoleIsHarmless) {
  TempDir dir;
  PolyMesh sphere = icosphere(4, 1.0);
  const double exact = volume(normalised(sphere, 0.2)) / 8;
  sphere.faces.erase(sphere.faces.begin() + 100);
  const auto target = load_target(dir.write("holed.stl", to_stl_binary(sphere)));
  const std::size_t n = 200000;
  EXPECT_NEAR(inside_fraction(*target, n, 8), exact, tolerance(exact, n));
}

// The two open meshes of tests/data/meshes/defective:
// - cgal_blade.off is a tube (a turbine blade's skin, 129 long, a 10 x 0.65 profile) open at
//   both ends. Rays leave through the ends only from points near them, or along the tube: the
//   mesh loads, and its inside fraction is the volume of the tube closed by two flat caps
//   (computed here) within 2%.
// - cgal_cylinder.off is half of a cylinder's side, an open sheet: rays disagree at almost
//   every point, and loading says that the mesh is not closed.
TEST(MeshTarget, DefectiveMeshes) {
  const std::string blade_path = data_file("meshes/defective/cgal_blade.off");
  PolyMesh blade = read_off(blade_path);
  // Close each boundary loop with a fan about its centroid, oriented against the open edges.
  std::map<std::pair<int, int>, int> directed;
  for (const auto& f : blade.faces) {
    for (std::size_t k = 0; k < f.size(); ++k) ++directed[{f[k], f[(k + 1) % f.size()]}];
  }
  std::map<int, int> next;  // boundary edges reversed: b -> a for each open edge a -> b
  for (const auto& [e, count] : directed) {
    if (!directed.count({e.second, e.first})) next[e.second] = e.first;
  }
  ASSERT_EQ(next.size(), 240u);
  int loops = 0;
  while (!next.empty()) {
    std::vector<int> loop;
    for (int v = next.begin()->first; next.count(v);) {
      loop.push_back(v);
      const int w = next[v];
      next.erase(v);
      v = w;
    }
    Vec3 c{0, 0, 0};
    for (int v : loop) c = c + (1.0 / loop.size()) * blade.vertices[v];
    blade.vertices.push_back(c);
    const int centre = static_cast<int>(blade.vertices.size()) - 1;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      blade.faces.push_back({centre, loop[k], loop[(k + 1) % loop.size()]});
    }
    ++loops;
  }
  EXPECT_EQ(loops, 2);
  const double closed = std::abs(volume(normalised(blade, 0.2))) / 8;
  const auto target = load_target(blade_path);
  EXPECT_EQ(target->describe(), "mesh cgal_blade.off: 16222 triangles");
  // The blade fills about 1e-4 of the cube: uniform points in its bounding box instead.
  Vec3 lo, hi;
  bounding_box(normalised(read_off(blade_path), 0.2), lo, hi);
  const double box = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
  Rng rng(6);
  const std::size_t n = 200000;
  std::vector<float> points = uniform_points(3, n, rng);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int k = static_cast<int>(i % 3);
    points[i] = static_cast<float>(lo[k] + (points[i] + 1) / 2 * (hi[k] - lo[k]));
  }
  std::vector<float> occ(n);
  target->occupancy(points, occ);
  double inside = 0;
  for (float o : occ) inside += o;
  const double expected = closed * 8 / box;  // the closed tube's share of its bounding box
  EXPECT_NEAR(inside / n, expected, 0.02 * expected);

  const std::string cylinder = data_file("meshes/defective/cgal_cylinder.off");
  EXPECT_EQ(load_error(cylinder),
            cylinder +
                ": mesh is not closed: rays from 99% of test points disagree on inside "
                "and outside");
}

TEST(MeshTarget, ZeroAreaFacesAreHarmless) {
  TempDir dir;
  PolyMesh mesh = box({0, 0, 0}, {1, 1, 1});
  // A repeated corner, three collinear points, and a face that is one point.
  mesh.vertices.push_back({0.5, 0, 0});
  mesh.faces.push_back({0, 0, 7});
  mesh.faces.push_back({0, 8, 1});
  mesh.faces.push_back({3, 3, 3});
  const auto target = load_target(dir.write("degenerate.off", to_off(mesh)));
  expect_exact_box(*target, {0.8, 0.8, 0.8});
  expect_box_boundary(*target, {0.8, 0.8, 0.8});
}

TEST(MeshTarget, BadFiles) {
  TempDir dir;
  const auto expect_error = [](const std::string& path, const std::string& message) {
    const std::string e = load_error(path);
    EXPECT_EQ(e.substr(0, path.size() + 2), path + ": ") << e;
    EXPECT_NE(e.find(message), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  };
  for (const char* ext : {".obj", ".stl", ".ply", ".off"}) {
    SCOPED_TRACE(ext);
    expect_error(dir.write(std::string("empty") + ext, ""), "empty file");
    const std::string garbage =
        dir.write(std::string("garbage") + ext, "\x01\xff\x7f garbage \x00\x13, more garbage"s);
    expect_error(garbage, std::string(ext) == ".obj" ? "no triangles" : "cannot read mesh (");
    expect_error(dir.file(std::string("missing") + ext), "cannot read (No such file or directory)");
  }
  expect_error(dir.write("dir.off", "x") + "/inside.off", "cannot read (Not a directory)");
  const PolyMesh cube = box({0, 0, 0}, {1, 1, 1});
  // Not-a-number and infinite coordinates.
  std::string nan_off = to_off(cube);
  nan_off.replace(nan_off.find("\n0 0 0\n"), 7, "\nnan 0 0\n");
  expect_error(dir.write("nan.off", nan_off),
               "a vertex has a coordinate that is not a finite number");
  // A NaN that joining vertices would merge into the finite vertex beside it, in every format.
  const std::string tetra = "4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 nan\n";
  const std::string faces = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
  expect_error(dir.write("nan_tetra.off", "OFF\n" + tetra + faces),
               "nan_tetra.off: a vertex has a coordinate that is not a finite number (0 0 nan)");
  expect_error(
      dir.write("nan_tetra.obj",
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 nan\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n"),
      "nan_tetra.obj: a vertex has a coordinate that is not a finite number");
  PolyMesh huge = cube;
  huge.vertices[3][1] = 1e300;  // infinite as a float
  expect_error(dir.write("inf.stl", to_stl_binary(huge)),
               "a vertex has a coordinate that is not a finite number");
  // Flat and degenerate meshes.
  PolyMesh square;
  square.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  square.faces = {{0, 1, 2, 3}};
  expect_error(dir.write("square.ply", to_ply(square)), "mesh encloses no volume");
  PolyMesh point;
  point.vertices = {{1, 2, 3}};
  point.faces = {{0, 0, 0}};
  expect_error(dir.write("point.obj", to_obj(point)), "mesh encloses no volume");
  PolyMesh thin = cube;
  for (auto& p : thin.vertices) p[2] *= 1e-9;
  expect_error(dir.write("thin.obj", to_obj(thin)), "mesh encloses no volume");
  // A single triangle off the centre encloses a (signed) volume but is not closed.
  PolyMesh triangle;
  triangle.vertices = {{0, 0, 0}, {1, 0, 1}, {0, 1, 1}};
  triangle.faces = {{0, 1, 2}};
  expect_error(dir.write("triangle.obj", to_obj(triangle)),
               "mesh is not closed: rays from 85% of test points disagree");
  // Faces that refer to missing vertices; lines and points only.
  // (assimp clamps a bad index in an OFF file to the last vertex.)
  expect_error(dir.write("index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"),
               "mesh encloses no volume");
  expect_error(dir.write("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\nf -1 -2 -9\n"),
               "cannot read mesh (OBJ: vertex index out of range)");
  std::string truncated = to_stl_binary(cube);
  truncated.resize(84 + 50 * 3 + 20);
  expect_error(dir.write("truncated.stl", truncated),
               "cannot read mesh (Failed to determine STL storage representation for "
               "truncated.stl.)");
  // Headers that declare more elements than the file holds are refused before assimp would
  // allocate for them.
  expect_error(dir.write("huge.ply",
                         "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\n"
                         "property float x\nproperty float y\nproperty float z\nelement face 1\n"
                         "property list uchar int vertex_indices\nend_header\n\x01\x02"),
               "cannot read mesh (the header declares 2000000001 elements, more than the file's "
               "180 bytes can hold)");
  expect_error(dir.write("huge.off", "OFF\n2000000000 2000000000 0\n0 0 0\n"),
               "the header declares 4000000000 elements");
  expect_error(
      dir.write("faces.off", "# comment\nOFF 3 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
      "the header declares 2000000003 elements");
  expect_error(dir.write("hugeascii.ply",
                         "ply\nformat ascii 1.0\nelement vertex 2000000000\n"
                         "property float x\nproperty float y\nproperty float z\nelement face 1\n"
                         "property list uchar int vertex_indices\nend_header\n0 0 0\n"),
               "the header declares 2000000001 elements");
  expect_error(dir.write("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\np 1\n"),
               "no triangles");
}

// A PLY header that does not end is refused before assimp, which runs on past it: a binary
// one crashed it, an ASCII one made it loop without end.
TEST(MeshTarget, PlyHeaderWithoutEndHeaderIsRefused) {
  TempDir dir;
  const std::string message =
      "cannot read mesh (no end_header line ends the PLY header within its first 65536 bytes)";
  for (const auto& [name, text] :
       {std::pair{"binary.ply", "ply\nformat binary_little_endian 1.0\n)\0\0"s},
        std::pair{"ascii.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n0\n"s},
        std::pair{"long.ply",
                  "ply\nformat ascii 1.0\n" + std::string(70000, '\n') + "end_header\n"}}) {
    SCOPED_TRACE(name);
    const std::string path = dir.write(name, text);
    EXPECT_EQ(load_error(path), path + ": " + message);
    try {
      read_mesh_file(path);
      ADD_FAILURE() << "read_mesh_file read " << name;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), path + ": " + message);
    }
  }
}

// Faces are checked before assimp triangulates them: a truncated OFF file made a face of no
// corners, and assimp's assertion aborted the program.
TEST(MeshTarget, FacesWithoutCornersAreRefused) {
  TempDir dir;
  const std::string path = dir.write("truncated.off", "OFF\n3 1 0\n0 0 1 2\n");
  EXPECT_EQ(load_error(path), path + ": face 0 has no corners");
}

// The normalisation maps the mesh's own coordinates to the box it is labelled in: the bounding
// box centred, its longest side to 2 (1 - padding); a tree file's domain likewise; pictures none.
TEST(MeshTarget, NormalisationMapsTheMeshIntoTheBox) {
  TempDir dir;
  const std::string path = dir.write("far.off", to_off(box({10, 20, -1}, {14, 22, 0})));
  const auto target = load_target(path, TargetOptions{0.2, 256, 1});
  const Similarity n = target->normalisation();
  EXPECT_NEAR(n.scale, 0.4, 1e-15);
  const auto lo = n.apply({10, 20, -1}), hi = n.apply({14, 22, 0});
  EXPECT_NEAR(lo[0], -0.8, 1e-12);
  EXPECT_NEAR(hi[0], 0.8, 1e-12);
  EXPECT_NEAR(lo[1], -0.4, 1e-12);
  EXPECT_NEAR(hi[2], 0.2, 1e-12);
  // Labels agree: the mesh's centre maps inside, a corner beyond the box outside.
  const auto c = n.apply({12, 21, -0.5}), out = n.apply({13.9, 21.9, 0.5});
  std::vector<float> occ(2);
  target->occupancy(std::vector<float>{float(c[0]), float(c[1]), float(c[2]), float(out[0]),
                                       float(out[1]), float(out[2])},
                    occ);
  EXPECT_EQ(occ[0], 1.0f);
  EXPECT_EQ(occ[1], 0.0f);

  const std::string tree = dir.write("t.json", R"({"format": "fuzzycsg-tree", "version": 1,
    "dim": 2, "domain": {"min": [2, 0], "max": [6, 2]},
    "root": {"type": "circle", "radius": 1, "translate": [4, 1], "step": "crisp"}})");
  const Similarity t = load_target(tree)->normalisation();
  EXPECT_NEAR(t.scale, 0.5, 1e-15);
  EXPECT_NEAR(t.apply({4, 1, 0})[0], 0.0, 1e-15);
  EXPECT_NEAR(t.apply({6, 1, 0})[0], 1.0, 1e-15);
}

}  // namespace
}  // namespace fuzzycsg::test
