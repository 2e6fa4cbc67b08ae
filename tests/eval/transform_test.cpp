// A tree moved and scaled as a whole (core/transform.hpp): the same shape at the mapped points,
// for every leaf placement and step, in 2D and 3D; the inverse map gives the tree back; shared
// placement parameters are refused.

#include "fuzzycsg/core/transform.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg {
namespace {

// A 3D tree with a leaf of every kind of placement and step: none, a rotation, a translation and
// a scale, a crisp step, an H_n step, a unified operator and a domain of its own.
const char* kTree3 = R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
  "domain": {"min": [-1, -1, -0.5], "max": [1, 1, 0.5]},
  "root": {"op": "difference", "children": [
    {"op": "unified", "logits": [0.3, -0.1, 0.2, 0.05], "children": [
      {"type": "sphere", "radius": 0.6, "sharpness": 20},
      {"type": "box", "size": [0.5, 0.3, 0.8], "rotate": [10, 20, 30], "step": "crisp"}]},
    {"op": "union", "children": [
      {"type": "cylinder", "radius": 0.2, "height": 1.5, "translate": [0.2, -0.1, 0],
       "scale": 0.8, "step": {"hn": 3, "range": 0.1}},
      {"type": "quadric", "coefficients": [1, 2, 3, 0.1, 0.2, 0.3, 0, 0, 0, -0.2],
       "sharpness": 5}]}]}})";

const char* kTree2 = R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
  "root": {"op": "union", "children": [
    {"type": "circle", "radius": 0.4, "translate": [0.3, 0.1], "sharpness": 30},
    {"type": "rectangle", "size": [0.6, 0.2], "rotate": 25, "step": "crisp"}]}})";

std::vector<double> occupancies(const Tree& tree, const std::vector<std::array<double, 3>>& at) {
  std::vector<double> out;
  const std::vector<double> params = tree.params.values();
  for (const auto& p : at) out.push_back(reference_occupancy(tree, params, p.data()));
  return out;
}

void expect_same_shape(const Tree& tree, const Similarity& m) {
  const Tree moved = transformed(tree, m);
  validate(moved, "moved");
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::array<double, 3>> x(2000), y(2000);
  for (std::size_t i = 0; i < x.size(); ++i) {
    for (int a = 0; a < tree.dim; ++a) x[i][a] = u(rng);
    y[i] = m.apply(x[i]);
    if (tree.dim == 2) y[i][2] = 0;
  }
  const std::vector<double> before = occupancies(tree, x), after = occupancies(moved, y);
  int inside = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    EXPECT_NEAR(after[i], before[i], 1e-9) << "point " << i;
    inside += before[i] > 0.5;
  }
  EXPECT_GT(inside, 20);  // the points see the shape
  EXPECT_LT(inside, 1980);
  // The domain moves with the shape.
  const Domain d = tree.domain_or_default(), e = moved.domain_or_default();
  for (int a = 0; a < tree.dim; ++a) {
    EXPECT_NEAR(e.min[a], m.scale * d.min[a] + m.translate[a], 1e-12);
    EXPECT_NEAR(e.max[a], m.scale * d.max[a] + m.translate[a], 1e-12);
  }
  // The inverse gives the tree back.
  const Tree back = transformed(moved, m.inverse());
  const std::vector<double> again = occupancies(back, x);
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(again[i], before[i], 1e-9);
}

TEST(Transform, EveryLeafKeepsItsShapeAtTheMappedPoints) {
  const Tree tree = io::read_tree_string(kTree3, "t3");
  expect_same_shape(tree, Similarity{{12.5, -3, 40}, 7.25});
  expect_same_shape(tree, Similarity{{0, 0, 0}, 0.01});
  expect_same_shape(tree, Similarity{{-5, 2, 0.5}, 1.0});
  expect_same_shape(io::read_tree_string(kTree2, "t2"), Similarity{{100, -50, 0}, 30});
}

TEST(Transform, LeavesGainNamedPlacementAndStepsScale) {
  const Tree tree = io::read_tree_string(kTree3, "t3");
  const Tree moved = transformed(tree, Similarity{{1, 2, 3}, 4});
  // The sphere had no placement: it gets one, named by its path.
  const auto t0 = moved.params.find("root.children[0].children[0].translate[0]");
  const auto s0 = moved.params.find("root.children[0].children[0].scale");
  ASSERT_TRUE(t0 && s0);
  EXPECT_EQ(moved.params[*t0].value, 1.0);
  EXPECT_EQ(moved.params[*s0].value, 4.0);
  // Sharpness divides by the scale, an H_n range multiplies, a translation maps.
  EXPECT_EQ(moved.params[*moved.params.find("root.children[0].children[0].sharpness")].value, 5.0);
  EXPECT_NEAR(moved.params[*moved.params.find("root.children[1].children[0].step.range")].value,
              0.4, 1e-15);
  EXPECT_NEAR(moved.params[*moved.params.find("root.children[1].children[0].translate[0]")].value,
              1.8, 1e-15);
  EXPECT_NEAR(moved.params[*moved.params.find("root.children[1].children[0].scale")].value, 3.2,
              1e-15);
  // Operators do not change; the file round-trips.
  EXPECT_EQ(io::write_tree_string(io::read_tree_string(io::write_tree_string(moved), "m")),
            io::write_tree_string(moved));
  // The identity changes nothing, not even the absent domain.
  const Tree same = transformed(io::read_tree_string(kTree2, "t2"), Similarity{});
  EXPECT_FALSE(same.domain.has_value());
  EXPECT_EQ(io::write_tree_string(same), io::write_tree_string(io::read_tree_string(kTree2, "")));
}

TEST(Transform, SharedPlacementAndBadMapsAreRefused) {
  const Tree shared = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
    "parameters": {"x": 0.2},
    "root": {"op": "union", "children": [
      {"type": "circle", "radius": 0.3, "translate": [{"param": "x"}, 0]},
      {"type": "circle", "radius": 0.3, "translate": [0, {"param": "x"}]}]}})",
                                           "shared");
  try {
    transformed(shared, Similarity{{1, 0, 0}, 2});
    ADD_FAILURE() << "a shared translation was moved";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("parameter \"x\": shared by several fields"),
              std::string::npos)
        << e.what();
  }
  const Tree tree = io::read_tree_string(kTree2, "t2");
  EXPECT_THROW(transformed(tree, Similarity{{0, 0, 0}, 0}), InputError);
  EXPECT_THROW(transformed(tree, Similarity{{0, 0, 0}, -1}), InputError);
  EXPECT_THROW(transformed(tree, Similarity{{std::nan(""), 0, 0}, 1}), InputError);
}

}  // namespace
}  // namespace fuzzycsg
