// Every class of bad tree file is rejected with one line naming the place and the problem.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "io/tree_text.hpp"

namespace fuzzycsg::io {
namespace {

using test::tree2;
using test::tree3;

std::string pair3(const std::string& a, const std::string& b) {
  return tree3(R"({"op": "union", "children": [)" + a + ", " + b + "]}");
}
const std::string kSphere = R"({"type": "sphere", "radius": 0.5})";

// The message of the InputError that reading `text` throws (or a note that it did not throw).
std::string error_of(const std::string& text) {
  try {
    read_tree_string(text, "tree.json");
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("unexpected exception: ") + e.what();
  }
  return "no error";
}

struct Case {
  std::string text;
  std::string message;
};

void expect_messages(const std::vector<Case>& cases) {
  for (const Case& c : cases) {
    const std::string message = error_of(c.text);
    EXPECT_EQ(message, c.message) << "input: " << c.text.substr(0, 300);
    EXPECT_EQ(message.find('\n'), std::string::npos) << "message is not one line";
  }
}

TEST(TreeJsonErrors, MalformedJson) {
  expect_messages({
      {"", "tree.json: the input is empty (expected a tree file)"},
      {" \n\t ", "tree.json: the input is empty (expected a tree file)"},
      {R"({"format": "fuzzycsg-tree",)",
       "tree.json: line 1, column 28: syntax error: unexpected end of input; expected string "
       "literal"},
      {R"({"format": tru})",
       "tree.json: line 1, column 15: syntax error: invalid literal; last read: '\"format\": "
       "tru}'"},
      {"{\n  \"format\": \"fuzzycsg-tree\"\n  \"version\": 1\n}",
       "tree.json: line 3, column 11: syntax error: unexpected string literal; expected '}'"},
      {"{} x",
       "tree.json: line 1, column 4: syntax error: invalid literal; last read: '{} x'; expected "
       "end "
       "of input"},
      {tree3(R"({"type": "sphere", "radius": NaN})"),
       "tree.json: line 1, column 90: syntax error: invalid literal; last read: '\"radius\": N'"},
      {"{\"a\": \"\xff\"}",
       "tree.json: line 1, column 8: syntax error: invalid string: ill-formed UTF-8 byte; last "
       "read: '\"\\xFF'"},
      {"{\"a\": \"" + std::string(100000, 'x') + "\\q\"}",
       "tree.json: line 1, column 100009: syntax error: invalid string: forbidden character "
       "after backslash; last read: '...xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx\\q'"},
      {"{\"a\": 1,\n\"b\": [1, 2,\n 1e999]}", "tree.json: b[2]: must be finite (got 1e999)"},
  });
}

TEST(TreeJsonErrors, NotATreeFile) {
  expect_messages({
      {"null", "tree.json: expected a JSON object at the top level (got null)"},
      {"[1, 2]", "tree.json: expected a JSON object at the top level (got an array)"},
      {"{}", "tree.json: missing field \"format\" (expected \"fuzzycsg-tree\")"},
      {R"({"format": "fuzzycsg-mesh", "version": 1})",
       "tree.json: format: expected \"fuzzycsg-tree\" (got \"fuzzycsg-mesh\")"},
      {R"({"format": 1})", "tree.json: format: expected \"fuzzycsg-tree\" (got 1)"},
      {R"({"format": "fuzzycsg-tree"})", "tree.json: missing field \"version\""},
      {R"({"format": "fuzzycsg-tree", "version": 2})",
       "tree.json: version: unsupported version 2 (this program reads version 1)"},
      {R"({"format": "fuzzycsg-tree", "version": "1"})",
       "tree.json: version: expected an integer (got \"1\")"},
      {R"({"format": "fuzzycsg-tree", "version": 1.0})",
       "tree.json: version: expected an integer (got 1.0)"},
      {R"({"format": "fuzzycsg-tree", "version": 1, "root": {}})",
       "tree.json: missing field \"dim\""},
      {R"({"format": "fuzzycsg-tree", "version": 1, "dim": 4})",
       "tree.json: dim: must be 2 or 3 (got 4)"},
      {R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "extra": 1})",
       "tree.json: unknown field \"extra\""},
      {R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3})",
       "tree.json: missing field \"root\""},
  });
}

