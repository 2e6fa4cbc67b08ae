// type_search_bench: what Evaluator::edit_loss_changes buys the search over operator types.
//
//   type_search_bench [--P 64,256,1024] [--N 8192] [--threads 2] [--reps 5]
//
// For a random full binary tree of P quadrics with unified operators at t = 1000 (App. A) and
// N uniform points labelled by a ball, the change of the MSE for every operator switched alone
// to each of its three other types (3 (P - 1) switches) is computed two ways in the same
// process: by one call of edit_loss_changes (one forward and one light reverse sweep), and by
// brute force, one forward pass with the switched parameters per switch. Prints the medians of
// both, their ratio, one training step (Evaluator::backward on the same points) for scale, and
// the largest difference between the two answers.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "bench/bench_lists.hpp"
#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/fit/types.hpp"

using namespace fuzzycsg;
using fuzzycsg::bench::median;
using fuzzycsg::bench::parse_list;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The search over operator types: one edit sweep against brute force"};
  std::string sizes = "64,256,1024";
  int n = 8192, threads = 2, reps = 5;
  app.add_option("--P", sizes, "Leaves (comma list of powers of two)");
  app.add_option("--N", n, "Points");
  app.add_option("--threads", threads, "Threads");
  app.add_option("--reps", reps, "Repetitions (medians)");
  CLI11_PARSE(app, argc, argv);

  std::printf("%6s %8s %14s %14s %10s %14s %12s\n", "P", "switches", "edit sweep ms", "brute ms",
              "ratio", "one step ms", "max |diff|");
  for (int leaves : parse_list(sizes)) {
    FullTreeOptions t;
    t.leaves = leaves;
    t.seed = 1;
    const Tree tree = make_full_binary_tree(t);
    const std::vector<double> params = tree.params.values();
    const Evaluator ev(tree, EvalOptions{threads});
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<float> points(static_cast<std::size_t>(n) * 3), labels(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      float r2 = 0;
      for (int k = 0; k < 3; ++k) {
        points[3 * i + k] = u(rng);
        r2 += points[3 * i + k] * points[3 * i + k];
      }
      labels[i] = r2 < 0.36f ? 1.0f : 0.0f;
    }
    const Loss loss{Loss::Kind::kMse, labels, {}};

    // Every switch: (node, from, to) and its edit.
    struct Switch {
      int node, from, to;
    };
    std::vector<Switch> switches;
    std::vector<BilinearEdit> edits;
    for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
      const Node& node = tree.nodes[k];
      if (node.kind != NodeKind::kOperator) continue;
      const auto c = unified_weights_at(node, params);
      const int from = unified_type(node, params);
      for (int to = 0; to < 4; ++to) {
        if (to == from) continue;
        switches.push_back({static_cast<int>(k), from, to});
        edits.push_back({static_cast<int>(k), swap_delta(c, from, to)});
      }
    }
    std::vector<double> fast(edits.size()), slow(edits.size()), grad(params.size());
    std::vector<float> occ(static_cast<std::size_t>(n));
    auto mse_of = [&](const std::vector<double>& p) {
      ev.forward(p, points, occ);
      double s = 0;
      for (int i = 0; i < n; ++i) s += (occ[i] - labels[i]) * (occ[i] - labels[i]);
      return s / n;
    };
    std::vector<double> t_fast, t_slow, t_step;
    for (int rep = 0; rep < reps; ++rep) {
      Clock::time_point t0 = Clock::now();
      ev.edit_loss_changes(params, points, loss, edits, fast);
      t_fast.push_back(seconds_since(t0));

      t0 = Clock::now();
      const double base = mse_of(params);
      std::vector<double> p = params;
      for (std::size_t e = 0; e < switches.size(); ++e) {
        const Node& node = tree.nodes[static_cast<std::size_t>(switches[e].node)];
        swap_unified_entries(node, switches[e].from, switches[e].to, p, {}, {});
        slow[e] = mse_of(p) - base;
        swap_unified_entries(node, switches[e].from, switches[e].to, p, {}, {});
      }
      t_slow.push_back(seconds_since(t0));

      t0 = Clock::now();
      ev.backward(params, points, loss, grad);
      t_step.push_back(seconds_since(t0));
    }
    double diff = 0;
    for (std::size_t e = 0; e < edits.size(); ++e)
      diff = std::max(diff, std::abs(fast[e] - slow[e]));
    const double f = median(t_fast), s = median(t_slow);
    std::printf("%6d %8zu %14.2f %14.1f %9.0fx %14.2f %12.2e\n", leaves, edits.size(), 1e3 * f,
                1e3 * s, s / f, 1e3 * median(t_step), diff);
  }
  return 0;
}
