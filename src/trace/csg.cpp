#include "fuzzycsg/trace/csg.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::trace {

void rotation(double theta_deg, double& c, double& s) {
  // The search asks for the same few angles again and again: the last one is remembered.
  thread_local double last = 0, last_c = 1, last_s = 0;
  if (theta_deg != last) {
    const double t = theta_deg * (std::numbers::pi / 180.0);
    last_c = std::cos(t);
    last_s = std::sin(t);
    last = theta_deg;
  }
  c = last_c;
  s = last_s;
}

bool contains(const Primitive& p, double px, double py) {
  const double dx = px - p.x, dy = py - p.y;
  if (p.shape == Shape::kCircle) return dx * dx + dy * dy < p.r * p.r;
  double c = 0, s = 0;
  rotation(p.theta, c, s);
  const double u = c * dx + s * dy, v = -s * dx + c * dy;
  return std::abs(u) < p.w / 2 && std::abs(v) < p.h / 2;
}

Box bounds(const Primitive& p) {
  if (p.shape == Shape::kCircle) return {p.x - p.r, p.y - p.r, p.x + p.r, p.y + p.r};
  double c = 0, s = 0;
  rotation(p.theta, c, s);
  const double ex = (std::abs(c) * p.w + std::abs(s) * p.h) / 2;
  const double ey = (std::abs(s) * p.w + std::abs(c) * p.h) / 2;
  return {p.x - ex, p.y - ey, p.x + ex, p.y + ey};
}

PixelBox PixelBox::joined(const PixelBox& o) const {
  if (o.empty()) return *this;
  if (empty()) return o;
  return {std::min(col0, o.col0), std::min(row0, o.row0), std::max(col1, o.col1),
          std::max(row1, o.row1)};
}

CsgTree::CsgTree(const Primitive& p) { add_leaf(p); }

int CsgTree::add_leaf(const Primitive& p) {
  Node n;
  n.leaf = true;
  n.prim = p;
  nodes_.push_back(n);
  root_ = static_cast<int>(nodes_.size()) - 1;
  return root_;
}

int CsgTree::add_op(Op op, int a, int b) {
  if (a == b || nodes_.at(static_cast<std::size_t>(a)).parent >= 0 ||
      nodes_.at(static_cast<std::size_t>(b)).parent >= 0) {
    throw Error("CsgTree::add_op: the children must be distinct roots");
  }
  Node n;
  n.leaf = false;
  n.op = op;
  n.children[0] = a;
  n.children[1] = b;
  nodes_.push_back(n);
  const int id = static_cast<int>(nodes_.size()) - 1;
  nodes_[static_cast<std::size_t>(a)].parent = id;
  nodes_[static_cast<std::size_t>(b)].parent = id;
  root_ = id;
  return id;
}

void CsgTree::set_root(int i) {
  nodes_.at(static_cast<std::size_t>(i)).parent = -1;
  root_ = i;
}

std::vector<int> CsgTree::post_order(int i) const {
  std::vector<int> out;
  if (i < 0) i = root_;
  if (i < 0) return out;
  // Iterative: (node, visited children) on a stack.
  std::vector<std::pair<int, int>> stack{{i, 0}};
  while (!stack.empty()) {
    auto& [n, k] = stack.back();
    const Node& node = nodes_[static_cast<std::size_t>(n)];
    if (node.leaf || k == 2) {
      out.push_back(n);
      stack.pop_back();
    } else {
      const int child = node.children[k++];
      stack.emplace_back(child, 0);
    }
  }
  return out;
}

std::vector<int> CsgTree::leaves(int i) const {
  std::vector<int> out;
  for (const int n : post_order(i)) {
    if (nodes_[static_cast<std::size_t>(n)].leaf) out.push_back(n);
  }
  return out;
}

int CsgTree::primitive_count(int i) const { return static_cast<int>(leaves(i).size()); }

int CsgTree::depth() const {
  int best = 0;
  for (const int leaf : leaves()) {
    int d = 0;
    for (int n = leaf; nodes_[static_cast<std::size_t>(n)].parent >= 0;
         n = nodes_[static_cast<std::size_t>(n)].parent) {
      ++d;
    }
    best = std::max(best, d);
  }
  return best;
}

int CsgTree::copy_from(const CsgTree& sub, int i) {
  const Node& n = sub.nodes_.at(static_cast<std::size_t>(i));
  if (n.leaf) {
    Node c;
    c.prim = n.prim;
    c.settled = n.settled;
    nodes_.push_back(c);
    return static_cast<int>(nodes_.size()) - 1;
  }
  const int a = copy_from(sub, n.children[0]);
  const int b = copy_from(sub, n.children[1]);
  Node c;
  c.leaf = false;
  c.op = n.op;
  c.children[0] = a;
  c.children[1] = b;
  nodes_.push_back(c);
  const int id = static_cast<int>(nodes_.size()) - 1;
  nodes_[static_cast<std::size_t>(a)].parent = id;
  nodes_[static_cast<std::size_t>(b)].parent = id;
  return id;
}

