// The global search (Fig. 1), its bookkeeping, morphing and variety, and the exactness of the
// local optimizer's skipping of settled leaves.
#include <gtest/gtest.h>

#include <filesystem>
#include <numeric>
#include <set>
#include <string>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/trace/search.hpp"

namespace fuzzycsg::trace {
namespace {

Bitmap render(const CsgTree& t, int width, int height) {
  return TreeEvaluator(t, width, height).result();
}

// A plate with a hole and a tab: a rectangle, less a circle, with a rectangle added.
Bitmap plate(int n) {
  CsgTree t;
  const int body = t.add_leaf({Shape::kRectangle, 30, 34, 1, 36, 28, 0});
  const int hole = t.add_leaf({Shape::kCircle, 30, 34, 8});
  const int cut = t.add_op(Op::kDifference, body, hole);
  const int tab = t.add_leaf({Shape::kRectangle, 50, 20, 1, 12, 30, 20});
  t.add_op(Op::kUnion, cut, tab);
  return render(t, n, n);
}

SearchOptions small_options() {
  SearchOptions o;
  o.population = 24;
  o.max_trees = 300;
  o.patience = 150;
  o.refocus = 20;
  o.initial_size = 4;
  o.statistics_window = 50;
  o.seed = 7;
  return o;
}

std::string structure(const CsgTree& t) {
  std::string s;
  for (const int n : t.post_order()) {
    const Node& node = t.node(n);
    s += node.leaf ? "L" : std::to_string(static_cast<int>(node.op));
    s += std::to_string(node.parent) + ",";
  }
  return s;
}

TEST(TraceSearch, OptionsOutOfRangeAreRefusedNamingTheField) {
  const auto refused = [](SearchOptions o, const std::string& field) {
    try {
      validate(o);
      ADD_FAILURE() << "accepted " << field;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  SearchOptions o;
  EXPECT_NO_THROW(validate(o));
  o.population = 0;
  refused(o, "population");
  o = {};
  o.probabilities = {0, 0, 0, 0};
  refused(o, "probabilities");
  o = {};
  o.probabilities[2] = -1;
  refused(o, "probabilities");
  o = {};
  o.local.k = -1;
  refused(o, "k");
  o = {};
  o.initial_size = 0.5;
  refused(o, "initial_size");
  o = {};
  o.population = 100000000;  // memory grows with population x pixels
  refused(o, "population");
  o = {};
  o.patience = 0;
  refused(o, "patience");
  o = {};
  o.batch = 0;
  refused(o, "batch");
}

TEST(TraceSearch, FindsAGoodTreeAndCountsItsEffort) {
  const int n = 64;
  const Bitmap target = plate(n);
  const SearchOptions o = small_options();
  const SearchResult r = search(target, o);
  const SearchStatistics& s = r.statistics;
  // The result is what its tree scores.
  const Score again = score(render(r.best, n, n), target, r.best.primitive_count(), o.local.k);
  EXPECT_EQ(again.total(), r.score.total());
  EXPECT_EQ(r.score.primitives, r.best.primitive_count());
  // Far better than the best single primitive could be, and no more primitives than the shape
  // has plus two.
  EXPECT_LT(r.score.mismatch(), target.count() / 10);
  EXPECT_LE(r.score.primitives, 5);
  // Bookkeeping.
  EXPECT_EQ(s.trees_evaluated, static_cast<std::uint64_t>(o.population + s.iterations));
  EXPECT_EQ(std::accumulate(s.tried.begin(), s.tried.end(), std::uint64_t{0}),
            static_cast<std::uint64_t>(s.iterations));
  std::array<std::uint64_t, 4> tried{}, improved{};
  for (const OperatorWindow& w : s.history) {
    EXPECT_LT(w.first_iteration, w.last_iteration);
    for (int k = 0; k < 4; ++k) {
      tried[k] += w.tried[k];
      improved[k] += w.improved[k];
    }
  }
  EXPECT_EQ(tried, s.tried);
  EXPECT_EQ(improved, s.improved);
  for (int k = 0; k < 4; ++k) EXPECT_LE(s.improved[k], s.tried[k]);
  EXPECT_GT(s.improved[static_cast<int>(Perturbation::kAdd)], 0u);
  ASSERT_FALSE(s.best_score.empty());
  for (std::size_t k = 1; k < s.best_score.size(); ++k) {
    EXPECT_LT(s.best_score[k].second, s.best_score[k - 1].second);
    EXPECT_GT(s.best_score[k].first, s.best_score[k - 1].first);
  }
  EXPECT_EQ(s.best_score.back().second, r.score.total());
  EXPECT_EQ(s.best_score.back().first, s.best_found_at);
  EXPECT_GT(s.tree_evaluations, s.trees_evaluated);
  EXPECT_GT(s.primitives_scanned, 0u);
  EXPECT_TRUE(std::string(s.stopped_by) == "patience" || std::string(s.stopped_by) == "max-trees");
}

TEST(TraceSearch, ASeedGivesTheSameTreeWhateverTheThreads) {
  const Bitmap target = plate(64);
  SearchOptions o = small_options();
  o.max_trees = 120;
  o.threads = 1;
  const SearchResult one = search(target, o);
  o.threads = 2;
  const SearchResult two = search(target, o);
  EXPECT_EQ(one.score.total(), two.score.total());
  EXPECT_EQ(structure(one.best), structure(two.best));
  EXPECT_EQ(render(one.best, 64, 64), render(two.best, 64, 64));
  EXPECT_EQ(one.statistics.tried, two.statistics.tried);
  // Another seed searches differently.
  o.seed = 8;
  const SearchResult other = search(target, o);
  EXPECT_NE(one.statistics.tree_evaluations, other.statistics.tree_evaluations);
}

TEST(TraceSearch, BatchOneIsTheSequentialSearchAndStopsOnPatience) {
  const Bitmap target = plate(48);
  SearchOptions o = small_options();
  o.batch = 1;
  o.patience = 20;
  o.max_trees = 5000;
  const SearchResult r = search(target, o);
  EXPECT_STREQ(r.statistics.stopped_by, "patience");
  EXPECT_LT(r.statistics.iterations, 5000);
  EXPECT_GE(r.statistics.iterations, 20);
}

TEST(TraceSearch, EmptyAndFullBitmaps) {
  Bitmap empty(20, 12);
  const SearchResult e = search(empty, small_options());
  EXPECT_EQ(e.score.mismatch(), 0);
  EXPECT_EQ(e.score.primitives, 1);
  EXPECT_STREQ(e.statistics.stopped_by, "empty");

  Bitmap full(20, 12);
  for (int r = 0; r < 12; ++r) full.set_span(r, 0, 20);
  const SearchResult f = search(full, small_options());
  EXPECT_LE(f.score.mismatch(), 4);
  EXPECT_LE(f.score.primitives, 2);

  Bitmap one(1, 1);
  one.set(0, 0);
  const SearchResult o = search(one, small_options());
  EXPECT_EQ(o.score.mismatch(), 0);
  EXPECT_EQ(o.score.primitives, 1);
}

TEST(TraceSearch, MorphKeepsTheTwoTreesStructurallyIdentical) {
  const int n = 48;
  CsgTree a_tree(Primitive{Shape::kCircle, 24, 24, 1, 1, 1, 0});
  a_tree.primitive(0).r = 14;
  CsgTree b_tree(Primitive{Shape::kRectangle, 22, 26, 1, 30, 16, 10});
  const Bitmap a = render(a_tree, n, n), b = render(b_tree, n, n);
  SearchOptions o = small_options();
  o.initial_size = 3;
  o.max_trees = 150;
  const MorphResult m = search_morph(a, b, o);
  EXPECT_EQ(structure(m.first), structure(m.second));
  EXPECT_EQ(m.first.primitive_count(), m.second.primitive_count());
  EXPECT_EQ(m.first_score.total(),
            score(render(m.first, n, n), a, m.first.primitive_count(), o.local.k).total());
  EXPECT_EQ(m.second_score.total(),
            score(render(m.second, n, n), b, m.second.primitive_count(), o.local.k).total());
  EXPECT_DOUBLE_EQ(m.score, (m.first_score.total() + m.second_score.total()) / 2);
  EXPECT_LT(m.first_score.mismatch(), a.count() / 8);
  EXPECT_LT(m.second_score.mismatch(), b.count() / 8);

  Bitmap other(40, 48);
  EXPECT_THROW(search_morph(a, other, o), InputError);
}

TEST(TraceSearch, VarietyKeepsDistinctTreesBestFirst) {
  const Bitmap target = plate(48);
  SearchOptions o = small_options();
  o.max_trees = 80;
  const Variety v = search_variety(target, o, 3);
  ASSERT_EQ(v.runs.size(), 3u);
  ASSERT_FALSE(v.distinct.empty());
  std::set<int> seen(v.distinct.begin(), v.distinct.end());
  EXPECT_EQ(seen.size(), v.distinct.size());
  for (std::size_t k = 1; k < v.distinct.size(); ++k) {
    EXPECT_LE(v.runs[static_cast<std::size_t>(v.distinct[k - 1])].score.total(),
              v.runs[static_cast<std::size_t>(v.distinct[k])].score.total());
  }
  // The best run is always kept, first.
  int best = 0;
  for (int r = 1; r < 3; ++r) {
    if (v.runs[static_cast<std::size_t>(r)].score.total() <
        v.runs[static_cast<std::size_t>(best)].score.total()) {
      best = r;
    }
  }
  EXPECT_EQ(v.runs[static_cast<std::size_t>(v.distinct[0])].score.total(),
            v.runs[static_cast<std::size_t>(best)].score.total());
  EXPECT_THROW(search_variety(target, o, 0), InputError);
}

// Skipping settled leaves gives exactly what adjusting every leaf gives.
TEST(TraceSearch, SettledLeavesAreSkippedExactly) {
  const int n = 64;
  const Bitmap target = plate(n);
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    SCOPED_TRACE(seed);
    Rng rng(seed);
    TreeEvaluator ev(random_tree(6, n, n, rng), n, n);
    LocalOptions o;
    o.prune = false;
    optimize_locally(ev, target, o);
    CsgTree settled = ev.tree();
    // An edit: one primitive moves; the pixels it covered and covers change.
    const std::vector<int> leaves = settled.leaves();
    const int leaf = leaves[seed % leaves.size()];
    const PixelBox before = pixel_box(settled.primitive(leaf), n, n);
    settled.primitive(leaf).x += 5;
    settled.primitive(leaf).r += 2;
    settled.primitive(leaf).w += 3;
    settled.settle(leaf, PixelBox{});
    settled.unsettle(before.joined(pixel_box(settled.primitive(leaf), n, n)));
    int kept = 0;
    for (const int l : settled.leaves()) kept += settled.node(l).settled.empty() ? 0 : 1;

    TreeEvaluator skipping(settled, n, n), full(settled, n, n);
    LocalOptions trusting = o;
    trusting.trust_settled = true;
    trusting.prune = true;
    LocalOptions every = o;
    every.prune = true;
    const LocalResult a = optimize_locally(skipping, target, trusting);
    const LocalResult b = optimize_locally(full, target, every);
    EXPECT_EQ(a.score.total(), b.score.total());
    EXPECT_EQ(structure(skipping.tree()), structure(full.tree()));
    EXPECT_EQ(skipping.result(), full.result());
    for (const int l : skipping.tree().leaves()) {
      EXPECT_EQ(skipping.tree().primitive(l), full.tree().primitive(l));
    }
    if (kept > 0) {
      EXPECT_LE(skipping.counters().trees_evaluated, full.counters().trees_evaluated);
    }
  }
}

}  // namespace
}  // namespace fuzzycsg::trace
