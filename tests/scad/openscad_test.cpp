// Exported files rendered by OpenSCAD (skipped when openscad is not installed): the volume of
// OpenSCAD's mesh against our own mesh of the same tree, and the inside of OpenSCAD's mesh (ray
// parity) against the tree at sampled points.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <random>
#include <sstream>

#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/mesh/mesh.hpp"
#include "fuzzycsg/scad/scad.hpp"
#include "scad_support.hpp"

namespace fuzzycsg {
namespace {

using scad_test::agreement;
using scad_test::inside_mesh;
using scad_test::json_numbers;
using scad_test::tree_text;

struct Rendered {
  std::shared_ptr<scad_test::TestDir> dir;  // keeps the files for the test's lifetime
  std::filesystem::path scad;
  TriangleMesh mesh;
  std::string log;
  int rc = -1;
};

Rendered render_file(const std::filesystem::path& scad, const std::string& ext) {
  Rendered r;
  r.scad = scad;
  const auto out = std::filesystem::path(scad).replace_extension(ext);
  r.rc = scad_test::run_openscad(scad, out, &r.log);
  if (ext == ".stl") r.mesh = scad_test::read_stl(out);
  return r;
}

Rendered render(const std::string& name, const Tree& tree, const scad::ExportOptions& o,
                scad::ExportReport* report = nullptr, const std::string& ext = ".stl") {
  auto dir = std::make_shared<scad_test::TestDir>(name);
  const auto scad = *dir / "model.scad";
  scad::write_scad(tree, tree.params.values(), scad, o, report);
  Rendered r = render_file(scad, ext);
  r.dir = std::move(dir);
  return r;
}

scad::ExportOptions options(int fn = 32) {
  scad::ExportOptions o;
  o.fn = fn;
  o.resolution = 40;
  return o;
}

// OpenSCAD's mesh against the tree: volume within `volume_tol` (relative) of our mesh's, and on
// sampled points the insides agree on more than 99.5% of the samples and their intersection
// over union exceeds `min_iou`. OpenSCAD may warn about a result that is not 2-manifold where
// solids touch (the apex of a double cone).
scad_test::Agreement expect_matches(const Tree& tree, const Rendered& r, double volume_tol,
                                    double min_iou, bool manifold = true) {
  EXPECT_EQ(r.rc, 0) << r.log;
  EXPECT_EQ(r.log.find("ERROR"), std::string::npos) << r.log;
  if (manifold) {
    EXPECT_EQ(r.log.find("WARNING"), std::string::npos) << r.log;
  }
  EXPECT_GT(r.mesh.triangles.size(), 0u) << r.log;
  MeshOptions mo;
  mo.resolution = 128;
  const TriangleMesh ours = extract_mesh(tree, tree.params.values(), mo);
  const double v_ours = signed_volume(ours), v_scad = signed_volume(r.mesh);
  EXPECT_NEAR(v_scad, v_ours, volume_tol * v_ours);
  const scad_test::Agreement a =
      agreement(tree, 8000, [&](const std::array<double, 3>& p) { return inside_mesh(r.mesh, p); });
  EXPECT_GT(a.fraction, 0.995);
  EXPECT_GT(a.iou, min_iou);
  std::cout << fmt::format(
      "  volume: OpenSCAD {:.6f}, ours {:.6f} ({:+.3f}%); inside: agree on "
      "{:.3f}% of the samples, IoU {:.4f}\n",
      v_scad, v_ours, 100.0 * (v_scad - v_ours) / v_ours, 100.0 * a.fraction, a.iou);
  return a;
}

TEST(OpenScad, PrimitivesWithPlacement) {
  FUZZYCSG_REQUIRE_OPENSCAD();
  const Tree tree =
      io::read_tree_string(tree_text(3, R"({"op": "union", "logic": "godel", "children": [
    {"type": "sphere", "radius": 0.3, "translate": [-0.5, -0.5, 0.4]},
    {"type": "box", "size": [0.5, 0.3, 0.2], "translate": [0.45, -0.45, 0.35], "rotate": [20, 35, -15]},
    {"type": "cylinder", "radius": 0.15, "height": 0.6, "translate": [-0.45, 0.45, -0.3], "rotate": [60, 0, 30]},
    {"type": "cone", "radius1": 0.25, "radius2": 0.05, "height": 0.5, "translate": [0.45, 0.45, -0.35],
     "rotate": [-30, 45, 10], "scale": 0.9},
    {"type": "torus", "major": 0.25, "minor": 0.08, "translate": [0, 0, -0.6], "rotate": [15, -20, 0]},
    {"type": "torus", "major": 0.05, "minor": 0.12, "translate": [0, 0.1, 0.55], "rotate": [0, 70, 0]},
    {"type": "ellipsoid", "radii": [0.25, 0.12, 0.08], "translate": [-0.5, 0.0, -0.5], "rotate": [0, 30, 60],
     "scale": 1.2},
    {"type": "capsule", "radius": 0.08, "height": 0.4, "translate": [0.5, 0.05, 0.0], "rotate": [90, 10, 0]}]})"));
  scad::ExportReport report;
  const Rendered r = render("primitives", tree, options(), &report);
  EXPECT_FALSE(report.clipped);
  EXPECT_EQ(report.meshed_leaves, 0);
  expect_matches(tree, r, 0.02, 0.97);
}

// Folded booleans (one union() of three boxes, one difference() taking a box and the union of
// two cylinders away) are the tree's solid.
TEST(OpenScad, FoldedBooleans) {
  FUZZYCSG_REQUIRE_OPENSCAD();
  const Tree tree = io::read_tree_string(tree_text(3, R"({"op": "difference", "children": [
    {"op": "difference", "children": [
      {"op": "union", "children": [
        {"op": "union", "children": [
          {"type": "box", "size": [1.6, 0.8, 0.8]},
          {"type": "box", "size": [0.8, 1.6, 0.8]}]},
        {"type": "box", "size": [0.8, 0.8, 1.6]}]},
      {"type": "box", "size": [0.3, 0.3, 2.0]}]},
    {"op": "union", "children": [
      {"type": "cylinder", "radius": 0.15, "height": 2.0, "rotate": [0, 90, 0]},
      {"type": "cylinder", "radius": 0.15, "height": 2.0, "rotate": [90, 0, 0]}]}]})"));
  scad::ExportReport report;
  const Rendered r = render("folded", tree, options(), &report);
  EXPECT_EQ(report.operators, 5);
  std::ifstream in(r.scad);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.find("difference() {\n  union() {"), text.find("difference() {")) << text;
  expect_matches(tree, r, 0.02, 0.97);
}

