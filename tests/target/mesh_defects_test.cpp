// Defects of meshes (find_mesh_defects, mesh_defect): the test data's good meshes pass, its
// defective ones are named with their counts, and small meshes built here have each defect (or a
// seam that welding or a T-junction closes) once.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fuzzycsg/target/mesh_file.hpp"
#include "mesh_support.hpp"
#include "test_support.hpp"

namespace fuzzycsg::test {
namespace {

namespace fs = std::filesystem;

TriangleMesh triangulated(const PolyMesh& m) {
  TriangleMesh t;
  t.vertices = m.vertices;
  t.triangles = m.triangles();
  return t;
}

// Two meshes as one: the second's vertices after the first's.
PolyMesh merged(PolyMesh a, const PolyMesh& b) {
  const int base = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto f : b.faces) {
    for (int& i : f) i += base;
    a.faces.push_back(f);
  }
  return a;
}

// Every face with vertices of its own (as STL, or a reader that splits vertices by normal).
PolyMesh unshared(const PolyMesh& m) {
  PolyMesh out;
  for (const auto& f : m.faces) {
    std::vector<int> g;
    for (const int i : f) {
      g.push_back(static_cast<int>(out.vertices.size()));
      out.vertices.push_back(m.vertices[static_cast<std::size_t>(i)]);
    }
    out.faces.push_back(g);
  }
  return out;
}

std::string defect(const PolyMesh& m) { return mesh_defect(triangulated(m)).value_or("none"); }

// The meshes of the test data as read_mesh_file reads them: the CAD parts, the OpenSCAD
// reference meshes, and the coupling as OBJ too.
std::vector<fs::path> good_meshes() {
  std::vector<fs::path> paths;
  for (const char* dir : {"meshes/cad", "scad/Basics", "scad/Old"}) {
    for (const auto& entry : fs::directory_iterator(fs::path(FUZZYCSG_TEST_DATA_DIR) / dir)) {
      const std::string name = entry.path().filename().string();
      const bool cad = std::string(dir) == "meshes/cad";
      if ((cad && (name.ends_with(".off") || name.ends_with(".obj"))) ||
          name.ends_with(".ref.off")) {
        paths.push_back(entry.path());
      }
    }
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

TEST(MeshDefects, TheTestDatasGoodMeshesAreClosedAndOriented) {
  const std::vector<fs::path> paths = good_meshes();
  ASSERT_EQ(paths.size(), 15u);  // 9 CAD parts (the coupling as OBJ too), 5 OpenSCAD references
  for (const fs::path& path : paths) {
    SCOPED_TRACE(path.filename().string());
    const TriangleMesh mesh = read_mesh_file(path);
    EXPECT_EQ(mesh_defect(mesh), std::nullopt);
    const MeshDefects d = find_mesh_defects(mesh);
    EXPECT_TRUE(d.closed_oriented());
    EXPECT_EQ(d.triangles, mesh.triangles.size());
    // Every edge in two triangles: 3 edges for every 2 triangles.
    EXPECT_EQ(2 * d.edges, 3 * (d.triangles - d.degenerate_triangles));
  }
}

TEST(MeshDefects, TheDefectiveMeshesAreOpen) {
  // Counted independently (vertices welded by position, faces' edges counted): the cylinder is
  // an open sheet with 136 boundary edges, the blade a tube open at both ends, 240.
  const TriangleMesh cylinder = read_mesh_file(data_file("meshes/defective/cgal_cylinder.off"));
  EXPECT_EQ(mesh_defect(cylinder), "mesh is open: 136 boundary edges");
  const TriangleMesh blade = read_mesh_file(data_file("meshes/defective/cgal_blade.off"));
  EXPECT_EQ(mesh_defect(blade), "mesh is open: 240 boundary edges");
  const MeshDefects d = find_mesh_defects(blade);
  EXPECT_EQ(d.nonmanifold_edges, 0u);
  EXPECT_EQ(d.misoriented_edges, 0u);
  EXPECT_EQ(d.t_junctions, 0u);
}

TEST(MeshDefects, EachDefectOfABox) {
  const PolyMesh cube = box({0, 0, 0}, {1, 1, 1});
  EXPECT_EQ(defect(cube), "none");
  EXPECT_EQ(defect(reversed(cube)), "none");  // inside out, but consistently

  TriangleMesh open = triangulated(cube);
  open.triangles.pop_back();
  EXPECT_EQ(mesh_defect(open), "mesh is open: 3 boundary edges");

  TriangleMesh flipped = triangulated(cube);
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  EXPECT_EQ(mesh_defect(flipped),
            "mesh is not consistently oriented: 3 edges run the same way in both of their "
            "triangles");

  // Two boxes that share the edge x = y = 1: four triangles meet at it.
  const PolyMesh pair = merged(cube, box({1, 1, 0}, {2, 2, 1}));
  EXPECT_EQ(defect(pair), "mesh is not manifold: 1 edge in more than two triangles");
  // Two boxes that share a whole face: the face's four edges and its diagonal, four times.
  EXPECT_EQ(defect(merged(cube, box({1, 0, 0}, {2, 1, 1}))),
            "mesh is not manifold: 5 edges in more than two triangles");

  // Several defects at once, in one line.
  TriangleMesh both = triangulated(pair);
  both.triangles.pop_back();
  EXPECT_EQ(mesh_defect(both),
            "mesh is open: 3 boundary edges; mesh is not manifold: 1 edge in more than two "
            "triangles");
}

TEST(MeshDefects, EmptyAndBrokenMeshes) {
  EXPECT_EQ(mesh_defect(TriangleMesh{}), "mesh is empty: no triangles");
  TriangleMesh points;
  points.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  points.triangles = {{0, 0, 1}, {0, 1, 2}};  // a repeated corner, and three on a line
  EXPECT_EQ(mesh_defect(points), "mesh is empty: all 2 triangles are degenerate");
  EXPECT_EQ(find_mesh_defects(points).degenerate_triangles, 2u);
  TriangleMesh beyond = triangulated(box({0, 0, 0}, {1, 1, 1}));
  beyond.triangles[3][1] = 8;
  EXPECT_EQ(mesh_defect(beyond), "mesh has 1 bad corner (not finite, or not one of its vertices)");
  beyond.triangles[3][1] = 1;
  beyond.vertices[2][0] = std::nan("");
  EXPECT_EQ(mesh_defect(beyond).value_or("none").rfind("mesh has ", 0), 0u);
}

TEST(MeshDefects, CoincidentVerticesAreWelded) {
  const PolyMesh cube = box({0, 0, 0}, {1, 1, 1});
  PolyMesh split = unshared(cube);  // 24 vertices, each corner three times
  EXPECT_EQ(defect(split), "none");
  EXPECT_EQ(find_mesh_defects(triangulated(split)).welded_vertices, 0u);  // all exactly equal
  // Later copies of two corners rounded apart by 1e-12 (the diagonal is sqrt 3): still one vertex
  // each. Vertex 10 is corner 5's second copy (the first is 5), 9 corner 1's (the first is 3).
  split.vertices[10][0] += 1e-12;
  split.vertices[9][2] -= 1e-12;
  EXPECT_EQ(defect(split), "none");
  EXPECT_EQ(find_mesh_defects(triangulated(split)).welded_vertices, 2u);
  EXPECT_EQ(find_mesh_defects(triangulated(split)).vertices, 8u);
  // 1e-6 apart is a gap: the faces at that corner no longer meet.
  split.vertices[10][0] += 1e-6;
  EXPECT_EQ(defect(split).rfind("mesh is open: ", 0), 0u);
}

TEST(MeshDefects, DegenerateTrianglesAreIgnored) {
  // A repeated corner, three collinear points along an edge and a face that is one point,
  // hanging off a closed box (as in the mesh target's test of zero-area faces).
  PolyMesh mesh = box({0, 0, 0}, {1, 1, 1});
  mesh.vertices.push_back({0.5, 0, 0});
  mesh.faces.push_back({0, 0, 7});
  mesh.faces.push_back({0, 8, 1});
  mesh.faces.push_back({3, 3, 3});
  EXPECT_EQ(defect(mesh), "none");
  EXPECT_EQ(find_mesh_defects(triangulated(mesh)).degenerate_triangles, 3u);
}

// A unit box whose top face is two rectangles split across the middle of x, at (0.5, 0, 1) and
// (0.5, 1, 1): the side faces y = 0 and y = 1 keep their top edge whole, so the split corners
// are T-junctions on it. With `on_sides`, those side faces have the middle corner too, as a
// pentagon whose fan from a top corner has a triangle of zero area along the top edge.
PolyMesh box_with_split_top(bool on_sides) {
  PolyMesh m = box({0, 0, 0}, {1, 1, 1});
  m.vertices.push_back({0.5, 0, 1});  // 8
  m.vertices.push_back({0.5, 1, 1});  // 9
  // box(): vertex k is at (k & 1, k & 2, k & 4); faces 1 (z = 1), 2 (y = 0) and 3 (y = 1).
  m.faces[1] = {4, 8, 9, 6};
  m.faces.push_back({8, 5, 7, 9});
  if (on_sides) {
    m.faces[2] = {5, 8, 4, 0, 1};  // fan from 5: (5, 8, 4) on a line, (5, 4, 0), (5, 0, 1)
    m.faces[3] = {6, 9, 7, 3, 2};  // fan from 6: (6, 9, 7) on a line, (6, 7, 3), (6, 3, 2)
  }
  return m;
}

TEST(MeshDefects, TJunctionsAreClosed) {
  const PolyMesh t_junctions = box_with_split_top(false);
  EXPECT_EQ(defect(t_junctions), "none");
  const MeshDefects d = find_mesh_defects(triangulated(t_junctions));
  EXPECT_EQ(d.t_junctions, 2u);
  EXPECT_EQ(d.boundary_edges, 0u);
  EXPECT_EQ(d.vertices, 10u);
  // With the corners on the sides as well, the fans' triangles of zero area along the top edges
  // are ignored: the rest of each side meets the top as at a T-junction, closed the same way.
  const PolyMesh fans = box_with_split_top(true);
  EXPECT_EQ(defect(fans), "none");
  const MeshDefects f = find_mesh_defects(triangulated(fans));
  EXPECT_EQ(f.degenerate_triangles, 2u);
  EXPECT_EQ(f.t_junctions, 2u);
  // A T-junction whose corner is off the edge by more than the tolerance is a gap.
  PolyMesh gap = t_junctions;
  gap.vertices[8][2] += 1e-6;
  EXPECT_EQ(defect(gap).rfind("mesh is open: ", 0), 0u);
}

TEST(MeshDefects, PolygonsTriangulatedByTheReader) {
  // read_mesh_file triangulates polygons itself (assimp): a pentagon with three corners on a
  // line, and quads beside T-junctions, read back closed.
  TempDir dir;
  for (const bool on_sides : {false, true}) {
    SCOPED_TRACE(on_sides);
    const PolyMesh m = box_with_split_top(on_sides);
    const TriangleMesh read = read_mesh_file(dir.write("split.off", to_off(m)));
    EXPECT_EQ(mesh_defect(read), std::nullopt);
    const TriangleMesh obj = read_mesh_file(dir.write("split.obj", to_obj(m)));
    EXPECT_EQ(mesh_defect(obj), std::nullopt);
  }
  const TriangleMesh cube =
      read_mesh_file(dir.write("cube.stl", to_stl_binary(box({0, 0, 0}, {1, 2, 3}))));
  EXPECT_EQ(mesh_defect(cube), std::nullopt);
}

}  // namespace
}  // namespace fuzzycsg::test
