// The .scad text: header, numbers, placement order, operators (unified snapping, complements,
// logic families), clipping, meshed leaves (closed, faces clockwise from outside), the report,
// and errors (no file written, an existing file left as it was).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/scad/scad.hpp"
#include "scad_support.hpp"

namespace fuzzycsg {
namespace {

using scad_test::tree_text;

std::string export_text(const std::string& root, int dim = 3, scad::ExportOptions o = {},
                        scad::ExportReport* report = nullptr) {
  const Tree tree = io::read_tree_string(tree_text(dim, root));
  return scad::export_scad(tree, tree.params.values(), o, report);
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

TEST(ScadExport, HeaderNumbersAndPlacementOrder) {
  scad::ExportOptions o;
  o.fn = 48;
  o.source = "part.json";
  const std::string s = export_text(R"({"op": "union", "children": [
      {"type": "sphere", "radius": 0.123456789123, "sharpness": 10},
      {"type": "box", "size": [0.5, 0.25, 0.125], "translate": [0.1, -0.2, 0.3], "rotate": [10, 20, 30],
       "scale": 1.5, "step": "crisp"}]})",
                                    3, o);
  EXPECT_EQ(count(s, "$fn"), 1u);
  EXPECT_NE(s.find("$fn = 48;"), std::string::npos);
  EXPECT_EQ(s.rfind("// part.json (3D, 2 leaves, 1 operator)", 0), 0u) << s;
  EXPECT_NE(s.find("crisp counterpart"), std::string::npos);
  EXPECT_NE(s.find("sphere(r = 0.123456789);"), std::string::npos) << s;
  // World -> local is R^-1 (p - t) / s: translate, then rotate, then scale, then the primitive.
  EXPECT_NE(s.find("translate([0.1, -0.2, 0.3]) rotate([10, 20, 30]) scale(1.5) cube([0.5, 0.25, "
                   "0.125], center = true);"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("union() {"), std::string::npos);
  EXPECT_EQ(s.find("intersection() {\n  fuzzycsg_domain();"), std::string::npos);  // bounded
}

TEST(ScadExport, EveryFamilyOpenScadHas) {
  const std::string s = export_text(R"({"op": "union", "children": [
      {"type": "cylinder", "radius": 0.2, "height": 0.5},
      {"type": "cone", "radius1": 0.3, "radius2": 0.1, "height": 0.4},
      {"type": "torus", "major": 0.5, "minor": 0.1},
      {"type": "torus", "major": 0.05, "minor": 0.2},
      {"type": "ellipsoid", "radii": [0.3, 0.2, 0.1]},
      {"type": "capsule", "radius": 0.1, "height": 0.6},
      {"type": "plane", "normal": [0, 0, 2], "offset": 0.25}]})");
  EXPECT_NE(s.find("cylinder(h = 0.5, r = 0.2, center = true);"), std::string::npos);
  EXPECT_NE(s.find("cylinder(h = 0.4, r1 = 0.3, r2 = 0.1, center = true);"), std::string::npos);
  EXPECT_NE(s.find("rotate_extrude() translate([0.5, 0]) circle(r = 0.1);"), std::string::npos);
  EXPECT_NE(s.find("rotate_extrude() intersection() {"), std::string::npos);  // spindle torus
  EXPECT_NE(s.find("scale([0.3, 0.2, 0.1]) sphere(r = 1);"), std::string::npos);
  EXPECT_NE(s.find("hull() {"), std::string::npos);
  EXPECT_NE(s.find("translate([0, 0, -0.3]) sphere(r = 0.1);"), std::string::npos);
  // The plane z < 0.25 as a cube turned (by no angle) with its top face in the plane, half as
  // wide as the cover's farthest corner is distant (1.2 sqrt 3 = 2.08, rounded up to 2.1); the
  // model is then clipped.
  EXPECT_NE(s.find("rotate([0, 0, 0]) translate([-2.1, -2.1, -3.95]) cube(4.2);  // half-space (0, "
                   "0, 1) . p <= 0.25"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("intersection() {\n  fuzzycsg_domain();"), std::string::npos) << s;
  EXPECT_NE(s.find("module fuzzycsg_space() translate([-1.2, -1.2, -1.2]) cube([2.4, 2.4, 2.4]);"),
            std::string::npos);
  const std::string s2 = export_text(R"({"op": "union", "children": [
      {"type": "circle", "radius": 0.2}, {"type": "rectangle", "size": [0.4, 0.2], "rotate": 30},
      {"type": "ellipse", "radii": [0.3, 0.1]}, {"type": "polygon", "vertices": [[0, 0], [0.5, 0], [0, 0.5]]}]})",
                                     2);
  EXPECT_NE(s2.find("circle(r = 0.2);"), std::string::npos);
  EXPECT_NE(s2.find("rotate(30) square([0.4, 0.2], center = true);"), std::string::npos);
  EXPECT_NE(s2.find("scale([0.3, 0.1]) circle(r = 1);"), std::string::npos);
  EXPECT_NE(s2.find("polygon([[0, 0], [0.5, 0], [0, 0.5]]);"), std::string::npos);
  // A bounded model uses neither the domain nor the cover: their modules are not written.
  EXPECT_EQ(s2.find("module fuzzycsg_domain()"), std::string::npos) << s2;
  EXPECT_EQ(s2.find("module fuzzycsg_space()"), std::string::npos) << s2;
  const std::string c2 = export_text(R"({"op": "complement", "children": [
      {"type": "circle", "radius": 0.2}]})",
                                     2);
  EXPECT_NE(c2.find("module fuzzycsg_domain() translate([-1, -1]) square([2, 2]);"),
            std::string::npos)
      << c2;
}

