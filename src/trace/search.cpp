#include "fuzzycsg/trace/search.hpp"

#include <fmt/core.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <span>
#include <string>
#include <thread>
#include <utility>

#include "distance.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/limits.hpp"

namespace fuzzycsg::trace {

void validate(const SearchOptions& o) {
  const auto bad = [](const std::string& field, const std::string& why) {
    throw OptionError(field, why);
  };
  if (o.population < 1 || o.population > kMaxPopulation) {
    bad("population", fmt::format("must be in 1..{} (|S|)", kMaxPopulation));
  }
  if (o.max_trees < 0) bad("max_trees", "must not be negative (N)");
  if (o.patience < 1) bad("patience", "must be at least 1 (B)");
  if (o.refocus < 1) bad("refocus", "must be at least 1 (n)");
  const auto size = [&](double v, const char* field) {
    if (!(v >= 1 && v <= 1e4)) bad(field, "must be in [1, 10000]");
  };
  const auto spread = [&](double v, const char* field) {
    if (!(v >= 0 && v <= 1e4)) bad(field, "must be in [0, 10000]");
  };
  size(o.initial_size, "initial_size");
  spread(o.initial_sd, "initial_sd");
  size(o.added_size, "added_size");
  spread(o.added_sd, "added_sd");
  double sum = 0;
  for (const double p : o.probabilities) {
    if (!(p >= 0 && std::isfinite(p))) bad("probabilities", "must be finite and >= 0");
    sum += p;
  }
  if (!(sum > 0)) bad("probabilities", "must not all be zero");
  if (o.local.max_iterations < 1) bad("local.max_iterations", "must be at least 1 (M)");
  if (!(o.local.k >= 0 && std::isfinite(o.local.k))) bad("local.k", "must be finite and >= 0");
  check_threads(o.threads);
  if (o.batch < 1 || o.batch > kMaxPopulation) {
    bad("batch", fmt::format("must be in 1..{}", kMaxPopulation));
  }
  if (!(o.time_limit >= 0) || std::isnan(o.time_limit)) bad("time_limit", "must not be negative");
  if (o.statistics_window < 1) bad("statistics_window", "must be at least 1");
}

namespace {

using Clock = std::chrono::steady_clock;

// splitmix64: independent streams from (seed, index).
std::uint64_t mix(std::uint64_t a, std::uint64_t b) {
  std::uint64_t z = a + 0x9e3779b97f4a7c15ull * (b + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

int uniform_index(Rng& rng, std::size_t n) {
  return static_cast<int>(std::min<std::size_t>(
      n - 1, static_cast<std::size_t>(uniform01(rng) * static_cast<double>(n))));
}

PixelBox subtree_box(const CsgTree& t, int node, int width, int height) {
  PixelBox b;
  for (const int l : t.leaves(node)) b = b.joined(pixel_box(t.primitive(l), width, height));
  return b;
}

// A random live node of the tree, uniformly; `not_root`: any but the root (-1 if none).
int random_node(const CsgTree& t, Rng& rng, bool not_root) {
  std::vector<int> nodes = t.post_order();
  if (not_root) nodes.pop_back();  // the root is last in post-order
  if (nodes.empty()) return -1;
  return nodes[static_cast<std::size_t>(uniform_index(rng, nodes.size()))];
}

Perturbation draw_perturbation(const std::array<double, 4>& p, Rng& rng) {
  const double sum = p[0] + p[1] + p[2] + p[3];
  double u = uniform01(rng) * sum;
  for (int k = 0; k < 3; ++k) {
    if (u < p[static_cast<std::size_t>(k)]) return static_cast<Perturbation>(k);
    u -= p[static_cast<std::size_t>(k)];
  }
  return p[3] > 0 ? Perturbation::kMod : Perturbation::kCut;
}

// What the ADD operator needs of one target.
struct Placement {
  int width = 0, height = 0;
  Extrema extrema;
};

Placement make_placement(const Bitmap& target) {
  Placement p;
  p.width = target.width();
  p.height = target.height();
  p.extrema = distance_extrema(distance_map(target));
  return p;
}

// Places the primitives of a freshly drawn tree at extrema of the distance map: inside the
// shape for a union (`add`), outside it for a difference, sizes max(1, norm(d, d)). Without
// such extrema (an empty or full bitmap) the primitives keep their random placement.
void place(CsgTree& sub, const Placement& where, bool add, Rng& rng) {
  const std::vector<Extremum>& at = add ? where.extrema.maxima : where.extrema.minima;
  if (at.empty()) return;
  for (const int leaf : sub.leaves()) {
    const Extremum& e = at[static_cast<std::size_t>(uniform_index(rng, at.size()))];
    Primitive& p = sub.primitive(leaf);
    p.x = e.col + 0.5;
    p.y = e.row + 0.5;
    const auto size = [&] {
      return std::max(1.0, static_cast<double>(norm_count(e.distance, e.distance, rng, 1)));
    };
    p.r = size();
    p.w = size();
    p.h = size();
  }
}

// Counters of one candidate's production.
struct Effort {
  std::uint64_t evaluations = 0, scanned = 0;
  void add(const Counters& c) {
    evaluations += c.trees_evaluated;
    scanned += c.primitives_scanned;
  }
};

Score optimize(CsgTree& tree, const Bitmap& target, const LocalOptions& local, Effort& effort) {
  tree.compact();
  // One evaluator per thread, its node bitmaps reused from candidate to candidate.
  thread_local std::unique_ptr<TreeEvaluator> cached;
  if (!cached || cached->width() != target.width() || cached->height() != target.height()) {
    cached = std::make_unique<TreeEvaluator>(target.width(), target.height());
  }
  TreeEvaluator& ev = *cached;
  ev.counters() = Counters{};
  ev.set_tree(tree);
  LocalOptions o = local;
  o.trust_settled = true;
  const LocalResult r = optimize_locally(ev, target, o);
  effort.add(ev.counters());
  tree = ev.tree();
  tree.compact();
  return r.score;
}

// --- the two problems the hill climber solves

struct TraceProblem {
  struct Candidate {
    CsgTree tree;
    Score score;
    double total() const { return score.total(); }
  };

  const Bitmap& target;
  const SearchOptions& o;
  Placement where;

  Candidate initial(Rng& rng, Effort& effort) const {
    Candidate c;
    c.tree = random_tree(norm_count(o.initial_size, o.initial_sd, rng), target.width(),
                         target.height(), rng);
    c.score = optimize(c.tree, target, o.local, effort);
    return c;
  }

  Candidate perturb(const Candidate& from, Perturbation what, Rng& rng, Effort& effort) const {
    Candidate c{from.tree, {}};
    CsgTree& t = c.tree;
    const int w = target.width(), h = target.height();
    switch (what) {
      case Perturbation::kRep: {
        const int at = random_node(t, rng, false);
        const int e = t.primitive_count(at);
        const CsgTree sub = random_tree(norm_count(e, o.added_sd, rng), w, h, rng);
        const PixelBox changed = subtree_box(t, at, w, h).joined(subtree_box(sub, -1, w, h));
        t.replace_subtree(at, sub);
        t.unsettle(changed);
        break;
      }
      case Perturbation::kAdd: {
        const int at = random_node(t, rng, false);
        const bool add = uniform01(rng) < 0.5;
        CsgTree sub = random_tree(norm_count(o.added_size, o.added_sd, rng), w, h, rng);
        place(sub, where, add, rng);
        const PixelBox changed = subtree_box(sub, -1, w, h);
        t.add_subtree(at, add ? Op::kUnion : Op::kDifference, sub);
        t.unsettle(changed);
        break;
      }
      case Perturbation::kCut: {
        const int at = random_node(t, rng, true);
        if (at < 0) break;  // a single primitive: nothing to cut
        const PixelBox changed = subtree_box(t, t.node(at).parent, w, h);
        t.cut_subtree(at);
        t.unsettle(changed);
        break;
      }
      case Perturbation::kMod: {
        const std::vector<int> leaves = t.leaves();
        const int leaf = leaves[static_cast<std::size_t>(uniform_index(rng, leaves.size()))];
        PixelBox changed = pixel_box(t.primitive(leaf), w, h);
        t.toggle_shape(leaf);
        changed = changed.joined(pixel_box(t.primitive(leaf), w, h));
        t.unsettle(changed);
        break;
      }
    }
    c.score = optimize(t, target, o.local, effort);
    return c;
  }
};

struct MorphProblem {
  struct Candidate {
    CsgTree first, second;
    Score first_score, second_score;
    double total() const { return (first_score.total() + second_score.total()) / 2; }
  };

  const Bitmap& a;
  const Bitmap& b;
  const SearchOptions& o;
  Placement where_a, where_b;
  LocalOptions local;  // o.local without pruning

  void score_both(Candidate& c, Effort& effort) const {
    c.first_score = optimize(c.first, a, local, effort);
    c.second_score = optimize(c.second, b, local, effort);
  }

  Candidate initial(Rng& rng, Effort& effort) const {
    Candidate c;
    c.first =
        random_tree(norm_count(o.initial_size, o.initial_sd, rng), a.width(), a.height(), rng);
    c.second = c.first;
    score_both(c, effort);
    return c;
  }

  Candidate perturb(const Candidate& from, Perturbation what, Rng& rng, Effort& effort) const {
    Candidate c = from;
    const int w = a.width(), h = a.height();
    const auto unsettle = [&](CsgTree& t, int node, const CsgTree* sub) {
      PixelBox changed = node >= 0 ? subtree_box(t, node, w, h) : PixelBox{};
      if (sub) changed = changed.joined(subtree_box(*sub, -1, w, h));
      t.unsettle(changed);
    };
    switch (what) {
      case Perturbation::kRep: {
        const int at = random_node(c.first, rng, false);
        const int e = c.first.primitive_count(at);
        const CsgTree sub = random_tree(norm_count(e, o.added_sd, rng), w, h, rng);
        unsettle(c.first, at, &sub);
        unsettle(c.second, at, &sub);
        c.first.replace_subtree(at, sub);
        c.second.replace_subtree(at, sub);
        break;
      }
      case Perturbation::kAdd: {
        const int at = random_node(c.first, rng, false);
        const bool add = uniform01(rng) < 0.5;
        CsgTree sub_a = random_tree(norm_count(o.added_size, o.added_sd, rng), w, h, rng);
        CsgTree sub_b = sub_a;
        place(sub_a, where_a, add, rng);
        place(sub_b, where_b, add, rng);
        unsettle(c.first, -1, &sub_a);
        unsettle(c.second, -1, &sub_b);
        c.first.add_subtree(at, add ? Op::kUnion : Op::kDifference, sub_a);
        c.second.add_subtree(at, add ? Op::kUnion : Op::kDifference, sub_b);
        break;
      }
      case Perturbation::kCut: {
        const int at = random_node(c.first, rng, true);
        if (at < 0) break;
        const int parent = c.first.node(at).parent;
        unsettle(c.first, parent, nullptr);
        unsettle(c.second, parent, nullptr);
        c.first.cut_subtree(at);
        c.second.cut_subtree(at);
        break;
      }
      case Perturbation::kMod: {
        for (CsgTree* t : {&c.first, &c.second}) {
          const std::vector<int> leaves = t->leaves();
          const int leaf = leaves[static_cast<std::size_t>(uniform_index(rng, leaves.size()))];
          PixelBox changed = pixel_box(t->primitive(leaf), w, h);
          t->toggle_shape(leaf);
          changed = changed.joined(pixel_box(t->primitive(leaf), w, h));
          t->unsettle(changed);
        }
        break;
      }
    }
    score_both(c, effort);
    return c;
  }
};

// Fig. 1, in batches of distinct trees (see search.hpp).
template <class Problem>
typename Problem::Candidate hill_climb(const Problem& problem, const SearchOptions& o,
                                       SearchStatistics& stats) {
  using Candidate = typename Problem::Candidate;
  const auto t0 = Clock::now();
  const int threads = thread_count(o.threads);
  stats.threads = threads;
  tbb::task_arena arena(threads);
  const auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  const auto out_of_time = [&] { return o.time_limit > 0 && elapsed() >= o.time_limit; };

  const std::size_t size = static_cast<std::size_t>(o.population);
  std::vector<Candidate> set(size);
  std::vector<Effort> effort(std::max<std::size_t>(size, static_cast<std::size_t>(o.batch)));
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, size, [&](std::size_t k) {
      Rng rng(mix(o.seed, k));
      set[k] = problem.initial(rng, effort[k]);
    });
  });
  Candidate best;
  double best_total = HUGE_VAL;
  const auto account = [&](const Effort& e) {
    stats.tree_evaluations += e.evaluations;
    stats.primitives_scanned += e.scanned;
  };
  for (std::size_t k = 0; k < size; ++k) {
    account(effort[k]);
    ++stats.trees_evaluated;
    if (set[k].total() < best_total) {
      best_total = set[k].total();
      best = set[k];
      stats.best_found_at = stats.trees_evaluated;
      stats.best_score.emplace_back(stats.trees_evaluated, best_total);
    }
  }

