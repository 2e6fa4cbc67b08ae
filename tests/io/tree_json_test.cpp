// Reading tree files: structure, defaults, parameter naming, and the canonical writer.
#include "fuzzycsg/io/tree_json.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "io/tree_compare.hpp"
#include "io/tree_text.hpp"

namespace fuzzycsg::io {
namespace {

using test::tree3;

namespace fs = std::filesystem;

const Parameter& param(const Tree& t, std::string_view name) {
  const auto ref = t.params.find(name);
  if (!ref) throw std::runtime_error("no parameter " + std::string(name));
  return t.params[*ref];
}

std::vector<std::string> names(const Tree& t) {
  std::vector<std::string> out;
  for (const Parameter& p : t.params.entries()) out.push_back(p.name);
  return out;
}

TEST(TreeJson, ReadsTheFormatExample) {
  const Tree t = read_tree_string(R"({
    "format": "fuzzycsg-tree", "version": 1, "dim": 3,
    "root": { "op": "difference", "children": [
      { "type": "box", "size": [1.2, 0.8, 0.4], "sharpness": 80 },
      { "type": "cylinder", "radius": 0.15, "height": 1.0, "rotate": [90, 0, 0] } ] }
  })");
  EXPECT_EQ(t.dim, 3);
  EXPECT_FALSE(t.domain.has_value());
  ASSERT_EQ(t.nodes.size(), 3u);
  const Node& root = t.node(t.root);
  EXPECT_EQ(root.kind, NodeKind::kOperator);
  EXPECT_EQ(root.op, OpKind::kDifference);
  EXPECT_EQ(root.logic.family, logic::Family::kProduct);
  EXPECT_EQ(root.complement.kind, logic::Complement::kStandard);
  ASSERT_EQ(root.children.size(), 2u);
  const Node& box = t.node(root.children[0]);
  EXPECT_EQ(box.shape.type, PrimitiveType::kBox);
  EXPECT_EQ(box.step.kind, StepKind::kSigmoid);
  EXPECT_EQ(t.params[*box.step.param].value, 80.0);
  const Node& cylinder = t.node(root.children[1]);
  EXPECT_EQ(cylinder.shape.type, PrimitiveType::kCylinder);
  ASSERT_EQ(cylinder.placement.rotate.size(), 3u);
  EXPECT_EQ(t.params[cylinder.placement.rotate[0]].value, 90.0);
  EXPECT_TRUE(cylinder.placement.translate.empty());
  EXPECT_FALSE(cylinder.placement.scale.has_value());

