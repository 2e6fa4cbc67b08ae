#include "fuzzycsg/trace/optimize.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "spans.hpp"

namespace fuzzycsg::trace {

PixelBox local_region(const Primitive& p, int width, int height, int margin) {
  const Box b = bounds(p);
  const double side = std::max(b.x1 - b.x0, b.y1 - b.y0);
  const int grown = std::max(margin, static_cast<int>(std::ceil(std::min(side, 1e6) / 4)));
  return grow(pixel_box(p, width, height), grown, width, height);
}

namespace {

// Bits of `row` in columns [c0, c1).
[[gnu::always_inline]] inline int count_span(const std::uint64_t* row, int c0, int c1) {
  const int w0 = c0 >> 6, w1 = (c1 - 1) >> 6;
  const std::uint64_t first = ~std::uint64_t{0} << (c0 & 63);
  const std::uint64_t last = ~std::uint64_t{0} >> (63 - ((c1 - 1) & 63));
  if (w0 == w1) return std::popcount(row[w0] & first & last);
  int n = std::popcount(row[w0] & first) + std::popcount(row[w1] & last);
  for (int w = w0 + 1; w < w1; ++w) n += std::popcount(row[w]);
  return n;
}

FUZZYCSG_TRACE_HOT
std::int64_t count_box(const Bitmap& b, const PixelBox& box) {
  std::int64_t n = 0;
  if (box.empty()) return 0;
  for (int r = box.row0; r < box.row1; ++r) n += count_span(b.row(r), box.col0, box.col1);
  return n;
}

// The result of the whole tree as a function of one leaf's bitmap L: per pixel it is 0, 1, L
// or not L, so it equals (R0 & ~L) | (R1 & L), R0 and R1 being the results with L empty and
// with L full. The mismatch with L is then mismatch(R0) + |L & hurt| - |L & help|, where help
// holds the pixels that L fixes (R0 wrong, R1 right) and hurt those it spoils (R0 right, R1
// wrong): a candidate primitive is scored from its spans alone, without evaluating the tree.
//
// A candidate's value is summed along its spans from per-row prefix sums of hurt - help, built
// for a row the first time a candidate reaches it.
struct LeafContext {
  Bitmap r0, r1, help, hurt;
  std::int64_t base = 0;  // mismatch with L empty
  std::int64_t full = 0;  // mismatch with L full
  int width = 0;
  std::vector<std::int32_t> prefix;  // row r: [r * (width + 1), (r + 1) * (width + 1))
  std::vector<std::uint8_t> built;   // by row

