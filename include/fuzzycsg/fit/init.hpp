#pragma once
// Starting points for inverse CSG that look at the target, and re-seeding of primitives that
// stopped contributing. Liu et al. (App. A) draw every parameter from U[-0.5, 0.5]; these are
// fuzzycsg's additions, measured against that in docs/results.md.
//
// Initialisation from the target, "--init balls": the target's interior is covered greedily
// by balls — the largest ball that fits inside, then the largest whose centre no earlier ball
// covers, and so on — with each ball's radius the distance from its centre to the nearest of
// many boundary samples. Leaf i of the full binary tree becomes ball i, the balls ordered by a
// recursive median split so that sibling subtrees are neighbours in space, and every unified
// operator leans to union (weight about 0.9 at the starting temperature, so its type can still
// change). The tree starts as a union of balls inside the shape instead of random quadrics.
// "--init surface": every quadric leaf is a random quadric through a random boundary point of
// the target, with the outward normal there as its gradient; operators stay random.
//
// Re-seeding ("--reseed-every N"): every N steps, leaves that pruning would remove (replacing
// one by a constant changes the output by less than the prune threshold) and that are not
// masked by their ancestors are moved, one at a time, to where the model is wrong: a ball at a
// point the model misses, a ball or (quadrics) everything but a ball at a point it covers
// wrongly, or a quadric through the boundary point nearest to either. A move is kept only if
// it lowers the loss on a fresh sample of the training distribution, so re-seeding never makes
// the fit worse there.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg {

struct Ball {
  std::array<double, 3> center{};  // the first dim entries are used
  double radius = 0.0;
};

// Distance to the target's boundary, approximated by the distance to the nearest of `samples`
// boundary samples (a k-d tree over them).
class BoundaryDistance {
 public:
  BoundaryDistance(const Target& target, std::size_t samples, Rng& rng);
  ~BoundaryDistance();
  BoundaryDistance(const BoundaryDistance&) = delete;
  BoundaryDistance& operator=(const BoundaryDistance&) = delete;