  // Every number is a named parameter, defaults included (the cylinder's sharpness).
  EXPECT_EQ(names(t),
            (std::vector<std::string>{"root.children[0].size[0]", "root.children[0].size[1]",
                                      "root.children[0].size[2]", "root.children[0].sharpness",
                                      "root.children[1].radius", "root.children[1].height",
                                      "root.children[1].rotate[0]", "root.children[1].rotate[1]",
                                      "root.children[1].rotate[2]", "root.children[1].sharpness"}));
  const Parameter& sharpness = param(t, "root.children[1].sharpness");
  EXPECT_EQ(sharpness.value, 50.0);
  EXPECT_FALSE(sharpness.fixed);
  EXPECT_TRUE(sharpness.range.contains(1.0));
  EXPECT_FALSE(sharpness.range.contains(0.0));
  const TreeCounts counts = count(t);
  EXPECT_EQ(counts.primitives, 2);
  EXPECT_EQ(counts.operators, 1);
  EXPECT_EQ(counts.parameters, 10);
  EXPECT_EQ(counts.free_parameters, 10);
  EXPECT_EQ(counts.depth, 1);
}

TEST(TreeJson, NamesEveryKindOfParameter) {
  const Tree t3 = read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
    "root": {"op": "union", "logic": "yager", "children": [
      {"type": "sphere", "radius": 1, "translate": [1, 2, 3], "rotate": [0, 0, 45], "scale": 2,
       "step": {"hn": 2, "range": 0.1}},
      {"op": "difference", "logic": "li-tian", "complement": "sugeno", "children": [
        {"type": "mlp", "hidden": [1], "weights": [1, 2, 3, 4, 5, 6]},
        {"op": "unified", "logits": [1, 2, 3, 4], "children": [
          {"type": "quadric", "coefficients": [1, 1, 1, 0, 0, 0, 0, 0, 0, -1], "step": "crisp"},
          {"op": "unified", "c": [0.25, 0.25, 0.25, 0.25], "children": [
            {"type": "sphere", "radius": 1}, {"type": "sphere", "radius": 2}]}]}]}]}})");
  EXPECT_EQ(names(t3), (std::vector<std::string>{
                           "root.p",
                           "root.children[0].radius",
                           "root.children[0].translate[0]",
                           "root.children[0].translate[1]",
                           "root.children[0].translate[2]",
                           "root.children[0].rotate[0]",
                           "root.children[0].rotate[1]",
                           "root.children[0].rotate[2]",
                           "root.children[0].scale",
                           "root.children[0].step.range",
                           "root.children[1].delta",
                           "root.children[1].complement.lambda",
                           "root.children[1].children[0].weights[0]",
                           "root.children[1].children[0].weights[1]",
                           "root.children[1].children[0].weights[2]",
                           "root.children[1].children[0].weights[3]",
                           "root.children[1].children[0].weights[4]",
                           "root.children[1].children[0].weights[5]",
                           "root.children[1].children[0].sharpness",
                           "root.children[1].children[1].logits[0]",
                           "root.children[1].children[1].logits[1]",
                           "root.children[1].children[1].logits[2]",
                           "root.children[1].children[1].logits[3]",
                           "root.children[1].children[1].temperature",
                           "root.children[1].children[1].omega",
                           "root.children[1].children[1].children[0].coefficients[0]",
                           "root.children[1].children[1].children[0].coefficients[1]",
                           "root.children[1].children[1].children[0].coefficients[2]",
                           "root.children[1].children[1].children[0].coefficients[3]",
                           "root.children[1].children[1].children[0].coefficients[4]",
                           "root.children[1].children[1].children[0].coefficients[5]",
                           "root.children[1].children[1].children[0].coefficients[6]",
                           "root.children[1].children[1].children[0].coefficients[7]",
                           "root.children[1].children[1].children[0].coefficients[8]",
                           "root.children[1].children[1].children[0].coefficients[9]",
                           "root.children[1].children[1].children[1].c[0]",
                           "root.children[1].children[1].children[1].c[1]",
                           "root.children[1].children[1].children[1].c[2]",
                           "root.children[1].children[1].children[1].c[3]",
                           "root.children[1].children[1].children[1].children[0].radius",
                           "root.children[1].children[1].children[1].children[0].sharpness",
                           "root.children[1].children[1].children[1].children[1].radius",
                           "root.children[1].children[1].children[1].children[1].sharpness",
                       }));

  const Tree t2 = read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
    "root": {"type": "polygon", "vertices": [[0, 0], [1, 0], [0, 1], [-1, -1]], "rotate": 30}})");
  EXPECT_EQ(names(t2),
            (std::vector<std::string>{
                "root.vertices[0][0]", "root.vertices[0][1]", "root.vertices[1][0]",
                "root.vertices[1][1]", "root.vertices[2][0]", "root.vertices[2][1]",
                "root.vertices[3][0]", "root.vertices[3][1]", "root.rotate", "root.sharpness"}));
  EXPECT_EQ(t2.node(t2.root).intrinsic.size(), 8u);
  EXPECT_EQ(param(t2, "root.vertices[3][1]").value, -1.0);

  // The extrude's profile: point k's coordinates, then the height; a shared entry keeps its
  // name and counts once.
  const Tree te = read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
    "parameters": {"w": 0.5},
    "root": {"op": "union", "children": [{"type": "sphere", "radius": 1},
      {"type": "extrude", "profile": [[0, 0], [0.3, 0], [0.6, 0], [{"param": "w"}, 1], [0.5, 1.2],
                                      [0.2, 1]], "height": 0.25}]}})");
  EXPECT_EQ(names(te), (std::vector<std::string>{
                           "w",
                           "root.children[0].radius",
                           "root.children[0].sharpness",
                           "root.children[1].profile[0][0]",
                           "root.children[1].profile[0][1]",
                           "root.children[1].profile[1][0]",
                           "root.children[1].profile[1][1]",
                           "root.children[1].profile[2][0]",
                           "root.children[1].profile[2][1]",
                           "root.children[1].profile[3][1]",
                           "root.children[1].profile[4][0]",
                           "root.children[1].profile[4][1]",
                           "root.children[1].profile[5][0]",
                           "root.children[1].profile[5][1]",
                           "root.children[1].height",
                           "root.children[1].sharpness",
                       }));
  EXPECT_EQ(te.node(te.node(te.root).children[1]).intrinsic.size(), 13u);
  EXPECT_EQ(param(te, "root.children[1].profile[4][1]").value, 1.2);
  EXPECT_EQ(param(te, "root.children[1].height").value, 0.25);
  EXPECT_EQ(param(te, "root.children[1].sharpness").value, 50.0);
}