TEST(TreeJsonErrors, EmptyTree) {
  expect_messages({
      {tree3("{}"), "tree.json: root: empty node (expected a primitive \"type\" or an \"op\")"},
      {tree3("null"), "tree.json: root: expected a node object (got null)"},
      {tree3("[]"), "tree.json: root: expected a node object (got an array)"},
      {tree3(R"({"name": "x"})"), "tree.json: root: missing field \"type\" or \"op\""},
      {tree3(R"({"type": "sphere", "op": "union"})"),
       "tree.json: root: a node has either \"type\" or \"op\", not both"},
  });
}

TEST(TreeJsonErrors, UnknownNames) {
  expect_messages({
      {tree3(R"({"type": "sphre", "radius": 1})"),
       "tree.json: root.type: unknown primitive type \"sphre\""},
      {tree3(R"({"type": 7})"), "tree.json: root.type: expected a primitive type name (got 7)"},
      {tree3(R"({"op": "xor", "children": []})"), "tree.json: root.op: unknown operator \"xor\""},
      {tree3(R"({"op": "union", "logic": "fuzzy", "children": []})"),
       "tree.json: root.logic: unknown logic family \"fuzzy\""},
      {pair3(R"({"type": "sphere", "radus": 0.5})", kSphere),
       "tree.json: root.children[0]: unknown field \"radus\""},
      {tree3(R"({"type": "sphere", "radius": 1, "children": []})"),
       "tree.json: root: unknown field \"children\""},
      {tree3(R"({"op": "union", "radius": 1, "children": []})"),
       "tree.json: root: unknown field \"radius\""},
      {tree3(R"({"op": "difference", "complement": "weird", "children": []})"),
       "tree.json: root.complement: unknown complement \"weird\""},
      {tree3(R"({"op": "difference", "complement": {"type": "sugeno", "lambda": 1, "mu": 2},)"
             R"( "children": []})"),
       "tree.json: root.complement: unknown field \"mu\""},
      {tree3(R"({"type": "sphere", "radius": 1, "step": "smooth"})"),
       "tree.json: root.step: unknown step \"smooth\" (expected \"sigmoid\", \"crisp\" or "
       "{\"hn\": n, \"range\": R})"},
      {tree3(R"({"type": "sphere", "radius": 1, "step": {"hn": 2, "range": 1, "x": 0}})"),
       "tree.json: root.step: unknown field \"x\""},
      {tree3(R"({"type": "sphere", "radius": {"value": 1, "fixd": true}})"),
       "tree.json: root.radius: unknown field \"fixd\""},
      {tree3(R"({"type": "sphere", "radius": {"param": "r", "value": 1}})"),
       "tree.json: root.radius: unknown field \"value\" beside \"param\""},
      {tree3(R"({"type": "sphere", "radius": 1, "bad\nkey": 1})"),
       "tree.json: root: unknown field \"bad\\nkey\""},
  });
}

TEST(TreeJsonErrors, FieldsThatDoNotApply) {
  const std::string children = R"("children": [{"type": "sphere", "radius": 1}])";
  expect_messages({
      {tree3(R"({"op": "union", "p": 2, )" + children + "}"),
       "tree.json: root: field \"p\" does not apply to logic \"product\""},
      {tree3(R"({"op": "union", "logic": "yager", "k": 2, )" + children + "}"),
       "tree.json: root: field \"k\" does not apply to logic \"yager\""},
      {tree3(R"({"op": "union", "logic": "godel", "n": 2, )" + children + "}"),
       "tree.json: root: field \"n\" does not apply to logic \"godel\""},
      {tree3(R"({"op": "union", "complement": "cosine", )" + children + "}"),
       "tree.json: root: field \"complement\" does not apply to union nodes"},
      {tree3(R"({"op": "union", "c": [0, 1, 0, 0], )" + children + "}"),
       "tree.json: root: field \"c\" does not apply to union nodes"},
      {tree3(R"({"op": "complement", "logic": "godel", )" + children + "}"),
       "tree.json: root: field \"logic\" does not apply to complement nodes"},
      {tree3(R"({"op": "unified", "logic": "godel", "c": [0, 1, 0, 0], )" + children + "}"),
       "tree.json: root.logic: unified nodes use product logic (got \"godel\")"},
      {tree3(R"({"op": "unified", "p": 1, "c": [0, 1, 0, 0], )" + children + "}"),
       "tree.json: root: field \"p\" does not apply to unified nodes"},
      {tree3(R"({"op": "unified", "c": [0, 1, 0, 0], "temperature": 10, )" + children + "}"),
       "tree.json: root.temperature: applies only with \"logits\""},
      {tree3(R"({"op": "unified", "c": [0, 1, 0, 0], "logits": [0, 0, 0, 0], )" + children + "}"),
       "tree.json: root: give either \"c\" or \"logits\", not both"},
      {tree3(R"({"op": "unified", )" + children + "}"),
       "tree.json: root: missing field \"c\" or \"logits\""},
      {tree3(R"({"op": "difference", "complement": {"type": "cosine", "lambda": 1}, )" + children +
             "}"),
       "tree.json: root.complement.lambda: does not apply to the \"cosine\" complement"},
      {tree3(R"({"type": "sphere", "radius": 1, "step": "crisp", "sharpness": 3})"),
       "tree.json: root.sharpness: applies only to sigmoid steps (the step is \"crisp\")"},
      {tree3(R"({"type": "sphere", "radius": 1, "hidden": [4]})"),
       "tree.json: root: unknown field \"hidden\""},
  });
}

