#include "convert/search.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <memory>

#include "fuzzycsg/core/limits.hpp"

namespace fuzzycsg::convert {

namespace {

using Cells = std::vector<std::uint32_t>;

// Cells [lo, hi] (inclusive) along one axis whose centres lie in [a, b], and the offsets.
struct AxisRange {
  int lo = 0, hi = -1;
  double a = 0, b = 0;
};

AxisRange axis_range(const LabelGrid& g, int axis, double a, double b) {
  AxisRange r;
  r.a = a;
  r.b = b;
  const double u0 = (a - g.origin[axis]) / g.cell - 0.5, u1 = (b - g.origin[axis]) / g.cell - 0.5;
  r.lo = std::max(0, static_cast<int>(std::ceil(u0 - 1e-9)));
  r.hi = std::min(g.n[static_cast<std::size_t>(axis)] - 1, static_cast<int>(std::floor(u1 + 1e-9)));
  return r;
}

// Every distinct cell range between two offsets along an axis, with the pair of offsets closest
// together that gives it.
std::vector<AxisRange> axis_ranges(const LabelGrid& g, int axis, std::vector<double> offsets) {
  std::sort(offsets.begin(), offsets.end());
  offsets.erase(std::unique(offsets.begin(), offsets.end()), offsets.end());
  std::map<std::pair<int, int>, AxisRange> unique;
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    for (std::size_t j = i + 1; j < offsets.size(); ++j) {
      const AxisRange r = axis_range(g, axis, offsets[i], offsets[j]);
      if (r.lo > r.hi) continue;
      auto [it, inserted] = unique.try_emplace({r.lo, r.hi}, r);
      if (!inserted && r.b - r.a < it->second.b - it->second.a) it->second = r;
    }
  }
  std::vector<AxisRange> out;
  out.reserve(unique.size());
  for (const auto& [key, r] : unique) out.push_back(r);
  return out;
}

Solid frame_box(const LabelGrid& g, const std::array<AxisRange, 3>& r) {
  Solid s;
  s.kind = SolidKind::kBox;
  s.rotation = g.frame;
  const Eigen::Vector3d lo(r[0].a, r[1].a, r[2].a), hi(r[0].b, r[1].b, r[2].b);
  s.centre = g.frame * (0.5 * (lo + hi));
  s.size = hi - lo;
  return s;
}

// The cells whose centres a solid contains.
Cells cells_of(const LabelGrid& g, const Solid& s) {
  std::array<int, 3> lo{0, 0, 0}, hi{g.n[0] - 1, g.n[1] - 1, g.n[2] - 1};
  if (s.kind != SolidKind::kHalfSpace) {
    // The solid's bounding box in frame coordinates, from the corners of its local box.
    const Eigen::AlignedBox3d local = s.local_bounds();
    Eigen::AlignedBox3d box;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d corner = local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
      box.extend(g.frame.transpose() * (s.rotation * corner + s.centre));
    }
    for (int a = 0; a < 3; ++a) {
      const AxisRange r = axis_range(g, a, box.min()[a], box.max()[a]);
      lo[static_cast<std::size_t>(a)] = r.lo;
      hi[static_cast<std::size_t>(a)] = r.hi;
    }
  }
  Cells cells;
  for (int k = lo[2]; k <= hi[2]; ++k) {
    for (int j = lo[1]; j <= hi[1]; ++j) {
      for (int i = lo[0]; i <= hi[0]; ++i) {
        if (s.contains(g.centre_world(i, j, k))) {
          cells.push_back(static_cast<std::uint32_t>(g.index(i, j, k)));
        }
      }
    }
  }
  return cells;
}