const std::string kTwoSpheres =
    R"("children": [{"type": "sphere", "radius": 1}, {"type": "sphere", "radius": 2}])";

TEST(TreeJson, MaterializesLogicDefaults) {
  struct Expected {
    std::string family;
    std::string field;
    double value;
    int n;
  };
  for (const Expected& e : std::vector<Expected>{{"yager", "p", 2, 0},
                                                 {"hamacher", "a", 0, 0},
                                                 {"dombi", "lambda", 1, 0},
                                                 {"dubois-prade", "k", 0.5, 0},
                                                 {"weber", "k", 0, 0},
                                                 {"li-tian", "delta", 0.5, 2},
                                                 {"li-tian-hat", "delta", 0.5, 2},
                                                 {"bezier", "", 0, 3},
                                                 {"godel", "", 0, 0}}) {
    SCOPED_TRACE(e.family);
    const Tree t = read_tree_string(
        tree3(R"({"op": "intersection", "logic": ")" + e.family + "\", " + kTwoSpheres + "}"));
    const Node& root = t.node(t.root);
    EXPECT_EQ(logic::family_name(root.logic.family), e.family);
    EXPECT_EQ(root.logic.n, e.n);
    EXPECT_EQ(root.logic.p.has_value(), !e.field.empty());
    if (!e.field.empty()) {
      const Parameter& p = param(t, "root." + e.field);
      EXPECT_EQ(p.value, e.value);
      EXPECT_FALSE(p.fixed);
      EXPECT_EQ(root.logic.p->index, t.params.find("root." + e.field)->index);
    }
  }
}

TEST(TreeJson, MaterializesLeafAndComplementDefaults) {
  const Tree quadric = read_tree_string(
      tree3(R"({"type": "quadric", "coefficients": [1, 1, 1, 0, 0, 0, 0, 0, 0, -1]})"));
  EXPECT_EQ(param(quadric, "root.sharpness").value, 1.0);

  const Tree mlp = read_tree_string(tree3(R"({"type": "mlp", "weights": [)" + [] {
    std::string w;
    for (int i = 0; i < 353; ++i) w += (i ? ", " : "") + std::to_string(i);
    return w;
  }() + "]}"));
  EXPECT_EQ(mlp.node(mlp.root).shape.hidden, (std::vector<int>{16, 16}));
  EXPECT_EQ(mlp.node(mlp.root).intrinsic.size(), 353u);
  EXPECT_EQ(param(mlp, "root.weights[352]").value, 352.0);

  const Tree sugeno = read_tree_string(
      tree3(R"({"op": "complement", "complement": "sugeno", "children": [{"type": "sphere",)"
            R"( "radius": 1}]})"));
  EXPECT_EQ(sugeno.node(sugeno.root).complement.kind, logic::Complement::kSugeno);
  EXPECT_EQ(param(sugeno, "root.complement.lambda").value, 0.0);

  const Tree yager = read_tree_string(
      tree3(R"({"op": "difference", "complement": {"type": "yager"}, )" + kTwoSpheres + "}"));
  EXPECT_EQ(yager.node(yager.root).complement.kind, logic::Complement::kYager);
  EXPECT_EQ(param(yager, "root.complement.lambda").value, 1.0);

  const Tree cosine = read_tree_string(
      tree3(R"({"op": "difference", "complement": {"type": "cosine"}, )" + kTwoSpheres + "}"));
  EXPECT_EQ(cosine.node(cosine.root).complement.kind, logic::Complement::kCosine);
  EXPECT_FALSE(cosine.node(cosine.root).complement.lambda.has_value());
}