  Rng chooser(mix(o.seed, 0xc0ffee));
  int i = 0, j = 0;
  stats.stopped_by = "max-trees";
  const int batch = std::min(o.batch, o.population);
  std::vector<int> picked;
  std::vector<Perturbation> kind;
  std::vector<Candidate> produced;
  bool done = false;
  while (!done) {
    if (i >= o.max_trees) break;
    if (j >= o.patience) {
      stats.stopped_by = "patience";
      break;
    }
    check_cancelled();
    if (out_of_time()) {
      stats.stopped_by = "time-limit";
      break;
    }
    // Iterations [i, end): up to the next refocusing (i mod n == 0 ends a batch).
    int end = std::min({i + batch, o.max_trees});
    const int next_refocus = ((i + o.refocus - 1) / o.refocus) * o.refocus;
    end = std::min(end, next_refocus + 1);
    if (end <= i) end = i + 1;
    const int count = end - i;
    picked.assign(static_cast<std::size_t>(count), -1);
    for (int m = 0; m < count; ++m) {
      int pick = 0;
      do {
        pick = uniform_index(chooser, size);
      } while (std::find(picked.begin(), picked.begin() + m, pick) != picked.begin() + m);
      picked[static_cast<std::size_t>(m)] = pick;
    }
    kind.assign(static_cast<std::size_t>(count), Perturbation::kRep);
    produced.assign(static_cast<std::size_t>(count), Candidate{});
    arena.execute([&] {
      tbb::parallel_for(0, count, [&](int m) {
        const std::size_t mm = static_cast<std::size_t>(m);
        Rng rng(mix(o.seed, 0x100000000ull + static_cast<std::uint64_t>(i + m)));
        kind[mm] = draw_perturbation(o.probabilities, rng);
        effort[mm] = Effort{};
        produced[mm] =
            problem.perturb(set[static_cast<std::size_t>(picked[mm])], kind[mm], rng, effort[mm]);
      });
    });
    for (int m = 0; m < count; ++m) {
      const std::size_t mm = static_cast<std::size_t>(m);
      if (i >= o.max_trees) break;
      if (j >= o.patience) {
        stats.stopped_by = "patience";
        done = true;
        break;
      }
      account(effort[mm]);
      ++stats.trees_evaluated;
      const std::size_t window = static_cast<std::size_t>(i / o.statistics_window);
      if (stats.history.size() <= window) {
        stats.history.resize(window + 1);
        for (std::size_t w = 0; w <= window; ++w) {
          stats.history[w].first_iteration = static_cast<int>(w) * o.statistics_window;
          stats.history[w].last_iteration = static_cast<int>(w + 1) * o.statistics_window;
        }
      }
      const std::size_t op = static_cast<std::size_t>(kind[mm]);
      ++stats.tried[op];
      ++stats.history[window].tried[op];
      Candidate& original = set[static_cast<std::size_t>(picked[mm])];
      if (produced[mm].total() < original.total()) {
        original = std::move(produced[mm]);
        j = 0;
        ++stats.improved[op];
        ++stats.history[window].improved[op];
        if (original.total() < best_total) {
          best_total = original.total();
          best = original;
          stats.best_found_at = stats.trees_evaluated;
          stats.best_score.emplace_back(stats.trees_evaluated, best_total);
        }
      } else {
        ++j;
      }
      if (i % o.refocus == 0) {
        std::vector<std::size_t> order(size);
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
          return set[x].total() < set[y].total();
        });
        std::vector<Candidate> sorted(size);
        for (std::size_t k = 0; k < size; ++k) sorted[k] = set[order[k]];
        for (std::size_t k = 0; k < size / 2; ++k) sorted[size - 1 - k] = sorted[k];
        set = std::move(sorted);
      }
      ++i;
    }
  }
  if (!stats.history.empty()) {
    stats.history.back().last_iteration = std::min(stats.history.back().last_iteration, i);
  }
  stats.iterations = i;
  stats.seconds = elapsed();
  return best;
}

}  // namespace

