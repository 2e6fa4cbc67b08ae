// The parameter table, tree validation, node paths and counts.
#include "fuzzycsg/core/tree.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/fields.hpp"
#include "fuzzycsg/core/numbers.hpp"

namespace fuzzycsg {
namespace {

std::string error_of(const Tree& t) {
  try {
    validate(t, "t");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

class TreeBuilder {
 public:
  explicit TreeBuilder(int dim) { tree.dim = dim; }

  ParamRef param(double value, Range range = Range::any()) {
    std::string name = std::to_string(tree.params.size());
    name.insert(0, 1, 'p');
    return tree.params.add(Parameter{std::move(name), value, false, false, range});
  }
  int leaf(PrimitiveType type, std::vector<double> values) {
    Node n;
    n.kind = NodeKind::kPrimitive;
    n.shape.type = type;
    for (double v : values) n.intrinsic.push_back(param(v));
    n.step.param = param(50, Range::positive());
    return add(std::move(n));
  }
  int sphere(double radius) { return leaf(PrimitiveType::kSphere, {radius}); }
  int op(OpKind kind, std::vector<int> children) {
    Node n;
    n.kind = NodeKind::kOperator;
    n.op = kind;
    n.children = std::move(children);
    return add(std::move(n));
  }
  int add(Node n) {
    tree.nodes.push_back(std::move(n));
    return static_cast<int>(tree.nodes.size()) - 1;
  }
  Node& node(int i) { return tree.nodes[static_cast<std::size_t>(i)]; }

  Tree tree;
};

TEST(ParameterTable, AddFindValues) {
  ParameterTable table;
  const ParamRef a = table.add(Parameter{"a", 1.5, false, false, Range::any()});
  const ParamRef b = table.add(Parameter{"b", -2.0, true, true, Range::positive()});
  EXPECT_EQ(a.index, 0u);
  EXPECT_EQ(b.index, 1u);
  EXPECT_EQ(table.size(), 2u);
  EXPECT_EQ(table.find("b"), b);
  EXPECT_FALSE(table.find("c").has_value());
  EXPECT_EQ(table.values(), (std::vector<double>{1.5, -2.0}));
  table.set_values(std::vector<double>{3, 4});
  EXPECT_EQ(table[a].value, 3.0);
  EXPECT_EQ(table.at(1).value, 4.0);
  EXPECT_THROW(table.set_values(std::vector<double>{1}), InputError);
  EXPECT_THROW(table.add(Parameter{"a", 0, false, false, Range::any()}), InputError);
  EXPECT_THROW(table.add(Parameter{"", 0, false, false, Range::any()}), InputError);
  // A renamed entry is found under its new name only.
  table[a].name = "alpha";
  EXPECT_EQ(table.find("alpha"), a);
  EXPECT_FALSE(table.find("a").has_value());
  EXPECT_EQ(table.add(Parameter{"a", 0, false, false, Range::any()}).index, 2u);
}

TEST(Tree, ValidTreePathsAndCounts) {
  TreeBuilder b(3);
  const int s0 = b.sphere(1);
  const int s1 = b.sphere(2);
  const int s2 = b.sphere(3);
  const int c = b.op(OpKind::kComplement, {s2});
  const int d = b.op(OpKind::kDifference, {s1, c});
  b.tree.root = b.op(OpKind::kUnion, {s0, d});
  b.tree.params[b.tree.params.find("p0").value()].fixed = true;
  EXPECT_EQ(error_of(b.tree), "no error");
  const auto paths = node_paths(b.tree);
  EXPECT_EQ(paths,
            (std::vector<std::string>{"root.children[0]", "root.children[1].children[0]",
                                      "root.children[1].children[1].children[0]",
                                      "root.children[1].children[1]", "root.children[1]", "root"}));
  const TreeCounts counts = count(b.tree);
  EXPECT_EQ(counts.primitives, 3);
  EXPECT_EQ(counts.operators, 3);
  EXPECT_EQ(counts.parameters, 6);
  EXPECT_EQ(counts.free_parameters, 5);
  EXPECT_EQ(counts.depth, 3);

  TreeBuilder lone(2);
  lone.tree.root = lone.leaf(PrimitiveType::kCircle, {1});
  EXPECT_EQ(error_of(lone.tree), "no error");
  EXPECT_EQ(count(lone.tree).depth, 0);
  EXPECT_EQ(node_paths(lone.tree), std::vector<std::string>{"root"});
}

TEST(Tree, Structure) {
  {
    Tree empty;
    EXPECT_EQ(error_of(empty), "t: the tree has no nodes");
  }
  {
    TreeBuilder b(3);
    b.sphere(1);
    b.tree.root = 1;
    EXPECT_EQ(error_of(b.tree), "t: root: node index 1 is out of range (the tree has 1 nodes)");
    b.tree.root = -1;
    EXPECT_EQ(error_of(b.tree), "t: root: node index -1 is out of range (the tree has 1 nodes)");
  }
  {
    TreeBuilder b(4);
    b.tree.root = b.sphere(1);
    EXPECT_EQ(error_of(b.tree), "t: dim: must be 2 or 3 (got 4)");
  }
  {
    TreeBuilder b(3);
    const int s = b.sphere(1);
    b.tree.root = b.op(OpKind::kUnion, {s, 7});
    EXPECT_EQ(error_of(b.tree),
              "t: root.children[1]: node index 7 is out of range (the tree has 2 nodes)");
  }
  {  // a node shared by two parents
    TreeBuilder b(3);
    const int s = b.sphere(1);
    const int t = b.sphere(2);
    const int u = b.op(OpKind::kUnion, {s, t});
    b.tree.root = b.op(OpKind::kUnion, {u, s});
    EXPECT_EQ(error_of(b.tree),
              "t: root.children[1]: node 0 already has a parent (it is "
              "root.children[0].children[0]); nodes may not be shared");
    const auto paths = node_paths(b.tree);  // still answers
    EXPECT_EQ(paths[0], "root.children[0].children[0]");
    EXPECT_EQ(count(b.tree).primitives, 2);
  }
  {  // a cycle through the root
    TreeBuilder b(3);
    const int s = b.sphere(1);
    const int c = b.op(OpKind::kComplement, {s});
    b.tree.root = b.op(OpKind::kUnion, {c, s});
    b.node(c).children = {b.tree.root};
    EXPECT_EQ(error_of(b.tree),
              "t: root.children[0].children[0]: refers back to the root (a cycle)");
    EXPECT_EQ(count(b.tree).depth, 1);  // terminates
  }
  {  // a node the root does not reach
    TreeBuilder b(3);
    const int s = b.sphere(1);
    b.sphere(2);
    b.tree.root = s;
    EXPECT_EQ(error_of(b.tree), "t: nodes[1]: is not reachable from the root");
    EXPECT_EQ(node_paths(b.tree), (std::vector<std::string>{"root", "nodes[1]"}));
  }
  {  // a deep chain is handled without recursion
    TreeBuilder b(3);
    int n = b.sphere(1);
    for (int i = 0; i < 200000; ++i) n = b.op(OpKind::kComplement, {n});
    b.tree.root = n;
    EXPECT_EQ(error_of(b.tree), "no error");
    EXPECT_EQ(count(b.tree).depth, 200000);
    // Errors deep down are still named by their path.
    b.tree.params.at(0).value = -1;
    const std::string message = error_of(b.tree);
    EXPECT_EQ(message.size(), std::string("t: root.radius: must be > 0 (got -1)").size() +
                                  200000 * std::string(".children[0]").size());
    EXPECT_EQ(message.substr(message.size() - 41), ".children[0].radius: must be > 0 (got -1)");
  }
  {
    TreeBuilder b(3);
    int n = b.sphere(1);
    for (int i = 0; i < 1000; ++i) n = b.op(OpKind::kComplement, {n});
    b.tree.root = n;
    const auto paths = node_paths(b.tree);
    EXPECT_EQ(paths[1000], "root");
    EXPECT_EQ(paths[999], "root.children[0]");
    EXPECT_EQ(paths[0].size(), 4 + 1000 * std::string(".children[0]").size());
  }
}

TEST(Tree, ChildrenCounts) {
  TreeBuilder b(3);
  const int s0 = b.sphere(1);
  const int s1 = b.sphere(1);
  const int s2 = b.sphere(1);
  b.tree.root = b.op(OpKind::kUnion, {s0, s1, s2});
  Node& root = b.node(b.tree.root);
  EXPECT_EQ(error_of(b.tree), "no error");  // n-ary
  root.op = OpKind::kIntersection;
  EXPECT_EQ(error_of(b.tree), "no error");
  root.op = OpKind::kDifference;
  EXPECT_EQ(error_of(b.tree), "t: root: a difference has exactly 2 children (got 3)");
  root.op = OpKind::kUnified;
  EXPECT_EQ(error_of(b.tree), "t: root: a unified node has exactly 2 children (got 3)");
  root.op = OpKind::kComplement;
  EXPECT_EQ(error_of(b.tree), "t: root: a complement has exactly 1 child (got 3)");
  root.op = OpKind::kUnion;
  root.children = {s0, s1};
  b.node(s0).children = {s2};
  EXPECT_EQ(error_of(b.tree), "t: root.children[0]: a primitive has no children (got 1)");

  TreeBuilder one(3);
  const int s = one.sphere(1);
  one.tree.root = one.op(OpKind::kIntersection, {s});
  EXPECT_EQ(error_of(one.tree), "t: root: an intersection needs at least 2 children (got 1)");
  one.node(one.tree.root).op = OpKind::kComplement;
  EXPECT_EQ(error_of(one.tree), "no error");
  one.node(one.tree.root).children.clear();
  one.node(one.tree.root).op = OpKind::kUnion;
  EXPECT_EQ(error_of(one.tree), "t: nodes[0]: is not reachable from the root");
}

TEST(Tree, SplineChecks) {
  TreeBuilder b(2);
  std::vector<int> leaves;
  for (int k = 0; k < 6; ++k) leaves.push_back(b.leaf(PrimitiveType::kCircle, {0.5}));
  b.tree.root = b.op(OpKind::kSpline, leaves);
  Node& root = b.node(b.tree.root);
  root.spline_cells = {3, 2};
  root.spline_degree = 1;
  EXPECT_EQ(error_of(b.tree), "no error");
  root.spline_box = Domain{{-1, -0.5, 0}, {1, 0.5, 0}};  // the third axis is not used in 2D
  EXPECT_EQ(error_of(b.tree), "no error");

  root.spline_degree = 2;
  EXPECT_EQ(error_of(b.tree), "t: root.cells[1]: must be in [3, 256] for degree 2 (got 2)");
  root.spline_degree = 0;
  EXPECT_EQ(error_of(b.tree), "t: root.degree: must be in [1, 5] (got 0)");
  root.spline_degree = 6;
  EXPECT_EQ(error_of(b.tree), "t: root.degree: must be in [1, 5] (got 6)");
  root.spline_degree = 1;
  root.spline_cells = {3, 2, 1};
  EXPECT_EQ(error_of(b.tree), "t: root.cells: needs 2 entries for a 2D tree (got 3)");
  root.spline_cells = {};
  EXPECT_EQ(error_of(b.tree), "t: root.cells: needs 2 entries for a 2D tree (got 0)");
  root.spline_cells = {257, 2};
  EXPECT_EQ(error_of(b.tree), "t: root.cells[0]: must be in [2, 256] for degree 1 (got 257)");
  root.spline_cells = {3, 3};
  EXPECT_EQ(error_of(b.tree),
            "t: root.children: a spline with cells [3, 3] needs 9 children (got 6)");

  TreeBuilder five(2);
  std::vector<int> circles;
  for (int k = 0; k < 5; ++k) circles.push_back(five.leaf(PrimitiveType::kCircle, {0.5}));
  five.tree.root = five.op(OpKind::kSpline, circles);
  Node& r5 = five.node(five.tree.root);
  r5.spline_degree = 1;
  r5.spline_cells = {3, 2};
  EXPECT_EQ(error_of(five.tree),
            "t: root.children: a spline with cells [3, 2] needs 6 children (got 5)");
  r5.spline_cells = {5, 1};
  EXPECT_EQ(error_of(five.tree), "t: root.cells[1]: must be in [2, 256] for degree 1 (got 1)");
  r5.spline_cells = {5, 2};
  EXPECT_EQ(error_of(five.tree),
            "t: root.children: a spline with cells [5, 2] needs 10 children (got 5)");

  TreeBuilder c(3);
  std::vector<int> spheres;
  for (int k = 0; k < 8; ++k) spheres.push_back(c.sphere(0.5));
  c.tree.root = c.op(OpKind::kSpline, spheres);
  Node& r3 = c.node(c.tree.root);
  r3.spline_cells = {2, 2, 2};
  r3.spline_degree = 1;
  EXPECT_EQ(error_of(c.tree), "no error");
  r3.spline_box = Domain{{-1, -1, -1}, {1, 1, -1}};
  EXPECT_EQ(error_of(c.tree), "t: root.box.max[2]: must be greater than box.min[2] = -1 (got -1)");
  r3.spline_box = Domain{{-1, std::numeric_limits<double>::infinity(), -1}, {1, 1, 1}};
  EXPECT_EQ(error_of(c.tree), "t: root.box.min[1]: must be finite (got inf)");
  r3.spline_box.reset();
  r3.logic.family = logic::Family::kGodel;
  EXPECT_EQ(error_of(c.tree), "t: root.logic: does not apply to spline nodes");
  r3.logic.family = logic::Family::kProduct;
  r3.complement.kind = logic::Complement::kCosine;
  EXPECT_EQ(error_of(c.tree),
            "t: root.complement: applies only to complement and difference nodes");
  r3.complement.kind = logic::Complement::kStandard;
  EXPECT_EQ(error_of(c.tree), "no error");
  // Spline fields on another operator.
  r3.op = OpKind::kUnion;
  EXPECT_EQ(error_of(c.tree), "t: root: cells and box apply only to spline nodes");
  r3.spline_cells.clear();
  EXPECT_EQ(error_of(c.tree), "no error");
  r3.spline_box = Domain{};
  EXPECT_EQ(error_of(c.tree), "t: root: cells and box apply only to spline nodes");
}

TEST(Tree, LeafChecks) {
  const auto check = [](int dim, PrimitiveType type, std::vector<double> values,
                        const std::string& expected) {
    TreeBuilder b(dim);
    b.tree.root = b.leaf(type, std::move(values));
    EXPECT_EQ(error_of(b.tree), expected);
  };
  check(3, PrimitiveType::kSphere, {-0.2}, "t: root.radius: must be > 0 (got -0.2)");
  check(3, PrimitiveType::kSphere, {std::nan("")}, "t: root.radius: must be finite (got nan)");
  check(3, PrimitiveType::kBox, {1, 1, -1}, "t: root.size[2]: must be > 0 (got -1)");
  check(3, PrimitiveType::kBox, {1, 1},
        "t: root: has 2 intrinsic parameters, but \"box\" needs more");
  check(3, PrimitiveType::kSphere, {1, 2},
        "t: root: has 2 intrinsic parameters, but \"sphere\" has 1");
  check(2, PrimitiveType::kSphere, {1},
        "t: root.type: \"sphere\" is a 3D primitive, but the tree is 2D");
  check(3, PrimitiveType::kPlane, {0, 0, 0, 1}, "t: root.normal: must be non-zero (got [0, 0, 0])");
  check(3, PrimitiveType::kCone, {0, 0, 1}, "t: root: radius1 and radius2 must not both be 0");
  check(3, PrimitiveType::kCone, {0, 0.5, 1}, "no error");
  check(2, PrimitiveType::kPolygon, {0, 0, 1, 0, 0},
        "t: root.vertices: needs 2 numbers per vertex (got 5 numbers)");
  check(2, PrimitiveType::kPolygon, {0, 0, 1, 0},
        "t: root.vertices: needs at least 3 vertices (got 2)");
  check(2, PrimitiveType::kPolygon, {0, 0, 1, 0, 0, 1}, "no error");
  // The extrude: 3 points (P, A, B) per segment, at least 2 segments, then the height.
  std::vector<double> extrude = {0, 0, 1, 0, 2, 0, 2, 1, 1, 2, 0, 1, 0.5};
  check(3, PrimitiveType::kExtrude, extrude, "no error");
  extrude.back() = 0;
  check(3, PrimitiveType::kExtrude, extrude, "t: root.height: must be > 0 (got 0)");
  extrude.back() = 0.5;
  extrude[7] = std::numeric_limits<double>::infinity();
  check(3, PrimitiveType::kExtrude, extrude, "t: root.profile[3][1]: must be finite (got inf)");
  check(3, PrimitiveType::kExtrude, {0, 0, 1, 0, 2, 0, 0.5},
        "t: root.profile: needs at least 6 points, 2 segments (got 3)");
  check(3, PrimitiveType::kExtrude, {0, 0, 1, 0, 2, 0, 2, 1, 0.5},
        "t: root.profile: needs 3 points (P, A, B) per segment (got 4)");
  check(3, PrimitiveType::kExtrude, {0, 0, 1, 0, 2, 0, 2, 1, 1, 2, 0, 0.5},
        "t: root.profile: needs 2 numbers per point (got 11 numbers)");
  check(2, PrimitiveType::kExtrude, {0, 0, 1, 0, 2, 0, 2, 1, 1, 2, 0, 1, 0.5},
        "t: root.type: \"extrude\" is a 3D primitive, but the tree is 2D");
  check(3, PrimitiveType::kMlp, {1, 2, 3, 4}, "no error");  // no hidden layers: 4 weights
  check(3, PrimitiveType::kMlp, {1, 2, 3},
        "t: root.weights: needs 4 numbers for 0 hidden layers (got 3)");
  check(3, PrimitiveType::kQuadric3,
        std::vector<double>(10, std::numeric_limits<double>::infinity()),
        "t: root.coefficients[0]: must be finite (got inf)");

  TreeBuilder b(3);
  b.tree.root = b.leaf(PrimitiveType::kMlp, {1, 2, 3, 4});
  Node& mlp = b.node(b.tree.root);
  mlp.shape.hidden = {0};
  EXPECT_EQ(error_of(b.tree), "t: root.hidden[0]: must be in [1, 64] (got 0)");
  mlp.shape.hidden = std::vector<int>(9, 1);
  EXPECT_EQ(error_of(b.tree), "t: root.hidden: must have at most 8 layers (got 9)");
  mlp.shape.hidden = {2};
  EXPECT_EQ(error_of(b.tree), "t: root.weights: needs 11 numbers for 1 hidden layers (got 4)");

  TreeBuilder c(3);
  c.tree.root = c.sphere(1);
  Node& s = c.node(c.tree.root);
  s.shape.hidden = {3};
  EXPECT_EQ(error_of(c.tree), "t: root.hidden: applies only to mlp primitives");
  s.shape.hidden = {};
  s.placement.translate = {c.param(1), c.param(2)};
  EXPECT_EQ(error_of(c.tree), "t: root.translate: needs 3 numbers (got 2)");
  s.placement.translate.push_back(c.param(std::numeric_limits<double>::infinity()));
  EXPECT_EQ(error_of(c.tree), "t: root.translate[2]: must be finite (got inf)");
  c.tree.params[s.placement.translate[2]].value = 3;
  s.placement.rotate = {c.param(90)};
  EXPECT_EQ(error_of(c.tree), "t: root.rotate: needs 3 numbers (got 1)");
  s.placement.rotate = {c.param(90), c.param(0), c.param(0)};
  s.placement.scale = c.param(0);
  EXPECT_EQ(error_of(c.tree), "t: root.scale: must be > 0 (got 0)");
  c.tree.params[*s.placement.scale].value = 2;
  EXPECT_EQ(error_of(c.tree), "no error");
  s.step.kind = StepKind::kCrisp;
  EXPECT_EQ(error_of(c.tree), "t: root.step: a crisp step has no parameter");
  s.step.param.reset();
  EXPECT_EQ(error_of(c.tree), "no error");
  s.step.kind = StepKind::kSigmoid;
  EXPECT_EQ(error_of(c.tree), "t: root.sharpness: missing");
  s.step.kind = StepKind::kHn;
  s.step.n = 17;
  s.step.param = c.param(0.5);
  EXPECT_EQ(error_of(c.tree), "t: root.step.hn: must be in [0, 16] (got 17)");
  s.step.n = 16;
  c.tree.params[*s.step.param].value = -0.5;
  EXPECT_EQ(error_of(c.tree), "t: root.step.range: must be > 0 (got -0.5)");
  s.step.param = ParamRef{999};
  EXPECT_EQ(error_of(c.tree),
            "t: root.step.range: refers to parameter 999, but the table has 11 entries");

  TreeBuilder h(2);
  h.tree.root = h.leaf(PrimitiveType::kCircle, {1});
  h.node(h.tree.root).placement.rotate = {h.param(1), h.param(2), h.param(3)};
  EXPECT_EQ(error_of(h.tree), "t: root.rotate: needs 1 number (got 3)");
}

TEST(Tree, OperatorChecks) {
  TreeBuilder b(3);
  const int s0 = b.sphere(1);
  const int s1 = b.sphere(2);
  b.tree.root = b.op(OpKind::kUnion, {s0, s1});
  Node& root = b.node(b.tree.root);
  const auto expect = [&](const std::string& message) { EXPECT_EQ(error_of(b.tree), message); };

  root.logic.family = logic::Family::kYager;
  expect("t: root.p: missing");
  root.logic.p = b.param(0);
  expect("t: root.p: must be > 0 (got 0)");
  b.tree.params[*root.logic.p].value = 2;
  expect("no error");
  root.logic.family = logic::Family::kGodel;
  expect("t: root: logic \"godel\" has no continuous parameter");
  root.logic.family = logic::Family::kDuboisPrade;
  expect("t: root.k: must be in (0, 1] (got 2)");
  root.logic.family = logic::Family::kWeber;
  b.tree.params[*root.logic.p].value = -1;
  expect("t: root.k: must be > -1 (got -1)");
  root.logic.family = logic::Family::kLiTian;
  b.tree.params[*root.logic.p].value = 0.5;
  root.logic.n = 17;
  expect("t: root.n: must be in [0, 16] (got 17)");
  root.logic.n = 16;
  expect("no error");
  root.logic.family = logic::Family::kBezier;
  root.logic.p.reset();
  root.logic.n = 0;
  expect("t: root.n: must be in [1, 64] (got 0)");
  root.logic.n = 64;
  expect("no error");
  root.complement.kind = logic::Complement::kCosine;
  expect("t: root.complement: applies only to complement and difference nodes");
  root.op = OpKind::kDifference;
  expect("no error");
  root.complement.kind = logic::Complement::kSugeno;
  expect("t: root.complement.lambda: missing");
  root.complement.lambda = b.param(-1);
  expect("t: root.complement.lambda: must be > -1 (got -1)");
  root.complement.kind = logic::Complement::kYager;
  b.tree.params[*root.complement.lambda].value = 0;
  expect("t: root.complement.lambda: must be > 0 (got 0)");
  root.complement.kind = logic::Complement::kStandard;
  expect("t: root.complement: the \"standard\" complement has no parameter");
  root.complement.lambda.reset();

  root.op = OpKind::kUnified;
  expect("t: root.logic: unified nodes use product logic (got \"bezier\")");
  root.logic = LogicSpec{};
  expect("t: root.c: needs 4 numbers (got 0)");
  root.unified = {b.param(0.5), b.param(0.5), b.param(0.5), b.param(0)};
  expect("t: root.c: must sum to 1 (got 1.5)");
  b.tree.params[root.unified[2]].value = -0.5;
  b.tree.params[root.unified[3]].value = 0.5;
  expect("t: root.c[2]: must be in [0, 1] (got -0.5)");
  b.tree.params[root.unified[2]].value = 0.0;
  b.tree.params[root.unified[3]].value = 1e-7;
  expect("no error");  // within the tolerance
  b.tree.params[root.unified[3]].value = 2e-6;
  expect("t: root.c: must sum to 1 (got 1.000002)");
  root.unified_logits = true;
  expect("t: root.temperature: missing");
  root.temperature = b.param(0);
  root.omega = b.param(10);
  expect("t: root.temperature: must be > 0 (got 0)");
  b.tree.params[*root.temperature].value = 1000;
  expect("no error");
  root.unified_logits = false;
  expect("t: root: temperature and omega apply only to unified nodes given by logits");
  root.op = OpKind::kIntersection;
  expect("t: root: c, logits, temperature and omega apply only to unified nodes");
}

TEST(Tree, SharedParameters) {
  TreeBuilder b(3);
  const int s0 = b.sphere(1);
  const int s1 = b.sphere(2);
  b.tree.root = b.op(OpKind::kUnion, {s0, s1});
  const ParamRef wheel =
      b.tree.params.add(Parameter{"wheel_radius", -1, false, true, Range::positive()});
  b.node(s1).intrinsic[0] = wheel;
  b.node(s0).intrinsic[0] = wheel;
  EXPECT_EQ(error_of(b.tree),
            "t: parameters.wheel_radius: must be > 0 (got -1) (used by root.children[0].radius)");
  b.tree.params[wheel].value = 1;
  EXPECT_EQ(error_of(b.tree), "no error");
  // An inline parameter may not be used twice.
  b.tree.params[wheel].shared = false;
  EXPECT_EQ(error_of(b.tree),
            "t: root.children[1].radius: uses parameter \"wheel_radius\", which "
            "root.children[0].radius uses too; only shared parameters may be used by several "
            "fields");
  b.tree.params[wheel].shared = true;
  // Unused entries must still be finite, and within their own range.
  const ParamRef unused = b.tree.params.add(
      Parameter{"spare", std::numeric_limits<double>::quiet_NaN(), false, true, Range::any()});
  EXPECT_EQ(error_of(b.tree), "t: parameters.spare: must be finite (got nan)");
  b.tree.params[unused].value = -3;
  b.tree.params[unused].range = Range::non_negative();
  EXPECT_EQ(error_of(b.tree), "t: parameters.spare: must be >= 0 (got -3)");
}

TEST(Tree, Domain) {
  TreeBuilder b(2);
  b.tree.root = b.leaf(PrimitiveType::kCircle, {1});
  b.tree.domain = Domain{};
  EXPECT_EQ(error_of(b.tree), "no error");
  b.tree.domain->max[1] = -1;
  EXPECT_EQ(error_of(b.tree), "t: domain.max[1]: must be greater than domain.min[1] = -1 (got -1)");
  b.tree.domain->max[1] = 1;
  b.tree.domain->min[0] = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(error_of(b.tree), "t: domain.min[0]: must be finite (got -inf)");
  b.tree.domain->min[0] = -1;
  b.tree.domain->min[2] = 5;  // ignored in 2D
  EXPECT_EQ(error_of(b.tree), "no error");
}

TEST(Fields, Tables) {
  EXPECT_EQ(fields::logic_param(logic::Family::kYager).name, "p");
  EXPECT_EQ(fields::logic_param(logic::Family::kHamacher).name, "a");
  EXPECT_EQ(fields::logic_param(logic::Family::kDombi).name, "lambda");
  EXPECT_EQ(fields::logic_param(logic::Family::kDuboisPrade).name, "k");
  EXPECT_EQ(fields::logic_param(logic::Family::kWeber).name, "k");
  EXPECT_EQ(fields::logic_param(logic::Family::kLiTian).name, "delta");
  for (int f = 0; f <= static_cast<int>(logic::Family::kLiTianHat); ++f) {
    const auto family = static_cast<logic::Family>(f);
    if (!logic::uses_p(family)) continue;
    const FieldSpec& spec = fields::logic_param(family);
    EXPECT_EQ(spec.name, logic::p_field_name(family));
    ASSERT_TRUE(spec.default_value.has_value());
    EXPECT_TRUE(spec.range.contains(*spec.default_value)) << spec.name;
  }
  EXPECT_EQ(fields::logic_degree_default(logic::Family::kBezier), 3);
  EXPECT_EQ(fields::logic_degree_default(logic::Family::kLiTianHat), 2);
  EXPECT_EQ(fields::complement_lambda(logic::Complement::kSugeno).range.describe(), "must be > -1");
  EXPECT_EQ(fields::sharpness(PrimitiveType::kQuadric2).default_value, 1.0);
  EXPECT_EQ(fields::sharpness(PrimitiveType::kTorus).default_value, 50.0);

  const Range r = fields::intersect(Range::greater_than(-1), Range::closed(0, 1));
  EXPECT_EQ(r.describe(), "must be in [0, 1]");
  EXPECT_EQ(fields::intersect(Range::non_negative(), Range::positive()).describe(), "must be > 0");
  EXPECT_EQ(fields::intersect(Range::any(), Range::left_open(0, 1)).describe(),
            "must be in (0, 1]");
}

TEST(Numbers, Shortest) {
  EXPECT_EQ(shortest_number(0.1), "0.1");
  EXPECT_EQ(shortest_number(-0.0), "-0");
  EXPECT_EQ(shortest_number(50), "50");
  EXPECT_EQ(shortest_number(1e100), "1e+100");
  EXPECT_EQ(shortest_number(5e-324), "5e-324");
  EXPECT_EQ(shortest_number(std::nan("")), "nan");
  EXPECT_EQ(shortest_number(-std::numeric_limits<double>::infinity()), "-inf");
}

}  // namespace
}  // namespace fuzzycsg
