#pragma once
// Search over the types of a tree's unified operators ("--type-search-every N"), fuzzycsg's
// way of optimising the operator types of Liu et al.'s B_c when the temperature saturates the
// softmax (App. A: t = 1000, where dL/dc̃ is ~0 and gradient descent alone changes almost no
// type).
//
// B_c(x, y) is linear in c, and a unified operator's value enters the root affinely when every
// operator above it is bilinear (a unified or product-logic boolean). So one forward sweep and
// one light reverse sweep over a batch of points give, for every unified operator and each of
// its three other types, the exact change of the mean squared error if that operator alone
// changed type (Evaluator::edit_loss_changes). A type changes by swapping two entries of the
// operator's weights (its logits, or c itself): the one of the current type (the largest) and
// the one of the new type, so c is permuted whatever the temperature, and the Adam moments of
// the two entries are swapped with them.
//
// One search draws two fresh samples of the training distribution, one to choose switches and
// one to judge them. Each round takes the switches that lower the loss on the first sample,
// best first, keeping at most `max_switches` of them and never two on one path to the root
// (their effects would not add), and makes them together if that lowers the loss on the second
// sample; otherwise it tries the best switch alone, and stops when that does not help either.
// So a search never makes the fit worse on points it did not choose on.

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg {

struct TypeSearchOptions {
  std::size_t points = 8192;  // each of the two samples
  int rounds = 3;             // rounds of switches per search
  int max_switches = 32;      // switches made together in one round
  double min_gain = 1e-6;     // a switch, or a round, must lower the MSE by this much
  SamplingOptions sampling;   // the training distribution
};

struct TypeSearchReport {
  int operators = 0;                       // unified operators searched
  int proposed = 0;                        // switches that lowered the choosing sample's loss
  int switched = 0;                        // switches made
  int rounds = 0;                          // rounds run
  double loss_before = 0, loss_after = 0;  // on the judging sample
};

// The type index (0 intersection, 1 union, 2 x \ y, 3 y \ x: core/logic.hpp) that a unified
// node selects: the largest of its weights.
int unified_type(const Node& node, std::span<const double> params);

// The structure bit of every binary operator, from `types` (indexed like tree.nodes: the type
// index as above, -1 for nodes that are not operators to consider): whether its parent sees an
// intersection or the complement of one. A type is N^o(N^l(x) ∩ N^r(y)), N the complement
// (intersection (0, 0, 0), union (1, 1, 1), x \ y (0, 0, 1), y \ x (0, 1, 0)), which product
// logic satisfies exactly; the bit is o XOR the negation the parent applies to this input (none
// at the root). When every leaf's family holds the complements of its members (quadrics,
// conics, planes: sigmoid(-s q) = 1 - sigmoid(s q)), two type assignments with the same bits
// are the same family of functions and train alike, the rest of a type being a negation of
// leaves; so of the 4^(P-1) assignments of a full tree at most 2^(P-1) differ. Entries of
// non-operators are -1.
std::vector<int> structure_bits(const Tree& tree, std::span<const int> types);

// The unified operator's weights c at `params` (softmax(sin(ω c̃) t) for logits).
std::array<double, 4> unified_weights_at(const Node& node, std::span<const double> params);

// The change of (a, b, d) of B_c when entries i and j of c swap places.
std::array<double, 3> swap_delta(const std::array<double, 4>& c, int i, int j);

// Swaps entries i and j of a unified node's weights in `params` (and in `adam_m`, `adam_v`
// when not empty).
void swap_unified_entries(const Node& node, int i, int j, std::span<double> params,
                          std::span<double> adam_m, std::span<double> adam_v);

// One search (see the header comment) on `model`'s binary unified operators whose weights are
// free and used by no other operator, in place on `params` and the Adam moments. `evaluator`
// must be compiled from `model`.
TypeSearchReport search_operator_types(const Tree& model, const Evaluator& evaluator,
                                       const Target& target, std::span<double> params,
                                       std::span<double> adam_m, std::span<double> adam_v,
                                       const TypeSearchOptions& options, Rng& rng);

}  // namespace fuzzycsg