SearchResult search(const Bitmap& target, const SearchOptions& options) {
  validate(options);
  if (target.empty()) throw Error("trace::search: empty bitmap");
  SearchResult result;
  if (target.count() == 0) {
    // Nothing to cover: one small circle outside the picture.
    Primitive p;
    p.x = -1;
    p.y = -1;
    p.r = 0.5;
    result.best = CsgTree(p);
    TreeEvaluator ev(result.best, target.width(), target.height());
    result.score = score(ev.result(), target, 1, options.local.k);
    result.statistics.stopped_by = "empty";
    result.statistics.trees_evaluated = 1;
    result.statistics.best_found_at = 1;
    result.statistics.best_score.emplace_back(1, result.score.total());
    return result;
  }
  const TraceProblem problem{target, options, make_placement(target)};
  TraceProblem::Candidate best = hill_climb(problem, options, result.statistics);
  result.best = std::move(best.tree);
  result.best.compact();
  result.score = best.score;
  return result;
}

MorphResult search_morph(const Bitmap& first, const Bitmap& second, const SearchOptions& options) {
  validate(options);
  if (first.empty() || second.empty()) throw Error("trace::search_morph: empty bitmap");
  if (first.width() != second.width() || first.height() != second.height()) {
    throw InputError(fmt::format("morph: the bitmaps differ in size ({}x{} and {}x{})",
                                 first.width(), first.height(), second.width(), second.height()));
  }
  LocalOptions local = options.local;
  local.prune = false;
  const MorphProblem problem{first, second, options, make_placement(first), make_placement(second),
                             local};
  MorphResult result;
  MorphProblem::Candidate best = hill_climb(problem, options, result.statistics);
  result.first = std::move(best.first);
  result.second = std::move(best.second);
  result.first.compact();
  result.second.compact();
  result.first_score = best.first_score;
  result.second_score = best.second_score;
  result.score = best.total();
  return result;
}

