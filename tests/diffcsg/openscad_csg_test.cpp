// OpenSCAD's flattened .csg models as meshed CSG: the examples of tests/data parse, their spheres
// and cylinders are tessellated as OpenSCAD does, and drawn by rays they match OpenSCAD's own CGAL
// mesh of the same model (its .ref.off) drawn the same way; unsupported nodes and broken text are
// refused naming the line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diffcsg/openscad_csg.hpp"
#include "fuzzycsg/diffcsg/visibility.hpp"

namespace fuzzycsg::diffcsg {
namespace {

const std::filesystem::path kScad = std::filesystem::path(FUZZYCSG_TEST_DATA_DIR) / "scad";

// An OFF mesh as a one-primitive scene (polygons as fans), normals turned outward.
Scene read_off(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string magic;
  in >> magic;
  std::size_t nv = 0, nf = 0, ne = 0;
  in >> nv >> nf >> ne;
  TriangleMesh m;
  for (std::size_t v = 0; v < nv; ++v) {
    Vec3 p;
    in >> p[0] >> p[1] >> p[2];
    m.vertices.push_back(p);
  }
  for (std::size_t f = 0; f < nf; ++f) {
    int n = 0;
    in >> n;
    std::vector<int> idx(static_cast<std::size_t>(n));
    for (int& i : idx) in >> i;
    for (int k = 1; k + 1 < n; ++k) {
      m.triangles.push_back(
          {idx[0], idx[static_cast<std::size_t>(k)], idx[static_cast<std::size_t>(k + 1)]});
    }
  }
  const double volume = signed_volume(m);
  if (volume < 0) {
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  }
  Scene s;
  s.primitives.push_back({std::move(m), {}});
  s.tree_node.push_back(0);
  s.nodes.push_back({CsgNode::Kind::kPrimitive, 0, {}});
  s.root = 0;
  return s;
}

TEST(DiffcsgOpenscad, TheExamplesMatchOpenscadsOwnMeshes) {
  struct Case {
    const char* name;
    std::size_t primitives;
  };
  for (const Case& c : {Case{"Basics/CSG", 6}, Case{"Basics/logo", 4}, Case{"Old/example001", 4},
                        Case{"Old/example003", 7}, Case{"Old/example004", 2}}) {
    SCOPED_TRACE(c.name);
    const Scene model = read_openscad_csg(kScad / (std::string(c.name) + ".openscad.csg"));
    EXPECT_EQ(model.primitives.size(), c.primitives);
    for (const PrimitiveMesh& primitive : model.primitives) {
      const TriangleMesh& m = primitive.mesh;
      // Convex primitives: every face's normal points away from the primitive's centre.
      Vec3 centre{0, 0, 0};
      for (const Vec3& v : m.vertices) {
        for (int k = 0; k < 3; ++k) centre[k] += v[k] / static_cast<double>(m.vertices.size());
      }
      int inward = 0;
      for (const auto& t : m.triangles) {
        const Vec3& a = m.vertices[static_cast<std::size_t>(t[0])];
        const Vec3& b = m.vertices[static_cast<std::size_t>(t[1])];
        const Vec3& d = m.vertices[static_cast<std::size_t>(t[2])];
        const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]},
            w{d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        const Vec3 n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                     u[0] * w[1] - u[1] * w[0]};
        const double out =
            n[0] * (a[0] - centre[0]) + n[1] * (a[1] - centre[1]) + n[2] * (a[2] - centre[2]);
        inward += out < 0;
      }
      EXPECT_EQ(inward, 0);
    }
    const Scene reference = read_off(kScad / (std::string(c.name) + ".ref.off"));
    for (const double azimuth : {30.0, 200.0}) {
      const Camera cam = Camera::orbit({0, 0, 0}, azimuth, 30, 160, 96, 96, 30);
      const Frame a = render_visibility(model, cam, 2), b = render_visibility(reference, cam, 2);
      int both = 0, either = 0, normals_apart = 0;
      for (std::size_t p = 0; p < a.primitive.size(); ++p) {
        const bool x = a.primitive[p] >= 0, y = b.primitive[p] >= 0;
        both += x && y;
        either += x || y;
        if (x && y) {
          const auto& n = a.normal[p];
          const auto& m = b.normal[p];
          normals_apart += n[0] * m[0] + n[1] * m[1] + n[2] * m[2] < 0.9;
        }
      }
      ASSERT_GT(either, 100);
      // The same tessellation: only pixels on edges may differ.
      EXPECT_GT(static_cast<double>(both) / either, 0.97) << "azimuth " << azimuth;
      EXPECT_LT(normals_apart, both / 50) << "azimuth " << azimuth;
    }
  }
}