// Inclusive prefix sums over cells [0, i) x [0, j) x [0, k).
class SummedTable {
 public:
  SummedTable(const LabelGrid& g, const std::vector<std::int8_t>& w)
      : n0_(g.n[0] + 1), n1_(g.n[1] + 1), sum_(static_cast<std::size_t>(n0_) * n1_ * (g.n[2] + 1)) {
    for (int k = 0; k < g.n[2]; ++k) {
      for (int j = 0; j < g.n[1]; ++j) {
        long long row = 0;
        for (int i = 0; i < g.n[0]; ++i) {
          row += w[g.index(i, j, k)];
          at(i + 1, j + 1, k + 1) =
              row + at(i + 1, j, k + 1) + at(i + 1, j + 1, k) - at(i + 1, j, k);
        }
      }
    }
  }
  // Sum over cells [r0.lo, r0.hi] x [r1.lo, r1.hi] x [r2.lo, r2.hi].
  long long box(const AxisRange& r0, const AxisRange& r1, const AxisRange& r2) const {
    const int x0 = r0.lo, x1 = r0.hi + 1, y0 = r1.lo, y1 = r1.hi + 1, z0 = r2.lo, z1 = r2.hi + 1;
    return get(x1, y1, z1) - get(x0, y1, z1) - get(x1, y0, z1) - get(x1, y1, z0) + get(x0, y0, z1) +
           get(x0, y1, z0) + get(x1, y0, z0) - get(x0, y0, z0);
  }

 private:
  long long& at(int i, int j, int k) {
    return sum_[(static_cast<std::size_t>(k) * n1_ + j) * n0_ + i];
  }
  long long get(int i, int j, int k) const {
    return sum_[(static_cast<std::size_t>(k) * n1_ + j) * n0_ + i];
  }
  int n0_, n1_;
  std::vector<long long> sum_;
};

struct CellCandidate {
  Solid solid;
  Cells cells;
};

struct ScoredMove {
  long long gain = 0;
  Move move = Move::kUnion;
  // A union placed second in the chain, before every carving step after the first solid: its
  // cells are those of the solid that the later differences and intersections leave (the arms
  // of a cross added before the holes through them are cut, rather than in pieces around them).
  bool early = false;
  int solid = -1;                  // index into the listed candidates, or -1 for a frame box
  std::array<AxisRange, 3> box{};  // the frame box
};

// Keeps the `size` best moves, in order of gain and then of arrival.
class TopMoves {
 public:
  explicit TopMoves(int size) : size_(static_cast<std::size_t>(std::max(1, size))) {}
  void offer(const ScoredMove& m) {
    if (moves_.size() == size_ && m.gain <= moves_.back().gain) return;
    auto at =
        std::upper_bound(moves_.begin(), moves_.end(), m,
                         [](const ScoredMove& a, const ScoredMove& b) { return a.gain > b.gain; });
    moves_.insert(at, m);
    if (moves_.size() > size_) moves_.pop_back();
  }
  const std::vector<ScoredMove>& moves() const { return moves_; }

 private:
  std::size_t size_;
  std::vector<ScoredMove> moves_;
};

// Applies a move to the state (1 inside the chain's solid so far).
void apply(const LabelGrid& g, Move move, const Cells& cells, std::vector<std::uint8_t>& state) {
  if (move == Move::kUnion) {
    for (const std::uint32_t c : cells) state[c] = 1;
  } else if (move == Move::kDifference) {
    for (const std::uint32_t c : cells) state[c] = 0;
  } else {
    std::vector<std::uint8_t> keep(g.size(), 0);
    for (const std::uint32_t c : cells) keep[c] = 1;
    for (std::size_t c = 0; c < g.size(); ++c) state[c] = state[c] & keep[c];
  }
}

long long error_of(const LabelGrid& g, const std::vector<std::uint8_t>& state) {
  long long e = 0;
  for (std::size_t c = 0; c < g.size(); ++c) {
    if (g.label[c] != 2 && g.label[c] != state[c]) ++e;
  }
  return e;
}

Cells box_cells(const LabelGrid& g, const std::array<AxisRange, 3>& r) {
  Cells cells;
  for (int k = r[2].lo; k <= r[2].hi; ++k) {
    for (int j = r[1].lo; j <= r[1].hi; ++j) {
      for (int i = r[0].lo; i <= r[0].hi; ++i) {
        cells.push_back(static_cast<std::uint32_t>(g.index(i, j, k)));
      }
    }
  }
  return cells;
}

