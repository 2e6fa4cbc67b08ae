#pragma once
// Snapping (Liu et al. 2024 App. A): every unified operator B_c becomes the crisp boolean its
// weights are closest to. A rewrite of the tree, used after training, by pruning, by the
// renderers and by differentiable refinement.

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg {

// The boolean a unified operator's weights c select: argmax of c. Index order as in eq. 12:
// 0 intersection, 1 union, 2 left minus right, 3 right minus left.
int snapped_operator(const Tree& tree, int node);

// A copy of `tree` where every unified operator is replaced by product-logic union /
// intersection / difference (children swapped for "right minus left"), which equals B_c where
// c is one-hot. Other nodes are unchanged; the weights, temperatures and omegas are dropped from
// the table (and shared parameters only they used), and the tree is in canonical form
// (core/tree_builder.hpp).
Tree snap_operators(const Tree& tree);

}  // namespace fuzzycsg
