#include "fuzzycsg/trace/evaluate.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

#include "fuzzycsg/core/error.hpp"
#include "spans.hpp"

namespace fuzzycsg::trace {

using detail::clamp_index;

PixelBox pixel_box(const Primitive& p, int width, int height) {
  const Box b = bounds(p);
  // Centres k + 1/2 in [b.x0, b.x1], one pixel of slack either side for rounding.
  PixelBox out;
  out.col0 = clamp_index(std::ceil(b.x0 - 0.5) - 1, 0, width);
  out.col1 = clamp_index(std::floor(b.x1 - 0.5) + 2, 0, width);
  out.row0 = clamp_index(std::ceil(b.y0 - 0.5) - 1, 0, height);
  out.row1 = clamp_index(std::floor(b.y1 - 0.5) + 2, 0, height);
  return out;
}

PixelBox grow(const PixelBox& b, int margin, int width, int height) {
  return {std::max(0, b.col0 - margin), std::max(0, b.row0 - margin),
          std::min(width, b.col1 + margin), std::min(height, b.row1 + margin)};
}

FUZZYCSG_TRACE_HOT
PixelBox scan_convert(const Primitive& p, Bitmap& out) {
  const PixelBox box = pixel_box(p, out.width(), out.height());
  out.clear_rows(box.row0, box.row1);
  detail::for_each_span(p, box, [&](int row, int c0, int c1) { out.set_span(row, c0, c1); });
  return box;
}

TreeEvaluator::TreeEvaluator(const CsgTree& tree, int width, int height)
    : width_(width), height_(height) {
  set_tree(tree);
}

const Bitmap& TreeEvaluator::set_tree(const CsgTree& tree) {
  if (tree.empty()) throw Error("TreeEvaluator: empty tree");
  tree_ = tree;
  masks_.resize(tree_.nodes().size());
  drawn_.assign(tree_.nodes().size(), PixelBox{});
  return evaluate();
}

FUZZYCSG_TRACE_HOT
void TreeEvaluator::combine(int node, int row0, int row1) {
  const Node& n = tree_.node(node);
  Bitmap& out = masks_[static_cast<std::size_t>(node)];
  const Bitmap& a = masks_[static_cast<std::size_t>(n.children[0])];
  const Bitmap& b = masks_[static_cast<std::size_t>(n.children[1])];
  const std::size_t w = static_cast<std::size_t>(out.words_per_row());
  const std::size_t begin = static_cast<std::size_t>(row0) * w;
  const std::size_t end = static_cast<std::size_t>(row1) * w;
  std::uint64_t* o = out.words().data();
  const std::uint64_t* x = a.words().data();
  const std::uint64_t* y = b.words().data();
  switch (n.op) {
    case Op::kDifference:
      for (std::size_t i = begin; i < end; ++i) o[i] = x[i] & ~y[i];
      break;
    case Op::kIntersection:
      for (std::size_t i = begin; i < end; ++i) o[i] = x[i] & y[i];
      break;
    case Op::kUnion:
      for (std::size_t i = begin; i < end; ++i) o[i] = x[i] | y[i];
      break;
  }
}

const Bitmap& TreeEvaluator::evaluate() {
  if (masks_.size() < tree_.nodes().size()) {
    masks_.resize(tree_.nodes().size());
    drawn_.resize(tree_.nodes().size());
  }
  for (const int id : tree_.post_order()) {
    Bitmap& m = masks_[static_cast<std::size_t>(id)];
    if (m.width() != width_ || m.height() != height_) m = Bitmap(width_, height_);
    const Node& n = tree_.node(id);
    if (n.leaf) {
      m.clear();
      drawn_[static_cast<std::size_t>(id)] = scan_convert(n.prim, m);
      ++counters_.primitives_scanned;
    } else {
      combine(id, 0, height_);
    }
  }
  ++counters_.trees_evaluated;
  return result();
}

const Bitmap& TreeEvaluator::update_primitive(int leaf, const Primitive& p) {
  if (!tree_.node(leaf).leaf) throw Error("TreeEvaluator::update_primitive: not a leaf");
  tree_.primitive(leaf) = p;
  Bitmap& m = masks_[static_cast<std::size_t>(leaf)];
  PixelBox& drawn = drawn_[static_cast<std::size_t>(leaf)];
  const PixelBox old = drawn;
  m.clear_rows(old.row0, old.row1);
  drawn = scan_convert(p, m);
  ++counters_.primitives_scanned;
  ++counters_.trees_evaluated;
  int r0 = height_, r1 = 0;
  for (const PixelBox& b : {old, drawn}) {
    if (b.row0 < b.row1) {
      r0 = std::min(r0, b.row0);
      r1 = std::max(r1, b.row1);
    }
  }
  if (r0 >= r1) return result();
  for (int n = tree_.node(leaf).parent; n >= 0; n = tree_.node(n).parent) combine(n, r0, r1);
  return result();
}

FUZZYCSG_TRACE_HOT
Score score(const Bitmap& tree, const Bitmap& target, int primitives, double k) {
  if (tree.width() != target.width() || tree.height() != target.height()) {
    throw Error("trace::score: the bitmaps differ in size");
  }
  Score s;
  s.primitives = primitives;
  s.k = k;
  const auto a = tree.words(), b = target.words();
  for (std::size_t i = 0; i < a.size(); ++i) {
    s.excess += std::popcount(a[i] & ~b[i]);
    s.uncovered += std::popcount(b[i] & ~a[i]);
  }
  return s;
}

FUZZYCSG_TRACE_HOT
LocalMismatch local_mismatch(const Bitmap& tree, const Bitmap& target, const PixelBox& box) {
  LocalMismatch m;
  double ex = 0, ey = 0, ux = 0, uy = 0;
  for (int j = box.row0; j < box.row1; ++j) {
    const std::uint64_t* a = tree.row(j);
    const std::uint64_t* b = target.row(j);
    for (int wi = box.col0 >> 6; wi <= (box.col1 - 1) >> 6 && box.col0 < box.col1; ++wi) {
      std::uint64_t range = ~std::uint64_t{0};
      const int base = wi << 6;
      if (box.col0 > base) range &= ~std::uint64_t{0} << (box.col0 - base);
      if (box.col1 < base + 64) range &= ~std::uint64_t{0} >> (base + 64 - box.col1);
      const std::uint64_t e = a[wi] & ~b[wi] & range, u = b[wi] & ~a[wi] & range;
      const auto sums = [&](std::uint64_t bits, std::int64_t& count, double& sx, double& sy) {
        const int n = std::popcount(bits);
        if (n == 0) return;
        count += n;
        sy += n * (j + 0.5);
        // The sum of the set bits' indices, bit by bit of the index.
        int index_sum = 0;
        index_sum += std::popcount(bits & 0xaaaaaaaaaaaaaaaaull);
        index_sum += 2 * std::popcount(bits & 0xccccccccccccccccull);
        index_sum += 4 * std::popcount(bits & 0xf0f0f0f0f0f0f0f0ull);
        index_sum += 8 * std::popcount(bits & 0xff00ff00ff00ff00ull);
        index_sum += 16 * std::popcount(bits & 0xffff0000ffff0000ull);
        index_sum += 32 * std::popcount(bits & 0xffffffff00000000ull);
        sx += n * (base + 0.5) + index_sum;
      };
      sums(e, m.excess, ex, ey);
      sums(u, m.uncovered, ux, uy);
    }
  }
  const double cx = (box.col0 + box.col1) / 2.0, cy = (box.row0 + box.row1) / 2.0;
  m.excess_x = m.excess ? ex / static_cast<double>(m.excess) : cx;
  m.excess_y = m.excess ? ey / static_cast<double>(m.excess) : cy;
  m.uncovered_x = m.uncovered ? ux / static_cast<double>(m.uncovered) : cx;
  m.uncovered_y = m.uncovered ? uy / static_cast<double>(m.uncovered) : cy;
  return m;
}

}  // namespace fuzzycsg::trace
