#include "fuzzycsg/core/builders.hpp"

#include <gtest/gtest.h>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg {
namespace {

TEST(Builders, FullBinaryTreeShapeAndParameters) {
  FullTreeOptions o;
  o.leaves = 16;
  o.seed = 4;
  const Tree t = make_full_binary_tree(o);
  EXPECT_NO_THROW(validate(t, "built"));
  const TreeCounts c = count(t);
  EXPECT_EQ(c.primitives, 16);
  EXPECT_EQ(c.operators, 15);
  EXPECT_EQ(c.depth, 4);
  // 11 per quadric leaf (10 coefficients + sharpness); 4 logits + fixed t, omega per operator.
  EXPECT_EQ(c.parameters, 16 * 11 + 15 * 6);
  EXPECT_EQ(c.free_parameters, 16 * 11 + 15 * 4);
  for (const Parameter& p : t.params.entries()) {
    if (p.name.ends_with("sharpness") || p.fixed) continue;
    EXPECT_LE(std::abs(p.value), 0.5) << p.name;
  }
  ASSERT_TRUE(
      t.params.find("root.children[0].children[1].children[0].children[0].coefficients[9]"));
  ASSERT_TRUE(t.params.find("root.logits[3]"));
}

TEST(Builders, SeedsAreReproducibleAndDistinct) {
  FullTreeOptions o;
  o.leaves = 8;
  o.seed = 1;
  const auto a = make_full_binary_tree(o).params.values();
  const auto b = make_full_binary_tree(o).params.values();
  o.seed = 2;
  const auto c = make_full_binary_tree(o).params.values();
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(Builders, FixedBooleanModesAndFamilies) {
  FullTreeOptions o;
  o.leaves = 32;
  o.ops = OperatorMode::kGodel;
  o.family = PrimitiveType::kBox;
  const Tree t = make_full_binary_tree(o);
  EXPECT_NO_THROW(validate(t, "built"));
  int ops = 0;
  for (const Node& n : t.nodes) {
    if (n.kind != NodeKind::kOperator) {
      EXPECT_EQ(n.placement.translate.size(), 3u);
      EXPECT_EQ(n.placement.rotate.size(), 3u);
      continue;
    }
    ++ops;
    EXPECT_EQ(n.logic.family, logic::Family::kGodel);
    EXPECT_NE(n.op, OpKind::kUnified);
  }
  EXPECT_EQ(ops, 31);
}

TEST(Builders, RejectsBadOptions) {
  FullTreeOptions o;
  o.leaves = 12;
  EXPECT_THROW(make_full_binary_tree(o), InputError);
  o.leaves = 8;
  o.family = PrimitiveType::kCircle;
  EXPECT_THROW(make_full_binary_tree(o), InputError);
  o.dim = 2;
  EXPECT_NO_THROW(make_full_binary_tree(o));
  o.family = PrimitiveType::kPolygon;
  EXPECT_THROW(make_full_binary_tree(o), InputError);
}

}  // namespace
}  // namespace fuzzycsg