TEST(DiffcsgOpenscad, UnsupportedNodesAndBrokenTextAreRefusedNamingTheLine) {
  const auto refused = [](const std::string& text, const std::string& expect) {
    try {
      parse_openscad_csg(text, "m.csg");
      ADD_FAILURE() << "accepted " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
    }
  };
  refused("union() {\n  cube(size = 1);\n  linear_extrude(height = 2) { square(1); }\n}\n",
          "m.csg: line 3: unsupported node 'linear_extrude'");
  refused("cube(size = [1, 2]);", "m.csg: line 1: cube: size");
  refused("union() {\n cube(1);\n", "missing '}'");
  refused("sphere(r = -1);", "r: must be positive");
  refused("cube(size = 1)", "expected ';'");
  refused("group() { }", "no primitives");
  // One limit on fragments for both readers, before any tessellation is made.
  refused("union() {\n  sphere($fn = 1000000000, r = 1);\n}\n",
          "m.csg: line 2: sphere: $fn, $fa, $fs: 1000000000 fragments, at most 4096");
  refused("cylinder($fn = 5000, h = 1, r = 1);", "line 1: cylinder: $fn, $fa, $fs: 5000 fragments");
  refused("sphere($fa = 1e-9, $fs = 1e-9, r = 1);", "fragments, at most 4096");
  try {
    parse_openscad_csg_tree("sphere($fn = 1e12, r = 1);", "t.csg");
    ADD_FAILURE() << "the tree reader accepted 1e12 fragments";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.csg: line 1: sphere: $fn, $fa, $fs: 2147483647 "
                                         "fragments, at most 4096"),
              std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(parse_openscad_csg("sphere($fn = 2048, r = 1);", "m.csg"));
  refused("%cube(1);", "no primitives");
  EXPECT_EQ(parse_openscad_csg("*sphere(1); #cube(1); !cylinder(h = 1, r = 1);", "m.csg")
                .primitives.size(),
            2u);
}