TEST(TreeJsonErrors, MissingFields) {
  expect_messages({
      {tree3(R"({"type": "sphere"})"), "tree.json: root: missing field \"radius\""},
      {tree3(R"({"type": "cone", "radius1": 1, "height": 1})"),
       "tree.json: root: missing field \"radius2\""},
      {tree3(R"({"op": "union"})"), "tree.json: root: missing field \"children\""},
      {tree3(R"({"type": "sphere", "radius": {"fixed": true}})"),
       "tree.json: root.radius: missing field \"value\""},
      {tree3(R"({"type": "sphere", "radius": 1, "step": {"range": 1}})"),
       "tree.json: root.step: missing field \"hn\""},
      {tree3(R"({"type": "sphere", "radius": 1, "step": {"hn": 1}})"),
       "tree.json: root.step: missing field \"range\""},
      {R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2, "domain": {"min": [0, 0]},)"
       R"( "root": {"type": "circle", "radius": 1}})",
       "tree.json: domain: missing field \"max\""},
      {tree3(R"({"op": "difference", "complement": {"lambda": 1}, "children": []})"),
       "tree.json: root.complement: missing field \"type\""},
      {tree3(R"({"type": "extrude", "profile": [[0, 0], [1, 0], [2, 0], [2, 1], [1, 2], [0, 1]]})"),
       "tree.json: root: missing field \"height\""},
      {tree3(R"({"type": "extrude", "height": 1})"), "tree.json: root: missing field \"profile\""},
  });
}