// The extrude: linear_extrude of the profile's sampled polygon (15 points per segment, P_k
// first), centred, under the leaf's placement; the samples of a straight side between its ends
// are left out (the same polygon).
TEST(ScadExport, ExtrudeIsTheLinearExtrusionOfItsPolygon) {
  const std::string s = export_text(R"({"type": "extrude",
      "profile": [[0, -0.5], [0, -0.2], [0, 0.2], [0, 0.5], [0.6, 0.5], [0.6, -0.5]],
      "height": 0.3, "translate": [0.1, 0, 0], "rotate": [90, 0, 0]})");
  const std::string head =
      "translate([0.1, 0, 0]) rotate([90, 0, 0]) linear_extrude(height = 0.3, center = true) "
      "polygon(";
  const std::size_t at = s.find(head);
  ASSERT_NE(at, std::string::npos) << s;
  const std::size_t end = s.find(");", at);
  ASSERT_NE(end, std::string::npos);
  const std::string points = s.substr(at + head.size(), end - at - head.size());
  // The list's bracket and 16 points: the first segment is straight (x = 0), so of its 15
  // samples only P0 is written; the second is curved: P1 and its 14 samples.
  EXPECT_EQ(count(points, "["), 17u) << points;
  EXPECT_EQ(points.rfind("[[0, -0.5], [0, 0.5], [0.112, ", 0), 0u) << points;
  // Sample 0 of the second segment is P1; sample 8 of it is the curve at t = 8/15,
  // x = 1.8 t (1 - t) = 0.448.
  EXPECT_NE(points.find("[0, 0.5], [0.112, "), std::string::npos) << points;
  EXPECT_NE(points.find("[0.448, -0.0499"), std::string::npos) << points;
  EXPECT_EQ(s.find("polyhedron"), std::string::npos);
}

