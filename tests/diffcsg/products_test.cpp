// A scene's tree as a sum of products: the same solid as the tree for every inside/outside
// assignment of random trees, the form product-at-a-time renderers need, and the bound on the
// expansion.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diffcsg/products.hpp"

namespace fuzzycsg::diffcsg {
namespace {

// A scene with `primitives` leaves and no meshes (only the tree matters here).
struct TreeBuilder {
  Scene scene;
  int leaf(int p) {
    scene.nodes.push_back({CsgNode::Kind::kPrimitive, p, {}});
    return static_cast<int>(scene.nodes.size()) - 1;
  }
  int op(CsgNode::Kind kind, std::vector<int> children) {
    scene.nodes.push_back({kind, -1, std::move(children)});
    return static_cast<int>(scene.nodes.size()) - 1;
  }
};

Scene random_tree(std::mt19937_64& rng, int primitives) {
  TreeBuilder b;
  b.scene.primitives.resize(static_cast<std::size_t>(primitives));
  // Each primitive once, combined pairwise (or in threes) by random operators.
  std::vector<int> pool;
  for (int p = 0; p < primitives; ++p) pool.push_back(b.leaf(p));
  while (pool.size() > 1) {
    std::shuffle(pool.begin(), pool.end(), rng);
    const int kind = static_cast<int>(rng() % 3);
    if (kind == 2 || pool.size() < 3) {
      const int x = pool.back();
      pool.pop_back();
      const int y = pool.back();
      pool.pop_back();
      pool.push_back(b.op(kind == 0   ? CsgNode::Kind::kUnion
                          : kind == 1 ? CsgNode::Kind::kIntersection
                                      : CsgNode::Kind::kDifference,
                          {x, y}));
    } else {
      std::vector<int> c(pool.end() - 3, pool.end());
      pool.resize(pool.size() - 3);
      pool.push_back(
          b.op(kind == 0 ? CsgNode::Kind::kUnion : CsgNode::Kind::kIntersection, std::move(c)));
    }
  }
  b.scene.root = pool.front();
  return b.scene;
}

TEST(DiffcsgProducts, RandomTreesAreTheSameSolidForEveryAssignment) {
  std::mt19937_64 rng(11);
  int checked = 0, multi = 0;
  for (int k = 0; k < 300; ++k) {
    const int primitives = 2 + static_cast<int>(rng() % 7);
    const Scene scene = random_tree(rng, primitives);
    const std::vector<Product> products = sum_of_products(scene);
    multi += products.size() > 1;
    for (const Product& p : products) {
      ASSERT_FALSE(p.empty());
      EXPECT_FALSE(p.front().subtracted) << "a product must intersect something first";
      for (std::size_t t = 1; t < p.size(); ++t) {
        EXPECT_TRUE(p[t - 1].subtracted < p[t].subtracted ||
                    (p[t - 1].subtracted == p[t].subtracted && p[t - 1].primitive < p[t].primitive))
            << "terms out of order";
      }
    }
    std::vector<std::uint8_t> inside(static_cast<std::size_t>(primitives));
    for (unsigned mask = 0; mask < (1u << primitives); ++mask) {
      for (int p = 0; p < primitives; ++p) inside[static_cast<std::size_t>(p)] = (mask >> p) & 1;
      ASSERT_EQ(products_contain(products, inside), scene.solid(inside))
          << "tree " << k << ", inside mask " << mask;
      ++checked;
    }
  }
  EXPECT_GT(checked, 10000);
  EXPECT_GT(multi, 100) << "too few trees expand to more than one product";
}

TEST(DiffcsgProducts, AUnionLessAUnionIsOneProductPerPositivePrimitive) {
  // OpenSCAD's example003: four boxes less three bars.
  TreeBuilder b;
  b.scene.primitives.resize(7);
  std::vector<int> plus, minus;
  for (int p = 0; p < 4; ++p) plus.push_back(b.leaf(p));
  for (int p = 4; p < 7; ++p) minus.push_back(b.leaf(p));
  b.scene.root = b.op(CsgNode::Kind::kDifference,
                      {b.op(CsgNode::Kind::kUnion, plus), b.op(CsgNode::Kind::kUnion, minus)});
  const std::vector<Product> products = sum_of_products(b.scene);
  ASSERT_EQ(products.size(), 4u);
  for (int p = 0; p < 4; ++p) {
    const Product expect{{p, false}, {4, true}, {5, true}, {6, true}};
    EXPECT_EQ(products[static_cast<std::size_t>(p)], expect) << p;
  }
}

TEST(DiffcsgProducts, AbsorptionAndContradictionsAreLeftOut) {
  TreeBuilder b;
  b.scene.primitives.resize(2);
  const int a = b.leaf(0), c = b.leaf(1);
  // a ∪ (a ∩ c) = a;  (a - c) ∩ c = ∅.
  b.scene.root = b.op(CsgNode::Kind::kUnion, {a, b.op(CsgNode::Kind::kIntersection, {a, c})});
  EXPECT_EQ(sum_of_products(b.scene), (std::vector<Product>{{{0, false}}}));
  b.scene.root = b.op(CsgNode::Kind::kIntersection, {b.op(CsgNode::Kind::kDifference, {a, c}), c});
  EXPECT_TRUE(sum_of_products(b.scene).empty());
}

TEST(DiffcsgProducts, AnExpansionTooLargeIsRefused) {
  // x - ((a1 ∩ b1) ∪ ... ∪ (a8 ∩ b8)) has 2^8 products of 9 terms.
  TreeBuilder b;
  b.scene.primitives.resize(17);
  std::vector<int> pairs;
  for (int k = 0; k < 8; ++k) {
    pairs.push_back(b.op(CsgNode::Kind::kIntersection, {b.leaf(1 + 2 * k), b.leaf(2 + 2 * k)}));
  }
  b.scene.root = b.op(CsgNode::Kind::kDifference, {b.leaf(0), b.op(CsgNode::Kind::kUnion, pairs)});
  EXPECT_EQ(sum_of_products(b.scene).size(), 256u);
  try {
    sum_of_products(b.scene, 1000);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("more than 1000 terms"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fuzzycsg::diffcsg