// Half-spaces (convert's cuts) as turned cubes: a box cut by two slanted planes, one of them
// with a normal along no world plane, and a plane that misses the box entirely.
TEST(OpenScad, HalfSpacesAsTurnedCubes) {
  FUZZYCSG_REQUIRE_OPENSCAD();
  const Tree tree = io::read_tree_string(tree_text(3, R"({"op": "intersection", "children": [
    {"type": "box", "size": [1.2, 1.0, 0.8]},
    {"type": "plane", "normal": [1, 1, 0], "offset": 0.3},
    {"type": "plane", "normal": [-1, 2, -3], "offset": 0.2},
    {"type": "plane", "normal": [0, 0, -1], "offset": 0.5}]})"));
  const Rendered r = render("half_spaces", tree, options());
  std::ifstream in(r.scad);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("rotate([0, 90, 45]) translate(["), std::string::npos) << text;
  EXPECT_EQ(text.find("multmatrix"), std::string::npos) << text;
  expect_matches(tree, r, 0.02, 0.97);
}

// The text with every "translate([...]) rotate([...])" written "rotate([...]) translate([...])".
std::string swap_translate_rotate(const std::string& text) {
  std::string out;
  std::size_t at = 0;
  while (true) {
    const std::size_t t = text.find("translate([", at);
    if (t == std::string::npos) break;
    const std::size_t t_end = text.find("])", t) + 2;
    if (text.compare(t_end, 9, " rotate([") != 0) {
      out += text.substr(at, t_end - at);
      at = t_end;
      continue;
    }
    const std::size_t r = t_end + 1;
    const std::size_t r_end = text.find("])", r) + 2;
    out += text.substr(at, t - at) + text.substr(r, r_end - r) + " " + text.substr(t, t_end - t);
    at = r_end;
  }
  return out + text.substr(at);
}

