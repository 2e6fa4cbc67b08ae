#pragma once
// Crisp CSG trees in pixel units, the representation the bitmap tracer searches over
// (Gibson et al. 1997): circles <(x, y), r> and rectangles <(x, y), (w, h), theta>, combined by
// binary difference, intersection and union.
//
// Coordinates are those of trace/bitmap.hpp (pixel (i, j) centred at (i + 1/2, j + 1/2), y
// down). A rectangle is centred at (x, y) with full extents w along its own u axis and h along
// its v axis, u at theta degrees from the +x axis towards +y (clockwise on screen, since y
// points down). A pixel belongs to a primitive when its centre lies strictly inside.
//
// The tree is a vector of nodes with child and parent indices, so that the search's edits
// (replace, cut or add a subtree, change a primitive's type) are index surgery; edits leave
// unused slots behind, which compact() removes. Node ids are stable until compact().

#include <cstdint>
#include <random>
#include <vector>

namespace fuzzycsg::trace {

using Rng = std::mt19937_64;

enum class Shape : std::uint8_t { kCircle, kRectangle };
enum class Op : std::uint8_t { kDifference, kIntersection, kUnion };

struct Primitive {
  Shape shape = Shape::kCircle;
  double x = 0, y = 0;
  double r = 1;         // circle
  double w = 1, h = 1;  // rectangle
  double theta = 0;     // rectangle, degrees
  friend bool operator==(const Primitive&, const Primitive&) = default;
};

// cos and sin of theta degrees (the same values wherever the module rotates).
void rotation(double theta_deg, double& c, double& s);

// Whether the point (px, py) lies strictly inside the primitive: the test scan conversion
// agrees with at every pixel centre.
bool contains(const Primitive& p, double px, double py);

// The box [x0, x1] x [y0, y1] (pixel units, unclipped) that holds the primitive.
struct Box {
  double x0, y0, x1, y1;
};
Box bounds(const Primitive& p);

// Rows [row0, row1) and columns [col0, col1) of a width x height bitmap; empty when row0 >= row1
// or col0 >= col1.
struct PixelBox {
  int col0 = 0, row0 = 0, col1 = 0, row1 = 0;
  bool empty() const { return col0 >= col1 || row0 >= row1; }
  bool intersects(const PixelBox& o) const {
    return !empty() && !o.empty() && col0 < o.col1 && o.col0 < col1 && row0 < o.row1 &&
           o.row0 < row1;
  }
  // The smallest box holding both (an empty box adds nothing).
  PixelBox joined(const PixelBox& o) const;
};

struct Node {
  bool leaf = true;
  Primitive prim;      // leaf
  Op op = Op::kUnion;  // inner node: children[0] op children[1]
  int children[2] = {-1, -1};
  int parent = -1;
  bool alive = true;  // false: an unused slot left by an edit
  // Bookkeeping of the local optimizer (trace/optimize.hpp), copied with the node: the pixels
  // the last adjustment of this leaf depended on, when that adjustment changed nothing. While
  // no other leaf changes a pixel there, adjusting the leaf again would change nothing either,
  // so it is skipped. Empty: the leaf must be adjusted.
  PixelBox settled;
};

class CsgTree {
 public:
  CsgTree() = default;
  // A tree of one primitive.
  explicit CsgTree(const Primitive& p);

  int root() const { return root_; }
  const std::vector<Node>& nodes() const { return nodes_; }
  const Node& node(int i) const { return nodes_.at(static_cast<std::size_t>(i)); }
  Primitive& primitive(int leaf) { return nodes_.at(static_cast<std::size_t>(leaf)).prim; }
  const Primitive& primitive(int leaf) const {
    return nodes_.at(static_cast<std::size_t>(leaf)).prim;
  }
  bool empty() const { return root_ < 0; }

  // Building from the leaves up: new nodes without parent; the last one made becomes the root
  // unless set_root() says otherwise.
  int add_leaf(const Primitive& p);
  int add_op(Op op, int a, int b);  // a op b; a and b must be roots (no parent yet)
  void set_root(int i);

  // Leaves (primitives) of the subtree at `i`, left to right; of the whole tree by default.
  std::vector<int> leaves(int i = -1) const;
  int primitive_count(int i = -1) const;
  // Nodes of the subtree at `i` in post-order (children before parents).
  std::vector<int> post_order(int i = -1) const;
  int depth() const;

  // --- edits of the global search
  // Replaces the subtree at `at` by a copy of `sub`; returns the id of the copy's root.
  int replace_subtree(int at, const CsgTree& sub);
  // Removes the subtree at `at`: its parent is replaced by its sibling. Cutting the root (or
  // the only primitive) is refused (returns false).
  bool cut_subtree(int at);
  // Replaces the subtree at `at` by (at op copy-of-sub); returns the id of the new operator.
  int add_subtree(int at, Op op, const CsgTree& sub);
  // A circle becomes a rectangle of the same centre with w = h = 2r and theta = 0, a rectangle
  // a circle of the same centre with r = (w + h) / 4. The leaf is unsettled.
  void toggle_shape(int leaf);
  // Removes unused slots (renumbers nodes; ids held outside become invalid).
  void compact();

  // --- the local optimizer's bookkeeping (Node::settled)
  void settle(int leaf, const PixelBox& box) {
    nodes_.at(static_cast<std::size_t>(leaf)).settled = box;
  }
  // Unsettles every leaf whose settled box meets `changed` (pixels whose value may have changed
  // for reasons other than the leaf itself).
  void unsettle(const PixelBox& changed);
  void unsettle_all();

 private:
  int copy_from(const CsgTree& sub, int i);
  std::vector<Node> nodes_;
  int root_ = -1;
};

// Random trees as the paper draws them (W, H: the bitmap's size): x in [W/4, 3W/4],
// y in [H/4, 3H/4], r in [1, min(W, H)/2], w in [1, W/2], h in [1, H/2], theta in [0, 360),
// shape and operator uniform.
Primitive random_primitive(int width, int height, Rng& rng);
// `primitives` >= 1 leaves; each inner node splits its leaves uniformly at random between its
// two subtrees.
CsgTree random_tree(int primitives, int width, int height, Rng& rng);
// norm(a, s): a normally distributed integer of mean a and standard deviation s, rounded to the
// nearest integer and at least `at_least`.
int norm_count(double a, double s, Rng& rng, int at_least = 1);

// Uniform in [0, 1) from 53 random bits (the same for a seed whatever the standard library).
inline double uniform01(Rng& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }
// Standard normal by Box-Muller on uniform01 (library independent).
double standard_normal(Rng& rng);

}  // namespace fuzzycsg::trace