TEST(ScadExport, OperatorsAreTheirCrispBooleans) {
  // Unified weights snapped to their argmax: B \ A is a difference with the children swapped.
  const std::string s = export_text(R"({"op": "unified", "c": [0.1, 0.2, 0.3, 0.4], "children": [
      {"type": "sphere", "radius": 0.5, "name": "first"}, {"type": "box", "size": [1, 1, 1], "name": "second"}]})");
  EXPECT_NE(s.find("difference() {  // unified, snapped to B \\ A"), std::string::npos) << s;
  EXPECT_LT(s.find("\"second\""), s.find("\"first\""));
  // Logits: c = softmax(sin(omega logits) t); sin(10 * 0.1) is the largest: intersection.
  const std::string l =
      export_text(R"({"op": "unified", "logits": [0.1, -0.05, 0.3, 0.02], "children": [
      {"type": "sphere", "radius": 0.5}, {"type": "box", "size": [1, 1, 1]}]})");
  EXPECT_NE(l.find("intersection() {  // unified, snapped to A & B"), std::string::npos) << l;
  // Any logic family: the crisp operator; n-ary unions stay n-ary.
  const std::string y = export_text(R"({"op": "union", "logic": "yager", "p": 3, "children": [
      {"type": "sphere", "radius": 0.5}, {"type": "box", "size": [1, 1, 1]},
      {"op": "difference", "logic": "dombi", "complement": "cosine", "children": [
        {"type": "sphere", "radius": 0.4}, {"type": "sphere", "radius": 0.2}]}]})");
  EXPECT_EQ(count(y, "union() {"), 1u);
  EXPECT_EQ(count(y, "difference() {"), 1u);
  EXPECT_EQ(y.find("intersection() {\n  fuzzycsg_domain();"), std::string::npos);
  // A complement: the cover minus its child, and the model clipped to the domain.
  scad::ExportReport report;
  const std::string c = export_text(
      R"({"op": "complement", "children": [{"type": "sphere", "radius": 0.5}]})", 3, {}, &report);
  EXPECT_NE(c.find("difference() {  // complement\n    fuzzycsg_space();"), std::string::npos) << c;
  EXPECT_TRUE(report.clipped);
  scad::ExportOptions never;
  never.clip = scad::Clip::kNever;
  EXPECT_EQ(export_text(R"({"op": "complement", "children": [{"type": "sphere", "radius": 0.5}]})",
                        3, never)
                .find("fuzzycsg_domain();"),
            std::string::npos);
  scad::ExportOptions always;
  always.clip = scad::Clip::kAlways;
  EXPECT_NE(
      export_text(R"({"type": "sphere", "radius": 0.5})", 3, always).find("fuzzycsg_domain();"),
      std::string::npos);
}

// The points and faces of the first polyhedron(...) of the text.
struct Polyhedron {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 3>> faces;
};

Polyhedron parse_polyhedron(const std::string& s) {
  Polyhedron p;
  const std::size_t at = s.find("polyhedron(points = [");
  const std::size_t faces = s.find("faces = [", at);
  const std::size_t end = s.find("], convexity", faces);
  if (at == std::string::npos || faces == std::string::npos || end == std::string::npos) return p;
  // Every innermost [a, b, c] of the points' and of the faces' lists.
  const auto triples = [](const std::string& t) {
    std::vector<std::array<double, 3>> out;
    for (std::size_t i = t.find('['); i != std::string::npos; i = t.find('[', i + 1)) {
      const std::size_t close = t.find(']', i);
      const std::string inner = t.substr(i + 1, close - i - 1);
      if (inner.find('[') != std::string::npos) continue;
      std::array<double, 3> v{};
      if (std::sscanf(inner.c_str(), "%lf, %lf, %lf", &v[0], &v[1], &v[2]) == 3) out.push_back(v);
    }
    return out;
  };
  p.points = triples(s.substr(at, faces - at));
  for (const auto& f : triples(s.substr(faces, end - faces))) {
    p.faces.push_back({static_cast<int>(f[0]), static_cast<int>(f[1]), static_cast<int>(f[2])});
  }
  return p;
}

