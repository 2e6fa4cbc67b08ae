#include "fuzzycsg/diffcsg/products.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cstdint>
#include <iterator>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::diffcsg {

namespace {

// A literal is 2 p for "inside primitive p" and 2 p + 1 for "outside"; a product is a sorted
// set of literals, a sum a list of products. The empty product is everything.
using Literals = std::vector<int>;
using Sum = std::vector<Literals>;

class Expander {
 public:
  Expander(const Scene& scene, std::size_t max_terms) : scene_(scene), max_terms_(max_terms) {}

  Sum expand(int node) {
    const CsgNode& n = scene_.nodes[static_cast<std::size_t>(node)];
    switch (n.kind) {
      case CsgNode::Kind::kPrimitive:
        return {{2 * n.primitive}};
      case CsgNode::Kind::kUnion: {
        Sum out;
        for (const int c : n.children) {
          Sum s = expand(c);
          out.insert(out.end(), s.begin(), s.end());
        }
        return simplify(std::move(out));
      }
      case CsgNode::Kind::kIntersection: {
        Sum out{{}};
        for (const int c : n.children) out = intersect(out, expand(c));
        return out;
      }
      case CsgNode::Kind::kDifference:
        return intersect(expand(n.children[0]), complement(expand(n.children[1])));
    }
    return {};
  }

 private:
  // X - (Y1 ∪ ... ∪ Yn) = X ∩ ¬Y1 ∩ ... ∩ ¬Yn, ¬(l1 ∩ ... ∩ lk) = ¬l1 ∪ ... ∪ ¬lk.
  Sum complement(const Sum& s) {
    Sum out{{}};
    for (const Literals& p : s) {
      Sum negated;
      for (const int l : p) negated.push_back({l ^ 1});
      out = intersect(out, negated);
    }
    return out;
  }

  Sum intersect(const Sum& a, const Sum& b) {
    Sum out;
    std::size_t terms = 0;
    for (const Literals& x : a) {
      for (const Literals& y : b) {
        Literals m;
        std::set_union(x.begin(), x.end(), y.begin(), y.end(), std::back_inserter(m));
        m.erase(std::unique(m.begin(), m.end()), m.end());
        bool empty = false;  // p and not p
        for (std::size_t k = 1; k < m.size() && !empty; ++k) empty = (m[k] ^ 1) == m[k - 1];
        if (empty) continue;
        terms += m.size();
        if (terms > max_terms_) {
          throw InputError(
              fmt::format("sum of products: the tree expands to more than {} terms", max_terms_));
        }
        out.push_back(std::move(m));
      }
    }
    return simplify(std::move(out));
  }

  // Drops duplicates and products that contain another product (a ∪ (a ∩ b) = a).
  static Sum simplify(Sum s) {
    std::sort(s.begin(), s.end(), [](const Literals& x, const Literals& y) {
      return x.size() != y.size() ? x.size() < y.size() : x < y;
    });
    s.erase(std::unique(s.begin(), s.end()), s.end());
    Sum out;
    for (Literals& p : s) {
      const bool absorbed = std::any_of(out.begin(), out.end(), [&](const Literals& q) {
        return std::includes(p.begin(), p.end(), q.begin(), q.end());
      });
      if (!absorbed) out.push_back(std::move(p));
    }
    return out;
  }

  const Scene& scene_;
  std::size_t max_terms_;
};

}  // namespace

std::vector<Product> sum_of_products(const Scene& scene, std::size_t max_terms) {
  if (scene.root < 0) return {};
  const Sum sum = Expander(scene, max_terms).expand(scene.root);
  std::vector<Product> out;
  for (const Literals& p : sum) {
    Product product;
    for (const bool subtracted : {false, true}) {
      for (const int l : p) {
        if (((l & 1) != 0) == subtracted) product.push_back({l / 2, subtracted});
      }
    }
    // Bounded solids: every product of a tree of primitives intersects one of them.
    FUZZYCSG_ASSERT(!product.empty() && !product.front().subtracted);
    out.push_back(std::move(product));
  }
  return out;
}

bool products_contain(const std::vector<Product>& products,
                      const std::vector<std::uint8_t>& inside) {
  return std::any_of(products.begin(), products.end(), [&](const Product& p) {
    return std::all_of(p.begin(), p.end(), [&](const ProductTerm& t) {
      return (inside[static_cast<std::size_t>(t.primitive)] != 0) != t.subtracted;
    });
  });
}

}  // namespace fuzzycsg::diffcsg