  const std::int32_t* row_prefix(int r) {
    std::int32_t* out = prefix.data() + static_cast<std::size_t>(r) * (width + 1);
    if (built[static_cast<std::size_t>(r)]) return out;
    const std::uint64_t* hp = help.row(r);
    const std::uint64_t* ht = hurt.row(r);
    std::int32_t sum = 0;
    out[0] = 0;
    for (int c = 0; c < width; ++c) {
      sum += static_cast<std::int32_t>((ht[c >> 6] >> (c & 63)) & 1u) -
             static_cast<std::int32_t>((hp[c >> 6] >> (c & 63)) & 1u);
      out[c + 1] = sum;
    }
    built[static_cast<std::size_t>(r)] = 1;
    return out;
  }
};

FUZZYCSG_TRACE_HOT
void compute_context(const TreeEvaluator& ev, const Bitmap& target, int leaf, LeafContext& c) {
  const int w = ev.width(), h = ev.height();
  for (Bitmap* b : {&c.r0, &c.r1, &c.help, &c.hurt}) {
    if (b->width() != w || b->height() != h) *b = Bitmap(w, h);
  }
  c.r0.clear();
  for (int r = 0; r < h; ++r) c.r1.set_span(r, 0, w);
  const CsgTree& t = ev.tree();
  const std::size_t n = c.r0.words().size();
  for (int node = leaf; t.node(node).parent >= 0; node = t.node(node).parent) {
    const Node& p = t.node(t.node(node).parent);
    const bool left = p.children[0] == node;
    const std::uint64_t* sib = ev.mask(p.children[left ? 1 : 0]).words().data();
    for (Bitmap* b : {&c.r0, &c.r1}) {
      std::uint64_t* x = b->words().data();
      switch (p.op) {
        case Op::kUnion:
          for (std::size_t i = 0; i < n; ++i) x[i] |= sib[i];
          break;
        case Op::kIntersection:
          for (std::size_t i = 0; i < n; ++i) x[i] &= sib[i];
          break;
        case Op::kDifference:
          if (left) {
            for (std::size_t i = 0; i < n; ++i) x[i] &= ~sib[i];
          } else {
            for (std::size_t i = 0; i < n; ++i) x[i] = sib[i] & ~x[i];
          }
          break;
      }
    }
  }
  // Bits past the width: r1 may have them set by "sib & ~x" only where sib has them (never).
  const std::uint64_t* tw = target.words().data();
  const std::uint64_t* x0 = c.r0.words().data();
  const std::uint64_t* x1 = c.r1.words().data();
  std::uint64_t* hp = c.help.words().data();
  std::uint64_t* ht = c.hurt.words().data();
  c.base = c.full = 0;
  c.width = w;
  c.prefix.resize(static_cast<std::size_t>(h) * static_cast<std::size_t>(w + 1));
  c.built.assign(static_cast<std::size_t>(h), 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t e0 = x0[i] ^ tw[i], e1 = x1[i] ^ tw[i];
    hp[i] = e0 & ~e1;
    ht[i] = e1 & ~e0;
    c.base += std::popcount(e0);
    c.full += std::popcount(e1);
  }
}

// |L & hurt| - |L & help| for the primitive's bitmap L.
FUZZYCSG_TRACE_HOT
std::int64_t leaf_value(LeafContext& c, const Primitive& p, const PixelBox& box) {
  std::int64_t v = 0;
  if (c.width <= 256) {
    // Spans of at most four words: counting their bits beats building prefix sums.
    detail::for_each_span(p, box, [&](int row, int c0, int c1) {
      v += count_span(c.hurt.row(row), c0, c1) - count_span(c.help.row(row), c0, c1);
    });
  } else {
    detail::for_each_span(p, box, [&](int row, int c0, int c1) {
      const std::int32_t* sums = c.row_prefix(row);
      v += sums[c1] - sums[c0];
    });
  }
  return v;
}

class Optimizer {
 public:
  Optimizer(TreeEvaluator& ev, const Bitmap& target, const LocalOptions& o)
      : ev_(ev), target_(target), o_(o) {
    mismatch_ = current_mismatch();
  }

  std::int64_t mismatch() const { return mismatch_; }

  // Adjusts one leaf (shift, resize, rotate); settles it when nothing changed, else unsettles
  // the leaves whose settled pixels it changed. Returns whether the leaf changed.
  bool adjust(int leaf) {
    leaf_ = leaf;
    compute_context(ev_, target_, leaf, context_);
    const Primitive& p = ev_.tree().primitive(leaf);
    const PixelBox box = pixel_box(p, ev_.width(), ev_.height());
    value_ = leaf_value(context_, p, box);
    ++ev_.counters().primitives_scanned;
    ++ev_.counters().trees_evaluated;
    changed_ = false;
    written_ = PixelBox{};
    failed_.clear();
    local_valid_ = false;
    // Every first step of every adjustment stays within `reach` of the primitive's box; when
    // no pixel there depends on the leaf, nothing can improve.
    read_ = grow(box, first_reach(p), ev_.width(), ev_.height());
    if (count_box(context_.help, read_) + count_box(context_.hurt, read_) == 0) {
      ev_.settle(leaf, read_);
      return false;
    }
    shift(leaf);
    resize(leaf);
    rotate(leaf);
    if (changed_) {
      ev_.unsettle(written_);
    } else {
      ev_.settle(leaf, read_);
    }
    return changed_;
  }

