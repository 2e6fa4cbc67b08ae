#pragma once
// Bounds of a tree's occupancy over an axis-aligned box, by interval arithmetic on the tree:
// the meshing of mesh.hpp evaluates the tree only in the boxes where the 0.5 level can lie.
//
// Every bound is conservative (the occupancy of every point of the box lies in it):
// - leaves with an exact Euclidean signed distance (PrimitiveInfo::exact_distance) are
//   1-Lipschitz in the world frame (placement is an isometry times a scale s applied as
//   s f(p / s)), so f lies within f(centre) +- the box's half-diagonal;
// - quadrics by their centred form f(c + d) = f(c) + grad f(c) . d + d^T A d, each term bounded
//   over |d_i| <= h_i (the box mapped to the leaf's frame when it is placed);
// - the ellipsoid (an approximate distance) and the MLP are not bounded: [0, 1];
// - steps are non-increasing in f; unions and intersections of every logic family are
//   non-decreasing in both arguments and differences non-decreasing in the first, non-increasing
//   in the second (checked for every family by sampling in tests/mesh/bounds_test.cpp), except
//   Li & Tian's hat-AND, which is not monotone and is bounded by [0, 1]; the unified operator
//   B_c is bilinear, so its extremes over a box lie at the corners;
// - a spline node is a convex combination of its children; over the box each weight lies in
//   the product of the axes' basis ranges (0 where a child's basis vanishes), so the node is
//   bounded by the extremes of such combinations of its children's bounds (within their hull).

#include <memory>
#include <span>
#include <vector>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg {

struct Interval {
  double lo = 0.0, hi = 1.0;
  bool contains(double v) const { return lo <= v && v <= hi; }
};

// The tree with its parameter values resolved once (leaf coefficients and frames, operator
// weights), bounded over many boxes.
class BoundsProgram {
 public:
  BoundsProgram(const Tree& tree, std::span<const double> params);
  ~BoundsProgram();
  BoundsProgram(BoundsProgram&&) noexcept;
  BoundsProgram& operator=(BoundsProgram&&) noexcept;

  // Bounds of the root's occupancy over the box [lo, hi] (dim coordinates each); when
  // `per_node` is given it receives every node's bounds, indexed like Tree::nodes.
  Interval bound(const double* lo, const double* hi,
                 std::vector<Interval>* per_node = nullptr) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One box: BoundsProgram(tree, params).bound(lo, hi).
Interval occupancy_bounds(const Tree& tree, std::span<const double> params, const double* lo,
                          const double* hi);

}  // namespace fuzzycsg
