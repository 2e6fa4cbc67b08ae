#include "fuzzycsg/mesh/mesh.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <array>
#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <utility>

#include "fuzzycsg/core/bezier.hpp"
#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg {
namespace {

constexpr double kPi = 3.14159265358979323846;

Tree sphere_tree(double radius, const char* extra = "") {
  return io::read_tree_string(std::string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
          "root": {"type": "sphere", "radius": )") +
                                  std::to_string(radius) + R"(, "sharpness": 200)" + extra + "}}",
                              "sphere");
}

long euler_characteristic(const TriangleMesh& m) {
  // Closed: every edge in two triangles, E = 3F / 2.
  return static_cast<long>(m.vertices.size()) - static_cast<long>(m.triangles.size()) * 3 / 2 +
         static_cast<long>(m.triangles.size());
}

TEST(Mesh, SphereIsClosedOrientedAndHasItsVolume) {
  const Tree tree = sphere_tree(0.6);
  MeshOptions o;
  o.resolution = 48;
  MeshStats stats;
  const TriangleMesh m = extract_mesh(tree, tree.params.values(), o, &stats);
  ASSERT_GT(m.triangles.size(), 1000u);
  EXPECT_EQ(open_or_misoriented_edges(m), 0u);
  EXPECT_EQ(euler_characteristic(m), 2);
  const double exact = 4.0 / 3.0 * kPi * 0.6 * 0.6 * 0.6;
  EXPECT_NEAR(signed_volume(m), exact, 0.01 * exact);
  for (const auto& v : m.vertices) {
    EXPECT_NEAR(std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), 0.6, 2e-3);
  }
  // Bounds keep the evaluation near the surface.
  EXPECT_EQ(stats.grid_points, 49u * 49u * 49u);
  EXPECT_LT(stats.points_evaluated, stats.grid_points);
  EXPECT_GT(stats.boxes_bounded, 0u);
}

TEST(Mesh, HoleGivesGenusOne) {
  const Tree tree = io::read_tree_file(FUZZYCSG_SOURCE_DIR "/examples/box_with_hole.json");
  MeshOptions o;
  o.resolution = 64;
  const TriangleMesh m = extract_mesh(tree, tree.params.values(), o);
  EXPECT_EQ(open_or_misoriented_edges(m), 0u);
  EXPECT_EQ(euler_characteristic(m), 0);
  const double exact = 1.2 * 0.8 * 0.4 - kPi * 0.15 * 0.15 * 0.8;
  EXPECT_NEAR(signed_volume(m), exact, 0.03 * exact);
}

// The slotted plate of examples/extrude_bracket.json: a rounded slot (two straight sides, two
// half-round ends of radius 0.3 as cubic Béziers) 0.2 thick, with a bolt hole through one end.
TEST(Mesh, ExtrudeBracketIsClosedWithItsVolume) {
  const Tree tree = io::read_tree_file(FUZZYCSG_SOURCE_DIR "/examples/extrude_bracket.json");
  MeshOptions o;
  o.resolution = 64;
  const TriangleMesh m = extract_mesh(tree, tree.params.values(), o);
  EXPECT_EQ(open_or_misoriented_edges(m), 0u);
  EXPECT_EQ(euler_characteristic(m), 0);  // one hole
  // The profile's polygon (the cubic ends bulge up to 1.9% beyond the circle): its area by the
  // shoelace formula, less the hole, times the height.
  const std::vector<double> control = {-0.45, -0.3, -0.15, -0.3, 0.15,  -0.3, 0.45,  -0.3,
                                       0.85,  -0.3, 0.85,  0.3,  0.45,  0.3,  0.15,  0.3,
                                       -0.15, 0.3,  -0.45, 0.3,  -0.85, 0.3,  -0.85, -0.3};
  const std::vector<double> poly = bezier_profile(control);
  double area = 0.0;
  const std::size_t n = poly.size() / 2;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    area += 0.5 * (poly[2 * i] * poly[2 * j + 1] - poly[2 * j] * poly[2 * i + 1]);
  }
  EXPECT_NEAR(area, 0.9 * 0.6 + kPi * 0.3 * 0.3, 0.03);
  const double exact = (area - kPi * 0.15 * 0.15) * 0.2;
  EXPECT_NEAR(signed_volume(m), exact, 0.03 * exact);
}

