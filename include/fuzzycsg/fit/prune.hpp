#pragma once
// After training and snapping (core/snap.hpp; Liu et al. 2024 App. A): remove redundant nodes
// (Tilove 1984, generalised to fuzzy occupancy by a mean-squared threshold), visiting nodes in
// post-order.

#include <cstddef>
#include <span>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg {

struct PruneOptions {
  double threshold = 1e-3;  // mean squared occupancy difference up to which a node is redundant
  int threads = 0;          // 0: all hardware threads
  // After the redundant nodes are gone, at most this many primitives are kept (0: no limit):
  // see prune().
  int max_primitives = 0;
};

struct PruneReport {
  int primitives_before = 0, primitives_after = 0;
  int operators_before = 0, operators_after = 0;
};

// Removes redundant nodes of a tree without unified operators (snap first; throws Error
// otherwise). Nodes are visited in post-order, each decided on its children as already pruned:
// - a node (leaf or operator) whose output is within the threshold (mean squared, over
//   `points`) of all 0 (all 1) becomes empty (full), and its parent simplifies it away:
//   A | empty = A, A | full = full, A & full = A, A & empty = empty, A \ empty = A,
//   A \ full = empty \ B = empty, full \ B = C(B) (a complement node with the difference's C),
//   C(empty) = full, C(full) = empty;
// - an operator whose output is within the threshold of one child's is replaced by the closer
//   child (ties: the left one): the other child is W- or empty-redundant. An n-ary union or
//   intersection drops, one at a time, the child whose removal changes its output least, while
//   the output stays within the threshold of that with all its children.
// Each removal is judged locally, so the changes of many add up: on large trees the pruned
// output may differ from the original by a few times the threshold.
// With options.max_primitives > 0, a tree that still has more primitives is then reduced one
// edit at a time, greedily: among the edits that replace a binary union, intersection or
// difference by one of its children or by the empty set (which its parent then simplifies
// away), the one that adds the least to the mean squared difference from the input tree's
// output at the points, per primitive it removes (counting no more than are still to go), is
// made, until the limit is met. For trees of product-logic booleans and standard complements
// (snapped unified trees, the product baseline) every edit's effect comes exactly from one
// forward and one reverse sweep (Evaluator::edit_loss_changes); other trees evaluate each
// candidate. Threshold pruning alone removes whole subtrees as soon as the threshold allows,
// so raising the threshold to reach a size can collapse a tree far below it; this does not.
// A whole tree that amounts to a constant becomes one crisp plane (half-plane in 2D) that is
// exactly that constant over the domain and the points: a tree has at least one node, and no
// leaf of a fuzzy tree need be close to 0 or 1. Parameters of removed nodes (and shared
// parameters no surviving node uses) are dropped, values and fixed flags kept; the result is
// valid and its parameter names follow the new node paths, as if written and read back.
Tree prune(const Tree& tree, std::span<const float> points, const PruneOptions& options = {},
           PruneReport* report = nullptr);

}  // namespace fuzzycsg
