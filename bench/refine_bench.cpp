// refine_bench: what refinement by fuzzy gradient descent (trace/refine.hpp) adds to the local
// optimizer of Gibson et al. 1997 on glyphs.
//
//   refine_bench [--seeds N] [--iterations N] [--threads N] [--batch N] [--lr X] [--lr-end X]
//                [--angle-lr X] [--sharpness-start X] [--sharpness-end X] [picture ...]
//
// For each picture (default: the 128x128 glyphs P, E, b and i of DejaVuSans-Bold in
// the data collection's glyphs/ (bench/data_dir.hpp)), N random trees (default 20, seeds 1..N) of
// norm(10, 2) primitives are locally optimized (optimize_locally, defaults) and the best is kept;
// it is then refined (refine, defaults but for the options given), and the refined tree is locally
// optimized once more. Printed: the crisp scores (EXCESS + UNCOVERED + 25 x primitives) and the
// times.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/data_dir.hpp"
#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/evaluate.hpp"
#include "fuzzycsg/trace/optimize.hpp"
#include "fuzzycsg/trace/refine.hpp"

using namespace fuzzycsg::trace;
using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 20;
  RefineOptions refine_options;
  std::vector<std::filesystem::path> pictures;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--seeds" && a + 1 < argc) {
      seeds = std::atoi(argv[++a]);
    } else if (arg == "--iterations" && a + 1 < argc) {
      refine_options.iterations = std::atoi(argv[++a]);
    } else if (arg == "--threads" && a + 1 < argc) {
      refine_options.threads = std::atoi(argv[++a]);
    } else if (arg == "--batch" && a + 1 < argc) {
      refine_options.batch = std::atoi(argv[++a]);
    } else if (arg == "--lr" && a + 1 < argc) {
      refine_options.lr = std::atof(argv[++a]);
    } else if (arg == "--angle-lr" && a + 1 < argc) {
      refine_options.angle_lr = std::atof(argv[++a]);
    } else if (arg == "--lr-end" && a + 1 < argc) {
      refine_options.lr_end = std::atof(argv[++a]);
    } else if (arg == "--sharpness-start" && a + 1 < argc) {
      refine_options.sharpness_start = std::atof(argv[++a]);
    } else if (arg == "--sharpness-end" && a + 1 < argc) {
      refine_options.sharpness_end = std::atof(argv[++a]);
    } else {
      pictures.emplace_back(arg);
    }
  }
  if (pictures.empty()) {
    const std::filesystem::path dir = fuzzycsg::bench::data_file("glyphs");
    for (const char* g : {"U0050_P", "U0045_E", "U0062_b", "U0069_i"}) {
      pictures.push_back(dir / (std::string("DejaVuSans-Bold_") + g + ".png"));
    }
  }
  std::printf(
      "best of %d seeds of random_tree + optimize_locally, then refine (%d iterations, batch %d, "
      "lr %g to %g, sharpness %g to %g)\n",
      seeds, refine_options.iterations, refine_options.batch, refine_options.lr,
      refine_options.lr * refine_options.lr_end, refine_options.sharpness_start,
      refine_options.sharpness_end);
  std::printf("%-32s %5s %9s %8s %9s %8s %9s %8s\n", "picture", "prims", "local", "time_s",
              "refined", "time_s", "+local", "time_s");
  for (const std::filesystem::path& picture : pictures) {
    const Bitmap target = read_bitmap(picture);
    const int w = target.width(), h = target.height();
    const auto t0 = Clock::now();
    CsgTree best;
    Score best_score;
    for (int seed = 1; seed <= seeds; ++seed) {
      Rng rng(static_cast<std::uint64_t>(seed));
      TreeEvaluator ev(random_tree(norm_count(10, 2, rng), w, h, rng), w, h);
      const LocalResult r = optimize_locally(ev, target);
      if (best.empty() || r.score.total() < best_score.total()) {
        best = ev.tree();
        best_score = r.score;
      }
    }
    best.compact();
    const double local_seconds = since(t0);
    const RefineResult r = refine(best, target, refine_options);
    const auto t1 = Clock::now();
    TreeEvaluator ev(r.tree, w, h);
    const LocalResult again = optimize_locally(ev, target);
    const double again_seconds = since(t1);
    std::printf("%-32s %5d %9.0f %8.2f %9.0f %8.2f %9.0f %8.2f\n", picture.stem().string().c_str(),
                best_score.primitives, r.before.total(), local_seconds, r.after.total(), r.seconds,
                again.score.total(), again_seconds);
  }
  return 0;
}