class Greedy {
 public:
  Greedy(const LabelGrid& g, const Candidates& candidates, const SearchOptions& options)
      : g_(g), options_(options) {
    for (int a = 0; a < 3; ++a) {
      ranges_[static_cast<std::size_t>(a)] =
          axis_ranges(g, a, candidates.box_offsets[static_cast<std::size_t>(a)]);
    }
    for (const Solid& s : candidates.solids) {
      Cells cells = cells_of(g, s);
      if (!cells.empty()) listed_.push_back({s, std::move(cells)});
    }
    inside_ = static_cast<long long>(g.count(1));
    min_gain_ = std::max(
        options.min_gain_cells,
        static_cast<long long>(std::ceil(options.min_gain * static_cast<double>(inside_))));
  }

  long long min_gain() const { return min_gain_; }
  long long inside() const { return inside_; }

  // The first moves worth starting from: the union of each listed solid and of the best frame
  // box, whatever their gain (a part that is mostly holes gains little from its outer shape
  // alone), at most `count`, best first; and the frame box around the whole part, which a part
  // that is mostly carved away (a cube less a large ball) loses cells by and starts from.
  std::vector<ScoredMove> first_moves(int count) const {
    const std::vector<std::uint8_t> empty(g_.size(), 0);
    const Weights w(g_, empty, nullptr);
    TopMoves boxes(1), listed(count);
    offer_boxes(w, boxes);
    offer_listed(w, listed);
    std::vector<ScoredMove> moves = listed.moves();
    moves.insert(moves.begin(), boxes.moves().begin(), boxes.moves().end());
    std::stable_sort(moves.begin(), moves.end(),
                     [](const ScoredMove& a, const ScoredMove& b) { return a.gain > b.gain; });
    if (moves.size() > static_cast<std::size_t>(count))
      moves.resize(static_cast<std::size_t>(count));
    if (const std::optional<ScoredMove> hull = hull_box(w.wu)) {
      const bool listed_already = std::any_of(moves.begin(), moves.end(), [&](const ScoredMove& m) {
        return m.solid < 0 && m.box[0].lo == hull->box[0].lo && m.box[0].hi == hull->box[0].hi &&
               m.box[1].lo == hull->box[1].lo && m.box[1].hi == hull->box[1].hi &&
               m.box[2].lo == hull->box[2].lo && m.box[2].hi == hull->box[2].hi;
      });
      if (!listed_already) moves.push_back(*hull);
    }
    return moves;
  }

