// trace_bench: how many trees per second the bitmap tracer evaluates (Gibson et al. 1997's unit
// of effort), full evaluation against incremental re-evaluation after one primitive changes.
//
//   trace_bench [picture] [primitives] [seed]
//
// Defaults: the 128x128 glyph P of the data collection's glyphs/ (bench/data_dir.hpp), 10
// primitives, seed 1. Each round moves one random primitive by a small random amount; "full"
// evaluates the whole tree again, "incremental" re-evaluates the leaf-to-root path only. Both also
// count the score (EXCESS + UNCOVERED), as the local optimizer does after every change. Then the
// local optimizer on five random trees of that size: time, sweeps, trees evaluated, primitives
// scan-converted.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "bench/data_dir.hpp"
#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/evaluate.hpp"
#include "fuzzycsg/trace/optimize.hpp"

using namespace fuzzycsg::trace;

int main(int argc, char** argv) {
  const std::filesystem::path picture =
      argc > 1 ? std::filesystem::path(argv[1])
               : fuzzycsg::bench::data_file("glyphs/DejaVuSans-Bold_U0050_P.png");
  const int primitives = argc > 2 ? std::atoi(argv[2]) : 10;
  const std::uint64_t seed = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 1;
  const Bitmap target = read_bitmap(picture);
  const int w = target.width(), h = target.height();
  Rng rng(seed);
  const CsgTree tree = random_tree(primitives, w, h, rng);
  const std::vector<int> leaves = tree.leaves();

  using Clock = std::chrono::steady_clock;
  const auto run = [&](bool incremental) {
    TreeEvaluator ev(tree, w, h);
    Rng moves(seed + 1);
    std::int64_t sink = 0;
    const int rounds = incremental ? 400000 : 40000;
    const auto t0 = Clock::now();
    for (int i = 0; i < rounds; ++i) {
      const int leaf = leaves[moves() % leaves.size()];
      Primitive p = ev.tree().primitive(leaf);
      p.x += uniform01(moves) - 0.5;
      p.y += uniform01(moves) - 0.5;
      if (incremental) {
        ev.update_primitive(leaf, p);
      } else {
        CsgTree changed = ev.tree();
        changed.primitive(leaf) = p;
        ev.set_tree(changed);
      }
      sink += score(ev.result(), target, primitives).mismatch();
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    std::printf(
        "%-12s %8d trees in %.3f s: %10.0f trees/s, %.2f us/tree, %.1f primitives "
        "scan-converted per tree (checksum %lld)\n",
        incremental ? "incremental" : "full", rounds, seconds, rounds / seconds,
        1e6 * seconds / rounds,
        static_cast<double>(ev.counters().primitives_scanned) /
            static_cast<double>(ev.counters().trees_evaluated),
        static_cast<long long>(sink));
  };
  std::printf("%s: %dx%d, %d primitives (seed %llu), tree depth %d\n",
              picture.filename().string().c_str(), w, h, primitives,
              static_cast<unsigned long long>(seed), tree.depth());
  run(false);
  run(true);
  for (int t = 0; t < 5; ++t) {
    TreeEvaluator ev(random_tree(primitives, w, h, rng), w, h);
    const Score before = score(ev.result(), target, primitives);
    const auto t0 = Clock::now();
    const LocalResult r = optimize_locally(ev, target);
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    std::printf(
        "local optimizer: score %.0f -> %.0f (%d primitives, %d pruned), %d sweeps, "
        "%llu trees evaluated, %llu primitives scan-converted, %.3f s\n",
        before.total(), r.score.total(), r.score.primitives, r.pruned, r.iterations,
        static_cast<unsigned long long>(ev.counters().trees_evaluated),
        static_cast<unsigned long long>(ev.counters().primitives_scanned), seconds);
  }
  return 0;
}
