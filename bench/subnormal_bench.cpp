// subnormal_bench: what flushing subnormal floats to zero buys the evaluator.
//
//   subnormal_bench [--P 64,256] [--N 1024,16384] [--threads 2] [--reps 7]
//
// Two trees of P quadric leaves with unified operators leaning to union (App. A's full binary
// tree): "random", the paper's U[-0.5, 0.5] initialisation (soft leaves: no subnormals), and
// "balls", every leaf a ball of radius 0.05-0.2 at a random centre with slope 20 across its
// sphere (what `fit --init balls` starts from, and what trained trees look like once their
// sharpness has grown: far from a leaf its sigmoid is below 1e-38). Each configuration times
// Evaluator::backward (MSE, forward + backward) with the flush on (the default) and off,
// alternating, in the same process, and prints the medians and their ratio.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "bench/bench_lists.hpp"
#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/fit/init.hpp"

using namespace fuzzycsg;

namespace {

using fuzzycsg::bench::median;

Tree make_tree(int leaves, bool balls, std::uint64_t seed) {
  FullTreeOptions o;
  o.leaves = leaves;
  o.seed = seed;
  o.temperature = 1000;
  Tree t = make_full_binary_tree(o);
  if (!balls) return t;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.8, 0.8), r(0.05, 0.2);
  std::vector<double> p = t.params.values();
  for (int leaf : leaves_in_order(t)) {
    Ball b;
    b.center = {u(rng), u(rng), u(rng)};
    b.radius = r(rng);
    set_leaf_to_ball(t, leaf, b, true, 20.0, p);
  }
  for (const Node& n : t.nodes) {  // union, as --init balls starts
    if (n.kind != NodeKind::kOperator) continue;
    for (int k = 0; k < 4; ++k) p[n.unified[static_cast<std::size_t>(k)].index] = 0.0;
    p[n.unified[1].index] = 0.05;
  }
  t.params.set_values(p);
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Evaluator::backward with and without flushing subnormal floats");
  std::vector<int> leaves_list{64, 256};
  std::vector<std::size_t> points_list{1024, 16384};
  int threads = 2, reps = 7;
  app.add_option("--P", leaves_list, "leaf counts (powers of two)")->delimiter(',');
  app.add_option("--N", points_list, "point counts")->delimiter(',');
  app.add_option("--threads", threads, "threads");
  app.add_option("--reps", reps, "timed calls per configuration and mode (median)");
  CLI11_PARSE(app, argc, argv);

  std::printf("threads %d, %d calls per mode, alternating; seconds per call are medians\n", threads,
              reps);
  std::printf("%-7s %5s %6s %14s %14s %8s\n", "tree", "P", "N", "flush s/call", "no-flush s",
              "ratio");
  for (const bool balls : {false, true}) {
    for (const int leaves : leaves_list) {
      const Tree tree = make_tree(leaves, balls, 1);
      const Evaluator on(tree, EvalOptions{threads, true});
      const Evaluator off(tree, EvalOptions{threads, false});
      const std::vector<double> params = tree.params.values();
      for (const std::size_t n : points_list) {
        std::mt19937_64 rng(2);
        std::uniform_real_distribution<float> u(-1.0f, 1.0f);
        std::vector<float> pts(3 * n), labels(n);
        for (float& v : pts) v = u(rng);
        for (std::size_t i = 0; i < n; ++i) labels[i] = pts[3 * i] > 0 ? 1.0f : 0.0f;
        Loss loss;
        loss.kind = Loss::Kind::kMse;
        loss.targets = labels;
        std::vector<double> grad(params.size());
        const auto time = [&](const Evaluator& ev) {
          const auto t0 = std::chrono::steady_clock::now();
          ev.backward(params, pts, loss, grad);
          return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        };
        time(on);  // warm-up: scratch, caches
        time(off);
        std::vector<double> t_on, t_off;
        for (int r = 0; r < reps; ++r) {
          t_on.push_back(time(on));
          t_off.push_back(time(off));
        }
        const double a = median(t_on), b = median(t_off);
        std::printf("%-7s %5d %6zu %14.3e %14.3e %7.2fx\n", balls ? "balls" : "random", leaves, n,
                    a, b, b / a);
      }
    }
  }
  return 0;
}