TEST(TreeJson, FixedAndFree) {
  const Tree t = read_tree_string(tree3(R"({"op": "union", "children": [
      {"type": "sphere", "radius": {"value": 1, "fixed": true}, "sharpness": {"value": 9}},
      {"op": "unified", "logits": [0, 0, 0, 0], "children": [
        {"type": "sphere", "radius": 1},
        {"op": "unified", "logits": [0, 0, 0, 0], "temperature": 5, "omega": {"value": 3},
         "children": [
          {"type": "sphere", "radius": 1},
          {"op": "unified", "logits": [0, 0, 0, 0], "temperature": {"value": 7, "fixed": false},
           "omega": {"value": 2, "fixed": false}, "children": [
            {"type": "sphere", "radius": 1}, {"type": "sphere", "radius": 1}]}]}]}]})"));
  EXPECT_TRUE(param(t, "root.children[0].radius").fixed);
  EXPECT_FALSE(param(t, "root.children[0].sharpness").fixed);
  const std::string u1 = "root.children[1].";
  const std::string u2 = u1 + "children[1].";
  const std::string u3 = u2 + "children[1].";
  EXPECT_EQ(param(t, u1 + "temperature").value, 1000.0);
  EXPECT_TRUE(param(t, u1 + "temperature").fixed);
  EXPECT_EQ(param(t, u1 + "omega").value, 10.0);
  EXPECT_TRUE(param(t, u1 + "omega").fixed);
  EXPECT_FALSE(param(t, u1 + "logits[0]").fixed);
  EXPECT_EQ(param(t, u2 + "temperature").value, 5.0);
  EXPECT_TRUE(param(t, u2 + "temperature").fixed);
  EXPECT_TRUE(param(t, u2 + "omega").fixed);
  EXPECT_FALSE(param(t, u3 + "temperature").fixed);
  EXPECT_FALSE(param(t, u3 + "omega").fixed);
  EXPECT_EQ(count(t).free_parameters, count(t).parameters - 5);
}

TEST(TreeJson, SharedParameters) {
  const Tree t = read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
    "parameters": {"r": 0.5, "k": {"value": 30, "fixed": true}, "unused": -3},
    "root": {"op": "union", "children": [
      {"type": "sphere", "radius": {"param": "r"}, "sharpness": {"param": "k"}},
      {"type": "sphere", "radius": {"param": "r"}, "translate": [{"param": "r"}, 0, 0]}]}})");
  // Shared parameters come first, in key order, named by their keys.
  EXPECT_EQ(t.params.at(0).name, "k");
  EXPECT_EQ(t.params.at(1).name, "r");
  EXPECT_EQ(t.params.at(2).name, "unused");
  const Parameter& r = param(t, "r");
  EXPECT_TRUE(r.shared);
  EXPECT_FALSE(r.fixed);
  EXPECT_TRUE(param(t, "k").fixed);
  // The range of a shared parameter is that of all its uses (radius > 0, translate any).
  EXPECT_FALSE(r.range.contains(0.0));
  EXPECT_TRUE(param(t, "unused").range.contains(-3.0));
  const Node& a = t.node(t.node(t.root).children[0]);
  const Node& b = t.node(t.node(t.root).children[1]);
  EXPECT_EQ(a.intrinsic[0], b.intrinsic[0]);
  EXPECT_EQ(b.placement.translate[0], b.intrinsic[0]);
  EXPECT_FALSE(t.params.find("root.children[0].radius").has_value());
}

