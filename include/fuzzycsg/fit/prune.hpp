#pragma once
// After training (Liu et al. 2024 App. A): snap every unified operator B_c to the crisp boolean
// its weights are closest to, then remove redundant nodes (Tilove 1984, generalised to fuzzy
// occupancy by a mean-squared threshold), visiting nodes in post-order.

#include <cstddef>
#include <span>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg {

// The boolean a unified operator's weights c select: argmax of c. Index order as in eq. 12:
// 0 intersection, 1 union, 2 left minus right, 3 right minus left.
int snapped_operator(const Tree& tree, int node);

// A copy of `tree` where every unified operator is replaced by product-logic union /
// intersection / difference (children swapped for "right minus left"). Other nodes unchanged.
Tree snap_operators(const Tree& tree);

struct PruneOptions {
  double threshold = 1e-3;  // mean squared occupancy difference below which a node is redundant
  int threads = 0;
};

struct PruneReport {
  int primitives_before = 0, primitives_after = 0;
  int operators_before = 0, operators_after = 0;
};

// Removes redundant nodes of a tree without unified operators (snap first): an operator whose
// output differs from one child's by less than the threshold (mean squared, over `points`)
// is replaced by that child (the other child is W- or empty-redundant); a subtree whose output
// is everywhere within the threshold of 0 (or 1) becomes empty (full) and is simplified away
// by its parent. Parameters of removed nodes are dropped; the result is valid and its parameter
// names follow the new node paths.
Tree prune(const Tree& tree, std::span<const float> points, const PruneOptions& options = {},
           PruneReport* report = nullptr);

}  // namespace fuzzycsg