// A box with a hole off its centre, rotated about two axes, and a notch: a transformation
// applied in the wrong order gives another solid. The check itself is shown to notice: the
// same file with rotate and translate swapped agrees much less.
TEST(OpenScad, AsymmetricPlacementOrder) {
  FUZZYCSG_REQUIRE_OPENSCAD();
  const Tree tree =
      io::read_tree_string(tree_text(3, R"({"op": "difference", "logic": "godel", "children": [
    {"type": "box", "size": [1.0, 0.6, 0.35], "translate": [0.15, -0.1, 0.05], "rotate": [25, 40, 0]},
    {"op": "union", "logic": "godel", "children": [
      {"type": "cylinder", "radius": 0.12, "height": 1.0, "translate": [0.35, -0.05, 0.2], "rotate": [25, 40, 0]},
      {"type": "sphere", "radius": 0.2, "translate": [-0.3, -0.2, -0.2], "scale": 1.1}]}]})"));
  const Rendered r = render("asymmetric", tree, options());
  const scad_test::Agreement good = expect_matches(tree, r, 0.02, 0.98);

  std::ifstream in(r.scad);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string swapped = swap_translate_rotate(ss.str());
  ASSERT_NE(swapped, ss.str());
  const auto wrong_path = r.scad.parent_path() / "wrong_order.scad";
  std::ofstream(wrong_path) << swapped;
  const Rendered wrong = render_file(wrong_path, ".stl");
  ASSERT_EQ(wrong.rc, 0) << wrong.log;
  const scad_test::Agreement bad = agreement(
      tree, 8000, [&](const std::array<double, 3>& p) { return inside_mesh(wrong.mesh, p); });
  std::cout << fmt::format(
      "  rotate and translate swapped: agree on {:.3f}% of the samples, IoU "
      "{:.4f}\n",
      100.0 * bad.fraction, bad.iou);
  EXPECT_LT(bad.iou, good.iou - 0.2);
}

TEST(OpenScad, ComplementUnifiedAndLogicFamilies) {
  FUZZYCSG_REQUIRE_OPENSCAD();
  // Sharp sigmoids: the fuzzy level set is within a few thousandths of the crisp one.
  const Tree tree =
      io::read_tree_string(tree_text(3, R"({"op": "union", "logic": "godel", "children": [
    {"op": "unified", "c": [0, 0, 0, 1], "children": [
      {"type": "sphere", "radius": 0.25, "translate": [0.5, 0.5, 0.3], "sharpness": 400},
      {"type": "box", "size": [0.6, 0.5, 0.4], "translate": [0.5, 0.5, 0.3], "sharpness": 400}]},
    {"op": "unified", "logits": [0.1, -0.05, 0.3, 0.02], "children": [
      {"type": "sphere", "radius": 0.3, "translate": [-0.5, 0.5, 0], "sharpness": 400},
      {"type": "cylinder", "radius": 0.2, "height": 1.0, "translate": [-0.5, 0.5, 0], "rotate": [0, 90, 0],
       "sharpness": 400}]},
    {"op": "unified", "c": [0, 0, 1, 0], "children": [
      {"type": "box", "size": [0.5, 0.5, 0.5], "translate": [-0.5, -0.5, 0], "sharpness": 400},
      {"type": "cylinder", "radius": 0.15, "height": 1.0, "translate": [-0.45, -0.5, 0], "sharpness": 400}]},
    {"op": "intersection", "logic": "godel", "children": [
      {"type": "box", "size": [0.7, 0.6, 0.6], "translate": [0.45, -0.5, 0], "sharpness": 400},
      {"op": "complement", "children": [
        {"type": "sphere", "radius": 0.2, "translate": [0.45, -0.5, 0], "sharpness": 400}]}]}]})"));
  scad::ExportReport report;
  const Rendered r = render("complement", tree, options(), &report);
  EXPECT_TRUE(report.clipped);  // the complement reaches the cover
  expect_matches(tree, r, 0.02, 0.97);
}