namespace {

// Operators and primitive types in post-order.
std::string structure(const CsgTree& t) {
  std::string s;
  for (const int n : t.post_order()) {
    const Node& node = t.node(n);
    if (node.leaf) {
      s += node.prim.shape == Shape::kCircle ? 'c' : 'r';
    } else {
      s += "-*+"[static_cast<int>(node.op)];
    }
  }
  return s;
}

}  // namespace

Variety search_variety(const Bitmap& target, const SearchOptions& options, int runs,
                       double min_difference) {
  if (runs < 1) throw InputError("search option runs: must be at least 1");
  if (!(min_difference >= 0 && min_difference <= 1)) {
    throw InputError("search option min-difference: must be in [0, 1]");
  }
  Variety v;
  for (int r = 0; r < runs; ++r) {
    SearchOptions o = options;
    o.seed = options.seed + static_cast<std::uint64_t>(r);
    v.runs.push_back(search(target, o));
  }
  std::vector<int> order(v.runs.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) {
    return v.runs[static_cast<std::size_t>(x)].score.total() <
           v.runs[static_cast<std::size_t>(y)].score.total();
  });
  const double pixels = static_cast<double>(target.width()) * target.height();
  std::vector<Bitmap> kept;
  std::vector<std::string> kept_structure;
  for (const int r : order) {
    const CsgTree& t = v.runs[static_cast<std::size_t>(r)].best;
    TreeEvaluator ev(t, target.width(), target.height());
    const Bitmap& bits = ev.result();
    const std::string st = structure(t);
    bool distinct = true;
    for (std::size_t k = 0; k < kept.size() && distinct; ++k) {
      std::int64_t differ = 0;
      const std::span<const std::uint64_t> x = bits.words(), y = std::as_const(kept[k]).words();
      for (std::size_t i = 0; i < x.size(); ++i) differ += std::popcount(x[i] ^ y[i]);
      if (st == kept_structure[k] && static_cast<double>(differ) <= min_difference * pixels) {
        distinct = false;
      }
    }
    if (!distinct) continue;
    kept.push_back(bits);
    kept_structure.push_back(st);
    v.distinct.push_back(r);
  }
  return v;
}

}  // namespace fuzzycsg::trace