TEST(TreeJsonErrors, BadValues) {
  expect_messages({
      {pair3(kSphere, R"({"type": "sphere", "radius": -0.2})"),
       "tree.json: root.children[1].radius: must be > 0 (got -0.2)"},
      {tree3(R"({"type": "sphere", "radius": 0})"), "tree.json: root.radius: must be > 0 (got 0)"},
      {tree3(R"({"type": "sphere", "radius": -0.0})"),
       "tree.json: root.radius: must be > 0 (got -0)"},
      {tree3(R"({"type": "sphere", "radius": 1e999})"),
       "tree.json: root.radius: must be finite (got 1e999)"},
      {tree3(R"({"type": "sphere", "radius": 1, "translate": [-1e999, 0, 0]})"),
       "tree.json: root.translate[0]: must be finite (got -1e999)"},
      {tree3(R"({"type": "box", "size": [1, 0, 1]})"),
       "tree.json: root.size[1]: must be > 0 (got 0)"},
      {tree3(R"({"type": "sphere", "radius": "0.5"})"),
       "tree.json: root.radius: expected a number (got \"0.5\")"},
      {tree3(R"({"type": "sphere", "radius": true})"),
       "tree.json: root.radius: expected a number (got true)"},
      {tree3(R"({"type": "sphere", "radius": {"value": "1"}})"),
       "tree.json: root.radius.value: expected a number (got \"1\")"},
      {tree3(R"({"type": "sphere", "radius": {"value": 1, "fixed": 1}})"),
       "tree.json: root.radius.fixed: expected true or false (got 1)"},
      {tree3(R"({"type": "sphere", "radius": 1, "sharpness": 0})"),
       "tree.json: root.sharpness: must be > 0 (got 0)"},
      {tree3(R"({"type": "sphere", "radius": 1, "scale": -1})"),
       "tree.json: root.scale: must be > 0 (got -1)"},
      {tree3(R"({"type": "sphere", "radius": 1, "step": {"hn": 2, "range": 0}})"),
       "tree.json: root.step.range: must be > 0 (got 0)"},
      {tree3(R"({"type": "sphere", "radius": 1, "step": {"hn": 17, "range": 1}})"),
       "tree.json: root.step.hn: must be in [0, 16] (got 17)"},
      {tree3(R"({"type": "sphere", "radius": 1, "step": {"hn": 2.5, "range": 1}})"),
       "tree.json: root.step.hn: expected an integer (got 2.5)"},
      {tree3(
           R"({"type": "sphere", "radius": 1, "step": {"hn": 99999999999999999999, "range": 1}})"),
       "tree.json: root.step.hn: expected an integer (got 1e+20)"},
      {tree3(R"({"type": "plane", "normal": [0, 0, 0], "offset": 1})"),
       "tree.json: root.normal: must be non-zero (got [0, 0, 0])"},
      {tree2(R"({"type": "half-plane", "normal": [0, -0.0], "offset": 1})"),
       "tree.json: root.normal: must be non-zero (got [0, -0])"},
      {tree3(R"({"type": "cone", "radius1": 0, "radius2": 0, "height": 1})"),
       "tree.json: root: radius1 and radius2 must not both be 0"},
      {tree3(R"({"type": "cone", "radius1": -1, "radius2": 0, "height": 1})"),
       "tree.json: root.radius1: must be >= 0 (got -1)"},
      {pair3(kSphere, R"({"type": "extrude", "profile": [[0, 0], [1, 0], [2, 0], [2, 1], [1, 2],)"
                      R"( [0, 1]], "height": -0.5})"),
       "tree.json: root.children[1].height: must be > 0 (got -0.5)"},
      {tree3(R"({"type": "extrude", "profile": [[0, 0], [1, 0], [2, 0], [2, 1e999], [1, 2],)"
             R"( [0, 1]], "height": 1})"),
       "tree.json: root.profile[3][1]: must be finite (got 1e999)"},
      {tree3(R"({"type": "mlp", "hidden": [0], "weights": []})"),
       "tree.json: root.hidden[0]: must be in [1, 64] (got 0)"},
      {tree3(R"({"type": "mlp", "hidden": [65], "weights": []})"),
       "tree.json: root.hidden[0]: must be in [1, 64] (got 65)"},
      {tree3(R"({"type": "mlp", "hidden": 16, "weights": []})"),
       "tree.json: root.hidden: expected an array of layer widths (got 16)"},
  });
}

TEST(TreeJsonErrors, BadOperatorValues) {
  const std::string children = R"("children": [{"type": "sphere", "radius": 1}, )"
                               R"({"type": "sphere", "radius": 2}])";
  expect_messages({
      {tree3(R"({"op": "union", "logic": "yager", "p": 0, )" + children + "}"),
       "tree.json: root.p: must be > 0 (got 0)"},
      {tree3(R"({"op": "union", "logic": "hamacher", "a": -1, )" + children + "}"),
       "tree.json: root.a: must be >= 0 (got -1)"},
      {tree3(R"({"op": "union", "logic": "dombi", "lambda": 0, )" + children + "}"),
       "tree.json: root.lambda: must be > 0 (got 0)"},
      {tree3(R"({"op": "union", "logic": "dubois-prade", "k": 1.5, )" + children + "}"),
       "tree.json: root.k: must be in (0, 1] (got 1.5)"},
      {tree3(R"({"op": "union", "logic": "weber", "k": -1, )" + children + "}"),
       "tree.json: root.k: must be > -1 (got -1)"},
      {tree3(R"({"op": "union", "logic": "li-tian", "delta": 0, )" + children + "}"),
       "tree.json: root.delta: must be > 0 (got 0)"},
      {tree3(R"({"op": "union", "logic": "bezier", "n": 0, )" + children + "}"),
       "tree.json: root.n: must be in [1, 64] (got 0)"},
      {tree3(R"({"op": "union", "logic": "li-tian-hat", "n": 17, )" + children + "}"),
       "tree.json: root.n: must be in [0, 16] (got 17)"},
      {tree3(R"({"op": "union", "logic": "bezier", "n": 3.0, )" + children + "}"),
       "tree.json: root.n: expected an integer (got 3.0)"},
      {tree3(R"({"op": "difference", "complement": {"type": "sugeno", "lambda": -2}, )" + children +
             "}"),
       "tree.json: root.complement.lambda: must be > -1 (got -2)"},
      {tree3(R"({"op": "difference", "complement": {"type": "yager", "lambda": 0}, )" + children +
             "}"),
       "tree.json: root.complement.lambda: must be > 0 (got 0)"},
      {tree3(R"({"op": "unified", "c": [0.5, 0.5, 0.5, 0], )" + children + "}"),
       "tree.json: root.c: must sum to 1 (got 1.5)"},
      {tree3(R"({"op": "unified", "c": [-0.5, 0.5, 0.5, 0.5], )" + children + "}"),
       "tree.json: root.c[0]: must be in [0, 1] (got -0.5)"},
      {tree3(R"({"op": "unified", "logits": [0, 0, 0, 0], "temperature": 0, )" + children + "}"),
       "tree.json: root.temperature: must be > 0 (got 0)"},
      {tree3(R"({"op": "unified", "logits": [0, 0, 0, 0], "omega": 1e999, )" + children + "}"),
       "tree.json: root.omega: must be finite (got 1e999)"},
  });
}

