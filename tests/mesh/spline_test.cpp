// The fuzzy spline node in meshing: its interval bounds contain the occupancy over random boxes
// (inside and outside the spline's box), drop the children whose basis vanishes on a box, and
// the per-brick simplification leaves the meshes and contours unchanged.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <cmath>
#include <random>
#include <string>

#include "bounds_support.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/mesh/mesh.hpp"
#include "mesh/bounds.hpp"

namespace fuzzycsg {
namespace {

// A spline with `cells` per axis of `degree` over `box` (a JSON object, or empty for the
// domain); its children are spheres (circles) centred near the origin with radii in
// [0.35, 0.75], every third one a box (rectangle) instead, and one in 3D a union of two.
Tree spline_tree(int dim, std::vector<int> cells, int degree, const std::string& box, unsigned seed,
                 double sharpness = 12.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> r(0.35, 0.75), t(-0.15, 0.15);
  int total = 1;
  std::string cells_text;
  for (std::size_t a = 0; a < cells.size(); ++a) {
    total *= cells[a];
    cells_text += fmt::format("{}{}", a ? ", " : "", cells[a]);
  }
  std::string children;
  for (int k = 0; k < total; ++k) {
    const std::string translate = dim == 3 ? fmt::format("[{}, {}, {}]", t(rng), t(rng), t(rng))
                                           : fmt::format("[{}, {}]", t(rng), t(rng));
    std::string leaf;
    if (k % 3 == 2) {
      const double s = 1.6 * r(rng);
      leaf = fmt::format(R"({{"type": "{}", "size": [{}], "translate": {}, "sharpness": {}}})",
                         dim == 3 ? "box" : "rectangle",
                         dim == 3 ? fmt::format("{}, {}, {}", s, 0.9 * s, 1.1 * s)
                                  : fmt::format("{}, {}", s, 0.8 * s),
                         translate, sharpness);
    } else {
      leaf = fmt::format(R"({{"type": "{}", "radius": {}, "translate": {}, "sharpness": {}}})",
                         dim == 3 ? "sphere" : "circle", r(rng), translate, sharpness);
    }
    if (dim == 3 && k == 4) {
      leaf = fmt::format(
          R"({{"op": "union", "children": [{}, {{"type": "sphere", "radius": 0.3, "translate": [0.5, 0, 0], "sharpness": {}}}]}})",
          leaf, sharpness);
    }
    children += (k ? ",\n" : "") + leaf;
  }
  return io::read_tree_string(
      fmt::format(R"({{"format": "fuzzycsg-tree", "version": 1, "dim": {}, "root": {{"op": "spline",
          "cells": [{}], "degree": {}{}, "children": [{}]}}}})",
                  dim, cells_text, degree, box.empty() ? "" : ", \"box\": " + box, children),
      "spline");
}

using test::check_bounds;

TEST(SplineBounds, ContainTheOccupancy) {
  for (int degree = 1; degree <= 3; ++degree) {
    SCOPED_TRACE(fmt::format("degree {}", degree));
    // A box inside the domain: boxes of the test lie partly or wholly outside it.
    const double w2 =
        check_bounds(spline_tree(2, {degree + 2, degree + 1}, degree,
                                 R"({"min": [-0.6, -0.8], "max": [0.7, 0.5]})", degree),
                     400, 10 + degree);
    EXPECT_LT(w2, 0.9);
    const double w3 = check_bounds(
        spline_tree(3, {degree + 1, degree + 2, degree + 1}, degree,
                    R"({"min": [-0.6, -0.8, -0.7], "max": [0.7, 0.5, 0.8]})", 20 + degree),
        300, 30 + degree);
    EXPECT_LT(w3, 0.9);
    check_bounds(spline_tree(2, {5, 4}, degree, "", 40 + degree, 40.0), 300, 50 + degree);
  }
}