// Pruning by bounds must not change the mesh: the same vertices and triangles, in the same
// order, as evaluating every grid point.
void expect_pruning_exact(const Tree& tree, int resolution, bool fewer = true,
                          bool simplify = true) {
  MeshOptions o;
  o.resolution = resolution;
  o.simplify = simplify;
  MeshStats pruned_stats, dense_stats;
  const TriangleMesh pruned = extract_mesh(tree, tree.params.values(), o, &pruned_stats);
  o.prune = false;
  const TriangleMesh dense = extract_mesh(tree, tree.params.values(), o, &dense_stats);
  ASSERT_FALSE(dense.triangles.empty());
  EXPECT_EQ(pruned.vertices, dense.vertices);
  EXPECT_EQ(pruned.triangles, dense.triangles);
  EXPECT_EQ(open_or_misoriented_edges(pruned), 0u);
  if (fewer) {
    EXPECT_LT(pruned_stats.points_evaluated, dense_stats.points_evaluated);
  }
  EXPECT_GE(dense_stats.points_evaluated, dense_stats.grid_points);
}

TEST(Mesh, PruningIsExactOnExamples) {
  expect_pruning_exact(io::read_tree_file(FUZZYCSG_SOURCE_DIR "/examples/box_with_hole.json"), 50);
  // The extrude's bounds alone: with bricks simplified, the hole's sigmoid (about 2e-8 at the
  // plate's middle, well within the simplifier's tolerance) changes the last bit of values on
  // the caps, where the level runs along grid edges, and so vertices by a few 1e-9.
  expect_pruning_exact(io::read_tree_file(FUZZYCSG_SOURCE_DIR "/examples/extrude_bracket.json"), 50,
                       true, false);
  expect_pruning_exact(sphere_tree(0.45, R"(, "translate": [0.2, -0.1, 0.05])"), 37);
}

TEST(Mesh, PruningIsExactOnRandomUnifiedQuadricTrees) {
  for (unsigned seed : {4u, 5u}) {
    FullTreeOptions o;
    o.leaves = 64;
    o.seed = seed;
    o.sharpness = 6.0;
    // Random trees have surfaces everywhere: nothing may be pruned, but nothing may change.
    expect_pruning_exact(make_full_binary_tree(o), 40, false);
  }
}

TriangleMesh expect_simplified_equal(const Tree& tree);