TEST(TreeJson, KeepsNamesAndDomain) {
  const Tree t = read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
    "domain": {"min": [-2, -1], "max": [2, 1.5]},
    "root": {"name": "wheel \"A\"\n", "type": "circle", "radius": 1}})");
  EXPECT_EQ(t.node(t.root).name, "wheel \"A\"\n");
  ASSERT_TRUE(t.domain.has_value());
  EXPECT_EQ(t.domain->min[0], -2.0);
  EXPECT_EQ(t.domain->max[1], 1.5);
  const Tree back = read_tree_string(write_tree_string(t));
  EXPECT_EQ(testing::tree_difference(t, back), "");
}

TEST(TreeJson, WritesCanonicalText) {
  const Tree t = read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
    "parameters": {"w": {"value": 0.25, "fixed": true}, "r": 0.1},
    "domain": {"max": [1, 1], "min": [-1, -1]},
    "root": {"children": [
       {"sharpness": 20, "type": "circle", "radius": {"param": "r"}, "name": "c",
        "translate": [0.5, {"value": -0.0, "fixed": true}], "rotate": 15, "scale": 2},
       {"op": "complement", "complement": {"type": "sugeno", "lambda": {"param": "w"}},
        "children": [{"type": "polygon", "vertices": [[0, 0], [1, 0], [0.1, 1e-300]],
                      "step": {"range": 0.5, "hn": 3}}]},
       {"op": "unified", "logits": [1, 2, 3, 4], "temperature": {"value": 50, "fixed": false},
        "children": [{"type": "rectangle", "size": [1, 2], "step": "crisp"},
                     {"type": "half-plane", "normal": [0, 1], "offset": 0}]}],
     "op": "intersection", "logic": "li-tian", "n": 3}})");
  const std::string expected = R"({
  "format": "fuzzycsg-tree",
  "version": 1,
  "dim": 2,
  "domain": {
    "min": [-1, -1],
    "max": [1, 1]
  },
  "parameters": {
    "r": 0.1,
    "w": {"value": 0.25, "fixed": true}
  },
  "root": {
    "op": "intersection",
    "logic": "li-tian",
    "delta": 0.5,
    "n": 3,
    "children": [
      {
        "name": "c",
        "type": "circle",
        "radius": {"param": "r"},
        "translate": [0.5, {"value": -0.0, "fixed": true}],
        "rotate": 15,
        "scale": 2,
        "sharpness": 20
      },
      {
        "op": "complement",
        "complement": {"type": "sugeno", "lambda": {"param": "w"}},
        "children": [
          {
            "type": "polygon",
            "vertices": [
              [0, 0],
              [1, 0],
              [0.1, 1e-300]
            ],
            "step": {"hn": 3, "range": 0.5}
          }
        ]
      },
      {
        "op": "unified",
        "logits": [1, 2, 3, 4],
        "temperature": {"value": 50, "fixed": false},
        "omega": 10,
        "children": [
          {
            "type": "rectangle",
            "size": [1, 2],
            "step": "crisp"
          },
          {
            "type": "half-plane",
            "normal": [0, 1],
            "offset": 0,
            "sharpness": 50
          }
        ]
      }
    ]
  }
}
)";
  EXPECT_EQ(write_tree_string(t), expected);
  const Tree back = read_tree_string(expected);
  EXPECT_EQ(testing::tree_difference(t, back), "");
  EXPECT_TRUE(
      std::signbit(t.params[t.node(t.node(t.root).children[0]).placement.translate[1]].value));
}

