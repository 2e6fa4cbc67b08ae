// trace_search_bench: one run of the global search of Gibson et al. 1997 with Table 2's
// defaults (|S| 500, N 5000, B 500, n 50, a 10, s 2, a' 3, s' 1.5, M 80, k 25) on a glyph,
// with every hardware thread and then with one thread, the baseline. A seed gives the same
// tree whatever the number of threads; the bench checks that and prints the ratio.
//
//   trace_search_bench [picture] [seed] [runs]
//   trace_search_bench --glyphs [threads]
//
// Defaults: the 128x128 glyph P of the data collection's glyphs/ (bench/data_dir.hpp), seed 1, 3
// runs of each (medians).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_lists.hpp"
#include "bench/data_dir.hpp"
#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/search.hpp"

using namespace fuzzycsg::trace;

using fuzzycsg::bench::median;

// --glyphs: the search on the paper's letters P, E, b, i (DejaVu Sans Bold), seeds 1 and 2,
// one thread each: score, primitives, effort and time, a row per run.
int glyph_table(int threads) {
  const std::filesystem::path dir = fuzzycsg::bench::data_file("glyphs");
  std::printf(
      "| glyph | seed | score | excess | uncovered | primitives | trees evaluated | "
      "best at | evaluations | s |\n|---|---|---|---|---|---|---|---|---|---|\n");
  double total = 0;
  for (const char* g : {"U0050_P", "U0045_E", "U0062_b", "U0069_i"}) {
    const Bitmap target = read_bitmap(dir / (std::string("DejaVuSans-Bold_") + g + ".png"));
    for (const std::uint64_t seed : {1u, 2u}) {
      SearchOptions o;
      o.seed = seed;
      o.threads = threads;
      const SearchResult r = search(target, o);
      const SearchStatistics& s = r.statistics;
      total += r.score.total();
      std::printf("| %s | %llu | %.0f | %lld | %lld | %d | %llu | %llu | %llu | %.2f |\n", g + 6,
                  static_cast<unsigned long long>(seed), r.score.total(),
                  static_cast<long long>(r.score.excess), static_cast<long long>(r.score.uncovered),
                  r.score.primitives, static_cast<unsigned long long>(s.trees_evaluated),
                  static_cast<unsigned long long>(s.best_found_at),
                  static_cast<unsigned long long>(s.tree_evaluations), s.seconds);
    }
  }
  std::printf("sum of scores %.0f\n", total);
  return 0;
}

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--glyphs") {
    return glyph_table(argc > 2 ? std::atoi(argv[2]) : 1);
  }
  const std::filesystem::path picture =
      argc > 1 ? std::filesystem::path(argv[1])
               : fuzzycsg::bench::data_file("glyphs/DejaVuSans-Bold_U0050_P.png");
  const std::uint64_t seed = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1;
  const int runs = argc > 3 ? std::max(1, std::atoi(argv[3])) : 3;
  const Bitmap target = read_bitmap(picture);
  const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  std::printf("%s: %dx%d, Table 2 defaults, seed %llu, %d hardware threads, %d runs each\n",
              picture.filename().string().c_str(), target.width(), target.height(),
              static_cast<unsigned long long>(seed), hw, runs);
  double reference = -1;
  std::vector<double> medians;
  for (const int threads : {hw, 1}) {
    std::vector<double> seconds, rates;
    for (int r = 0; r < runs; ++r) {
      SearchOptions o;
      o.seed = seed;
      o.threads = threads;
      const SearchResult res = search(target, o);
      const SearchStatistics& s = res.statistics;
      if (reference < 0) reference = res.score.total();
      if (res.score.total() != reference) {
        std::printf("error: %d threads gave score %.0f, not %.0f\n", threads, res.score.total(),
                    reference);
        return 1;
      }
      seconds.push_back(s.seconds);
      rates.push_back(static_cast<double>(s.trees_evaluated) / s.seconds);
      std::printf(
          "  %d thread(s): %.3f s, score %.0f (excess %lld, uncovered %lld, %d primitives), "
          "%llu trees evaluated (%d iterations, stopped by %s, best at %llu), %.0f trees/s, "
          "%llu evaluations in the local optimizer, %llu primitives scan-converted\n",
          threads, s.seconds, res.score.total(), static_cast<long long>(res.score.excess),
          static_cast<long long>(res.score.uncovered), res.score.primitives,
          static_cast<unsigned long long>(s.trees_evaluated), s.iterations, s.stopped_by,
          static_cast<unsigned long long>(s.best_found_at), rates.back(),
          static_cast<unsigned long long>(s.tree_evaluations),
          static_cast<unsigned long long>(s.primitives_scanned));
    }
    std::printf("%d thread(s): median %.3f s, %.0f trees/s\n", threads, median(seconds),
                median(rates));
    medians.push_back(median(seconds));
  }
  std::printf("ratio: %d threads %.2fx faster than 1 thread (same tree)\n", hw,
              medians[1] / medians[0]);
  return 0;
}