// Sixteen balls in a union: each brick needs one or two of them. The simplified trees give the
// same triangles as the whole tree, and vertices within rounding.
TEST(Mesh, SimplifiedBricksMatchTheWholeTree) {
  std::string children;
  for (int i = 0; i < 16; ++i) {
    const double x = -0.6 + 0.4 * (i % 4), y = -0.6 + 0.4 * (i / 4), z = 0.1 * (i % 3);
    children += fmt::format(R"({}{{"type": "sphere", "radius": 0.15, "translate": [{}, {}, {}],
        "sharpness": 60}})",
                            i ? ", " : "", x, y, z);
  }
  const Tree tree = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {"op": "union", "children": [)" +
          children + "]}}",
      "balls");
  EXPECT_EQ(euler_characteristic(expect_simplified_equal(tree)), 2 * 16);  // sixteen spheres
  // The balls carved out of a slab through a complement node (kept by the simplification).
  const Tree carved = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {"op": "intersection",
          "children": [{"type": "box", "size": [1.8, 1.8, 0.5], "translate": [0, 0, 0.1], "sharpness": 60},
                       {"op": "complement", "children": [{"op": "union", "children": [)" +
          children + "]}]}]}}",
      "carved");
  expect_simplified_equal(carved);
}

TriangleMesh expect_simplified_equal(const Tree& tree) {
  MeshOptions o;
  o.resolution = 64;
  MeshStats simple_stats, whole_stats;
  const TriangleMesh simple = extract_mesh(tree, tree.params.values(), o, &simple_stats);
  o.simplify = false;
  const TriangleMesh whole = extract_mesh(tree, tree.params.values(), o, &whole_stats);
  EXPECT_FALSE(simple.triangles.empty());
  EXPECT_EQ(simple.triangles, whole.triangles);
  EXPECT_EQ(simple.vertices.size(), whole.vertices.size());
  for (std::size_t v = 0; v < std::min(simple.vertices.size(), whole.vertices.size()); ++v) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(simple.vertices[v][c], whole.vertices[v][c], 1e-4);
  }
  EXPECT_EQ(open_or_misoriented_edges(simple), 0u);
  EXPECT_EQ(simple_stats.points_evaluated, whole_stats.points_evaluated);
  EXPECT_LT(simple_stats.leaves_evaluated * 3, whole_stats.leaves_evaluated);
  return simple;
}

TEST(Mesh, CappedAtTheDomainBoundary) {
  // A sphere larger than the domain fills it: the mesh is the domain's box, closed.
  const Tree tree = sphere_tree(1.5);
  MeshOptions o;
  o.resolution = 16;
  const TriangleMesh m = extract_mesh(tree, tree.params.values(), o);
  EXPECT_EQ(open_or_misoriented_edges(m), 0u);
  EXPECT_EQ(euler_characteristic(m), 2);
  // The boundary points count as outside, so the box ends half a cell inside.
  const double side = 2.0 - 2.0 / 16.0;
  EXPECT_NEAR(signed_volume(m), side * side * side, 0.02 * 8.0);
}

// Counted without check_mesh(): positions welded through a std::map, each triangle's corners
// and area, each undirected edge's triangles.
struct PositionCounts {
  std::size_t positions = 0;
  std::size_t repeated = 0;   // triangles with a position twice
  std::size_t zero_area = 0;  // the others with corners on a line
  std::size_t edges_not_two = 0;
};

PositionCounts count_by_position(const TriangleMesh& m) {
  std::map<std::array<double, 3>, int> ids;
  std::vector<int> id;
  for (const auto& v : m.vertices) id.push_back(ids.emplace(v, ids.size()).first->second);
  PositionCounts c;
  c.positions = ids.size();
  std::map<std::pair<int, int>, int> edges;
  for (const auto& t : m.triangles) {
    const int a = id[t[0]], b = id[t[1]], d = id[t[2]];
    if (a == b || b == d || d == a) {
      ++c.repeated;
    } else {
      const auto& p = m.vertices[t[0]];
      const auto& q = m.vertices[t[1]];
      const auto& r = m.vertices[t[2]];
      double n2 = 0.0;
      for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        const double x = (double{q[i]} - p[i]) * (double{r[j]} - p[j]) -
                         (double{q[j]} - p[j]) * (double{r[i]} - p[i]);
        n2 += x * x;
      }
      if (n2 == 0.0) ++c.zero_area;
    }
    for (const auto& [u, v] : {std::pair{a, b}, std::pair{b, d}, std::pair{d, a}}) {
      if (u != v) ++edges[{std::min(u, v), std::max(u, v)}];
    }
  }
  for (const auto& [e, n] : edges) c.edges_not_two += n != 2 ? 1 : 0;
  return c;
}

void expect_manifold_by_position(const TriangleMesh& m, const std::string& what) {
  const PositionCounts c = count_by_position(m);
  EXPECT_EQ(c.positions, m.vertices.size()) << what << ": vertices at one position";
  EXPECT_EQ(c.repeated, 0u) << what;
  EXPECT_EQ(c.zero_area, 0u) << what;
  EXPECT_EQ(c.edges_not_two, 0u) << what;
  const MeshCheck check = check_mesh(m);
  EXPECT_EQ(check.vertices, c.positions) << what;
  EXPECT_EQ(check.degenerate_triangles, c.repeated + c.zero_area) << what;
  EXPECT_EQ(check.nonmanifold_edges, c.edges_not_two) << what;
  EXPECT_TRUE(check.closed_oriented_manifold()) << what;
}

// A box whose faces lie on grid planes (at resolution 16 over [-1, 1], multiples of 1/8): the
// occupancy at the grid points on them is exactly 0.5, on the level. Vertices on the edges that
// meet at such a point used to be put on it, so that different vertices of the mesh coincided
// and their triangles collapsed (index-closed, not a manifold by position). The table's board
// sides (y = +-0.5) and its legs' feet (z = 0) are on grid planes at resolution 128, likewise.
TEST(Mesh, SurfaceThroughGridPointsIsAManifoldByPosition) {
  const Tree box = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
          "root": {"type": "box", "size": [1.0, 0.5, 0.75], "sharpness": 40}})",
      "box");
  // On the level exactly at a grid point of the face x = 0.5 (and below it just inside).
  std::vector<float> occupancy(2);
  Evaluator(box, EvalOptions{1})
      .forward(box.params.values(), std::vector<float>{0.5f, 0.0f, 0.0f, 0.375f, 0.0f, 0.0f},
               occupancy);
  ASSERT_EQ(occupancy[0], 0.5f);
  ASSERT_GT(occupancy[1], 0.5f);
  MeshOptions o;
  o.resolution = 16;
  const TriangleMesh m = extract_mesh(box, box.params.values(), o);
  ASSERT_GT(m.triangles.size(), 100u);
  EXPECT_EQ(open_or_misoriented_edges(m), 0u);
  EXPECT_EQ(euler_characteristic(m), 2);
  expect_manifold_by_position(m, "box");
  // The level runs through the grid points: vertices sit a thousandth of a cell off them.
  EXPECT_NEAR(signed_volume(m), 1.0 * 0.5 * 0.75, 0.01);
  const Tree table = io::read_tree_file(FUZZYCSG_SOURCE_DIR "/examples/table.json");
  o.resolution = 128;
  const TriangleMesh t = extract_mesh(table, table.params.values(), o);
  EXPECT_EQ(open_or_misoriented_edges(t), 0u);
  expect_manifold_by_position(t, "table");
}