// Nested booleans that one OpenSCAD statement says at once are one statement: unions in a union,
// intersections in an intersection, a difference first in a difference and unions after it.
// Others stay nested: a difference second in a difference, a union in an intersection, a
// unified operator. The header still counts the tree's operators.
TEST(ScadExport, NestedBooleansAreFoldedWhereOneStatementSaysTheSame) {
  const std::string leaf = R"({"type": "sphere", "radius": 0.1})";
  const auto op = [](const std::string& name, const std::string& a, const std::string& b) {
    return R"({"op": ")" + name + R"(", "children": [)" + a + ", " + b + "]}";
  };
  // ((a | b) | c) \ d \ (e | f): one difference() of one union() and three spheres.
  scad::ExportOptions bare;
  bare.leaf_comments = false;
  const std::string folded = export_text(
      op("difference", op("difference", op("union", op("union", leaf, leaf), leaf), leaf),
         op("union", leaf, leaf)),
      3, bare);
  EXPECT_NE(folded.find("(3D, 6 leaves, 5 operators)"), std::string::npos) << folded;
  EXPECT_EQ(count(folded, "union() {"), 1u) << folded;
  EXPECT_EQ(count(folded, "difference() {"), 1u) << folded;
  EXPECT_NE(folded.find("difference() {\n  union() {\n    sphere(r = 0.1);\n    sphere(r = 0.1);\n"
                        "    sphere(r = 0.1);\n  }\n  sphere(r = 0.1);\n  sphere(r = 0.1);\n"
                        "  sphere(r = 0.1);\n}"),
            std::string::npos)
      << folded;
  const std::string meet =
      export_text(op("intersection", op("intersection", leaf, leaf), op("union", leaf, leaf)));
  EXPECT_EQ(count(meet, "intersection() {"), 1u) << meet;
  EXPECT_EQ(count(meet, "union() {"), 1u) << meet;
  // a \ (b \ c) keeps its inner difference; a unified operator is not folded into a union.
  const std::string kept = export_text(op("difference", leaf, op("difference", leaf, leaf)));
  EXPECT_EQ(count(kept, "difference() {"), 2u) << kept;
  const std::string unified = export_text(
      R"({"op": "union", "children": [{"op": "unified", "c": [0, 1, 0, 0], "children": [)" + leaf +
      ", " + leaf + "]}, " + leaf + "]}");
  EXPECT_EQ(count(unified, "union() {"), 2u) << unified;
}

// Leaf comments name the node path; without them only named leaves have one.
TEST(ScadExport, LeafCommentsCanBeLeftOut) {
  const std::string root = R"({"op": "union", "children": [{"type": "sphere", "radius": 0.1},
      {"type": "box", "size": [1, 1, 1], "name": "plate"}]})";
  const std::string with = export_text(root);
  EXPECT_NE(with.find("// root.children[0]: sphere\n"), std::string::npos) << with;
  EXPECT_NE(with.find("// root.children[1] \"plate\": box\n"), std::string::npos) << with;
  scad::ExportOptions o;
  o.leaf_comments = false;
  const std::string without = export_text(root, 3, o);
  EXPECT_EQ(without.find("root.children"), std::string::npos) << without;
  EXPECT_NE(without.find("  // \"plate\"\n  cube("), std::string::npos) << without;
}

