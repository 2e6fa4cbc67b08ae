#pragma once
// A tree simplified for one box (after Keeter 2020, "Massively parallel rendering of complex
// closed-form implicit surfaces", interval tape pruning): a subtree that cannot change the
// root by more than a little over the box (its bounds are narrow, or its ancestors damp it: an
// intersection with a partner near 0, a union with one near 1) becomes a constant leaf, and an
// operator one of whose children is such a constant and that then passes its other child
// through (a union with ~0, an intersection with ~1) is replaced by that child. Inside the box
// the simplified tree differs from the tree by at most `error`.
//
// The bound on the error adds the error of each replacement times the root's sensitivity to
// it, which holds when every operator is Lipschitz in each argument with the constants used:
// product-logic and Gödel booleans with the standard complement, Łukasiewicz, the unified operator
// (barycentric weights), standard complements, spline nodes (a convex combination). For other
// trees reducible() is false and meshing evaluates the whole tree.

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "bounds.hpp"
#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg::mesh_detail {

bool reducible(const Tree& tree);

struct Reduced {
  Tree tree;         // parameters all fixed, values resolved
  double error = 0;  // bound on |simplified - original| inside the box
  int leaves = 0;    // leaves of the simplified tree (constants included)
};

// A subtree is replaced when its bounds' half-width, times the sensitivity of the root to it
// over the box (the product of the bounds of |d parent / d child| along its path), is at most
// `tau`; each replacement adds that much to `error`.
class Reducer {
 public:
  Reducer(const Tree& tree, std::span<const double> params);
  ~Reducer();
  // `bounds` are the per-node bounds over the box (BoundsProgram::bound's per_node). When the
  // simplified tree would have more than `max_leaves` leaves it is not built: `tree.root` is
  // -1 and `leaves` says how many it would have. `lo`, `hi` (optional) are the box: a spline
  // node then drops the children whose basis function vanishes on it.
  Reduced reduce(const std::vector<Interval>& bounds, double tau, int max_leaves,
                 const double* lo = nullptr, const double* hi = nullptr) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace fuzzycsg::mesh_detail
