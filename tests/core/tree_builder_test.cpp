// The tree builder and the canonical form: names by node path, defaults, shared parameters,
// validation messages, misuse, and snapping as a rewrite in canonical form.
#include "fuzzycsg/core/tree_builder.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/fields.hpp"
#include "fuzzycsg/core/snap.hpp"

namespace fuzzycsg {
namespace {

std::vector<std::string> names(const Tree& t) {
  std::vector<std::string> out;
  for (const Parameter& p : t.params.entries()) out.push_back(p.name);
  return out;
}

std::string finish_error(TreeBuilder b, int root) {
  try {
    std::move(b).finish(root, "built");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// difference(box, union(sphere, cylinder)) built bottom-up: nodes in pre-order, parameters named
// by path in reading order, the default sharpness materialised.
TEST(TreeBuilder, NamesByPathInPreOrder) {
  TreeBuilder b(3);
  const int sphere = b.leaf(PrimitiveType::kSphere, std::vector<Number>{0.5});
  b.translate(sphere, std::vector<Number>{1, 2, 3});
  const int cylinder = b.leaf(PrimitiveType::kCylinder, std::vector<Number>{0.25, 2});
  b.crisp(cylinder);
  const int box = b.leaf(PrimitiveType::kBox, std::vector<Number>{1, 2, 3});
  b.sigmoid(box, Number::with_fixed(40, true));
  b.name(box, "plate");
  const int u = b.op(OpKind::kUnion, {sphere, cylinder});
  const int root = b.op(OpKind::kDifference, {box, u});
  const Tree t = std::move(b).finish(root, "built");

  ASSERT_EQ(t.nodes.size(), 5u);
  EXPECT_EQ(t.root, 0);
  EXPECT_EQ(t.node(0).op, OpKind::kDifference);
  EXPECT_EQ(t.node(0).children, (std::vector<int>{1, 2}));
  EXPECT_EQ(t.node(1).name, "plate");
  EXPECT_EQ(t.node(2).children, (std::vector<int>{3, 4}));
  EXPECT_EQ(t.node(3).shape.type, PrimitiveType::kSphere);
  EXPECT_EQ(
      names(t),
      (std::vector<std::string>{
          "root.children[0].size[0]", "root.children[0].size[1]", "root.children[0].size[2]",
          "root.children[0].sharpness", "root.children[1].children[0].radius",
          "root.children[1].children[0].translate[0]", "root.children[1].children[0].translate[1]",
          "root.children[1].children[0].translate[2]", "root.children[1].children[0].sharpness",
          "root.children[1].children[1].radius", "root.children[1].children[1].height"}));
  const Parameter& plate_sharpness = t.params.at(3);
  EXPECT_EQ(plate_sharpness.value, 40);
  EXPECT_TRUE(plate_sharpness.fixed);
  const Parameter& sphere_sharpness = t.params.at(8);
  EXPECT_EQ(sphere_sharpness.value, primitive_info(PrimitiveType::kSphere).default_sharpness);
  EXPECT_FALSE(sphere_sharpness.fixed);
  EXPECT_TRUE(t.params.at(4).range.contains(0.5));
  EXPECT_FALSE(t.params.at(4).range.contains(0.0));  // a radius is > 0
  EXPECT_EQ(t.node(4).step.kind, StepKind::kCrisp);
  EXPECT_FALSE(t.node(4).step.param.has_value());
}

// Shared parameters come first, sorted by name, with the intersection of their uses' ranges;
// canonical() drops the unused ones only when asked.
TEST(TreeBuilder, SharedParameters) {
  TreeBuilder b(2);
  const ParamRef zeta = b.shared("zeta", 3.0);
  const ParamRef r = b.shared("r", 0.5, true);
  b.shared("unused", 7.0);
  EXPECT_EQ(b.find_shared("r"), r);
  EXPECT_FALSE(b.find_shared("nothing").has_value());
  const int a = b.leaf(PrimitiveType::kCircle, std::vector<Number>{Number::shared(r)});
  b.translate(a, std::vector<Number>{Number::shared(zeta), 0});
  const int c = b.leaf(PrimitiveType::kCircle, std::vector<Number>{Number::shared(r)});
  const int u = b.op(OpKind::kUnion, {a, c});
  const Tree t = std::move(b).finish(u, "built");

  EXPECT_EQ(names(t)[0], "r");
  EXPECT_EQ(names(t)[1], "unused");
  EXPECT_EQ(names(t)[2], "zeta");
  EXPECT_TRUE(t.params.at(0).shared);
  EXPECT_TRUE(t.params.at(0).fixed);
  EXPECT_FALSE(t.params.at(0).range.contains(0.0));  // used as a radius
  EXPECT_TRUE(t.params.at(2).range.contains(-5.0));  // used as an offset only
  EXPECT_EQ(t.node(1).intrinsic[0], t.node(2).intrinsic[0]);

  const Tree dropped = canonical(t, UnusedShared::kDrop);
  EXPECT_EQ(names(dropped)[0], "r");
  EXPECT_EQ(names(dropped)[1], "zeta");
  EXPECT_EQ(dropped.params.size(), t.params.size() - 1);
  // Canonical form is a fixed point.
  const Tree again = canonical(t);
  EXPECT_EQ(names(again), names(t));
}

TEST(TreeBuilder, OperatorDefaults) {
  TreeBuilder b(3);
  const int x = b.leaf(PrimitiveType::kSphere, std::vector<Number>{1});
  const int y = b.leaf(PrimitiveType::kSphere, std::vector<Number>{1});
  const int z = b.leaf(PrimitiveType::kSphere, std::vector<Number>{1});
  const int w = b.leaf(PrimitiveType::kSphere, std::vector<Number>{1});
  const int unified =
      b.unified_logits(std::vector<Number>{0.1, 0.2, 0.3, 0.4}, std::nullopt, std::nullopt, {x, y});
  const int yager = b.op(OpKind::kIntersection, {z, w});
  b.logic(yager, logic::Family::kYager);
  const int diff = b.op(OpKind::kDifference, {unified, yager});
  b.complement(diff, logic::Complement::kSugeno);
  const Tree t = std::move(b).finish(diff, "built");

  const Node& u = t.node(1);
  ASSERT_TRUE(u.temperature && u.omega);
  EXPECT_EQ(t.params[*u.temperature].value, *fields::kTemperature.default_value);
  EXPECT_TRUE(t.params[*u.temperature].fixed);
  EXPECT_EQ(t.params[*u.omega].name, "root.children[0].omega");
  const Node& i = t.node(4);
  ASSERT_TRUE(i.logic.p.has_value());
  EXPECT_EQ(t.params[*i.logic.p].name, "root.children[1].p");
  EXPECT_EQ(t.params[*i.logic.p].value, *fields::logic_param(logic::Family::kYager).default_value);
  ASSERT_TRUE(t.node(0).complement.lambda.has_value());
  EXPECT_EQ(t.params[*t.node(0).complement.lambda].name, "root.complement.lambda");
}

// finish() validates: messages name the node path and field, as the reader's do.
TEST(TreeBuilder, ValidationNamesPaths) {
  {
    TreeBuilder b(3);
    const int a = b.leaf(PrimitiveType::kSphere, std::vector<Number>{1});
    const int c = b.leaf(PrimitiveType::kSphere, std::vector<Number>{-1});
    const int root = b.op(OpKind::kUnion, {a, c});
    EXPECT_EQ(finish_error(std::move(b), root),
              "built: root.children[1].radius: must be > 0 (got -1)");
  }
  {
    TreeBuilder b(3);
    const int a = b.leaf(PrimitiveType::kBox, std::vector<Number>{1, 2});  // size needs 3
    EXPECT_NE(finish_error(std::move(b), a).find("built: root"), std::string::npos);
  }
  {
    TreeBuilder b(3);
    const int a = b.leaf(PrimitiveType::kSphere, std::vector<Number>{1});
    b.leaf(PrimitiveType::kSphere, std::vector<Number>{1});  // never given a parent
    EXPECT_EQ(finish_error(std::move(b), a), "built: nodes[1]: is not reachable from the root");
  }
}

TEST(TreeBuilder, Misuse) {
  TreeBuilder b(2);
  const int a = b.leaf(PrimitiveType::kCircle, std::vector<Number>{1});
  const int c = b.leaf(PrimitiveType::kCircle, std::vector<Number>{1});
  const int u = b.op(OpKind::kUnion, {a, c});
  EXPECT_THROW(b.op(OpKind::kUnion, {a, c}), Error);               // a second parent
  EXPECT_THROW(b.translate(u, std::vector<Number>{0, 0}), Error);  // not a leaf
  EXPECT_THROW(b.logic(a, logic::Family::kGodel), Error);          // not an operator
  EXPECT_THROW(b.name(17, "x"), Error);
  EXPECT_THROW(b.op(OpKind::kUnified, {}), Error);
  EXPECT_THROW(b.shared("root2", 1), InputError);
  EXPECT_THROW(b.shared("2x", 1), InputError);
  b.shared("x", 1);
  EXPECT_THROW(b.shared("x", 2), InputError);
  EXPECT_THROW(TreeBuilder(4), InputError);
}

// Snapping rewrites unified operators and returns the canonical tree: the weights, the
// temperature and omega (and a shared parameter only they used) are gone, the children of
// "right minus left" are swapped.
TEST(TreeBuilder, SnapIsACanonicalRewrite) {
  TreeBuilder b(2);
  const ParamRef t = b.shared("t", 1000, true);
  const int x = b.leaf(PrimitiveType::kCircle, std::vector<Number>{1});
  const int y = b.leaf(PrimitiveType::kRectangle, std::vector<Number>{1, 2});
  // c = (0, 0, 0, 1): y \ x.
  const int root = b.unified(std::vector<Number>{0, 0, 0, 1}, {x, y});
  const int other = b.leaf(PrimitiveType::kCircle, std::vector<Number>{2});
  // sin(10 * 0.157) is about 1, the largest: union.
  const int top = b.unified_logits(std::vector<Number>{0, 0.157, 0, 0}, Number::shared(t),
                                   std::nullopt, {root, other});
  const Tree tree = std::move(b).finish(top, "built");
  const Tree s = snap_operators(tree);
  EXPECT_EQ(s.node(0).op, OpKind::kUnion);
  EXPECT_EQ(s.node(1).op, OpKind::kDifference);
  EXPECT_EQ(s.node(2).shape.type, PrimitiveType::kRectangle);  // swapped: y first
  EXPECT_FALSE(s.params.find("t").has_value());
  for (const Parameter& p : s.params.entries()) {
    EXPECT_EQ(p.name.find("logits"), std::string::npos) << p.name;
    EXPECT_EQ(p.name.find(".c["), std::string::npos) << p.name;
  }
  EXPECT_EQ(s.params.at(0).name, "root.children[0].children[0].size[0]");
  EXPECT_EQ(canonical(s).params.size(), s.params.size());
}

}  // namespace
}  // namespace fuzzycsg