// Children whose basis function vanishes on a box do not widen its bounds: four linear hats
// per axis over [0, 3]^2 (knots at the integers), child k full (a disc covering the domain) and
// every other child empty (a disc far away).
TEST(SplineBounds, DropChildrenWhoseBasisVanishes) {
  const auto tree_with_full = [](int full) {
    std::string children;
    for (int k = 0; k < 16; ++k) {
      children += fmt::format(
          R"({}{{"type": "circle", "radius": {}, "translate": [{}, 0], "sharpness": 50}})",
          k ? ", " : "", k == full ? 10 : 0.1, k == full ? 0 : 50);
    }
    return io::read_tree_string(
        R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2, "domain": {"min": [-1, -1], "max": [4, 4]},
            "root": {"op": "spline", "cells": [4, 4], "degree": 1,
                     "box": {"min": [0, 0], "max": [3, 3]}, "children": [)" +
            children + "]}}",
        "hat");
  };
  // Child 5 is (i, j) = (1, 1): its hat lives on (0, 2) x (0, 2).
  const Tree tree = tree_with_full(5);
  const auto params = tree.params.values();
  const auto bound = [&](double x0, double y0, double x1, double y1) {
    const double lo[2] = {x0, y0}, hi[2] = {x1, y1};
    return occupancy_bounds(tree, params, lo, hi);
  };
  EXPECT_LT(bound(2.0, 0.5, 3.0, 1.5).hi, 1e-6);    // x >= 2: outside the hat's support
  EXPECT_LT(bound(2.2, 2.2, 3.5, 3.9).hi, 1e-6);    // and beyond the box
  EXPECT_LT(bound(-1.0, -1.0, 0.0, 3.0).hi, 1e-6);  // x <= 0, clamped to the box's face
  EXPECT_GT(bound(0.5, 0.5, 1.5, 1.5).hi, 0.99);
  // The weights' ranges count, not only which children take part: near the support's corner
  // the full child's weight is at most 0.1^2, near its peak at least 0.9^2.
  const Interval corner_of_support = bound(1.9, 1.9, 2.0, 2.0);
  EXPECT_GT(corner_of_support.hi, 0.0099);
  EXPECT_LT(corner_of_support.hi, 0.0101);
  EXPECT_GT(bound(0.9, 0.9, 1.1, 1.1).lo, 0.8);
  // Beyond the box's corner the corner child alone has weight 1.
  const Tree corner = tree_with_full(0);
  const auto cp = corner.params.values();
  const double lo[2] = {-0.9, -0.8}, hi[2] = {0.0, 0.0};
  EXPECT_GT(occupancy_bounds(corner, cp, lo, hi).lo, 0.999);
}

// The simplified bricks (children with vanishing basis replaced, single children passed
// through) give the same triangles as evaluating the whole tree, and the mesh is closed.
TEST(SplineMesh, ClosedAndSimplifiedMatchesWhole) {
  const Tree tree = spline_tree(3, {4, 4, 4}, 2, "", 7, 20.0);
  MeshOptions o;
  o.resolution = 48;
  MeshStats simple_stats, whole_stats;
  const TriangleMesh simple = extract_mesh(tree, tree.params.values(), o, &simple_stats);
  o.simplify = false;
  const TriangleMesh whole = extract_mesh(tree, tree.params.values(), o, &whole_stats);
  ASSERT_GT(simple.triangles.size(), 1000u);
  EXPECT_EQ(open_or_misoriented_edges(simple), 0u);
  EXPECT_EQ(simple.triangles, whole.triangles);
  ASSERT_EQ(simple.vertices.size(), whole.vertices.size());
  for (std::size_t v = 0; v < simple.vertices.size(); ++v) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(simple.vertices[v][c], whole.vertices[v][c], 1e-4);
  }
  EXPECT_GT(signed_volume(simple), 0.1);
  // Each brick needs at most 3 of the 4 functions per axis (27 of the 64 children).
  EXPECT_LT(simple_stats.leaves_evaluated * 2, whole_stats.leaves_evaluated);

  // Degree 1 with the knot at 0 on a brick boundary: each brick needs 8 of the 27 children.
  const Tree hats = spline_tree(3, {3, 3, 3}, 1, "", 8, 20.0);
  o.simplify = true;
  const TriangleMesh h1 = extract_mesh(hats, hats.params.values(), o, &simple_stats);
  o.simplify = false;
  const TriangleMesh h2 = extract_mesh(hats, hats.params.values(), o, &whole_stats);
  EXPECT_EQ(open_or_misoriented_edges(h1), 0u);
  EXPECT_EQ(h1.triangles, h2.triangles);
  EXPECT_LT(simple_stats.leaves_evaluated * 3, whole_stats.leaves_evaluated);

  // Octree pruning by the bounds changes nothing either.
  o.simplify = true;
  o.prune = false;
  const TriangleMesh dense = extract_mesh(hats, hats.params.values(), o);
  EXPECT_EQ(dense.triangles, h1.triangles);
}

TEST(SplineContours, ExampleIsOneClosedLoopAndSimplificationChangesNothing) {
  const Tree tree = io::read_tree_file(FUZZYCSG_SOURCE_DIR "/examples/spline_shape.json");
  MeshOptions o;
  o.resolution = 200;
  MeshStats simple_stats, whole_stats;
  const Contours simple = extract_contours(tree, tree.params.values(), o, &simple_stats);
  o.simplify = false;
  const Contours whole = extract_contours(tree, tree.params.values(), o, &whole_stats);
  ASSERT_EQ(simple.loops.size(), 1u);
  EXPECT_GT(simple.loops[0].size(), 100u);
  EXPECT_EQ(simple.loops, whole.loops);
  EXPECT_LT(simple_stats.leaves_evaluated * 2, whole_stats.leaves_evaluated);
  o.prune = false;
  const Contours dense = extract_contours(tree, tree.params.values(), o);
  EXPECT_EQ(dense.loops, simple.loops);
  // The enclosed area against a count of the grid points inside.
  const Evaluator ev(tree);
  std::vector<float> points;
  const int n = 400;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      points.push_back(-1.0f + 2.0f * (static_cast<float>(i) + 0.5f) / n);
      points.push_back(-1.0f + 2.0f * (static_cast<float>(j) + 0.5f) / n);
    }
  }
  std::vector<float> occ(points.size() / 2);
  ev.forward(tree.params.values(), points, occ);
  double inside = 0;
  for (float v : occ) inside += v >= 0.5f ? 1 : 0;
  const double area = inside * 4.0 / (n * n);
  EXPECT_GT(area, 0.5);
  EXPECT_NEAR(contours_area(simple), area, 0.01 * area);
}

// A box smaller than the domain: beyond its corners one child has weight 1 and replaces the
// node, beyond its faces only the children along that face count.
TEST(SplineContours, BoxSmallerThanTheDomain) {
  const Tree tree = spline_tree(2, {3, 4}, 2, R"({"min": [-0.4, -0.3], "max": [0.3, 0.5]})", 9);
  MeshOptions o;
  o.resolution = 160;
  o.brick = 4;
  MeshStats simple_stats, whole_stats;
  const Contours simple = extract_contours(tree, tree.params.values(), o, &simple_stats);
  o.simplify = false;
  const Contours whole = extract_contours(tree, tree.params.values(), o, &whole_stats);
  ASSERT_FALSE(simple.loops.empty());
  EXPECT_EQ(simple.loops, whole.loops);
  EXPECT_GT(contours_area(simple), 0.3);
  EXPECT_LT(simple_stats.leaves_evaluated * 2, whole_stats.leaves_evaluated);
}

}  // namespace
}  // namespace fuzzycsg