  // The smallest frame box of the listed offsets that holds every inside cell, as a union
  // (`wu`: the cells' gains for a union).
  std::optional<ScoredMove> hull_box(const std::vector<std::int8_t>& wu) const {
    std::array<int, 3> lo{g_.n[0], g_.n[1], g_.n[2]}, hi{-1, -1, -1};
    for (int k = 0; k < g_.n[2]; ++k) {
      for (int j = 0; j < g_.n[1]; ++j) {
        for (int i = 0; i < g_.n[0]; ++i) {
          if (g_.label[g_.index(i, j, k)] != 1) continue;
          const std::array<int, 3> at{i, j, k};
          for (std::size_t a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], at[a]);
            hi[a] = std::max(hi[a], at[a]);
          }
        }
      }
    }
    ScoredMove m;
    for (std::size_t a = 0; a < 3; ++a) {
      const AxisRange* best = nullptr;
      for (const AxisRange& r : ranges_[a]) {
        if (r.lo <= lo[a] && r.hi >= hi[a] && (!best || r.hi - r.lo < best->hi - best->lo)) {
          best = &r;
        }
      }
      if (!best) return std::nullopt;
      m.box[a] = *best;
    }
    m.gain = 0;
    for (const std::uint32_t c : box_cells(g_, m.box)) m.gain += wu[c];
    m.move = Move::kUnion;
    return m;
  }

  // One greedy descent; `random` picks among the best moves (restarts), else the best. `first`:
  // the first move, taken whatever its gain.
  std::vector<ChainStep> run(std::mt19937_64* random, const ScoredMove* first = nullptr) const {
    std::vector<std::uint8_t> state(g_.size(), 0);
    // The cells that the steps after the first leave standing (differences and intersections
    // take theirs away): what an early union can add.
    std::vector<std::uint8_t> survive(g_.size(), 1);
    bool carved = false;
    std::vector<ChainStep> steps;
    for (int step = 0; step < options_.max_steps; ++step) {
      check_cancelled();
      if (step > 0 && options_.deadline && std::chrono::steady_clock::now() > *options_.deadline) {
        break;
      }
      ScoredMove chosen;
      if (step == 0 && first) {
        chosen = *first;
      } else {
        const Weights w(g_, state, carved ? &survive : nullptr);
        TopMoves top(random ? options_.top_moves : 1);
        offer_boxes(w, top);
        offer_listed(w, top);
        if (top.moves().empty() || top.moves().front().gain < min_gain_) break;
        chosen = pick(top, random);
      }
      ChainStep s;
      s.move = chosen.move;
      s.gain = chosen.gain;
      const Cells* cells = nullptr;
      Cells box;
      if (chosen.solid >= 0) {
        const CellCandidate& c = listed_[static_cast<std::size_t>(chosen.solid)];
        s.solid = c.solid;
        cells = &c.cells;
      } else {
        s.solid = frame_box(g_, chosen.box);
        box = box_cells(g_, chosen.box);
        cells = &box;
      }
      if (chosen.early) {
        for (const std::uint32_t c : *cells) state[c] = state[c] | survive[c];
        steps.insert(steps.begin() + 1, std::move(s));
        continue;
      }
      apply(g_, s.move, *cells, state);
      if (step > 0 && s.move != Move::kUnion) {
        carved = true;
        apply(g_, s.move, *cells, survive);
      }
      steps.push_back(std::move(s));
    }
    return steps;
  }

 private:
  // Per cell, what each move would put right (+1) or wrong (-1): a union where the chain's solid
  // is not, a difference where it is; and the cells of the target that the solid holds (which a
  // difference or an intersection may lose).
  // `survive` (when something was carved after the first solid): the cells an early union adds,
  // weighed in we.
  struct Weights {
    std::vector<std::int8_t> wu, wd, wt, we;
    long long total_d = 0, total_t = 0;
    bool any = false;
    Weights(const LabelGrid& g, const std::vector<std::uint8_t>& state,
            const std::vector<std::uint8_t>* survive)
        : wu(g.size()), wd(g.size()), wt(g.size()) {
      if (survive) we.resize(g.size());
      for (std::size_t c = 0; c < g.size(); ++c) {
        const std::uint8_t l = g.label[c];
        const bool in = state[c] != 0;
        any = any || in;
        wu[c] = static_cast<std::int8_t>(l == 2 || in ? 0 : (l == 1 ? 1 : -1));
        if (survive) we[c] = (*survive)[c] ? wu[c] : std::int8_t{0};
        wd[c] = static_cast<std::int8_t>(l == 2 || !in ? 0 : (l == 1 ? -1 : 1));
        wt[c] = static_cast<std::int8_t>(in && l == 1 ? 1 : 0);
        total_d += wd[c];
        total_t += wt[c];
      }
    }
  };

  // A difference or intersection that takes away more than `max_loss` of the target's cells
  // that the chain holds undoes the chain rather than carving it: not offered.
  bool keeps_enough(const Weights& w, long long lost) const {
    return static_cast<double>(lost) <= options_.max_loss * static_cast<double>(w.total_t);
  }

  void offer_carving(const Weights& w, long long d, long long t, ScoredMove m,
                     TopMoves& top) const {
    if (!w.any) return;
    if (keeps_enough(w, t)) {
      m.gain = d;
      m.move = Move::kDifference;
      top.offer(m);
    }
    if (keeps_enough(w, w.total_t - t)) {
      m.gain = w.total_d - d;
      m.move = Move::kIntersection;
      top.offer(m);
    }
  }

  // An early union is offered only where it gains more than the same union at the end.
  static void offer_early(long long gain, ScoredMove m, TopMoves& top) {
    if (gain <= m.gain) return;
    m.gain = gain;
    m.early = true;
    top.offer(m);
  }

  void offer_boxes(const Weights& w, TopMoves& top) const {
    const SummedTable su(g_, w.wu), sd(g_, w.wd), st(g_, w.wt);
    const std::unique_ptr<const SummedTable> se =
        w.we.empty() ? nullptr : std::make_unique<const SummedTable>(g_, w.we);
    for (const AxisRange& r2 : ranges_[2]) {
      for (const AxisRange& r1 : ranges_[1]) {
        for (const AxisRange& r0 : ranges_[0]) {
          ScoredMove m;
          m.box = {r0, r1, r2};
          m.gain = su.box(r0, r1, r2);
          m.move = Move::kUnion;
          top.offer(m);
          if (se) offer_early(se->box(r0, r1, r2), m, top);
          if (w.any) offer_carving(w, sd.box(r0, r1, r2), st.box(r0, r1, r2), m, top);
        }
      }
    }
  }

  void offer_listed(const Weights& w, TopMoves& top) const {
    for (std::size_t i = 0; i < listed_.size(); ++i) {
      long long u = 0, d = 0, t = 0, e = 0;
      for (const std::uint32_t c : listed_[i].cells) {
        u += w.wu[c];
        d += w.wd[c];
        t += w.wt[c];
        if (!w.we.empty()) e += w.we[c];
      }
      ScoredMove m;
      m.solid = static_cast<int>(i);
      m.gain = u;
      m.move = Move::kUnion;
      top.offer(m);
      if (!w.we.empty()) offer_early(e, m, top);
      offer_carving(w, d, t, m, top);
    }
  }

  ScoredMove pick(const TopMoves& top, std::mt19937_64* random) const {
    const auto& moves = top.moves();
    if (!random) return moves.front();
    const double floor = (1.0 - options_.tolerance) * static_cast<double>(moves.front().gain);
    std::size_t n = 0;
    while (n < moves.size() && static_cast<double>(moves[n].gain) >= floor &&
           moves[n].gain >= min_gain_) {
      ++n;
    }
    std::uniform_int_distribution<std::size_t> pick(0, std::max<std::size_t>(n, 1) - 1);
    return moves[pick(*random)];
  }

  const LabelGrid& g_;
  const SearchOptions& options_;
  std::array<std::vector<AxisRange>, 3> ranges_;
  std::vector<CellCandidate> listed_;
  long long inside_ = 0, min_gain_ = 1;
};