TEST(TreeJson, SplineNodes) {
  // Degree and box left out: degree 2, the tree's domain. Children's parameters are named by
  // their paths as anywhere else; the spline itself has none.
  const Tree t = read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
    "root": {"op": "spline", "name": "blend", "cells": [3, 3], "children": [
      {"type": "circle", "radius": 0.1}, {"type": "circle", "radius": 0.2},
      {"type": "circle", "radius": 0.3}, {"type": "circle", "radius": 0.4},
      {"type": "circle", "radius": 0.5}, {"type": "circle", "radius": 0.6},
      {"type": "circle", "radius": 0.7}, {"type": "circle", "radius": 0.8},
      {"op": "spline", "cells": [2, 2], "degree": 1,
       "box": {"min": [-0.5, 1e-300], "max": [0.5, 0.75]}, "children": [
        {"type": "circle", "radius": 0.9}, {"type": "circle", "radius": 1},
        {"type": "circle", "radius": 1.1}, {"type": "circle", "radius": 1.2}]}]}})");
  const Node& root = t.node(t.root);
  EXPECT_EQ(root.op, OpKind::kSpline);
  EXPECT_EQ(root.spline_cells, (std::vector<int>{3, 3}));
  EXPECT_EQ(root.spline_degree, 2);
  EXPECT_FALSE(root.spline_box.has_value());
  const Node& inner = t.node(root.children[8]);
  EXPECT_EQ(inner.spline_degree, 1);
  ASSERT_TRUE(inner.spline_box.has_value());
  EXPECT_EQ(inner.spline_box->min[1], 1e-300);
  EXPECT_EQ(inner.spline_box->max[1], 0.75);
  EXPECT_EQ(t.params.size(), 24u);  // radius and sharpness of 12 circles
  EXPECT_EQ(param(t, "root.children[8].children[3].radius").value, 1.2);
  EXPECT_EQ(count(t).operators, 2);
  EXPECT_EQ(count(t).primitives, 12);

  const std::string written = write_tree_string(t);
  const std::string inner_text = R"("op": "spline",
        "cells": [2, 2],
        "degree": 1,
        "box": {
          "min": [-0.5, 1e-300],
          "max": [0.5, 0.75]
        },
        "children": [)";
  EXPECT_NE(written.find(inner_text), std::string::npos) << written;
  EXPECT_NE(written.find(R"("name": "blend",
    "op": "spline",
    "cells": [3, 3],
    "degree": 2,
    "children": [)"),
            std::string::npos)
      << written;
  const Tree back = read_tree_string(written);
  EXPECT_EQ(testing::tree_difference(t, back), "");
  EXPECT_EQ(write_tree_string(back), written);
}

TEST(TreeJson, WriterRejectsInvalidTrees) {
  Tree t = read_tree_string(tree3(R"({"type": "sphere", "radius": 1})"));
  t.params[*t.params.find("root.radius")].value = -1;
  try {
    write_tree_string(t);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "write_tree: root.radius: must be > 0 (got -1)");
  }
}

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("fuzzycsg-tree-json-test-" + std::to_string(::getpid()) + "-" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(path_)) out.push_back(e.path().filename());
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  fs::path path_;
};

TEST(TreeJson, WritesFilesAtomically) {
  TempDir dir;
  const Tree t = read_tree_string(tree3(R"({"type": "sphere", "radius": 1})"));
  const fs::path file = dir.path() / "tree.json";
  write_tree_file(t, file);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"tree.json"});
  const Tree back = read_tree_file(file);
  EXPECT_EQ(testing::tree_difference(t, back), "");

  // Overwrites in place.
  Tree bigger = t;
  bigger.params[*bigger.params.find("root.radius")].value = 2;
  write_tree_file(bigger, file);
  EXPECT_EQ(read_tree_file(file).params.find("root.radius")->index, 0u);
  EXPECT_EQ(read_tree_file(file).params.at(0).value, 2.0);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"tree.json"});

  // A directory in the way: the error names it and nothing is left behind.
  fs::create_directory(dir.path() / "sub");
  try {
    write_tree_file(t, dir.path() / "sub");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "cannot write " + (dir.path() / "sub").string() + ": Is a directory");
  }
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"sub", "tree.json"}));

  // A missing folder.
  try {
    write_tree_file(t, dir.path() / "missing" / "tree.json");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "cannot write " +
                                         (dir.path() / "missing" / "tree.json").string() +
                                         ": No such file or directory");
  }

  // An invalid tree is not written, and the old file stays.
  Tree bad = t;
  bad.params[*bad.params.find("root.radius")].value = -1;
  EXPECT_THROW(write_tree_file(bad, file), InputError);
  EXPECT_EQ(read_tree_file(file).params.at(0).value, 2.0);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"sub", "tree.json"}));
}

}  // namespace
}  // namespace fuzzycsg::io