// Quadric leaves of every kind, placed by random rotations as a fit leaves them (one with a
// placement of its own, as fits to meshes write them): written as primitives through
// multmatrix, and one hyperboloid as a polyhedron.
TEST(OpenScad, ClassifiedQuadricLeaves) {
  FUZZYCSG_REQUIRE_OPENSCAD();
  std::mt19937_64 rng(11);
  const auto rot = [&] { return scad_test::random_rotation(rng); };
  const auto quadric = [&](Eigen::Vector3d g, Eigen::Vector3d h, double k0, Eigen::Vector3d axes,
                           Eigen::Vector3d c, double s, const std::string& placement = "") {
    return std::string(R"({"type": "quadric", "coefficients": )") +
           json_numbers(scad_test::make_quadric3(Eigen::Matrix3d(g.asDiagonal()), h, k0, rot(),
                                                 axes, c, s)) +
           placement + "}";
  };
  using V = Eigen::Vector3d;
  const std::string sphere =
      quadric(V(1, 1, 1), V(0, 0, 0), -1, V(0.25, 0.25, 0.25), V(-0.5, -0.5, 0.5), 2);
  const std::string ellipsoid =
      quadric(V(1, 1, 1), V(0, 0, 0), -1, V(0.3, 0.2, 0.12), V(0.5, -0.5, 0.5), 0.3,
              R"(, "translate": [0.05, -0.1, 0], "rotate": [10, 20, 30], "scale": 0.8)");
  const std::string cylinder =
      quadric(V(1, 1, 0), V(0, 0, 0), -1, V(0.15, 0.2, 1), V(-0.5, 0.5, 0.5), 5);
  const std::string slab = quadric(V(0, 0, 1), V(0, 0, 0), -1, V(1, 1, 0.3), V(-0.5, 0.5, 0.5), 1);
  const std::string cone = quadric(V(1, 1, -1), V(0, 0, 0), 0, V(0.4, 0.3, 1), V(0.5, 0.5, 0.5), 1);
  const std::string ball = R"({"type": "sphere", "radius": 0.35, "translate": [0.5, 0.5, 0.5]})";
  const std::string paraboloid =
      quadric(V(1, 1, 0), V(0, 0, -1), 0, V(0.2, 0.25, 1), V(0.5, 0.5, -0.6), 3);
  const std::string plane = quadric(V(0, 0, 0), V(0, 0, 1), 0, V(1, 1, 1), V(0.5, 0.5, -0.2), 1);
  // The outside of a cylinder (negated coefficients) cut from a box.
  const std::string box =
      R"({"type": "box", "size": [0.6, 0.6, 0.5], "translate": [-0.5, 0.5, -0.5]})";
  const std::string hole =
      quadric(V(1, 1, 0), V(0, 0, 0), -1, V(0.12, 0.12, 1), V(-0.5, 0.5, -0.5), -1);
  // A hyperboloid of one sheet inside a sphere: meshed.
  const std::string hyperboloid =
      quadric(V(1, 1, -1), V(0, 0, 0), -0.2, V(0.15, 0.15, 0.3), V(-0.5, -0.5, -0.5), 1);
  const std::string ball2 =
      R"({"type": "sphere", "radius": 0.35, "translate": [-0.5, -0.5, -0.5]})";
  const std::string root =
      R"({"op": "union", "logic": "godel", "children": [)" + sphere + ", " + ellipsoid +
      R"(, {"op": "intersection", "logic": "godel", "children": [)" + cylinder + ", " + slab +
      R"(]}, {"op": "intersection", "logic": "godel", "children": [)" + cone + ", " + ball +
      R"(]}, {"op": "intersection", "logic": "godel", "children": [)" + paraboloid + ", " + plane +
      R"(]}, {"op": "intersection", "logic": "godel", "children": [)" + box + ", " + hole +
      R"(]}, {"op": "intersection", "logic": "godel", "children": [)" + hyperboloid + ", " + ball2 +
      "]}]}";
  const Tree tree = io::read_tree_string(tree_text(3, root));
  scad::ExportReport report;
  scad::ExportOptions o = options();
  o.resolution = 24;
  const Rendered r = render("quadrics", tree, o, &report);
  EXPECT_EQ(report.quadric_leaves, 9);
  EXPECT_EQ(report.quadrics_classified, 8);
  EXPECT_EQ(report.quadrics_outside, 1);
  const std::map<std::string, int> kinds{{"cone", 1},       {"cylinder", 2}, {"ellipsoid", 1},
                                         {"paraboloid", 1}, {"plane", 1},    {"polyhedron", 1},
                                         {"slab", 1},       {"sphere", 1}};
  EXPECT_EQ(report.quadric_kinds, kinds);
  EXPECT_TRUE(report.clipped);
  expect_matches(tree, r, 0.02, 0.97, /*manifold=*/false);
}

// The extrude example (a slotted plate with a bolt hole), placed: its linear_extrude against
// the tree.
TEST(OpenScad, ExtrudedProfile) {
  FUZZYCSG_REQUIRE_OPENSCAD();
  const Tree tree =
      io::read_tree_string(tree_text(3, R"({"op": "difference", "logic": "godel", "children": [
    {"type": "extrude",
     "profile": [[-0.45, -0.3], [-0.15, -0.3], [0.15, -0.3], [0.45, -0.3], [0.85, -0.3], [0.85, 0.3],
                 [0.45, 0.3], [0.15, 0.3], [-0.15, 0.3], [-0.45, 0.3], [-0.85, 0.3], [-0.85, -0.3]],
     "height": 0.4, "translate": [0.05, -0.1, 0.1], "rotate": [30, -20, 10], "scale": 0.9},
    {"type": "cylinder", "radius": 0.15, "height": 1.0, "translate": [0.45, -0.05, 0.2],
     "rotate": [30, -20, 10]}]})"));
  scad::ExportReport report;
  const Rendered r = render("extrude", tree, options(), &report);
  EXPECT_EQ(report.meshed_leaves, 0);
  expect_matches(tree, r, 0.02, 0.97);
}

