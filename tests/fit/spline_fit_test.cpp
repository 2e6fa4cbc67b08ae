// Trees with fuzzy spline nodes in fit: as targets of a fit (the tree target evaluates them),
// and through pruning, which prunes inside a spline's children and keeps the node valid.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "fit/fit_support.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "fuzzycsg/fit/prune.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/target/target.hpp"
#include "io/tree_text.hpp"

namespace fuzzycsg {
namespace {

using test::tree2;

using testing::mse;
using testing::occupancy;
using testing::random_points;

TEST(SplineFit, ASplineTreeIsATarget) {
  const auto target = load_target(FUZZYCSG_SOURCE_DIR "/examples/spline_shape.json");
  ASSERT_EQ(target->dim(), 2);
  FitOptions o;
  o.prims = 4;
  o.iters = 60;
  o.batch = 256;
  o.lr = 1e-2;
  o.threads = 2;
  o.measure = false;
  o.prune_points = 4096;
  const FitResult r = fit(*target, o);
  ASSERT_EQ(r.stop, StopReason::kIterations);
  EXPECT_EQ(r.state.step, 60);
  for (const LossPoint& p : r.state.curve) EXPECT_TRUE(std::isfinite(p.loss));
  validate(r.pruned, "pruned");
}

const std::vector<float>& points_2d() {
  static const std::vector<float> p = random_points(20000, 2, 21);
  return p;
}

Tree pruned_2d(const Tree& tree, PruneReport* report = nullptr) {
  return prune(tree, points_2d(), PruneOptions{1e-3, 2}, report);
}

const std::string kDisc = R"({"type": "circle", "radius": 0.5, "sharpness": 20})";
const std::string kFar = R"({"type": "circle", "radius": 0.01, "translate": [5, 5]})";
const std::string kAll = R"({"type": "rectangle", "size": [10, 10]})";

std::string spline(const std::vector<std::string>& children, const std::string& cells = "[2, 2]") {
  std::string s;
  for (std::size_t k = 0; k < children.size(); ++k) s += (k ? ", " : "") + children[k];
  return R"({"op": "spline", "cells": )" + cells + R"(, "degree": 1, "children": [)" + s + "]}";
}

// Inside the children: a union with a far-away speck prunes to its disc; a constant child (the
// speck alone) keeps its subtree, since the node needs all its children.
TEST(SplinePrune, PrunesInsideChildrenAndStaysValid) {
  const std::string speckled = R"({"op": "union", "children": [)" + kDisc + ", " + kFar + "]}";
  const std::string shifted =
      R"({"type": "circle", "radius": 0.4, "translate": [0.3, 0.2], "sharpness": 20})";
  const Tree tree = io::read_tree_string(tree2(spline({speckled, shifted, kFar, kDisc})), "t");
  PruneReport report;
  const Tree out = pruned_2d(tree, &report);
  validate(out, "pruned");
  const Node& root = out.node(out.root);
  ASSERT_EQ(root.op, OpKind::kSpline);
  ASSERT_EQ(root.children.size(), 4u);
  EXPECT_EQ(out.node(root.children[0]).kind, NodeKind::kPrimitive);  // the union's disc
  EXPECT_EQ(out.node(root.children[2]).kind, NodeKind::kPrimitive);  // the speck, kept
  EXPECT_EQ(report.operators_before, 2);
  EXPECT_EQ(report.operators_after, 1);
  EXPECT_LT(mse(occupancy(tree, points_2d()), occupancy(out, points_2d())), 1e-3);
  // Written and read back (prune returns canonical trees).
  EXPECT_EQ(io::write_tree_string(io::read_tree_string(io::write_tree_string(out), "back")),
            io::write_tree_string(out));
}

// A spline all of whose children are the same shape is that shape; one of empty children is
// empty; a spline below a union that another child covers goes with the union.
TEST(SplinePrune, SimplifiesTheNodeItself) {
  const Tree same = io::read_tree_string(tree2(spline({kDisc, kDisc, kDisc, kDisc})), "same");
  const Tree a = pruned_2d(same);
  EXPECT_EQ(a.node(a.root).kind, NodeKind::kPrimitive);
  EXPECT_EQ(count(a).primitives, 1);

  const Tree empty = io::read_tree_string(tree2(spline({kFar, kFar, kFar, kFar})), "empty");
  const Tree b = pruned_2d(empty);
  EXPECT_EQ(count(b).operators, 0);
  EXPECT_LT(mse(occupancy(b, points_2d()), std::vector<float>(points_2d().size() / 2, 0.0f)), 1e-6);

  const Tree covered =
      io::read_tree_string(tree2(R"({"op": "union", "children": [)" + kAll + ", " +
                                 spline({kDisc, kFar, kDisc, kFar, kFar, kDisc}, "[3, 2]") + "]}"),
                           "covered");
  const Tree c = pruned_2d(covered);
  EXPECT_EQ(count(c).primitives, 1);

  // A real blend stays a spline.
  const Tree example = io::read_tree_file(FUZZYCSG_SOURCE_DIR "/examples/spline_shape.json");
  const Tree d = pruned_2d(example);
  validate(d, "example");
  EXPECT_EQ(d.node(d.root).op, OpKind::kSpline);
  EXPECT_LT(mse(occupancy(example, points_2d()), occupancy(d, points_2d())), 1e-3);
}

}  // namespace
}  // namespace fuzzycsg