// Drops steps whose removal costs fewer than `min_gain` cells, the cheapest first, until none.
std::vector<ChainStep> eliminate(const LabelGrid& g, std::vector<ChainStep> steps,
                                 long long min_gain) {
  std::vector<Cells> cells;
  cells.reserve(steps.size());
  for (const ChainStep& s : steps) cells.push_back(cells_of(g, s.solid));
  const auto error_without = [&](std::size_t skip) {
    std::vector<std::uint8_t> state(g.size(), 0);
    for (std::size_t i = 0; i < steps.size(); ++i) {
      if (i != skip) apply(g, steps[i].move, cells[i], state);
    }
    return error_of(g, state);
  };
  long long error = error_without(steps.size());
  for (;;) {
    long long best_cost = std::numeric_limits<long long>::max();
    std::size_t best = steps.size();
    for (std::size_t i = 0; i < steps.size(); ++i) {
      const long long cost = error_without(i) - error;
      if (cost < best_cost) {
        best_cost = cost;
        best = i;
      }
    }
    if (best == steps.size() || best_cost >= min_gain) return steps;
    steps.erase(steps.begin() + static_cast<std::ptrdiff_t>(best));
    cells.erase(cells.begin() + static_cast<std::ptrdiff_t>(best));
    error += best_cost;
  }
}

}  // namespace

