#include "fuzzycsg/mesh/bounds.hpp"
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