TEST(ScadExport, UnclassifiedLeavesAreClosedPolyhedraClockwiseFromOutside) {
  scad::ExportOptions o;
  o.resolution = 24;
  scad::ExportReport report;
  // A hyperboloid of one sheet (not classified) and a small MLP.
  const std::string s = export_text(R"({"op": "union", "children": [
      {"type": "quadric", "coefficients": [4, 4, -4, 0, 0, 0, 0, 0, 0, -0.5]},
      {"type": "mlp", "hidden": [], "weights": [1, 0.5, -0.25, -0.3]}]})",
                                    3, o, &report);
  EXPECT_EQ(report.meshed_leaves, 2);
  EXPECT_EQ(report.quadrics_classified, 0);
  EXPECT_EQ(report.quadric_kinds, (std::map<std::string, int>{{"polyhedron", 1}}));
  EXPECT_TRUE(report.clipped);  // both reach the edge of the meshed box
  const Polyhedron p = parse_polyhedron(s);
  ASSERT_GT(p.faces.size(), 500u);
  // Closed and consistently oriented: every directed edge once, and its reverse once.
  std::map<std::pair<int, int>, int> edges;
  for (const auto& f : p.faces) {
    for (int e = 0; e < 3; ++e)
      ++edges[{f[static_cast<std::size_t>(e)], f[static_cast<std::size_t>((e + 1) % 3)]}];
  }
  int bad = 0;
  for (const auto& [e, n] : edges) bad += n != 1 || edges.count({e.second, e.first}) != 1 ? 1 : 0;
  EXPECT_EQ(bad, 0);
  // Clockwise seen from outside: the signed volume of the faces as written is negative.
  double volume = 0.0;
  for (const auto& f : p.faces) {
    const auto& a = p.points[static_cast<std::size_t>(f[0])];
    const auto& b = p.points[static_cast<std::size_t>(f[1])];
    const auto& c = p.points[static_cast<std::size_t>(f[2])];
    volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
               a[2] * (b[0] * c[1] - b[1] * c[0])) /
              6.0;
  }
  EXPECT_LT(volume, -0.5);
  // No two vertices closer than OpenSCAD merges them (2^-20).
  double closest = 1.0;
  for (std::size_t i = 0; i < p.points.size(); ++i) {
    for (std::size_t k = i + 1; k < p.points.size(); ++k) {
      double d = 0.0;
      for (std::size_t a = 0; a < 3; ++a)
        d = std::max(d, std::abs(p.points[i][a] - p.points[k][a]));
      closest = std::min(closest, d);
    }
  }
  EXPECT_GT(closest, 4.0 / (1 << 20));
  // 2D: the contour of a hyperbola as polygon(points, paths).
  scad::ExportReport r2;
  const std::string s2 =
      export_text(R"({"type": "quadric", "coefficients": [4, -4, 0, 0, 0, -0.5]})", 2, o, &r2);
  EXPECT_NE(s2.find("polygon(points = ["), std::string::npos);
  EXPECT_NE(s2.find("paths = [[0, 1, 2"), std::string::npos);
  EXPECT_EQ(r2.quadric_kinds, (std::map<std::string, int>{{"polygon", 1}}));
}

TEST(ScadExport, QuadricsAreWrittenAsTheirPrimitives) {
  scad::ExportReport report;
  // x^2 + y^2 - 0.25 < 0 (a cylinder), its negation (the outside), z - 0.5 < 0 (a plane), and
  // a sphere with a translation.
  const std::string s = export_text(R"({"op": "union", "children": [
      {"type": "quadric", "coefficients": [1, 1, 0, 0, 0, 0, 0, 0, 0, -0.25]},
      {"type": "quadric", "coefficients": [-1, -1, 0, 0, 0, 0, 0, 0, 0, 0.81]},
      {"type": "quadric", "coefficients": [0, 0, 0, 0, 0, 0, 0, 0, 3, -1.5]},
      {"type": "quadric", "coefficients": [1, 1, 1, 0, 0, 0, 0, 0, 0, -0.04], "translate": [0.5, 0, 0]}]})",
                                    3, {}, &report);
  EXPECT_EQ(report.quadric_leaves, 4);
  EXPECT_EQ(report.quadrics_classified, 4);
  EXPECT_EQ(report.quadrics_outside, 1);
  EXPECT_EQ(report.quadric_kinds,
            (std::map<std::string, int>{{"cylinder", 2}, {"plane", 1}, {"sphere", 1}}));
  EXPECT_EQ(report.meshed_leaves, 0);
  EXPECT_EQ(count(s, "multmatrix("), 4u);
  EXPECT_NE(s.find("cylinder(h = "), std::string::npos);
  EXPECT_NE(s.find("// root.children[1]: quadric, the outside of a cylinder"), std::string::npos);
  EXPECT_NE(s.find("multmatrix([[0.2, 0, 0, 0.5], [0, 0.2, 0, 0], [0, 0, 0.2, 0], [0, 0, 0, 1]]) "
                   "sphere(r = 1);"),
            std::string::npos)
      << s;
  // The report as JSON.
  const auto j = nlohmann::json::parse(scad::report_json(report));
  EXPECT_EQ(j["quadric_leaves"], 4);
  EXPECT_EQ(j["quadric_kinds"]["cylinder"], 2);
  EXPECT_EQ(j["leaf_details"].size(), 4u);
  EXPECT_EQ(j["leaf_details"][3]["written"], "sphere");
  EXPECT_NEAR(j["leaf_details"][3]["axes"][0].get<double>(), 0.2, 1e-12);
  EXPECT_EQ(j["leaf_details"][1]["outside"], true);
}