TEST(TreeJsonErrors, WrongArrayLengths) {
  expect_messages({
      {tree3(R"({"type": "box", "size": [1, 2]})"),
       "tree.json: root.size: expected 3 numbers (got 2)"},
      {tree3(R"({"type": "box", "size": 1})"),
       "tree.json: root.size: expected an array of 3 numbers (got 1)"},
      {tree3(R"({"type": "sphere", "radius": 1, "translate": [1, 2]})"),
       "tree.json: root.translate: expected 3 numbers (got 2)"},
      {tree3(R"({"type": "sphere", "radius": 1, "rotate": 90})"),
       "tree.json: root.rotate: expected an array of 3 numbers (got 90)"},
      {tree2(R"({"type": "circle", "radius": 1, "rotate": [90]})"),
       "tree.json: root.rotate: expected one angle in degrees (got an array; 2D rotations are "
       "one number)"},
      {tree2(R"({"type": "circle", "radius": 1, "translate": [1, 2, 3]})"),
       "tree.json: root.translate: expected 2 numbers (got 3)"},
      {tree2(R"({"type": "polygon", "vertices": [[0, 0], [1, 0]]})"),
       "tree.json: root.vertices: needs at least 3 vertices (got 2)"},
      {tree2(R"({"type": "polygon", "vertices": [[0, 0], [1, 0, 2], [0, 1]]})"),
       "tree.json: root.vertices[1]: expected an [x, y] pair (got an array of 3 elements)"},
      {tree2(R"({"type": "polygon", "vertices": [[0, 0], [1, 0], 5]})"),
       "tree.json: root.vertices[2]: expected an [x, y] pair (got 5)"},
      {tree2(R"({"type": "polygon", "vertices": {"x": 1}})"),
       "tree.json: root.vertices: expected an array of [x, y] vertices (got an object)"},
      {tree3(R"({"type": "extrude", "profile": [[0, 0], [1, 0], [1, 1], [0, 1]], "height": 1})"),
       "tree.json: root.profile: needs 3 points (P, A, B) per segment (got 4)"},
      {tree3(R"({"type": "extrude", "profile": [[0, 0], [1, 0], [1, 1]], "height": 1})"),
       "tree.json: root.profile: needs at least 6 points, 2 segments (got 3)"},
      {tree3(R"({"type": "extrude", "profile": {"x": 1}, "height": 1})"),
       "tree.json: root.profile: expected an array of [x, y] points (got an object)"},
      {tree3(R"({"type": "extrude", "profile": [[0, 0], [1, 0], [2, 0], [2, 1], [1], [0, 1]],)"
             R"( "height": 1})"),
       "tree.json: root.profile[4]: expected an [x, y] pair (got an array of 1 elements)"},
      {tree3(R"({"type": "mlp", "weights": [1, 2, 3]})"),
       "tree.json: root.weights: expected 353 numbers for hidden layers [16, 16] (got 3)"},
      {tree3(R"({"type": "mlp", "hidden": [], "weights": [1, 2, 3]})"),
       "tree.json: root.weights: expected 4 numbers for hidden layers [] (got 3)"},
      {tree3(R"({"op": "unified", "c": [0, 1, 0], "children": []})"),
       "tree.json: root.c: expected 4 numbers (got 3)"},
      {R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2, "domain": {"min": [0], )"
       R"("max": [1, 1]}, "root": {"type": "circle", "radius": 1}})",
       "tree.json: domain.min: expected 2 numbers (got 1)"},
  });
}

