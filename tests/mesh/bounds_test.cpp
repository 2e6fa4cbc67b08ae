#include "mesh/bounds.hpp"
#include "bounds_support.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <random>
#include <string>

#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg {
namespace {

using test::check_bounds;

TEST(Bounds, ContainUnifiedQuadricTrees) {
  for (unsigned seed : {1u, 2u, 3u}) {
    FullTreeOptions o;
    o.leaves = 32;
    o.seed = seed;
    o.temperature = 10.0;  // soft operators: B_c's bilinear corners matter
    const double width = check_bounds(make_full_binary_tree(o), 300, seed);
    EXPECT_LT(width, 0.9);
    o.dim = 2;
    o.family = PrimitiveType::kQuadric2;
    check_bounds(make_full_binary_tree(o), 300, seed + 10);
  }
}

TEST(Bounds, ContainPlacedPrimitivesAndFixedLogics) {
  for (OperatorMode ops : {OperatorMode::kProduct, OperatorMode::kGodel}) {
    FullTreeOptions o;
    o.leaves = 16;
    o.ops = ops;
    o.families = {PrimitiveType::kSphere, PrimitiveType::kBox, PrimitiveType::kCylinder,
                  PrimitiveType::kQuadric3};
    o.sharpness = 8.0;
    const double width = check_bounds(make_full_binary_tree(o), 300, 7);
    EXPECT_LT(width, 0.9);
    o.dim = 2;
    o.families = {PrimitiveType::kCircle, PrimitiveType::kRectangle};
    check_bounds(make_full_binary_tree(o), 300, 8);
  }
}

// Every logic family's union, intersection and difference (with each complement) is bounded by
// its values at the ends of the argument intervals: the monotonicity bounds.hpp relies on.
TEST(Bounds, ContainEveryLogicFamily) {
  const char* families[] = {"product",  "godel",    "lukasiewicz", "yager",
                            "einstein", "hamacher", "dombi",       "dubois-prade",
                            "weber",    "bezier",   "li-tian",     "li-tian-hat"};
  for (const char* fam : families) {
    const auto family = logic::family_from_name(fam);
    ASSERT_TRUE(family) << fam;
    std::string extra;
    if (logic::uses_p(*family)) {
      extra += fmt::format(", \"{}\": 0.6", logic::p_field_name(*family));
    }
    if (logic::uses_n(*family)) extra += ", \"n\": 3";
    for (const char* op : {"union", "intersection", "difference"}) {
      for (const char* complement : {"standard", "sugeno", "yager", "cosine"}) {
        if (std::string(op) != "difference" && std::string(complement) != "standard") continue;
        const auto kind = logic::complement_from_name(complement);
        ASSERT_TRUE(kind) << complement;
        std::string c;
        if (std::string(complement) != "standard") {
          c = fmt::format(", \"complement\": {{\"type\": \"{}\"{}}}", complement,
                          logic::complement_uses_lambda(*kind) ? ", \"lambda\": 1.5" : "");
        }
        const std::string text = fmt::format(
            R"({{"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {{
                "op": "{}", "logic": "{}"{}{}, "children": [
                  {{"type": "sphere", "radius": 0.5, "sharpness": 6}},
                  {{"type": "box", "size": [0.8, 0.5, 0.6], "translate": [0.3, 0, 0],
                    "sharpness": 4}}]}}}})",
            op, fam, extra, c);
        SCOPED_TRACE(fmt::format("{} {} {}", fam, op, complement));
        check_bounds(io::read_tree_string(text, "family"), 120, 3);
      }
    }
  }
}

// The extrude is an exact distance, so its bounds are Lipschitz ones: they hold for placed
// extrudes (one with a profile that crosses itself, whose f is still 1-Lipschitz) and the
// example, and are tight away from the surface.
TEST(Bounds, ContainPlacedExtrudes) {
  const Tree tree = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
    "root": {"op": "union", "logic": "godel", "children": [
      {"type": "extrude",
       "profile": [[-0.5, -0.3], [-0.2, -0.3], [0.2, -0.3], [0.5, -0.3], [0.9, -0.3], [0.9, 0.3],
                   [0.5, 0.3], [0.1, 0.4], [-0.2, 0.3], [-0.5, 0.3], [-0.9, 0.3], [-0.8, -0.3]],
       "height": 0.4, "translate": [0.1, -0.2, 0.1], "rotate": [20, -30, 40], "scale": 0.8,
       "sharpness": 12},
      {"type": "extrude",
       "profile": [[-0.4, -0.4], [0, 0], [0, 0], [0.4, 0.4], [0.6, 0], [0.6, 0], [0.4, -0.4],
                   [0, 0], [0, 0], [-0.4, 0.4], [-0.6, 0], [-0.6, 0]],
       "height": 0.3, "translate": [0, 0.5, -0.4], "rotate": [90, 0, 0], "sharpness": 20}]}})",
                                         "extrudes");
  EXPECT_LT(check_bounds(tree, 300, 11), 0.9);
  check_bounds(io::read_tree_file(FUZZYCSG_SOURCE_DIR "/examples/extrude_bracket.json"), 300, 12);
  const Tree plate = io::read_tree_file(FUZZYCSG_SOURCE_DIR "/examples/extrude_bracket.json");
  const std::vector<double> params = plate.params.values();
  const double above_lo[3] = {-0.2, -0.1, 0.4}, above_hi[3] = {0.0, 0.1, 0.5};
  EXPECT_LT(occupancy_bounds(plate, params, above_lo, above_hi).hi, 1e-3);
  const double in_lo[3] = {-0.26, -0.01, -0.01}, in_hi[3] = {-0.24, 0.01, 0.01};
  EXPECT_GT(occupancy_bounds(plate, params, in_lo, in_hi).lo, 0.99);
}

TEST(Bounds, TightFarFromTheSurface) {
  const Tree tree = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
          "root": {"type": "sphere", "radius": 0.3, "sharpness": 50}})",
      "sphere");
  const std::vector<double> params = tree.params.values();
  const double out_lo[3] = {0.6, 0.6, 0.6}, out_hi[3] = {0.8, 0.8, 0.8};
  EXPECT_LT(occupancy_bounds(tree, params, out_lo, out_hi).hi, 1e-3);
  const double in_lo[3] = {-0.05, -0.05, -0.05}, in_hi[3] = {0.05, 0.05, 0.05};
  EXPECT_GT(occupancy_bounds(tree, params, in_lo, in_hi).lo, 0.999);
  const double across_lo[3] = {0.25, -0.05, -0.05}, across_hi[3] = {0.35, 0.05, 0.05};
  const Interval across = occupancy_bounds(tree, params, across_lo, across_hi);
  EXPECT_TRUE(across.contains(0.5));
}

}  // namespace
}  // namespace fuzzycsg