// Both readers' message for `text`, or "accepted".
std::string scene_error(const std::string& text, std::size_t max_triangles) {
  try {
    parse_openscad_csg(text, "m.csg", max_triangles);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}
std::string tree_error(const std::string& text, std::size_t max_triangles) {
  try {
    parse_openscad_csg_tree(text, "m.csg", max_triangles);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

// Statements and vectors nest at most 512 deep: deeper ones overflowed the stack.
TEST(DiffcsgOpenscad, DeepNestingIsRefusedNotAStackOverflow) {
  constexpr int kDeep = 200000;
  std::string vectors = "cube(";
  vectors.append(kDeep, '[');
  vectors.append(kDeep, ']');
  vectors += ");";
  std::string chain;
  for (int i = 0; i < kDeep; ++i) chain += "group() ";
  chain += "cube(1);";
  std::string braces;
  for (int i = 0; i < kDeep; ++i) braces += "group() {\n";
  braces += "cube(1);";
  braces.append(kDeep, '}');
  for (const std::string* text : {&vectors, &chain, &braces}) {
    const std::string line = text == &braces ? "513" : "1";
    EXPECT_EQ(scene_error(*text, scad::kMaxOpenscadTriangles),
              "m.csg: line " + line + ": nested deeper than 512 levels");
    EXPECT_EQ(tree_error(*text, scad::kMaxOpenscadTriangles),
              "m.csg: line " + line + ": nested deeper than 512 levels");
  }
  // 511 groups around a cube: 512 statements.
  std::string deepest;
  for (int i = 0; i < 511; ++i) deepest += "group() {\n";
  deepest += "cube(1);";
  deepest.append(511, '}');
  EXPECT_EQ(parse_openscad_csg(deepest, "m.csg").primitives.size(), 1u);
  EXPECT_EQ(parse_openscad_csg_tree(deepest, "m.csg").tree.nodes.size(), 1u);
}

// A model's triangles in all are bounded, as a primitive's fragments are: a few bytes asked for
// any number of spheres of 4096 fragments (16777212 triangles each), and one such sphere costs
// minutes and gigabytes to draw.
TEST(DiffcsgOpenscad, ModelsOfTooManyTrianglesAreRefusedBeforeTessellation) {
  // A sphere of 2048 fragments fits the default budget (the tree reader tessellates nothing, so
  // this costs nothing); one of 4096 does not, nor do two of 2048.
  const std::string one = "sphere($fn = 2048, r = 1);\n";
  EXPECT_EQ(tree_error(one, scad::kMaxOpenscadTriangles), "accepted");
  EXPECT_EQ(tree_error("sphere($fn = 4096, r = 1);\n", scad::kMaxOpenscadTriangles),
            "m.csg: line 1: sphere: 16777212 triangles in the model with it, at most 4194304");
  EXPECT_EQ(tree_error(one + one, scad::kMaxOpenscadTriangles).substr(0, 22),
            "m.csg: line 2: sphere:");
  // The count is the scene's: a cube (12), a sphere of 8 fragments (60) and a cone of 6 (10).
  const std::string small =
      "cube(1);\nsphere($fn = 8, r = 1);\ncylinder($fn = 6, h = 1, r1 = 1, r2 = 0);\n";
  EXPECT_EQ(parse_openscad_csg(small, "m.csg", 82).triangle_count(), 82u);
  EXPECT_EQ(tree_error(small, 82), "accepted");
  for (const auto& error : {scene_error(small, 81), tree_error(small, 81)}) {
    EXPECT_EQ(error, "m.csg: line 3: cylinder: 82 triangles in the model with it, at most 81");
  }
  EXPECT_EQ(scene_error(small, 71),
            "m.csg: line 2: sphere: 72 triangles in the model with it, at most 71");
}

// The same depth and primitive at every pixel but a few on edges.
void expect_same_image(const Scene& a_scene, const Scene& b_scene, double azimuth,
                       double elevation) {
  const auto [lo, hi] = a_scene.bounds();
  const Vec3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  const double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const Camera cam = Camera::orbit(centre, azimuth, elevation, 3 * size, 96, 96, 30);
  const Frame a = render_visibility(a_scene, cam, 2), b = render_visibility(b_scene, cam, 2);
  int covered = 0, differ = 0;
  for (std::size_t p = 0; p < a.primitive.size(); ++p) {
    covered += a.primitive[p] >= 0;
    if ((a.primitive[p] >= 0) != (b.primitive[p] >= 0) ||
        (a.primitive[p] >= 0 && std::abs(a.depth[p] - b.depth[p]) > 1e-4 * size)) {
      ++differ;
    }
  }
  ASSERT_GT(covered, 200);
  EXPECT_LE(differ, covered / 200) << "azimuth " << azimuth;
}

TEST(DiffcsgOpenscad, ModelsReadAsTreesDrawTheSameAsTheirMeshes) {
  for (const char* name :
       {"Basics/CSG", "Basics/logo", "Old/example001", "Old/example003", "Old/example004"}) {
    SCOPED_TRACE(name);
    const std::filesystem::path path = kScad / (std::string(name) + ".openscad.csg");
    const Scene direct = read_openscad_csg(path);
    const OpenscadModel model = read_openscad_csg_tree(path);
    const Scene tree = scene_from_tree(model.tree, path.string(), model.tessellation);
    ASSERT_EQ(tree.primitives.size(), direct.primitives.size());
    // Every sphere and cylinder keeps OpenSCAD's fragments: the same vertex count on rings.
    for (std::size_t p = 0; p < tree.primitives.size(); ++p) {
      EXPECT_NEAR(static_cast<double>(tree.primitives[p].mesh.vertices.size()),
                  static_cast<double>(direct.primitives[p].mesh.vertices.size()), 2.0);
    }
    for (const double azimuth : {30.0, 200.0}) expect_same_image(direct, tree, azimuth, 30);
  }
}

TEST(DiffcsgOpenscad, PlacementsBecomeTranslateRotateAndSizes) {
  // Uncentred primitives, a mirror, a rotation about two axes, scales folded into sizes, a
  // sphere scaled unevenly (an ellipsoid), a cone.
  const std::string text = R"(
multmatrix([[0.8660254, -0.5, 0, 1], [0.5, 0.8660254, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]) {
  cube(size = [1, 2, 3], center = false);
  multmatrix([[2, 0, 0, 0], [0, 2, 0, 0], [0, 0, 2, 0.5], [0, 0, 0, 1]]) {
    cylinder($fn = 12, h = 2, r1 = 1, r2 = 0.5, center = false);
  }
}
multmatrix([[-1, 0, 0, 0], [0, 0.6, -0.8, 0], [0, 0.8, 0.6, 0], [0, 0, 0, 1]]) {
  cube(size = [0.5, 1, 2], center = true);
}
multmatrix([[1, 0, 0, -2], [0, 2, 0, 0], [0, 0, 3, 0], [0, 0, 0, 1]]) sphere($fn = 10, r = 0.5);
)";
  const Scene direct = parse_openscad_csg(text, "m.csg");
  const OpenscadModel model = parse_openscad_csg_tree(text, "m.csg");
  const Scene tree = scene_from_tree(model.tree, "m.csg", model.tessellation);
  ASSERT_EQ(tree.primitives.size(), 4u);
  const Node& cone = model.tree.node(tree.tree_node[1]);
  EXPECT_EQ(cone.shape.type, PrimitiveType::kCone);
  EXPECT_EQ(cone.name, "cylinder line 5");
  EXPECT_NEAR(model.tree.params[cone.intrinsic[2]].value, 4, 1e-12);  // height 2 scaled by 2
  EXPECT_EQ(model.tree.node(tree.tree_node[3]).shape.type, PrimitiveType::kEllipsoid);
  for (const double azimuth : {0.0, 70.0, 160.0, 250.0}) {
    expect_same_image(direct, tree, azimuth, 25);
    expect_same_image(direct, tree, azimuth, -40);
  }
  const auto refused = [](const std::string& t, const std::string& expect) {
    try {
      parse_openscad_csg_tree(t, "m.csg");
      ADD_FAILURE() << "accepted " << t;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
    }
  };
  refused("multmatrix([[1, 1, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) cube(1);",
          "m.csg: line 1: cube: its placement shears it");
  refused(
      "multmatrix([[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])\n"
      "  cylinder(h = 1, r = 1);",
      "m.csg: line 2: cylinder: a scale that differs across its axis");
}

}  // namespace
}  // namespace fuzzycsg::diffcsg
