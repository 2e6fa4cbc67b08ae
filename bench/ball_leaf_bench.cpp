// ball_leaf_bench: the kernel's vector path for balls against its scalar leaf path.
//
//   ball_leaf_bench [--P 32,256] [--N 8192] [--threads 2] [--reps 7]
//
// For full binary trees of P spheres (3D) and of P circles (2D) with unified operators, as
// `fuzzycsg fit --family sphere|circle` builds them, one forward+backward call (MSE to a ball's
// occupancy on N uniform points) is timed two ways in the same process: as built (translated
// balls: the vector path), and with a fixed scale of 1 added to every leaf, which is the same
// function but takes the scalar path of placed primitives. Prints the medians, their ratio and
// the largest difference of the two losses and gradients.

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

using namespace fuzzycsg;
using fuzzycsg::bench::median;
using fuzzycsg::bench::parse_list;

namespace {

using Clock = std::chrono::steady_clock;

// The same tree with a fixed scale of 1 on every primitive (the scalar path).
Tree with_unit_scales(Tree tree) {
  for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
    Node& n = tree.nodes[k];
    if (n.kind != NodeKind::kPrimitive) continue;
    Parameter p;
    p.name = "scale" + std::to_string(k);
    p.value = 1.0;
    p.fixed = true;
    p.range = Range::positive();
    n.placement.scale = tree.params.add(std::move(p));
  }
  return tree;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Balls on the kernel's vector path against its scalar leaf path"};
  std::string sizes = "32,256";
  int n = 8192, threads = 2, reps = 7;
  app.add_option("--P", sizes, "Leaves (comma list of powers of two)");
  app.add_option("--N", n, "Points");
  app.add_option("--threads", threads, "Threads");
  app.add_option("--reps", reps, "Repetitions (medians)");
  CLI11_PARSE(app, argc, argv);

  std::printf("%4s %6s %14s %14s %8s %12s %12s\n", "dim", "P", "vector ms", "scalar ms", "ratio",
              "|d loss|", "max |d grad|");
  for (int dim : {3, 2}) {
    for (int leaves : parse_list(sizes)) {
      FullTreeOptions t;
      t.dim = dim;
      t.leaves = leaves;
      t.family = dim == 3 ? PrimitiveType::kSphere : PrimitiveType::kCircle;
      t.seed = 1;
      const Tree fast_tree = make_full_binary_tree(t);
      const Tree slow_tree = with_unit_scales(fast_tree);
      const Evaluator fast(fast_tree, EvalOptions{threads});
      const Evaluator slow(slow_tree, EvalOptions{threads});
      const std::vector<double> pf = fast_tree.params.values(), ps = slow_tree.params.values();

      std::mt19937_64 rng(2);
      std::uniform_real_distribution<float> u(-1.0f, 1.0f);
      const auto d = static_cast<std::size_t>(dim);
      std::vector<float> points(static_cast<std::size_t>(n) * d),
          labels(static_cast<std::size_t>(n));
      for (std::size_t i = 0; i < labels.size(); ++i) {
        float r2 = 0;
        for (std::size_t k = 0; k < d; ++k) {
          points[d * i + k] = u(rng);
          r2 += points[d * i + k] * points[d * i + k];
        }
        labels[i] = r2 < 0.36f ? 1.0f : 0.0f;
      }
      const Loss loss{Loss::Kind::kMse, labels, {}};
      std::vector<double> gf(pf.size()), gs(ps.size());
      std::vector<double> tf, ts;
      double lf = 0, ls = 0;
      for (int rep = 0; rep <= reps; ++rep) {  // the first of each is a warm-up
        Clock::time_point t0 = Clock::now();
        lf = fast.backward(pf, points, loss, gf);
        const double a = std::chrono::duration<double>(Clock::now() - t0).count();
        t0 = Clock::now();
        ls = slow.backward(ps, points, loss, gs);
        const double b = std::chrono::duration<double>(Clock::now() - t0).count();
        if (rep > 0) {
          tf.push_back(a);
          ts.push_back(b);
        }
      }
      double dg = 0;
      for (std::size_t k = 0; k < gf.size(); ++k) dg = std::max(dg, std::abs(gf[k] - gs[k]));
      const double mf = median(tf), ms = median(ts);
      std::printf("%4d %6d %14.3f %14.3f %7.1fx %12.2e %12.2e\n", dim, leaves, 1e3 * mf, 1e3 * ms,
                  ms / mf, std::abs(lf - ls), dg);
    }
  }
  return 0;
}