TEST(TreeJsonErrors, WrongDimension) {
  expect_messages({
      {tree2(R"({"type": "extrude", "profile": [[0, 0], [1, 0], [2, 0], [2, 1], [1, 2], [0, 1]],)"
             R"( "height": 1})"),
       "tree.json: root.type: \"extrude\" is a 3D primitive, but the tree is 2D"},
      {tree3(R"({"type": "circle", "radius": 1})"),
       "tree.json: root.type: \"circle\" is a 2D primitive, but the tree is 3D"},
      {tree2(R"({"type": "box", "size": [1, 1, 1]})"),
       "tree.json: root.type: \"box\" is a 3D primitive, but the tree is 2D"},
      {tree2(R"({"type": "quadric", "coefficients": [1, 1, 0, 0, 0, 0, 0, 0, 0, -1]})"),
       "tree.json: root.coefficients: expected 6 numbers (got 10)"},
  });
}

TEST(TreeJsonErrors, Domain) {
  const std::string head = R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2, "domain": )";
  const std::string tail = R"(, "root": {"type": "circle", "radius": 1}})";
  expect_messages({
      {head + R"({"min": [0, 1], "max": [1, 1]})" + tail,
       "tree.json: domain.max[1]: must be greater than domain.min[1] = 1 (got 1)"},
      {head + R"({"min": [0, "a"], "max": [1, 1]})" + tail,
       "tree.json: domain.min[1]: expected a number (got \"a\")"},
      {head + R"({"min": [0, 0], "max": [1, 1e999]})" + tail,
       "tree.json: domain.max[1]: must be finite (got 1e999)"},
      {head + R"({"min": [0, 0], "max": [1, 1], "mid": 0})" + tail,
       "tree.json: domain: unknown field \"mid\""},
      {head + "[0, 1]" + tail,
       "tree.json: domain: expected {\"min\": [...], \"max\": [...]} (got an array)"},
  });
}

TEST(TreeJsonErrors, Parameters) {
  const std::string head = R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, )";
  expect_messages({
      {tree3(R"({"type": "sphere", "radius": {"param": "r"}})"),
       "tree.json: root.radius: unknown parameter \"r\" (the file declares no \"parameters\")"},
      {head + R"("parameters": {"s": 1}, "root": {"type": "sphere", "radius": {"param": "r"}}})",
       "tree.json: root.radius: unknown parameter \"r\""},
      {head + R"("parameters": {"s": 1}, "root": {"type": "sphere", "radius": {"param": 1}}})",
       "tree.json: root.radius.param: expected a parameter name (got 1)"},
      {head + R"("parameters": {"1x": 1}, "root": {"type": "sphere", "radius": 1}})",
       "tree.json: parameters: invalid parameter name \"1x\" (names match "
       "[A-Za-z_][A-Za-z0-9_.-]*)"},
      {head + R"("parameters": {"a b": 1}, "root": {"type": "sphere", "radius": 1}})",
       "tree.json: parameters: invalid parameter name \"a b\" (names match "
       "[A-Za-z_][A-Za-z0-9_.-]*)"},
      {head + R"("parameters": {"root_size": 1}, "root": {"type": "sphere", "radius": 1}})",
       "tree.json: parameters: invalid parameter name \"root_size\" (names starting with "
       "\"root\" are node paths)"},
      {head + R"("parameters": {"r": "big"}, "root": {"type": "sphere", "radius": 1}})",
       "tree.json: parameters.r: expected a number or {\"value\": v, \"fixed\": true|false} "
       "(got \"big\")"},
      {head + R"("parameters": {"r": {"param": "q"}}, "root": {"type": "sphere", "radius": 1}})",
       "tree.json: parameters.r: unknown field \"param\""},
      {head + R"("parameters": [1], "root": {"type": "sphere", "radius": 1}})",
       "tree.json: parameters: expected an object of named numbers (got an array)"},
      {head + R"("parameters": {"wheel_radius": -1}, "root": {"op": "union", "children": [)"
              R"({"type": "sphere", "radius": {"param": "wheel_radius"}}, )"
              R"({"type": "sphere", "radius": {"param": "wheel_radius"}}]}})",
       "tree.json: parameters.wheel_radius: must be > 0 (got -1) (used by "
       "root.children[0].radius)"},
      {head + R"("parameters": {"s": 1e999}, "root": {"type": "sphere", "radius": 1}})",
       "tree.json: parameters.s: must be finite (got 1e999)"},
      // Shared by a field that takes any number and one that must be positive.
      {head + R"("parameters": {"t": -0.5}, "root": {"type": "sphere", "radius": 1, )"
              R"("translate": [{"param": "t"}, 0, 0], "scale": {"param": "t"}}})",
       "tree.json: parameters.t: must be > 0 (got -0.5) (used by root.scale)"},
  });
}