  int dim() const;
  double operator()(const float* point) const;
  // The nearest boundary sample, its position and its outward normal.
  std::size_t nearest(const float* point) const;
  const float* point(std::size_t i) const;
  const float* normal(std::size_t i) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Up to `count` balls inside the target, greedily (see the header comment), from `candidates`
// uniformly drawn interior points. Fewer when the target's interior yields fewer candidates.
std::vector<Ball> cover_with_balls(const Target& target, const BoundaryDistance& distance,
                                   int count, Rng& rng, std::size_t candidates = 20000);

// Orders balls so that each half, quarter, ... of the list is a compact group in space: the
// leaves of each subtree of a full binary tree are neighbours.
void order_for_tree(std::vector<Ball>& balls, int dim);

// Sets the parameters (in `params`, the tree's table order) of primitive node `node` so that it
// is `ball` (inside = true) or everything outside it (inside = false), with the occupancy
// rising from 0.5 on the sphere to about 1 - e^{-slope d} at depth d. Quadrics take both
// forms; sphere, box, cylinder, ellipsoid, capsule, circle, rectangle and ellipse take only
// inside = true (the largest of their shape centred in the ball). Returns false, changing
// nothing, for other families or forms.
bool set_leaf_to_ball(const Tree& tree, int node, const Ball& ball, bool inside, double slope,
                      std::span<double> params);

// Leaves of a tree in left-to-right order (node indices).
std::vector<int> leaves_in_order(const Tree& tree);

struct TargetInitOptions {
  double temperature = 10.0;  // the temperature of the unified operators at the first step
  double union_weight = 0.9;  // the weight of union at that temperature
  double slope = 20.0;        // see set_leaf_to_ball
  std::size_t candidates = 20000;
  std::size_t boundary_samples = 50000;
  std::uint64_t seed = 0;
};

// Initialisation from the target (see the header comment), in place on the tree's parameter
// values; fixed intersections and differences (product or Gödel trees) become unions. Leaves of
// a family that cannot be a ball keep their values. Returns the number of leaves set; throws
// InputError when no point inside the target is found.
int initialise_from_target(Tree& tree, const Target& target, const TargetInitOptions& options);

// Sets quadric leaf `node` to a random quadric through `point` whose gradient there is `normal`
// (unit, outward): f(x) = x^T A x + b.x + c with the entries of A ~ U[-curvature, curvature].
// The sharpness becomes `slope` (the slope of the occupancy across the surface at the point).
// Returns false, changing nothing, for other families.
bool set_leaf_through_point(const Tree& tree, int node, const float* point, const float* normal,
                            double curvature, double slope, Rng& rng, std::span<double> params);

struct SurfaceInitOptions {
  double curvature = 0.5;  // the paper's U[-0.5, 0.5] for the quadratic part
  double slope = 1.0;      // the quadrics' default sharpness
  std::uint64_t seed = 0;
};

// Initialisation on the surface: every quadric leaf becomes a random quadric through a random
// boundary point of the target, oriented by its normal; operators keep their random values.
// Returns the number of leaves set.
int initialise_on_surface(Tree& tree, const Target& target, const SurfaceInitOptions& options);

// The parameter indices of a primitive node (intrinsic, placement, step).
std::vector<std::size_t> leaf_parameters(const Node& node);

// Moves a ball's centre away from the nearest boundary sample while that makes it larger (a
// walk towards the medial axis, on the side of the boundary the centre is on), within
// [-1, 1]^dim; the radius becomes the distance to the boundary there.
void grow_ball(Ball& ball, const BoundaryDistance& distance, int steps = 24);

// Sets leaf `node` to a constant: empty (full = false) or everything (full = true). Quadrics
// take both; families with a translation take only empty (moved far away). Returns false,
// changing nothing, otherwise.
bool set_leaf_constant(const Tree& tree, int node, bool full, std::span<double> params);

struct ReseedOptions {
  std::size_t points = 8192;     // fresh samples (near the surface and uniform) judging it all
  double near_distance = 0.1;    // of those samples
  double threshold = 1e-3;       // dead: replacing the leaf by a constant changes less (MSE)
  std::size_t max_tested = 256;  // leaves tested per round (at random)
  int max_leaves = 32;           // dead leaves tried per round, in random order, of those
  double masked = 1e-7;          // that emptying or filling changes by this (others are masked)
  double slope = 20.0;           // of ball moves
  double patch_slope = 5.0;      // of surface-patch moves
  double curvature = 0.5;        // of surface-patch moves
  double min_radius = 0.02, max_radius = 0.5;
  int candidates = 16;     // wrong points drawn per move; the deepest is used
  double min_gain = 1e-6;  // a move must lower the loss by this much
};

struct ReseedReport {
  int dead = 0;                            // leaves found dead
  int tried = 0;                           // of which tried
  int moved = 0;                           // of which moved
  double loss_before = 0, loss_after = 0;  // on the round's samples
};

// One round of re-seeding: leaves that pruning would remove (replacing them by a constant
// changes the output by less than the threshold) and that are not masked (emptying or filling
// them changes it at all) are moved, one at a time, in random order, to where the model
// is wrong (the deepest of a few wrong points drawn at random, and the ball there grown by
// grow_ball), trying a ball at a missed point, a ball and everything-but-a-ball at a wrongly
// covered point, and a quadric through the boundary sample nearest to either (oriented by its
// normal); the best move is kept if it lowers the loss on the round's samples. Moved leaves'
// Adam moments are reset to 0.
ReseedReport reseed_dead_leaves(const Tree& model, const Evaluator& evaluator, const Target& target,
                                const BoundaryDistance& distance, std::span<double> params,
                                std::span<double> adam_m, std::span<double> adam_v,
                                const ReseedOptions& options, Rng& rng);

}  // namespace fuzzycsg