  // Tries `p` for the leaf being adjusted: kept when the mismatch strictly decreases.
  //
  // While one leaf is adjusted its context is fixed, so a candidate's mismatch is fixed and
  // the current one only falls: a candidate that failed, or a state the leaf has left, would
  // fail again. Those are remembered and not evaluated again.
  bool attempt(int leaf, const Primitive& p) {
    if (!failed_.insert(key(p))) return false;
    const PixelBox box = pixel_box(p, ev_.width(), ev_.height());
    read_ = read_.joined(box);
    const std::int64_t v = leaf_value(context_, p, box);
    ++ev_.counters().primitives_scanned;
    ++ev_.counters().trees_evaluated;
    if (v >= value_) return false;
    failed_.insert(key(ev_.tree().primitive(leaf)));
    written_ = written_.joined(box).joined(
        pixel_box(ev_.tree().primitive(leaf), ev_.width(), ev_.height()));
    ev_.update_primitive(leaf, p);
    local_valid_ = false;
    mismatch_ += v - value_;
    value_ = v;
    changed_ = true;
    return true;
  }

  // The local EXCESS and UNCOVERED of the leaf being adjusted (changes only when it does).
  const LocalMismatch& local(int leaf) {
    if (local_valid_) return local_;
    const Primitive& p = ev_.tree().primitive(leaf);
    const PixelBox region = local_region(p, ev_.width(), ev_.height(), o_.margin);
    read_ = read_.joined(region);
    local_ = local_mismatch(ev_.result(), target_, region);
    local_valid_ = true;
    return local_;
  }

  // Repeats `step(sign)` (the candidate for one step in direction sign, sign carrying the
  // step's multiple) while it improves; if the first step in direction `first` fails, tries
  // -first. Returns the steps kept.
  //
  // The pace doubles after every kept step (at most kMaxPace times the base step), so that a
  // primitive far from its place gets there in few steps; a step that does not improve is
  // tried again at half the pace, down to the base step, and then at twice the base step (a
  // small step may change no pixel: an edge that moves by less than the distance to the next
  // pixel centre) before the climb stops.
  static constexpr double kMaxPace = 32.0;
  template <class Step>
  int climb(int leaf, double first, Step step) {
    for (const double sign : {first, -first}) {
      int kept = 0;
      double pace = 1.0;
      for (int s = 0; s < o_.max_steps; ++s) {
        bool improved = false;
        double scales[8];
        int n = 0;
        for (double v = pace; v >= 1.0; v /= 2) scales[n++] = v;
        for (const double v : {2.0}) {
          if (v > pace) scales[n++] = v;
        }
        for (int k = 0; k < n; ++k) {
          Primitive p = ev_.tree().primitive(leaf);
          if (!step(sign * scales[k], p)) break;
          if (attempt(leaf, p)) {
            improved = true;
            pace = std::min(kMaxPace, 2 * scales[k]);
            break;
          }
        }
        if (!improved) break;
        ++kept;
      }
      if (kept > 0) return kept;
    }
    return 0;
  }

  void shift(int leaf) {
    climb(leaf, 1.0, [&](double sign, Primitive& p) {
      const LocalMismatch& lm = local(leaf);
      const double total = static_cast<double>(lm.excess + lm.uncovered);
      if (total == 0) return false;
      double dx = 0, dy = 0;
      const auto toward = [&](double cx, double cy, double weight) {
        const double ux = cx - p.x, uy = cy - p.y, len = std::hypot(ux, uy);
        if (len > 1e-12) {
          dx += weight * ux / len;
          dy += weight * uy / len;
        }
      };
      toward(lm.uncovered_x, lm.uncovered_y, static_cast<double>(lm.uncovered) / total);
      toward(lm.excess_x, lm.excess_y, -static_cast<double>(lm.excess) / total);
      const double len = std::hypot(dx, dy);
      if (len < 1e-9) return false;
      p.x += sign * o_.shift_step * dx / len;
      p.y += sign * o_.shift_step * dy / len;
      return true;
    });
    for (const double fraction : {1.0, 0.5, 0.25}) {
      for (int axis = 0; axis < 2; ++axis) {
        climb(leaf, 1.0, [&](double sign, Primitive& p) {
          (axis == 0 ? p.x : p.y) += sign * fraction * o_.shift_step;
          return true;
        });
      }
    }
  }

