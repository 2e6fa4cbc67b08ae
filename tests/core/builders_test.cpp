#include "fuzzycsg/core/builders.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

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

// The share of each operator type (argmax of sin(ω c̃)): union, intersection, A - B, B - A.
std::array<double, 4> type_shares(const FullTreeOptions& o) {
  const Tree t = make_full_binary_tree(o);
  std::array<double, 4> share{};
  int ops = 0;
  for (const Node& n : t.nodes) {
    if (n.kind != NodeKind::kOperator) continue;
    EXPECT_EQ(n.op, OpKind::kUnified);
    int best = 0;
    for (int i = 0; i < 4; ++i) {
      const double v = t.params.at(n.unified[i].index).value;
      EXPECT_LE(std::abs(v), o.init_range);
      if (std::sin(o.omega * v) > std::sin(o.omega * t.params.at(n.unified[best].index).value)) {
        best = i;
      }
    }
    share[best] += 1.0;
    ++ops;
  }
  for (double& s : share) s /= ops;
  return share;
}

TEST(Builders, OperatorInitDrawsTheTypesAsDocumented) {
  FullTreeOptions o;
  o.leaves = 4096;  // 4095 operators: a share's standard error is below 0.008
  o.seed = 3;
  const std::array<double, 4> uniform = type_shares(o);
  for (double s : uniform) EXPECT_NEAR(s, 0.25, 0.03);
  o.op_init = OperatorInit::kBalanced;
  const std::array<double, 4> balanced = type_shares(o);
  EXPECT_NEAR(balanced[0], 1.0 / 3.0, 0.03);
  EXPECT_NEAR(balanced[1], 1.0 / 3.0, 0.03);
  EXPECT_NEAR(balanced[2], 1.0 / 6.0, 0.03);
  EXPECT_NEAR(balanced[3], 1.0 / 6.0, 0.03);
  // Degenerate settings end (ω = 0: every draw has the same argmax).
  o.omega = 0.0;
  o.leaves = 64;
  EXPECT_NO_THROW(make_full_binary_tree(o));
}

TEST(Builders, UnionIntersectionOperatorsPinTheirDifferences) {
  FullTreeOptions o;
  o.leaves = 4096;
  o.seed = 3;
  o.op_types = OperatorTypes::kUnionIntersection;
  const std::array<double, 4> uniform = type_shares(o);
  EXPECT_NEAR(uniform[0], 0.5, 0.03);
  EXPECT_NEAR(uniform[1], 0.5, 0.03);
  EXPECT_EQ(uniform[2] + uniform[3], 0.0);
  o.op_init = OperatorInit::kBalanced;
  const std::array<double, 4> balanced = type_shares(o);
  EXPECT_NEAR(balanced[0], 0.5, 0.03);
  EXPECT_EQ(balanced[2] + balanced[3], 0.0);
  o.leaves = 8;
  const Tree t = make_full_binary_tree(o);
  for (const Node& n : t.nodes) {
    if (n.kind != NodeKind::kOperator) continue;
    for (int i = 0; i < 4; ++i) {
      const Parameter& p = t.params[n.unified[static_cast<std::size_t>(i)]];
      EXPECT_EQ(p.fixed, i >= 2) << p.name;
      if (i >= 2) {
        EXPECT_NEAR(std::sin(o.omega * p.value), -1.0, 1e-12) << p.name;
      }
    }
  }
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
  o.dim = 3;
  o.family = PrimitiveType::kExtrude;
  try {
    make_full_binary_tree(o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "make_full_binary_tree: the extrude family is not supported");
  }
}

}  // namespace
}  // namespace fuzzycsg