TEST(MeshCheck, CountsByPositionNotIndex) {
  TriangleMesh tet;
  tet.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  MeshCheck c = check_mesh(tet);
  EXPECT_EQ(c.vertices, 4u);
  EXPECT_EQ(c.triangles, 4u);
  EXPECT_EQ(c.edges, 6u);
  EXPECT_TRUE(c.closed_oriented_manifold());
  // Vertex 3 moved onto vertex 0: closed by its indices, two triangles collapsed by position.
  TriangleMesh pinched = tet;
  pinched.vertices[3] = pinched.vertices[0];
  EXPECT_EQ(open_or_misoriented_edges(pinched), 0u);
  c = check_mesh(pinched);
  EXPECT_EQ(c.vertices, 3u);
  EXPECT_EQ(c.degenerate_triangles, 2u);
  EXPECT_FALSE(c.closed_oriented_manifold());
  // Corners on a line: zero area without a repeated position.
  TriangleMesh flat = tet;
  flat.vertices[3] = {2, 0, 0};
  EXPECT_EQ(check_mesh(flat).degenerate_triangles, 1u);  // 0, 1, 3 on the x axis
  // One triangle turned: its three edges run the same way as their other triangles'.
  TriangleMesh turned = tet;
  std::swap(turned.triangles[3][1], turned.triangles[3][2]);
  EXPECT_EQ(check_mesh(turned).misoriented_edges, 3u);
  // A triangle missing: three open edges, and its corners' fans not closed.
  TriangleMesh open = tet;
  open.triangles.pop_back();
  c = check_mesh(open);
  EXPECT_EQ(c.nonmanifold_edges, 3u);
  EXPECT_EQ(c.nonmanifold_vertices, 3u);
  // A fin on an edge: that edge in three triangles.
  TriangleMesh fin = tet;
  fin.vertices.push_back({1, 1, 1});
  fin.triangles.push_back({0, 1, 4});
  EXPECT_EQ(check_mesh(fin).nonmanifold_edges, 3u);  // 0-1 in three, 1-4 and 4-0 in one
  // Two tetrahedra touching at one corner (a separate vertex at the same position): every edge
  // in two triangles, the corner pinched.
  TriangleMesh touching = tet;
  for (const auto& v : tet.vertices) touching.vertices.push_back({-v[0], -v[1], -v[2]});
  for (const auto& t : tet.triangles) touching.triangles.push_back({t[0] + 4, t[2] + 4, t[1] + 4});
  c = check_mesh(touching);
  EXPECT_EQ(c.vertices, 7u);
  EXPECT_EQ(c.nonmanifold_edges, 0u);
  EXPECT_EQ(c.misoriented_edges, 0u);
  EXPECT_EQ(c.nonmanifold_vertices, 1u);
}

