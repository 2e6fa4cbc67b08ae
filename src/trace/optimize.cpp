#include "fuzzycsg/trace/optimize.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::trace {

PixelBox local_region(const Primitive& p, int width, int height, int margin) {
  const Box b = bounds(p);
  const double side = std::max(b.x1 - b.x0, b.y1 - b.y0);
  const int grown = std::max(margin, static_cast<int>(std::ceil(std::min(side, 1e6) / 4)));
  return grow(pixel_box(p, width, height), grown, width, height);
}

namespace {

class Optimizer {
 public:
  Optimizer(TreeEvaluator& ev, const Bitmap& target, const LocalOptions& o)
      : ev_(ev), target_(target), o_(o) {
    mismatch_ = current_mismatch();
  }

  std::int64_t mismatch() const { return mismatch_; }

  // Tries `p` for `leaf`: kept when the mismatch strictly decreases.
  bool attempt(int leaf, const Primitive& p) {
    const Primitive old = ev_.tree().primitive(leaf);
    ev_.update_primitive(leaf, p);
    const std::int64_t m = current_mismatch();
    if (m < mismatch_) {
      mismatch_ = m;
      return true;
    }
    ev_.update_primitive(leaf, old);
    return false;
  }

  LocalMismatch local(int leaf) const {
    const Primitive& p = ev_.tree().primitive(leaf);
    return local_mismatch(ev_.result(), target_,
                          local_region(p, ev_.width(), ev_.height(), o_.margin));
  }

  // Repeats `step(sign)` (the candidate for one step in direction sign) while it improves;
  // if the first step in direction `first` fails, tries -first. Returns the steps kept.
  //
  // A step may change no pixel at all (an edge that moves by less than the distance to the
  // next pixel centre), so a step that does not improve is tried again at twice and at four
  // times its size before the climb stops.
  template <class Step>
  int climb(int leaf, double first, Step step) {
    for (const double sign : {first, -first}) {
      int kept = 0;
      for (int s = 0; s < o_.max_steps; ++s) {
        bool improved = false;
        for (const double scale : {1.0, 2.0, 4.0}) {
          Primitive p = ev_.tree().primitive(leaf);
          if (!step(sign * scale, p)) break;
          if (attempt(leaf, p)) {
            improved = true;
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
      const LocalMismatch lm = local(leaf);
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
      for (const double fraction : {1.0, 0.5, 0.25}) {
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

  int prune() {
    int removed = 0;
    bool again = true;
    while (again && ev_.tree().primitive_count() > 1) {
      again = false;
      for (const int leaf : ev_.tree().leaves()) {
        CsgTree cut = ev_.tree();
        if (!cut.cut_subtree(leaf)) continue;
        cut.compact();
        const CsgTree before = ev_.tree();
        ev_.set_tree(cut);
        const std::int64_t m = current_mismatch();
        if (m <= mismatch_) {
          mismatch_ = m;
          ++removed;
          again = true;
          break;  // the leaves were renumbered
        }
        ev_.set_tree(before);
      }
    }
    return removed;
  }

  Score full_score() const {
    return score(ev_.result(), target_, ev_.tree().primitive_count(), o_.k);
  }

 private:
  std::int64_t current_mismatch() const { return score(ev_.result(), target_, 0, o_.k).mismatch(); }

  TreeEvaluator& ev_;
  const Bitmap& target_;
  const LocalOptions& o_;
  std::int64_t mismatch_ = 0;
};

}  // namespace

LocalResult optimize_locally(TreeEvaluator& evaluator, const Bitmap& target,
                             const LocalOptions& options) {
  if (target.width() != evaluator.width() || target.height() != evaluator.height()) {
    throw Error("optimize_locally: the target's size differs from the evaluator's");
  }
  if (evaluator.tree().empty()) throw Error("optimize_locally: empty tree");
  Optimizer opt(evaluator, target, options);
  LocalResult result;
  for (int j = 0; j < options.max_iterations; ++j) {
    const std::int64_t before = opt.mismatch();
    for (const int leaf : evaluator.tree().leaves()) {
      opt.shift(leaf);
      opt.resize(leaf);
      opt.rotate(leaf);
    }
    ++result.iterations;
    if (opt.mismatch() >= before) break;
  }
  if (options.prune) result.pruned = opt.prune();
  result.score = opt.full_score();
  return result;
}

}  // namespace fuzzycsg::trace