namespace {

void kill(std::vector<Node>& nodes, const std::vector<int>& ids) {
  for (const int n : ids) nodes[static_cast<std::size_t>(n)].alive = false;
}

void relink(std::vector<Node>& nodes, int parent, int old_child, int new_child) {
  nodes[static_cast<std::size_t>(new_child)].parent = parent;
  if (parent < 0) return;
  Node& p = nodes[static_cast<std::size_t>(parent)];
  for (int& c : p.children) {
    if (c == old_child) c = new_child;
  }
}

}  // namespace

int CsgTree::replace_subtree(int at, const CsgTree& sub) {
  if (sub.empty()) throw Error("CsgTree::replace_subtree: empty subtree");
  const int parent = nodes_.at(static_cast<std::size_t>(at)).parent;
  kill(nodes_, post_order(at));
  const int copy = copy_from(sub, sub.root());
  relink(nodes_, parent, at, copy);
  if (at == root_) root_ = copy;
  return copy;
}

bool CsgTree::cut_subtree(int at) {
  const int parent = nodes_.at(static_cast<std::size_t>(at)).parent;
  if (parent < 0) return false;
  Node& p = nodes_[static_cast<std::size_t>(parent)];
  const int sibling = p.children[0] == at ? p.children[1] : p.children[0];
  const int grand = p.parent;
  kill(nodes_, post_order(at));
  p.alive = false;
  relink(nodes_, grand, parent, sibling);
  if (parent == root_) root_ = sibling;
  return true;
}

int CsgTree::add_subtree(int at, Op op, const CsgTree& sub) {
  if (sub.empty()) throw Error("CsgTree::add_subtree: empty subtree");
  const int parent = nodes_.at(static_cast<std::size_t>(at)).parent;
  const int copy = copy_from(sub, sub.root());
  Node n;
  n.leaf = false;
  n.op = op;
  n.children[0] = at;
  n.children[1] = copy;
  nodes_.push_back(n);
  const int id = static_cast<int>(nodes_.size()) - 1;
  nodes_[static_cast<std::size_t>(copy)].parent = id;
  relink(nodes_, parent, at, id);
  nodes_[static_cast<std::size_t>(at)].parent = id;
  if (at == root_) root_ = id;
  return id;
}

void CsgTree::unsettle(const PixelBox& changed) {
  for (Node& n : nodes_) {
    if (n.alive && n.leaf && n.settled.intersects(changed)) n.settled = PixelBox{};
  }
}

void CsgTree::unsettle_all() {
  for (Node& n : nodes_) n.settled = PixelBox{};
}

void CsgTree::toggle_shape(int leaf) {
  nodes_.at(static_cast<std::size_t>(leaf)).settled = PixelBox{};
  Primitive& p = primitive(leaf);
  if (p.shape == Shape::kCircle) {
    p.shape = Shape::kRectangle;
    p.w = p.h = 2 * p.r;
    p.theta = 0;
  } else {
    p.shape = Shape::kCircle;
    p.r = (p.w + p.h) / 4;
  }
}

void CsgTree::compact() {
  if (root_ < 0) {
    nodes_.clear();
    return;
  }
  CsgTree fresh;
  fresh.root_ = fresh.copy_from(*this, root_);
  *this = std::move(fresh);
}

double standard_normal(Rng& rng) {
  double u = uniform01(rng);
  while (u <= 0.0) u = uniform01(rng);
  const double v = uniform01(rng);
  return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * std::numbers::pi * v);
}

int norm_count(double a, double s, Rng& rng, int at_least) {
  const double v = std::round(a + s * standard_normal(rng));
  return std::max(at_least, static_cast<int>(std::clamp(v, -1e6, 1e6)));
}

Primitive random_primitive(int width, int height, Rng& rng) {
  const auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * uniform01(rng); };
  Primitive p;
  p.shape = (rng() >> 63) != 0 ? Shape::kRectangle : Shape::kCircle;
  p.x = uniform(width / 4.0, 3.0 * width / 4.0);
  p.y = uniform(height / 4.0, 3.0 * height / 4.0);
  p.r = uniform(1.0, std::max(1.0, std::min(width, height) / 2.0));
  p.w = uniform(1.0, std::max(1.0, width / 2.0));
  p.h = uniform(1.0, std::max(1.0, height / 2.0));
  p.theta = uniform(0.0, 360.0);
  return p;
}

namespace {

int grow(CsgTree& t, int leaves, int width, int height, Rng& rng) {
  if (leaves <= 1) return t.add_leaf(random_primitive(width, height, rng));
  const int left = 1 + static_cast<int>(uniform01(rng) * (leaves - 1));
  const Op op =
      static_cast<Op>(std::min<std::uint64_t>(2, static_cast<std::uint64_t>(uniform01(rng) * 3.0)));
  const int a = grow(t, left, width, height, rng);
  const int b = grow(t, leaves - left, width, height, rng);
  return t.add_op(op, a, b);
}

}  // namespace

CsgTree random_tree(int primitives, int width, int height, Rng& rng) {
  CsgTree t;
  t.set_root(grow(t, std::max(1, primitives), width, height, rng));
  return t;
}

}  // namespace fuzzycsg::trace