TEST(Mesh, EmptyLevelSetGivesAnEmptyMesh) {
  const Tree tree = sphere_tree(0.2, R"(, "translate": [5, 5, 5])");
  MeshStats stats;
  const TriangleMesh m = extract_mesh(tree, tree.params.values(), {}, &stats);
  EXPECT_TRUE(m.triangles.empty());
  EXPECT_EQ(stats.points_evaluated, 0u);
}

TEST(Mesh, ThreadCountDoesNotChangeTheMesh) {
  const Tree tree = io::read_tree_file(FUZZYCSG_SOURCE_DIR "/examples/box_with_hole.json");
  MeshOptions o;
  o.resolution = 40;
  o.threads = 1;
  const TriangleMesh one = extract_mesh(tree, tree.params.values(), o);
  o.threads = 2;
  o.brick = 4;
  const TriangleMesh two = extract_mesh(tree, tree.params.values(), o);
  // Another brick size visits the bricks in another order: compare as sets of triangles.
  EXPECT_EQ(one.vertices.size(), two.vertices.size());
  EXPECT_EQ(one.triangles.size(), two.triangles.size());
  EXPECT_NEAR(signed_volume(one), signed_volume(two), 1e-9);
}

TEST(Mesh, RejectsBadResolutions) {
  const Tree tree = sphere_tree(0.5);
  for (int r : {0, -3, 1000000}) {
    MeshOptions o;
    o.resolution = r;
    EXPECT_THROW(extract_mesh(tree, tree.params.values(), o), InputError) << r;
  }
  MeshOptions o;
  o.brick = 0;
  EXPECT_THROW(extract_mesh(tree, tree.params.values(), o), InputError);
  EXPECT_THROW(extract_contours(tree, tree.params.values()), InputError);  // 3D tree
}

Tree disc_with_hole() {
  return io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
          "root": {"op": "difference", "children": [
            {"type": "rectangle", "size": [1.2, 0.8], "sharpness": 200},
            {"type": "circle", "radius": 0.2, "translate": [0.1, 0], "sharpness": 200}]}})",
      "plate");
}

TEST(Contours, LoopsAreClosedOrientedAndEncloseTheArea) {
  const Tree tree = disc_with_hole();
  MeshOptions o;
  o.resolution = 200;
  const Contours c = extract_contours(tree, tree.params.values(), o);
  ASSERT_EQ(c.loops.size(), 2u);
  const double exact = 1.2 * 0.8 - kPi * 0.2 * 0.2;
  EXPECT_NEAR(contours_area(c), exact, 0.01 * exact);
  // Outer loop counter-clockwise, hole clockwise.
  int ccw = 0, cw = 0;
  for (const auto& loop : c.loops) {
    Contours one;
    one.loops = {loop};
    (contours_area(one) > 0 ? ccw : cw) += 1;
  }
  EXPECT_EQ(ccw, 1);
  EXPECT_EQ(cw, 1);
}