  void resize(int leaf) {
    const bool circle = ev_.tree().primitive(leaf).shape == Shape::kCircle;
    for (int dim = 0; dim < (circle ? 1 : 2); ++dim) {
      for (const double fraction : {1.0, 0.5, 0.25}) {
        const LocalMismatch lm = local(leaf);
        if (lm.excess == lm.uncovered && lm.excess == 0) break;
        const double first = lm.uncovered > lm.excess ? 1.0 : -1.0;
        climb(leaf, first, [&](double sign, Primitive& p) {
          double& v = circle ? p.r : (dim == 0 ? p.w : p.h);
          const double next = std::max(o_.min_size, v + sign * fraction * o_.size_step);
          if (next == v) return false;
          v = next;
          return true;
        });
      }
      if (circle) continue;
      // One edge at a time: the dimension changes by delta and the centre moves by delta / 2
      // along the rectangle's axis, so that the opposite edge stays.
      for (const double fraction : {1.0, 0.5}) {
        for (const double side : {1.0, -1.0}) {
          climb(leaf, 1.0, [&](double sign, Primitive& p) {
            double& v = dim == 0 ? p.w : p.h;
            const double next = std::max(o_.min_size, v + sign * fraction * o_.size_step);
            if (next == v) return false;
            const double t = p.theta * (std::numbers::pi / 180.0);
            const double ax = dim == 0 ? std::cos(t) : -std::sin(t);
            const double ay = dim == 0 ? std::sin(t) : std::cos(t);
            p.x += side * (next - v) / 2 * ax;
            p.y += side * (next - v) / 2 * ay;
            v = next;
            return true;
          });
        }
      }
    }
  }

  void rotate(int leaf) {
    if (ev_.tree().primitive(leaf).shape != Shape::kRectangle) return;
    for (const double fraction : {1.0, 0.5, 0.25}) {
      climb(leaf, 1.0, [&](double sign, Primitive& p) {
        p.theta = std::fmod(p.theta + sign * fraction * o_.angle_step + 360.0, 360.0);
        return true;
      });
    }
  }

  // Removes, one at a time, the first primitive (left to right) whose cut does not increase
  // the mismatch, until none can go. A cut replaces the leaf's parent by its sibling, which for
  // a union, an intersection and a subtracted leaf is the tree with the leaf's bitmap empty,
  // full and empty: those are scored from the leaf's context; a leaf subtracted from is
  // evaluated.
  int prune() {
    int removed = 0;
    bool again = true;
    while (again && ev_.tree().primitive_count() > 1) {
      again = false;
      for (const int leaf : ev_.tree().leaves()) {
        const CsgTree& t = ev_.tree();
        const int parent = t.node(leaf).parent;
        if (parent < 0) continue;
        const Node& pn = t.node(parent);
        std::int64_t m = 0;
        if (pn.op == Op::kDifference && pn.children[0] == leaf) {
          CsgTree cut = t;
          cut.cut_subtree(leaf);
          cut.compact();
          TreeEvaluator probe(cut, ev_.width(), ev_.height());
          m = score(probe.result(), target_, 0, o_.k).mismatch();
          ev_.counters().trees_evaluated += probe.counters().trees_evaluated;
          ev_.counters().primitives_scanned += probe.counters().primitives_scanned;
        } else {
          compute_context(ev_, target_, leaf, context_);
          ++ev_.counters().trees_evaluated;
          m = pn.op == Op::kIntersection ? context_.full : context_.base;
        }
        if (m > mismatch_) continue;
        PixelBox changed;
        for (const int l : t.leaves(parent)) {
          changed = changed.joined(pixel_box(t.primitive(l), ev_.width(), ev_.height()));
        }
        CsgTree cut = t;
        cut.cut_subtree(leaf);
        cut.compact();
        ev_.set_tree(cut);
        ev_.unsettle(changed);
        mismatch_ = m;
        ++removed;
        again = true;
        break;  // the leaves were renumbered
      }
    }
    return removed;
  }

  Score full_score() const {
    return score(ev_.result(), target_, ev_.tree().primitive_count(), o_.k);
  }

 private:
  std::int64_t current_mismatch() const { return score(ev_.result(), target_, 0, o_.k).mismatch(); }

