#pragma once
// Scan conversion of primitives, evaluation of crisp trees to bitmaps, and the score of
// Gibson et al. 1997: EXCESS (set in the tree's bitmap, clear in the target) + UNCOVERED (set
// in the target, clear in the tree's) + k * primitives.
//
// TreeEvaluator keeps one bitmap per node. A full evaluation scan-converts every primitive and
// combines the children of every inner node a word at a time; when one primitive changes,
// update_primitive() scan-converts it again and recomputes only the nodes on the path from its
// leaf to the root, and only the rows where the primitive was or is now (no other pixel can
// change).

#include <cstdint>

#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/csg.hpp"

namespace fuzzycsg::trace {

// The pixels whose centres may lie in bounds(p), clipped to the bitmap.
PixelBox pixel_box(const Primitive& p, int width, int height);
// `b` grown by `margin` pixels on every side, clipped to the bitmap.
PixelBox grow(const PixelBox& b, int margin, int width, int height);

// Clears rows [box.row0, box.row1) of `out` (the rest untouched) and sets the pixels of `p`:
// exactly those whose centres satisfy contains(p, ...). Returns the pixel box drawn.
PixelBox scan_convert(const Primitive& p, Bitmap& out);

// The paper's measures of effort. Every full evaluation and every incremental update counts
// as a tree evaluated, including the updates that undo a rejected step of the local optimizer.
struct Counters {
  std::uint64_t primitives_scanned = 0;  // primitive scan conversions
  std::uint64_t trees_evaluated = 0;     // full evaluations and incremental updates
};

class TreeEvaluator {
 public:
  TreeEvaluator(int width, int height) : width_(width), height_(height) {}
  TreeEvaluator(const CsgTree& tree, int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }
  const CsgTree& tree() const { return tree_; }

  // Replaces the tree (any structure) and evaluates it fully.
  const Bitmap& set_tree(const CsgTree& tree);
  // Evaluates the current tree from scratch.
  const Bitmap& evaluate();
  // Sets the primitive of `leaf` and re-evaluates incrementally.
  const Bitmap& update_primitive(int leaf, const Primitive& p);

  // The tree's bitmap (of the last evaluation), and any node's.
  const Bitmap& result() const { return mask(tree_.root()); }
  const Bitmap& mask(int node) const { return masks_.at(static_cast<std::size_t>(node)); }

  // The local optimizer's bookkeeping on the evaluator's tree (CsgTree::settle, unsettle).
  void settle(int leaf, const PixelBox& box) { tree_.settle(leaf, box); }
  void unsettle(const PixelBox& changed) { tree_.unsettle(changed); }
  void unsettle_all() { tree_.unsettle_all(); }

  const Counters& counters() const { return counters_; }
  Counters& counters() { return counters_; }

 private:
  void combine(int node, int row0, int row1);
  CsgTree tree_;
  int width_, height_;
  std::vector<Bitmap> masks_;    // by node id
  std::vector<PixelBox> drawn_;  // by node id: the box a leaf was last drawn in
  Counters counters_;
};

struct Score {
  std::int64_t excess = 0, uncovered = 0;
  int primitives = 0;
  double k = 25.0;
  std::int64_t mismatch() const { return excess + uncovered; }
  double total() const { return static_cast<double>(mismatch()) + k * primitives; }
};

// Over the whole bitmap; tree and target of the same size.
Score score(const Bitmap& tree, const Bitmap& target, int primitives, double k = 25.0);

// EXCESS and UNCOVERED within a box, and the centroids (pixel centres) of each region there
// (the box's centre where a region is empty).
struct LocalMismatch {
  std::int64_t excess = 0, uncovered = 0;
  double excess_x = 0, excess_y = 0, uncovered_x = 0, uncovered_y = 0;
};
LocalMismatch local_mismatch(const Bitmap& tree, const Bitmap& target, const PixelBox& box);

}  // namespace fuzzycsg::trace