// A rectangle whose sides lie on grid lines (multiples of 1/8 at resolution 16): its contour
// points, which used to repeat at the grid points on the level, are all distinct.
TEST(Contours, SidesOnGridLinesGiveDistinctPoints) {
  const Tree tree = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
          "root": {"type": "rectangle", "size": [1.0, 0.5], "sharpness": 40}})",
      "rectangle");
  MeshOptions o;
  o.resolution = 16;
  const Contours c = extract_contours(tree, tree.params.values(), o);
  ASSERT_EQ(c.loops.size(), 1u);
  std::set<std::array<float, 2>> points(c.loops[0].begin(), c.loops[0].end());
  EXPECT_EQ(points.size(), c.loops[0].size());
  EXPECT_GT(points.size(), 20u);
  EXPECT_NEAR(contours_area(c), 0.5, 0.01);
}

TEST(Contours, PruningIsExact) {
  const Tree tree = disc_with_hole();
  MeshOptions o;
  o.resolution = 120;
  MeshStats ps, ds;
  const Contours pruned = extract_contours(tree, tree.params.values(), o, &ps);
  o.prune = false;
  const Contours dense = extract_contours(tree, tree.params.values(), o, &ds);
  EXPECT_EQ(pruned.loops, dense.loops);
  EXPECT_LT(ps.points_evaluated, ds.points_evaluated / 2);
}

std::size_t read_back_triangles(const std::filesystem::path& path) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate);
  if (scene == nullptr || scene->mNumMeshes == 0) return 0;
  std::size_t faces = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) faces += scene->mMeshes[m]->mNumFaces;
  return faces;
}

TEST(MeshFiles, ObjStlPlyRoundTripThroughAssimp) {
  const Tree tree = sphere_tree(0.5);
  MeshOptions o;
  o.resolution = 20;
  const TriangleMesh m = extract_mesh(tree, tree.params.values(), o);
  const std::filesystem::path dir = ::testing::TempDir();
  for (const char* name : {"fuzzycsg_mesh.obj", "fuzzycsg_mesh.stl", "fuzzycsg_mesh.ply"}) {
    const std::filesystem::path path = dir / name;
    std::filesystem::remove(path);
    write_mesh(m, path);
    EXPECT_EQ(read_back_triangles(path), m.triangles.size()) << name;
  }
  // No material file beside the OBJ.
  EXPECT_FALSE(std::filesystem::exists(dir / "fuzzycsg_mesh.mtl"));
}

// The mesh as stored in a file, read by assimp with nothing joined (each format its own way:
// OBJ's exporter welds positions, PLY keeps the vertices, STL repeats them per triangle).
TriangleMesh read_back_mesh(const std::filesystem::path& path) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path.string(), 0);
  TriangleMesh m;
  if (scene == nullptr || scene->mNumMeshes != 1) return m;
  const aiMesh* mesh = scene->mMeshes[0];
  for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
    m.vertices.push_back({mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z});
  }
  for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
    const unsigned* i = mesh->mFaces[f].mIndices;
    m.triangles.push_back({static_cast<int>(i[0]), static_cast<int>(i[1]), static_cast<int>(i[2])});
  }
  return m;
}