TEST(ScadExport, BadPathsAndOptionsWriteNothing) {
  const Tree tree = io::read_tree_string(tree_text(3, R"({"type": "sphere", "radius": 0.5})"));
  const scad_test::TestDir dir("errors");
  const auto expect_error = [&](const std::filesystem::path& path, const scad::ExportOptions& o,
                                const std::string& want) {
    try {
      scad::write_scad(tree, tree.params.values(), path, o);
      ADD_FAILURE() << "no error for " << path;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  };
  expect_error(dir / "model.stl", {}, "model.stl: unknown format '.stl'");
  EXPECT_FALSE(std::filesystem::exists(dir / "model.stl"));
  expect_error(dir / "no" / "such" / "model.scad", {}, "cannot write");
  scad::ExportOptions bad;
  bad.fn = 2;
  std::ofstream(dir / "kept.scad") << "previous";
  expect_error(dir / "kept.scad", bad, "fn: ");
  bad.fn = 32;
  bad.resolution = 1;
  expect_error(dir / "kept.scad", bad, "resolution: ");
  std::ifstream in(dir / "kept.scad");
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(ss.str(), "previous");
  // Nothing but the kept file is left in the directory (no temporary files).
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1);
  scad::write_scad(tree, tree.params.values(), dir / "kept.scad");
  std::ifstream again(dir / "kept.scad");
  std::stringstream ss2;
  ss2 << again.rdbuf();
  EXPECT_NE(ss2.str().find("sphere(r = 0.5);"), std::string::npos);
}

}  // namespace
}  // namespace fuzzycsg

namespace fuzzycsg {
namespace {

// A spline node blends, it has no crisp boolean: it is written as the polygon (2D) or polyhedron
// (3D) of its 0.5 level set, and its own leaves are not visited.
TEST(ScadExport, SplineNodesAreMeshedAsAWhole) {
  const std::string cells = R"("op": "spline", "cells": [2, 2], "degree": 1, "children": [)";
  const std::string kid2 = R"({"type": "circle", "radius": 0.5, "sharpness": 20})";
  const std::string kid3 = R"({"type": "sphere", "radius": 0.5, "sharpness": 20})";
  for (int dim : {2, 3}) {
    std::string children;
    const int n = dim == 2 ? 4 : 8;
    std::string root =
        dim == 2
            ? std::string("{") + cells
            : std::string(R"({"op": "spline", "cells": [2, 2, 2], "degree": 1, "children": [)");
    for (int k = 0; k < n; ++k) root += (k ? ", " : "") + (dim == 2 ? kid2 : kid3);
    root += "]}";
    scad::ExportReport report;
    scad::ExportOptions o;
    o.resolution = 16;
    const std::string s = export_text(root, dim, o, &report);
    EXPECT_NE(s.find("spline blend of " + std::to_string(n) + " shapes"), std::string::npos) << s;
    EXPECT_EQ(count(s, dim == 2 ? "polygon(points" : "polyhedron(points"), 1u) << s;
    EXPECT_EQ(report.meshed_subtrees, 1);
    EXPECT_EQ(report.leaves, 0);  // the blend's children are inside the mesh
  }
}

}  // namespace
}  // namespace fuzzycsg