  // How far beyond the primitive's box the first step of any adjustment can reach, with a
  // margin: shifts and size changes of up to four steps (climb() tries at most two at first),
  // and corners turned by up to four angle steps.
  int first_reach(const Primitive& p) const {
    const Box b = bounds(p);
    const double half_diagonal = std::hypot(b.x1 - b.x0, b.y1 - b.y0) / 2;
    const double turn = half_diagonal * 4 * o_.angle_step * (std::numbers::pi / 180.0);
    const double reach = std::max({4 * o_.shift_step, 4 * o_.size_step, turn});
    return static_cast<int>(std::ceil(std::min(reach, 1e6))) + 1;
  }

  TreeEvaluator& ev_;
  const Bitmap& target_;
  const LocalOptions& o_;
  std::int64_t mismatch_ = 0;
  LeafContext context_;
  int leaf_ = -1;
  std::int64_t value_ = 0;
  PixelBox read_, written_;
  bool changed_ = false;
  LocalMismatch local_;
  bool local_valid_ = false;

  // The candidates of the current adjustment known to fail, by bit pattern.
  using Key = std::array<std::uint64_t, 6>;
  static Key key(const Primitive& p) {
    const bool circle = p.shape == Shape::kCircle;
    return {static_cast<std::uint64_t>(p.shape),
            std::bit_cast<std::uint64_t>(p.x),
            std::bit_cast<std::uint64_t>(p.y),
            std::bit_cast<std::uint64_t>(circle ? p.r : p.w),
            std::bit_cast<std::uint64_t>(circle ? 0.0 : p.h),
            std::bit_cast<std::uint64_t>(circle ? 0.0 : p.theta)};
  }
  // An open-addressing set of keys, emptied in O(1) by a generation stamp.
  class KeySet {
   public:
    void clear() {
      ++generation_;
      count_ = 0;
      if (generation_ == 0) {  // wrapped: forget every stamp
        std::fill(stamp_.begin(), stamp_.end(), 0u);
        generation_ = 1;
      }
    }
    // Whether `k` was not in the set (and is now).
    bool insert(const Key& k) {
      if (2 * (count_ + 1) > keys_.size()) grow();
      const std::size_t mask = keys_.size() - 1;
      for (std::size_t i = hash(k) & mask;; i = (i + 1) & mask) {
        if (stamp_[i] != generation_) {
          stamp_[i] = generation_;
          keys_[i] = k;
          ++count_;
          return true;
        }
        if (keys_[i] == k) return false;
      }
    }

   private:
    static std::size_t hash(const Key& k) {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (const std::uint64_t v : k) h = (h ^ v) * 0xff51afd7ed558ccdull;
      return static_cast<std::size_t>(h ^ (h >> 29));
    }
    void grow() {
      std::vector<Key> old_keys = std::move(keys_);
      std::vector<std::uint32_t> old_stamp = std::move(stamp_);
      const std::size_t size = std::max<std::size_t>(256, 2 * old_keys.size());
      keys_.assign(size, Key{});
      stamp_.assign(size, 0u);
      const std::uint32_t g = generation_;
      generation_ = 1;
      count_ = 0;
      for (std::size_t i = 0; i < old_keys.size(); ++i) {
        if (old_stamp[i] == g) insert(old_keys[i]);
      }
    }
    std::vector<Key> keys_;
    std::vector<std::uint32_t> stamp_;
    std::uint32_t generation_ = 1;
    std::size_t count_ = 0;
  };
  KeySet failed_;
};

}  // namespace

LocalResult optimize_locally(TreeEvaluator& evaluator, const Bitmap& target,
                             const LocalOptions& options) {
  if (target.width() != evaluator.width() || target.height() != evaluator.height()) {
    throw Error("optimize_locally: the target's size differs from the evaluator's");
  }
  if (evaluator.tree().empty()) throw Error("optimize_locally: empty tree");
  if (!options.trust_settled) evaluator.unsettle_all();
  Optimizer opt(evaluator, target, options);
  LocalResult result;
  for (int j = 0; j < options.max_iterations; ++j) {
    bool visited = false;
    for (const int leaf : evaluator.tree().leaves()) {
      if (!evaluator.tree().node(leaf).settled.empty()) continue;
      visited = true;
      opt.adjust(leaf);
    }
    if (!visited) break;
    ++result.iterations;
  }
  if (options.prune) result.pruned = opt.prune();
  result.score = opt.full_score();
  return result;
}

}  // namespace fuzzycsg::trace