TEST(TreeJsonErrors, ChildrenCounts) {
  const std::string s = R"({"type": "sphere", "radius": 1})";
  expect_messages({
      {tree3(R"({"op": "union", "children": [)" + s + "]}"),
       "tree.json: root: a union needs at least 2 children (got 1)"},
      {tree3(R"({"op": "intersection", "children": []})"),
       "tree.json: root: an intersection needs at least 2 children (got 0)"},
      {tree3(R"({"op": "difference", "children": [)" + s + ", " + s + ", " + s + "]}"),
       "tree.json: root: a difference has exactly 2 children (got 3)"},
      {tree3(R"({"op": "complement", "children": [)" + s + ", " + s + "]}"),
       "tree.json: root: a complement has exactly 1 child (got 2)"},
      {tree3(R"({"op": "unified", "c": [0, 1, 0, 0], "children": [)" + s + "]}"),
       "tree.json: root: a unified node has exactly 2 children (got 1)"},
      {tree3(R"({"op": "union", "children": {"a": 1}})"),
       "tree.json: root.children: expected an array of nodes (got an object)"},
      {tree3(R"({"op": "union", "children": [1, 2]})"),
       "tree.json: root.children[0]: expected a node object (got 1)"},
  });
}

TEST(TreeJsonErrors, Spline) {
  const std::string c = R"({"type": "circle", "radius": 0.5})";
  const auto circles = [&](int n) {
    std::string s;
    for (int k = 0; k < n; ++k) s += (k ? ", " : "") + c;
    return "[" + s + "]";
  };
  const auto spline2 = [&](const std::string& fields, int children) {
    return tree2(R"({"op": "spline", )" + fields + R"(, "children": )" + circles(children) + "}");
  };
  // A valid one, to be sure the cases below fail for the reason they name.
  EXPECT_EQ(error_of(spline2(R"("cells": [3, 2], "degree": 1)", 6)), "no error");
  expect_messages({
      {spline2(R"("cells": [3, 2, 2], "degree": 1)", 12),
       "tree.json: root.cells: needs 2 entries for a 2D tree (got 3)"},
      {spline2(R"("cells": [3, 2], "degree": 1)", 5),
       "tree.json: root.children: a spline with cells [3, 2] needs 6 children (got 5)"},
      {spline2(R"("cells": [3, 2])", 6),
       "tree.json: root.cells[1]: must be in [3, 256] for degree 2 (got 2)"},
      {spline2(R"("cells": [300, 2], "degree": 1)", 6),
       "tree.json: root.cells[0]: must be in [2, 256] for degree 1 (got 300)"},
      {spline2(R"("cells": [3, 2.0], "degree": 1)", 6),
       "tree.json: root.cells[1]: expected an integer (got 2.0)"},
      {spline2(R"("cells": 6, "degree": 1)", 6),
       "tree.json: root.cells: expected an array of 2 integers (got 6)"},
      {spline2(R"("cells": [3, 3], "degree": 6)", 9),
       "tree.json: root.degree: must be in [1, 5] (got 6)"},
      {spline2(R"("cells": [3, 3], "degree": 0)", 9),
       "tree.json: root.degree: must be in [1, 5] (got 0)"},
      {spline2(R"("cells": [3, 3], "degree": {"value": 2})", 9),
       "tree.json: root.degree: expected an integer (got an object)"},
      {tree2(R"({"op": "spline", "children": [{"type": "circle", "radius": 1}]})"),
       "tree.json: root: missing field \"cells\""},
      {spline2(R"("cells": [3, 3], "box": {"min": [0, 0], "max": [1, 0]})", 9),
       "tree.json: root.box.max[1]: must be greater than box.min[1] = 0 (got 0)"},
      {spline2(R"("cells": [3, 3], "box": {"min": [0, 0], "max": [1, 1e999]})", 9),
       "tree.json: root.box.max[1]: must be finite (got 1e999)"},
      {spline2(R"("cells": [3, 3], "box": {"min": [0, 0, 0], "max": [1, 1]})", 9),
       "tree.json: root.box.min: expected 2 numbers (got 3)"},
      {spline2(R"("cells": [3, 3], "box": {"min": [0, {"value": 0}], "max": [1, 1]})", 9),
       "tree.json: root.box.min[1]: expected a number (got an object)"},
      {spline2(R"("cells": [3, 3], "box": {"min": [0, 0]})", 9),
       "tree.json: root.box: missing field \"max\""},
      {spline2(R"("cells": [3, 3], "box": {"min": [0, 0], "max": [1, 1], "mid": 0})", 9),
       "tree.json: root.box: unknown field \"mid\""},
      {spline2(R"("cells": [3, 3], "box": [0, 1])", 9),
       "tree.json: root.box: expected {\"min\": [...], \"max\": [...]} (got an array)"},
      {spline2(R"("cells": [3, 3], "logic": "godel")", 9),
       "tree.json: root: field \"logic\" does not apply to spline nodes"},
      {spline2(R"("cells": [3, 3], "complement": "cosine")", 9),
       "tree.json: root: field \"complement\" does not apply to spline nodes"},
      {spline2(R"("cells": [3, 3], "p": 2)", 9),
       "tree.json: root: field \"p\" does not apply to spline nodes"},
      {spline2(R"("cells": [3, 3], "knots": [0, 1])", 9),
       "tree.json: root: unknown field \"knots\""},
      {tree2(R"({"op": "union", "cells": [2, 2], "children": )" + circles(2) + "}"),
       "tree.json: root: field \"cells\" does not apply to union nodes"},
      {tree2(R"({"op": "complement", "degree": 2, "children": )" + circles(1) + "}"),
       "tree.json: root: field \"degree\" does not apply to complement nodes"},
      {tree3(R"({"op": "spline", "cells": [2, 2, 2], "degree": 1, "children": [)" + kSphere + "]}"),
       "tree.json: root.children: a spline with cells [2, 2, 2] needs 8 children (got 1)"},
  });
}

