#pragma once
// Trees of solids: a union of chains built as a tree (crisp, or soft with unified operators
// for refinement), a tree of solids rebuilt crisp in other coordinates, and a tree's count of
// wrong cells on a grid.

#include <cstdint>
#include <span>
#include <vector>

#include "convert/search.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg::convert {

struct BuildOptions {
  double sharpness = 0.0;  // > 0: sigmoid steps of this sharpness; 0: crisp steps
  // Unified operators (Liu et al. 2024) whose logits select the chain's boolean with weight
  // softmax(sin(omega l) t), at temperature t and omega 10; else plain booleans.
  bool unified = false;
  double temperature = 3.0;
};

// ((c1 ∪ c2) ∪ c3) ... of the chains, each chain left-deep: ((s1 op2 s2) op3 s3) ...
Tree chains_tree(const std::vector<Chain>& chains, const BuildOptions& options = {});

// A tree whose leaves are solids (solid_of_leaf) and whose operators are booleans or unified
// operators, rebuilt with each leaf moved by `m`, crisp steps and unified operators snapped.
// Throws Error for a leaf that is not a solid.
Tree crisp_tree(const Tree& tree, const Similarity& m = {});

// The structure of `tree` (operators snapped to booleans) with the given solids as its leaves,
// in pre-order, crisp, over `domain`. Throws Error when the counts differ.
Tree tree_with_solids(const Tree& tree, std::span<const Solid> solids, const Domain& domain);

// The solids of a tree's leaves, in pre-order.
std::vector<Solid> tree_solids(const Tree& tree);

// The counted cells of a grid on which the tree's occupancy (>= 0.5) differs from the label.
long long tree_error(const Tree& tree, const LabelGrid& grid, int threads = 0);

// tree_error for many trees on one grid (the cells' centres computed once), or on any labelled
// points.
class GridScorer {
 public:
  explicit GridScorer(const LabelGrid& grid);
  // Points (x, y, z each) with their labels (0 outside, 1 inside, 2 not counted).
  GridScorer(std::vector<float> points, std::vector<std::uint8_t> labels);
  long long error(const Tree& tree, int threads = 0) const;
  std::size_t inside() const;  // points labelled 1

 private:
  std::vector<float> points_;
  std::vector<std::uint8_t> labels_;
};

// A scorer at `n` uniform random points over the grid's box, labelled by the target. Unlike the
// cells' centres, these do not judge a change smaller than a cell by aliasing (a face moved
// across a whole layer of centres at once).
GridScorer sample_scorer(const Target& target, const LabelGrid& grid, std::size_t n,
                         std::uint64_t seed);

}  // namespace fuzzycsg::convert
