#pragma once
// Global search of Gibson et al. 1997 (Fig. 1): parallel hill climbing with refocusing over a
// set S of candidate trees, each perturbation followed by the local optimizer
// (trace/optimize.hpp), and the morphing variant over pairs of structurally identical trees.
//
//   S <- |S| random trees of norm(a, s) primitives, each locally optimized and scored;
//   repeat while i < N and j < B:
//     perturb a randomly chosen tree of S (Table 1: REP 0.3, ADD 0.3, CUT 0.3, MOD 0.1),
//     locally optimize and score it; it replaces the original when its score is lower
//     (then j <- 0, else j <- j + 1);
//     every n iterations sort S by score and replace the worse half by copies of the better;
//     i <- i + 1.
//
// The perturbations:
//   REP  replaces a random subtree of e primitives by a random tree of norm(e, s') primitives;
//   ADD  unions (probability 1/2) or differences a random tree of norm(a', s') primitives with
//        a random subtree; each new primitive sits at a local maximum of the distance map
//        (trace/distance.hpp) inside the shape for a union, outside it for a difference,
//        chosen uniformly, and its sizes (r; or w and h) are max(1, norm(d, d)), d the map's
//        value there; its type, angle and operators as for random trees;
//   CUT  removes a random subtree (not the whole tree);
//   MOD  switches a random primitive between circle and rectangle (CsgTree::toggle_shape).
// A subtree is any node, chosen uniformly.
//
// Parallelism. The iterations are processed in batches of `batch` (a fixed number, not the
// number of threads) consecutive iterations that perturb distinct trees of S; the batch's
// candidates are optimized in parallel and then accepted or rejected in iteration order, with
// the counters and the refocusing of Fig. 1. Every iteration draws from its own random
// generator, seeded from (seed, iteration), so a seed gives the same result whatever the
// number of threads. With batch = 1 the search is exactly Fig. 1.
//
// Effort is counted as the paper counts it: a "tree evaluated" is a candidate produced and
// scored (the |S| initial trees and one per iteration); the local optimizer's own incremental
// evaluations and the primitives scan-converted are counted separately.

#include <array>
#include <cstdint>
#include <vector>

#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/csg.hpp"
#include "fuzzycsg/trace/evaluate.hpp"
#include "fuzzycsg/trace/optimize.hpp"

namespace fuzzycsg::trace {

enum class Perturbation : std::uint8_t { kRep, kAdd, kCut, kMod };
inline constexpr std::array<const char*, 4> kPerturbationNames{"REP", "ADD", "CUT", "MOD"};

struct SearchOptions {
  int population = 500;        // |S|
  int max_trees = 5000;        // N: iterations
  int patience = 500;          // B: iterations without improvement
  int refocus = 50;            // n
  double initial_size = 10.0;  // a
  double initial_sd = 2.0;     // s
  double added_size = 3.0;     // a'
  double added_sd = 1.5;       // s'
  // Table 1: REP, ADD, CUT, MOD (normalised to sum 1).
  std::array<double, 4> probabilities{0.3, 0.3, 0.3, 0.1};
  LocalOptions local;  // M (max_iterations) and k
  std::uint64_t seed = 1;
  int threads = 0;              // 0: every hardware thread
  int batch = 8;                // iterations optimized in parallel (see above)
  double time_limit = 0;        // seconds; 0: none
  int statistics_window = 100;  // iterations per row of SearchResult::history
};

// Throws InputError naming the field for values out of range (sizes < 1, probabilities
// negative or all zero, k < 0, ...).
void validate(const SearchOptions& options);

// The largest population (and batch) a search takes: each tree of the population keeps a
// picture-sized scan of its own, so memory grows with population x pixels.
inline constexpr int kMaxPopulation = 100000;

// The rate of improvement of each perturbation: of the candidates it produced in a window of
// iterations, the share that replaced the tree they came from.
struct OperatorWindow {
  int first_iteration = 0, last_iteration = 0;  // [first, last)
  std::array<std::uint64_t, 4> tried{}, improved{};
};

struct SearchStatistics {
  std::uint64_t trees_evaluated = 0;     // |S| + iterations (the paper's measure)
  std::uint64_t tree_evaluations = 0;    // every evaluation, the local optimizer's included
  std::uint64_t primitives_scanned = 0;  // primitive scan conversions
  int iterations = 0;
  // Why the search ended: "max-trees" (N), "patience" (B), "time-limit", or "empty" (an
  // empty bitmap, answered without a search).
  const char* stopped_by = "max-trees";
  std::uint64_t best_found_at = 0;  // trees evaluated when the best tree was first produced
  std::array<std::uint64_t, 4> tried{}, improved{};  // whole run, by Perturbation
  std::vector<OperatorWindow> history;
  std::vector<std::pair<std::uint64_t, double>> best_score;  // (trees evaluated, score)
  double seconds = 0;
  int threads = 1;
};

struct SearchResult {
  CsgTree best;  // compacted
  Score score;
  SearchStatistics statistics;
};

// The search on one bitmap. An empty bitmap gives a tree of one primitive outside the
// picture (score k); a full one is traced like any other.
SearchResult search(const Bitmap& target, const SearchOptions& options = {});

// Morphing (Gibson et al. 1997, "Application to geometric morphing"): candidates are pairs of
// structurally identical trees, the first fitted to `first`, the second to `second` (bitmaps
// of the same size). They start as copies; REP, ADD and CUT make the same change to both (ADD
// places each tree's new primitives by its own bitmap's distance map, the structure and types
// being the same); MOD and the local optimizer act on each tree independently, without
// pruning; the score is the mean of the two trees' scores. Node i of `first` corresponds to
// node i of `second` (same structure, same ids after compaction).
struct MorphResult {
  CsgTree first, second;
  Score first_score, second_score;
  double score = 0;  // the mean
  SearchStatistics statistics;
};
MorphResult search_morph(const Bitmap& first, const Bitmap& second,
                         const SearchOptions& options = {});

// Distinct results of several runs (seeds seed, seed + 1, ...): the best of each run, sorted
// by score, keeping a tree only when its bitmap differs from every kept tree's by more than
// `min_difference` pixels (the share of the picture's pixels, in [0, 1]) or it has a different
// structure (operators and primitive types in order).
struct Variety {
  std::vector<SearchResult> runs;  // in seed order
  std::vector<int> distinct;       // indices into runs, best first
};
Variety search_variety(const Bitmap& target, const SearchOptions& options, int runs,
                       double min_difference = 0.01);

}  // namespace fuzzycsg::trace