// 2D: OpenSCAD writes SVG; the area of its paths and the inside (even-odd) against the tree.
TEST(OpenScad, TwoDimensionalTree) {
  FUZZYCSG_REQUIRE_OPENSCAD();
  using V = Eigen::Vector2d;
  const auto quadric = [](Eigen::Vector2d g, Eigen::Vector2d h, double k0, double angle,
                          Eigen::Vector2d axes, Eigen::Vector2d c, double s) {
    return std::string(R"({"type": "quadric", "coefficients": )") +
           json_numbers(scad_test::make_quadric2(Eigen::Matrix2d(g.asDiagonal()), h, k0, angle,
                                                 axes, c, s)) +
           "}";
  };
  const std::string root =
      R"({"op": "union", "logic": "godel", "children": [
        {"type": "circle", "radius": 0.2, "translate": [-0.6, 0.6]},
        {"type": "rectangle", "size": [0.4, 0.2], "translate": [0.0, 0.65], "rotate": 30},
        {"type": "ellipse", "radii": [0.25, 0.1], "translate": [0.6, 0.6], "rotate": -20, "scale": 1.1},
        {"type": "polygon", "vertices": [[-0.9, -0.2], [-0.3, -0.2], [-0.3, 0.3], [-0.5, 0.0], [-0.9, 0.3]]},
        {"op": "intersection", "logic": "godel", "children": [
          {"type": "half-plane", "normal": [1, 1], "offset": 0.1, "translate": [0.5, 0.1]},
          {"type": "circle", "radius": 0.3, "translate": [0.5, 0.1]}]},
        )" +
      quadric(V(1, 1), V(0, 0), -1, 0.3, V(0.15, 0.15), V(0.0, 0.1), 3) + R"(,
        {"op": "intersection", "logic": "godel", "children": [
          )" +
      quadric(V(1, 0), V(0, -1), 0, 0.5, V(0.2, 1), V(-0.5, -0.75), 1) + R"(,
          {"type": "circle", "radius": 0.25, "translate": [-0.5, -0.6]}]},
        {"op": "intersection", "logic": "godel", "children": [
          )" +
      quadric(V(0, 1), V(0, 0), -1, -0.4, V(1, 0.05), V(0.1, -0.5), 2) + R"(,
          {"type": "circle", "radius": 0.25, "translate": [0.1, -0.5]}]},
        {"op": "intersection", "logic": "godel", "children": [
          )" +
      quadric(V(1, -1), V(0, 0), -0.1, 0.2, V(0.1, 0.1), V(0.65, -0.55), 1) + R"(,
          {"type": "rectangle", "size": [0.4, 0.4], "translate": [0.65, -0.55]}]}]})";
  const Tree tree = io::read_tree_string(tree_text(2, root));
  scad::ExportReport report;
  const Rendered r = render("planar", tree, options(), &report, ".svg");
  ASSERT_EQ(r.rc, 0) << r.log;
  EXPECT_EQ(report.quadric_leaves, 4);
  EXPECT_EQ(report.quadrics_classified, 3);
  const std::map<std::string, int> kinds{
      {"band", 1}, {"circle", 1}, {"parabola", 1}, {"polygon", 1}};
  EXPECT_EQ(report.quadric_kinds, kinds);
  const auto loops =
      scad_test::read_svg_loops(std::filesystem::path(r.scad).replace_extension(".svg"));
  ASSERT_FALSE(loops.empty());
  MeshOptions mo;
  mo.resolution = 512;
  const double ours = contours_area(extract_contours(tree, tree.params.values(), mo));
  const double theirs = scad_test::loops_area(loops);
  EXPECT_NEAR(theirs, ours, 0.02 * ours);
  const scad_test::Agreement a = agreement(tree, 20000, [&](const std::array<double, 3>& p) {
    return scad_test::inside_loops(loops, p[0], p[1]);
  });
  EXPECT_GT(a.fraction, 0.995);
  EXPECT_GT(a.iou, 0.98);
  std::cout << fmt::format(
      "  area: OpenSCAD {:.6f}, ours {:.6f} ({:+.3f}%); inside: agree on "
      "{:.3f}% of the samples, IoU {:.4f}\n",
      theirs, ours, 100.0 * (theirs - ours) / ours, 100.0 * a.fraction, a.iou);
}

}  // namespace
}  // namespace fuzzycsg