// What --check reads (read_triangle_mesh() and check_mesh()) agrees with an independent count
// of each file written, and the table's files are closed 2-manifolds by position.
TEST(MeshFiles, WrittenTableIsAManifoldAndTheCheckAgrees) {
  const Tree tree = io::read_tree_file(FUZZYCSG_SOURCE_DIR "/examples/table.json");
  MeshOptions o;
  o.resolution = 128;
  const TriangleMesh m = extract_mesh(tree, tree.params.values(), o);
  const std::filesystem::path dir = ::testing::TempDir();
  for (const char* name : {"fuzzycsg_table.obj", "fuzzycsg_table.stl", "fuzzycsg_table.ply"}) {
    const std::filesystem::path path = dir / name;
    write_mesh(m, path);
    const TriangleMesh stored = read_back_mesh(path);
    ASSERT_EQ(stored.triangles.size(), m.triangles.size()) << name;
    const PositionCounts c = count_by_position(stored);
    EXPECT_EQ(c.positions, m.vertices.size()) << name;
    EXPECT_EQ(c.repeated, 0u) << name;
    EXPECT_EQ(c.zero_area, 0u) << name;
    EXPECT_EQ(c.edges_not_two, 0u) << name;
    const MeshCheck check = check_mesh(read_triangle_mesh(path));
    EXPECT_EQ(check.vertices, c.positions) << name;
    EXPECT_EQ(check.triangles, m.triangles.size()) << name;
    EXPECT_EQ(check.degenerate_triangles, c.repeated + c.zero_area) << name;
    EXPECT_EQ(check.nonmanifold_edges, c.edges_not_two) << name;
    EXPECT_TRUE(check.closed_oriented_manifold()) << name;
  }
  EXPECT_THROW(read_triangle_mesh(dir / "fuzzycsg_no_such_mesh.obj"), InputError);
}

// Extraction computes its vertices in float and the mesh keeps those values exactly (its
// coordinates are double): every file, whose coordinates are float, holds the same positions.
TEST(MeshFiles, FilesHoldTheVerticesExactly) {
  const Tree tree = io::read_tree_file(FUZZYCSG_SOURCE_DIR "/examples/table.json");
  MeshOptions o;
  o.resolution = 64;
  const TriangleMesh m = extract_mesh(tree, tree.params.values(), o);
  ASSERT_GT(m.vertices.size(), 100u);
  for (const auto& v : m.vertices) {
    for (const double x : v) ASSERT_EQ(x, static_cast<double>(static_cast<float>(x)));
  }
  const std::set<std::array<double, 3>> positions(m.vertices.begin(), m.vertices.end());
  const std::filesystem::path dir = ::testing::TempDir();
  for (const char* name : {"fuzzycsg_exact.obj", "fuzzycsg_exact.stl", "fuzzycsg_exact.ply"}) {
    const std::filesystem::path path = dir / name;
    write_mesh(m, path);
    const TriangleMesh stored = read_triangle_mesh(path);
    EXPECT_EQ(stored.triangles.size(), m.triangles.size()) << name;
    const std::set<std::array<double, 3>> stored_positions(stored.vertices.begin(),
                                                           stored.vertices.end());
    EXPECT_EQ(stored_positions, positions) << name;
  }
}

TEST(MeshFiles, BadPathsLeaveNothing) {
  const Tree tree = sphere_tree(0.5);
  MeshOptions o;
  o.resolution = 8;
  const TriangleMesh m = extract_mesh(tree, tree.params.values(), o);
  EXPECT_THROW(write_mesh(m, "/nonexistent-dir/x.obj"), InputError);
  const std::filesystem::path odd = std::filesystem::path(::testing::TempDir()) / "mesh.xyz";
  EXPECT_THROW(write_mesh(m, odd), InputError);
  EXPECT_FALSE(std::filesystem::exists(odd));
}

TEST(MeshFiles, ContoursAsSvgAndObj) {
  const Tree tree = disc_with_hole();
  MeshOptions o;
  o.resolution = 40;
  const Contours c = extract_contours(tree, tree.params.values(), o);
  const std::filesystem::path dir = ::testing::TempDir();
  write_contours(c, tree, dir / "fuzzycsg_contours.svg");
  write_contours(c, tree, dir / "fuzzycsg_contours.obj");
  std::size_t points = 0;
  for (const auto& loop : c.loops) points += loop.size();
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile((dir / "fuzzycsg_contours.obj").string(), 0);
  ASSERT_NE(scene, nullptr);
  EXPECT_EQ(scene->mMeshes[0]->mNumFaces, points);  // one segment per loop vertex
  EXPECT_GT(std::filesystem::file_size(dir / "fuzzycsg_contours.svg"), 200u);
  EXPECT_THROW(write_contours(c, tree, dir / "x.png"), InputError);
}

}  // namespace
}  // namespace fuzzycsg
