#pragma once
// The local optimizer of Gibson et al. 1997 (Fig. 3 and 4): adjusts each primitive of a tree to
// the target bitmap, then prunes the primitives that do not contribute.
//
// The local region of a primitive is its pixel box (pixel_box()) grown on every side by
// max(margin, a quarter of the box's longer side) pixels, clipped to the bitmap. Local EXCESS
// and UNCOVERED are the tree's EXCESS and UNCOVERED pixels in that region.
//
// One sweep visits every primitive in turn (leaves left to right) and
//   1. shifts it in steps of shift_step pixels towards the centroid of the local UNCOVERED
//      region and away from that of the local EXCESS region (the direction is the sum of the
//      unit vectors to each centroid, weighted by the region's share of the local mismatch,
//      recomputed after every step), while the mismatch improves; if the first step does not,
//      in the opposite direction (a primitive that is subtracted moves the other way); then by
//      steps of shift_step, then 1/2 and 1/4 of it, along +-x and +-y while they improve (a
//      refinement the paper does not name);
//   2. for each dimension (r; or w, then h) grows it by size_step while the local UNCOVERED
//      exceeds the local EXCESS, or shrinks it when the EXCESS exceeds the UNCOVERED, while the
//      mismatch improves, trying the opposite change when the first step does not improve;
//      dimensions stay >= min_size; then the same with 1/2 and 1/4 of the step; for a
//      rectangle then one edge at a time (the dimension changes and the centre follows by half
//      the change, the opposite edge staying), both edges, in the three step sizes, while the
//      mismatch improves (also a refinement of ours: a centred change moves two edges, which
//      can leave an edge off by one pixel);
//   3. rotates a rectangle by +angle_step degrees while the mismatch improves, or by
//      -angle_step if the first step does not; then the same with 1/2 and 1/4 of the step.
// "Improves" is a strict decrease of the whole tree's EXCESS + UNCOVERED. After every kept step
// the pace doubles (up to 32 steps at once); a step that does not improve is tried again at half
// the pace down to one step, then at two steps (a small step may move no pixel centre across an
// edge), before the adjustment stops. At most max_steps steps per adjustment. Sweeps repeat, at most max_iterations (M) times, while a sweep changes something.
//
// Candidates are scored without evaluating the tree: with every other leaf fixed, the tree's
// result is (R0 & ~L) | (R1 & L) for the leaf's bitmap L (R0, R1: the results with L empty and
// full), so a candidate's mismatch follows from counting, along its scan-converted spans, the
// pixels it would fix and those it would spoil. A kept step updates the tree incrementally
// (TreeEvaluator::update_primitive). Both count as trees evaluated.
//
// A leaf whose adjustment changed nothing records the pixels it read (Node::settled); until
// another leaf, or an edit of the tree, changes one of those pixels, adjusting it again would
// give the same nothing, and later sweeps skip it. The result is that of sweeping every leaf.
//
// Pruning then removes, one at a time, every primitive whose removal (cut_subtree()) does not
// increase EXCESS + UNCOVERED, as long as one primitive remains.

#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/evaluate.hpp"

namespace fuzzycsg::trace {

struct LocalOptions {
  int max_iterations = 80;  // M
  double k = 25.0;          // tree-size weight of the score
  int margin = 3;           // local region: at least this many pixels around the primitive
  double shift_step = 1.0;  // pixels
  double size_step = 1.0;   // pixels
  double angle_step = 1.0;  // degrees
  double min_size = 0.5;    // smallest radius, width or height
  int max_steps = 256;      // per adjustment of one parameter
  bool prune = true;
  // Skip the leaves whose Node::settled box says that adjusting them would change nothing
  // (left by an earlier optimization against the same target and options, and kept up to date
  // by CsgTree::unsettle() after edits; the global search does this). Otherwise every leaf's
  // bookkeeping is cleared first.
  bool trust_settled = false;
};

struct LocalResult {
  Score score;         // of the optimized (and pruned) tree
  int iterations = 0;  // sweeps made
  int pruned = 0;      // primitives removed
};

// The local region of `p` as defined above.
PixelBox local_region(const Primitive& p, int width, int height, int margin);

// Optimizes the evaluator's tree in place against `target` (of the evaluator's size).
LocalResult optimize_locally(TreeEvaluator& evaluator, const Bitmap& target,
                             const LocalOptions& options = {});

}  // namespace fuzzycsg::trace
