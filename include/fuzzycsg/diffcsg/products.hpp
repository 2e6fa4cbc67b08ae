#pragma once
// A scene's tree as a union of products (Goldfeather normalisation, notes §1.2): each product
// intersects some primitives and subtracts others, the form product-at-a-time renderers
// (DiffCSG's peeling, OpenCSG) draw. The union of the products is the same solid as the tree,
// for every assignment of inside/outside to the primitives.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzzycsg/diffcsg/scene.hpp"

namespace fuzzycsg::diffcsg {

struct ProductTerm {
  int primitive = 0;
  bool subtracted = false;
  bool operator==(const ProductTerm&) const = default;
};

// The intersected terms first, then the subtracted ones, each in increasing primitive order;
// every product has at least one intersected term.
using Product = std::vector<ProductTerm>;

// Products that are empty whatever the primitives (one both intersected and subtracted) are
// left out, and so are duplicates and products that contain another (absorption). Throws
// InputError when a step of the expansion would hold more than `max_terms` terms (a difference
// of intersections grows exponentially).
std::vector<Product> sum_of_products(const Scene& scene, std::size_t max_terms = 1u << 16);

// Whether a point inside exactly the primitives p with inside[p] != 0 is in the union of
// `products`.
bool products_contain(const std::vector<Product>& products,
                      const std::vector<std::uint8_t>& inside);

}  // namespace fuzzycsg::diffcsg