std::size_t LabelGrid::count(std::uint8_t value) const {
  return static_cast<std::size_t>(std::count(label.begin(), label.end(), value));
}

LabelGrid make_label_grid(const Target& target, const Eigen::Matrix3d& frame,
                          const Eigen::AlignedBox3d& bounds, int resolution, int margin_cells) {
  LabelGrid g;
  g.frame = frame;
  const Eigen::Vector3d extent = bounds.sizes();
  g.cell = std::max(extent.maxCoeff(), 1e-9) / static_cast<double>(std::max(resolution, 1));
  for (int a = 0; a < 3; ++a) {
    const int cells = static_cast<int>(std::ceil(extent[a] / g.cell - 1e-9)) + 2 * margin_cells;
    g.n[static_cast<std::size_t>(a)] = std::max(cells, 1);
    // Centred on the bounds.
    g.origin[a] = bounds.center()[a] - 0.5 * g.cell * g.n[static_cast<std::size_t>(a)];
  }
  const std::size_t total = static_cast<std::size_t>(g.n[0]) * g.n[1] * g.n[2];
  std::vector<float> points(3 * total), inside(total);
  for (int k = 0; k < g.n[2]; ++k) {
    for (int j = 0; j < g.n[1]; ++j) {
      for (int i = 0; i < g.n[0]; ++i) {
        const Eigen::Vector3d p = g.centre_world(i, j, k);
        const std::size_t c = g.index(i, j, k);
        for (int a = 0; a < 3; ++a)
          points[3 * c + static_cast<std::size_t>(a)] = static_cast<float>(p[a]);
      }
    }
  }
  target.occupancy(points, inside);
  g.label.resize(total);
  for (std::size_t c = 0; c < total; ++c) g.label[c] = inside[c] >= 0.5f ? 1 : 0;
  return g;
}

std::vector<LabelGrid> split_components(const LabelGrid& grid, std::size_t min_cells,
                                        int margin_cells, std::size_t& dropped_cells) {
  dropped_cells = 0;
  std::vector<int> component(grid.size(), -1);
  struct Found {
    std::vector<std::uint32_t> cells;
    std::array<int, 3> lo{}, hi{};
  };
  std::vector<Found> found;
  const auto coords = [&](std::size_t c) {
    const int i = static_cast<int>(c % static_cast<std::size_t>(grid.n[0]));
    const std::size_t rest = c / static_cast<std::size_t>(grid.n[0]);
    return std::array<int, 3>{i, static_cast<int>(rest % static_cast<std::size_t>(grid.n[1])),
                              static_cast<int>(rest / static_cast<std::size_t>(grid.n[1]))};
  };
  for (std::size_t start = 0; start < grid.size(); ++start) {
    if (grid.label[start] != 1 || component[start] >= 0) continue;
    Found f;
    f.lo = coords(start);
    f.hi = f.lo;
    const int id = static_cast<int>(found.size());
    std::deque<std::uint32_t> queue{static_cast<std::uint32_t>(start)};
    component[start] = id;
    while (!queue.empty()) {
      const std::uint32_t c = queue.front();
      queue.pop_front();
      f.cells.push_back(c);
      const std::array<int, 3> p = coords(c);
      for (int a = 0; a < 3; ++a) {
        f.lo[static_cast<std::size_t>(a)] =
            std::min(f.lo[static_cast<std::size_t>(a)], p[static_cast<std::size_t>(a)]);
        f.hi[static_cast<std::size_t>(a)] =
            std::max(f.hi[static_cast<std::size_t>(a)], p[static_cast<std::size_t>(a)]);
        for (int d = -1; d <= 1; d += 2) {
          std::array<int, 3> q = p;
          q[static_cast<std::size_t>(a)] += d;
          if (q[static_cast<std::size_t>(a)] < 0 ||
              q[static_cast<std::size_t>(a)] >= grid.n[static_cast<std::size_t>(a)])
            continue;
          const std::size_t qc = grid.index(q[0], q[1], q[2]);
          if (grid.label[qc] == 1 && component[qc] < 0) {
            component[qc] = id;
            queue.push_back(static_cast<std::uint32_t>(qc));
          }
        }
      }
    }
    found.push_back(std::move(f));
  }
  std::vector<LabelGrid> out;
  for (std::size_t id = 0; id < found.size(); ++id) {
    const Found& f = found[id];
    if (f.cells.size() < min_cells) {
      dropped_cells += f.cells.size();
      continue;
    }
    if (found.size() == 1) {
      out.push_back(grid);
      break;
    }
    LabelGrid sub;
    sub.frame = grid.frame;
    sub.cell = grid.cell;
    std::array<int, 3> lo{}, hi{};
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = std::max(0, f.lo[a] - margin_cells);
      hi[a] = std::min(grid.n[a] - 1, f.hi[a] + margin_cells);
      sub.n[a] = hi[a] - lo[a] + 1;
      sub.origin[static_cast<Eigen::Index>(a)] =
          grid.origin[static_cast<Eigen::Index>(a)] + lo[a] * grid.cell;
    }
    sub.label.resize(static_cast<std::size_t>(sub.n[0]) * sub.n[1] * sub.n[2]);
    for (int k = 0; k < sub.n[2]; ++k) {
      for (int j = 0; j < sub.n[1]; ++j) {
        for (int i = 0; i < sub.n[0]; ++i) {
          const std::size_t c = grid.index(i + lo[0], j + lo[1], k + lo[2]);
          std::uint8_t l = grid.label[c];
          if (l == 1 && component[c] != static_cast<int>(id)) l = 2;
          sub.label[sub.index(i, j, k)] = l;
        }
      }
    }
    out.push_back(std::move(sub));
  }
  return out;
}