TEST(TreeJsonErrors, DuplicateKeys) {
  expect_messages({
      {R"({"format": "fuzzycsg-tree", "format": "fuzzycsg-tree"})",
       "tree.json: duplicate key \"format\""},
      {pair3(R"({"type": "sphere", "radius": 1, "radius": 2})", kSphere),
       "tree.json: root.children[0]: duplicate key \"radius\""},
      {tree3(R"({"type": "sphere", "radius": {"value": 1, "value": 2}})"),
       "tree.json: root.radius: duplicate key \"value\""},
  });
}

TEST(TreeJsonErrors, DeepNesting) {
  // 100000 nested arrays: rejected before anything recurses.
  std::string arrays(100000, '[');
  arrays += std::string(100000, ']');
  EXPECT_EQ(error_of(arrays), "tree.json: nested deeper than 512 levels");
  EXPECT_EQ(error_of(tree3(arrays)), "tree.json: nested deeper than 512 levels");
  std::string objects;
  for (int i = 0; i < 100000; ++i) objects += "{\"a\":";
  EXPECT_EQ(error_of(objects), "tree.json: nested deeper than 512 levels");

  // A chain of complements deeper than a tree file may be.
  const auto chain = [](int depth) {
    std::string root;
    for (int i = 0; i < depth; ++i) root += R"({"op": "complement", "children": [)";
    root += R"({"type": "sphere", "radius": 1})";
    for (int i = 0; i < depth; ++i) root += "]}";
    return root;
  };
  EXPECT_EQ(error_of(tree3(chain(251))), "tree.json: the tree is deeper than 250 levels");
  EXPECT_EQ(error_of(tree3(chain(250))), "no error");
}

TEST(TreeJsonErrors, UnreadableFile) {
  try {
    read_tree_file("/nonexistent/dir/tree.json");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "/nonexistent/dir/tree.json: cannot read (No such file or directory)");
  }
}

}  // namespace
}  // namespace fuzzycsg::io
