// trace_compare: three ways from a bitmap to a crisp CSG tree of circles and rectangles, on the
// same glyphs and the same time budget, scored the same way (EXCESS + UNCOVERED + k x
// primitives, k = 25, on the bitmap's pixels):
//
//   heuristic   the global search of Gibson et al. 1997 (trace/search.hpp), Table 2's
//               defaults, stopped at the budget if it has not stopped by itself;
//   fuzzy fit   Liu et al.'s inverse CSG by gradient descent (fit/fit.hpp) with a full binary
//               tree of circles and rectangles (alternating) and unified operators, trained for
//               the budget, snapped and pruned, evaluated crisply at the pixel centres;
//   heur+refine the heuristic for 70% of the budget, then refinement by fuzzy gradient descent
//               (trace/refine.hpp) for the rest.
//
//   trace_compare [--budget S] [--prims N] [--threads N] [glyph.png ...]
//
// Defaults: 10 s, 32 leaves for the fuzzy fit, every hardware thread, and the paper's letters
// P, E, b, i of DejaVu Sans Bold from the data collection's glyphs/ (bench/data_dir.hpp). Prints a
// Markdown table.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "bench/data_dir.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "fuzzycsg/target/target.hpp"
#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/refine.hpp"
#include "fuzzycsg/trace/search.hpp"

using namespace fuzzycsg;
using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The crisp bitmap of a tree fitted on the picture's normalised domain: pixel (i, j) of a
// W x H picture (square: the fit's image target maps it onto [-1, 1]^2, +y up) is inside when
// the occupancy at its centre is at least 1/2.
trace::Bitmap rasterise(const Tree& tree, int width, int height) {
  const Evaluator ev(tree);
  std::vector<float> points(static_cast<std::size_t>(width) * height * 2);
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const std::size_t k = (static_cast<std::size_t>(j) * width + i) * 2;
      points[k] = static_cast<float>(-1.0 + (2.0 * i + 1.0) / width);
      points[k + 1] = static_cast<float>(1.0 - (2.0 * j + 1.0) / height);
    }
  }
  std::vector<float> occ(static_cast<std::size_t>(width) * height);
  ev.forward(tree.params.values(), points, occ);
  trace::Bitmap b(width, height);
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      if (occ[static_cast<std::size_t>(j) * width + i] >= 0.5f) b.set(i, j);
    }
  }
  return b;
}

struct Row {
  trace::Score score;
  double seconds = 0;
};

void print(const char* method, const Row& r) {
  std::printf(" %s %.0f (%lld + %lld + 25 x %d) in %.1f s |", method, r.score.total(),
              static_cast<long long>(r.score.excess), static_cast<long long>(r.score.uncovered),
              r.score.primitives, r.seconds);
}

}  // namespace

int main(int argc, char** argv) {
  double budget = 10;
  int prims = 32, threads = 0;
  std::vector<std::filesystem::path> glyphs;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--budget" && a + 1 < argc) {
      budget = std::atof(argv[++a]);
    } else if (arg == "--prims" && a + 1 < argc) {
      prims = std::atoi(argv[++a]);
    } else if (arg == "--threads" && a + 1 < argc) {
      threads = std::atoi(argv[++a]);
    } else {
      glyphs.emplace_back(arg);
    }
  }
  if (glyphs.empty()) {
    const std::filesystem::path dir = fuzzycsg::bench::data_file("glyphs");
    for (const char* g : {"U0050_P", "U0045_E", "U0062_b", "U0069_i"}) {
      glyphs.push_back(dir / (std::string("DejaVuSans-Bold_") + g + ".png"));
    }
  }
  const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  std::printf("budget %.1f s per method, %d threads, fuzzy fit with %d leaves\n\n", budget,
              threads > 0 ? threads : hw, prims);
  std::printf("| bitmap | heuristic | fuzzy fit | heuristic + refine |\n|---|---|---|---|\n");
  for (const std::filesystem::path& g : glyphs) {
    const trace::Bitmap target = trace::read_bitmap(g);
    const int w = target.width(), h = target.height();
    std::printf("| %s |", g.stem().string().c_str());

    Row heuristic;
    {
      const auto t0 = Clock::now();
      trace::SearchOptions o;
      o.threads = threads;
      o.time_limit = budget;
      heuristic.score = trace::search(target, o).score;
      heuristic.seconds = since(t0);
    }
    print("", heuristic);

    Row fuzzy;
    {
      const auto t0 = Clock::now();
      TargetOptions to;
      to.image_resolution = 0;  // the picture's own pixels
      to.threads = threads;
      const std::unique_ptr<Target> t = load_target(g.string(), to);
      FitOptions fo;
      fo.prims = prims;
      fo.families = {PrimitiveType::kCircle, PrimitiveType::kRectangle};
      fo.iters = 100000000;
      fo.time_limit = budget;
      fo.threads = threads;
      fo.measure = false;
      const FitResult r = fit(*t, fo);
      const trace::Bitmap bits = rasterise(r.pruned, w, h);
      fuzzy.score = trace::score(bits, target, count(r.pruned).primitives);
      fuzzy.seconds = since(t0);
    }
    print("", fuzzy);

    Row refined;
    {
      const auto t0 = Clock::now();
      trace::SearchOptions o;
      o.threads = threads;
      o.time_limit = 0.7 * budget;
      const trace::SearchResult s = trace::search(target, o);
      trace::RefineOptions ro;
      ro.threads = threads;
      ro.time_limit = std::max(0.1, budget - since(t0));
      const trace::RefineResult r = trace::refine(s.best, target, ro);
      refined.score = r.after;
      refined.seconds = since(t0);
    }
    print("", refined);
    std::printf("\n");
    std::fflush(stdout);
  }
  return 0;
}