std::string_view move_name(Move move) {
  switch (move) {
    case Move::kUnion:
      return "union";
    case Move::kDifference:
      return "difference";
    case Move::kIntersection:
      return "intersection";
  }
  return "?";
}

long long chain_error(const LabelGrid& g, const std::vector<ChainStep>& steps) {
  std::vector<std::uint8_t> state(g.size(), 0);
  for (const ChainStep& s : steps) apply(g, s.move, cells_of(g, s.solid), state);
  return error_of(g, state);
}

Chain search_chain(const LabelGrid& grid, const Candidates& candidates,
                   const SearchOptions& options) {
  const Greedy greedy(grid, candidates, options);
  // Runs: the greedy descent, one from each first move, and the random restarts.
  const std::vector<ScoredMove> firsts = greedy.first_moves(options.first_moves);
  const int fixed = 1 + static_cast<int>(firsts.size());
  const int runs = fixed + std::max(0, options.restarts);
  std::vector<Chain> chains(static_cast<std::size_t>(runs));
  tbb::parallel_for(0, runs, [&](int r) {
    std::mt19937_64 random(options.seed * 1000003ULL + static_cast<std::uint64_t>(r));
    const ScoredMove* first =
        r >= 1 && r < fixed ? &firsts[static_cast<std::size_t>(r - 1)] : nullptr;
    std::vector<ChainStep> steps = greedy.run(r < fixed ? nullptr : &random, first);
    steps = eliminate(grid, std::move(steps), greedy.min_gain());
    Chain& c = chains[static_cast<std::size_t>(r)];
    c.error = chain_error(grid, steps);
    c.steps = std::move(steps);
    c.inside = greedy.inside();
  });
  const auto score = [&](const Chain& c) {
    return c.error + greedy.min_gain() * static_cast<long long>(c.steps.size());
  };
  std::size_t best = 0;
  for (std::size_t r = 1; r < chains.size(); ++r) {
    if (score(chains[r]) < score(chains[best])) best = r;
  }
  return chains[best];
}

}  // namespace fuzzycsg::convert
