// eval_bench: forward+backward throughput of the evaluator on the full binary trees of quadrics
// with unified operators of Liu et al. 2024 (App. A), with an MSE loss, in leaf-point
// evaluations per second (P * N per forward+backward), next to this machine's measured peak.
//
//   eval_bench [--P 64,256,1024] [--N 1024,65536] [--threads 1,2] [--reps 5] [--min-time 0.2]
//              [--seed 1] [--no-peak] [--peak-seconds 0.1] [--peak-runs 5] [--json]
//   eval_bench --dump-case case.json [--case-P 64] [--case-N 2048] [--seed 1] [--threads 2]
//
// Points are uniform in [-1, 1]³, targets the occupancy of the ball of radius 0.6. Every
// configuration: one warm-up call, then at least --reps timed calls and at least --min-time
// seconds of them; the median is reported, with the fraction of the compute limit that the
// measured peaks (peak.hpp) and the work count (leaf_point_cost.hpp) give for that thread count,
// and whether the gradient is bit-identical to the one of the first thread count ("det").
// --json prints JSON lines instead of the table:
//   {"impl":"peak","threads":..,"flops_per_s":..,"exps_per_s":..,...}   per thread count
//   {"impl":"cost","P":..,"fma":..,"other":..,"exps":..,"flops":..}      per P
//   {"impl":"fuzzycsg","P":..,"N":..,"threads":..,"median_s":..,"leaf_points_per_s":..,
//    "fraction_of_peak":..,"fraction_of_slot_peak":..,"reps":..,...}    per configuration
//
// --dump-case writes one tree, its parameters, points, targets and the evaluator's occupancy,
// loss and gradient to a JSON file, which bench/check_against_torch.py recomputes with PyTorch
// autograd (format described there).

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bench_lists.hpp"
#include "bench/leaf_point_cost.hpp"
#include "bench/peak.hpp"
#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/core/primitives.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/eval/evaluator.hpp"

namespace {

using fuzzycsg::bench::median;

using Clock = std::chrono::steady_clock;
namespace fb = fuzzycsg::bench;

constexpr double kTargetRadius = 0.6;

std::vector<float> make_points(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> p(static_cast<std::size_t>(n) * 3);
  for (auto& v : p) v = u(rng);
  return p;
}

std::vector<float> ball_targets(const std::vector<float>& points) {
  std::vector<float> t(points.size() / 3);
  for (std::size_t i = 0; i < t.size(); ++i) {
    const float x = points[3 * i], y = points[3 * i + 1], z = points[3 * i + 2];
    t[i] = x * x + y * y + z * z < kTargetRadius * kTargetRadius ? 1.0f : 0.0f;
  }
  return t;
}

fuzzycsg::Tree make_tree(int leaves, std::uint64_t seed) {
  fuzzycsg::FullTreeOptions options;
  options.dim = 3;
  options.leaves = leaves;
  options.family = fuzzycsg::PrimitiveType::kQuadric3;
  options.ops = fuzzycsg::OperatorMode::kUnified;
  options.seed = seed;
  return fuzzycsg::make_full_binary_tree(options);
}

struct Timing {
  double median_s = 0;
  int reps = 0;
  double loss = 0;
};

Timing time_backward(const fuzzycsg::Evaluator& ev, const std::vector<double>& params,
                     const std::vector<float>& points, const std::vector<float>& targets,
                     std::vector<double>& grad, int min_reps, double min_time) {
  const fuzzycsg::Loss loss{fuzzycsg::Loss::Kind::kMse, targets, {}};
  Timing t;
  t.loss = ev.backward(params, points, loss, grad);  // warm-up
  std::vector<double> times;
  double total = 0;
  while (static_cast<int>(times.size()) < min_reps || (total < min_time && times.size() < 1000)) {
    const auto t0 = Clock::now();
    t.loss = ev.backward(params, points, loss, grad);
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    times.push_back(s);
    total += s;
  }
  t.median_s = median(times);
  t.reps = static_cast<int>(times.size());
  return t;
}

// ---- --dump-case -------------------------------------------------------------------------

nlohmann::json param_or_value(const std::optional<fuzzycsg::ParamRef>& ref, double fallback) {
  if (ref) return {{"param", ref->index}};
  return {{"value", fallback}};
}

int dump_case(const std::string& path, int leaves, int n, std::uint64_t seed, int threads) {
  const fuzzycsg::Tree tree = make_tree(leaves, seed);
  const fuzzycsg::FullTreeOptions defaults;
  nlohmann::json nodes = nlohmann::json::array();
  for (const auto& node : tree.nodes) {
    if (node.kind == fuzzycsg::NodeKind::kPrimitive) {
      if (node.shape.type != fuzzycsg::PrimitiveType::kQuadric3 || node.intrinsic.size() != 10 ||
          !node.placement.empty() || node.step.kind != fuzzycsg::StepKind::kSigmoid ||
          !node.step.param) {
        throw std::runtime_error("dump-case: expected plain quadric leaves with a sigmoid step");
      }
      std::vector<std::uint32_t> coef;
      for (const auto& r : node.intrinsic) coef.push_back(r.index);
      nodes.push_back(
          {{"kind", "quadric"}, {"coefficients", coef}, {"sharpness", node.step.param->index}});
    } else {
      if (node.op != fuzzycsg::OpKind::kUnified || !node.unified_logits ||
          node.unified.size() != 4 || node.children.size() != 2) {
        throw std::runtime_error("dump-case: expected unified operators with logits");
      }
      std::vector<std::uint32_t> logits;
      for (const auto& r : node.unified) logits.push_back(r.index);
      nodes.push_back({{"kind", "unified"},
                       {"children", node.children},
                       {"logits", logits},
                       {"temperature", param_or_value(node.temperature, defaults.temperature)},
                       {"omega", param_or_value(node.omega, defaults.omega)}});
    }
  }
  const auto params = tree.params.values();
  std::vector<std::string> names;
  std::vector<bool> fixed;
  for (const auto& p : tree.params.entries()) {
    names.push_back(p.name);
    fixed.push_back(p.fixed);
  }
  const auto points = make_points(n, seed + 1);
  const auto targets = ball_targets(points);
  fuzzycsg::Evaluator ev(tree, {.threads = threads});
  std::vector<double> grad(ev.num_params());
  std::vector<float> occupancy(static_cast<std::size_t>(n));
  const double loss =
      ev.backward(params, points, {fuzzycsg::Loss::Kind::kMse, targets, {}}, grad, occupancy);

  nlohmann::json j;
  j["format"] = "fuzzycsg-bench-case";
  j["version"] = 1;
  j["dim"] = 3;
  j["monomials"] = {"x^2", "y^2", "z^2", "xy", "yz", "zx", "x", "y", "z", "1"};
  j["leaves"] = leaves;
  j["seed"] = seed;
  j["root"] = tree.root;
  j["nodes"] = nodes;
  j["params"] = params;
  j["param_names"] = names;
  j["fixed"] = fixed;
  j["points"] = points;  // N x 3, row-major
  j["targets"] = targets;
  j["fuzzycsg"] = {{"threads", threads}, {"loss", loss}, {"grad", grad}, {"occupancy", occupancy}};
  std::ofstream out(path);
  if (!out) throw std::runtime_error("dump-case: cannot write " + path);
  out << j.dump() << '\n';
  std::printf("wrote %s: P=%d N=%d params=%zu loss=%.9g\n", path.c_str(), leaves, n, params.size(),
              loss);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> leaves_list{64, 256, 1024};
  std::vector<int> points_list{1024, 65536};
  std::vector<int> threads_list{1, 2};
  int min_reps = 5;
  double min_time = 0.2;
  std::uint64_t seed = 1;
  bool no_peak = false;
  bool json = false;
  double peak_seconds = 0.1;
  int peak_runs = 5;
  std::string case_path;
  int case_leaves = 64, case_points = 2048;

  CLI::App app{"Forward+backward throughput of the fuzzycsg evaluator (full quadric trees)"};
  app.add_option("--P", leaves_list, "leaf counts (powers of two)")->delimiter(',');
  app.add_option("--N", points_list, "point counts")->delimiter(',');
  app.add_option("--threads", threads_list, "thread counts (--dump-case: the first)")
      ->delimiter(',');
  app.add_option("--reps", min_reps, "minimum timed calls per configuration");
  app.add_option("--min-time", min_time, "minimum timed seconds per configuration");
  app.add_option("--seed", seed, "tree and point seed");
  app.add_flag("--no-peak", no_peak, "skip the peak measurement");
  app.add_flag("--json", json, "print JSON lines instead of the table");
  app.add_option("--peak-seconds", peak_seconds, "seconds per peak run");
  app.add_option("--peak-runs", peak_runs, "peak runs (the best is the peak)");
  app.add_option("--dump-case", case_path, "write a cross-check case (JSON) and exit");
  app.add_option("--case-P", case_leaves, "leaves of the dumped case");
  app.add_option("--case-N", case_points, "points of the dumped case");
  CLI11_PARSE(app, argc, argv);

  try {
    if (!case_path.empty()) {
      return dump_case(case_path, case_leaves, case_points, seed,
                       threads_list.empty() ? 1 : threads_list.front());
    }

    const auto simd = fb::simd_info();
    if (!json) {
      std::printf("Highway target: %s (%zu fp32 lanes)\n", simd.target.c_str(), simd.float_lanes);
    }
    std::map<int, fb::PeakResult> peaks;
    if (!no_peak) {
      for (int t : threads_list) {
        const auto r = fb::measure_peak(t, peak_seconds, peak_runs);
        peaks[t] = r;
        if (json) {
          std::printf(
              "{\"impl\":\"peak\",\"threads\":%d,\"target\":\"%s\",\"lanes\":%zu,"
              "\"flops_per_s\":%.6g,\"exps_per_s\":%.6g,\"flops_per_s_median\":%.6g,"
              "\"exps_per_s_median\":%.6g,\"runs\":%d}\n",
              t, simd.target.c_str(), simd.float_lanes, r.flops_per_s, r.exps_per_s,
              r.flops_per_s_median, r.exps_per_s_median, r.runs);
        } else {
          std::printf("peak, %d thread(s): %.1f GFLOP/s, %.2f G exp/s (best of %d runs)\n", t,
                      r.flops_per_s * 1e-9, r.exps_per_s * 1e-9, r.runs);
        }
      }
    }
    for (int p : leaves_list) {
      const auto c = fb::per_leaf_point(p);
      if (json) {
        std::printf(
            "{\"impl\":\"cost\",\"P\":%d,\"fma\":%.6g,\"other\":%.6g,\"exps\":%.6g,"
            "\"flops\":%.6g}\n",
            p, c.fma, c.other, c.exp, c.flops());
      } else {
        std::printf("Work of one leaf-point forward+backward, P = %d:\n%s", p,
                    fb::cost_table(p).c_str());
      }
    }

    if (!json) {
      std::printf("%6s %7s %7s %12s %6s %14s %9s %9s %5s\n", "P", "N", "threads", "median_s",
                  "reps", "leaf-pts/s", "frac", "frac_slot", "det");
    }
    for (int p : leaves_list) {
      const fuzzycsg::Tree tree = make_tree(p, seed);
      const auto params = tree.params.values();
      const auto cost = fb::per_leaf_point(p);
      for (int n : points_list) {
        const auto points = make_points(n, seed + 1);
        const auto targets = ball_targets(points);
        // Gradient of the first thread count, to check that every thread count agrees bit for bit.
        std::vector<double> first_grad;
        for (int t : threads_list) {
          fuzzycsg::Evaluator ev(tree, {.threads = t});
          std::vector<double> grad(ev.num_params());
          const Timing tm = time_backward(ev, params, points, targets, grad, min_reps, min_time);
          const bool deterministic = first_grad.empty() || first_grad == grad;
          if (first_grad.empty()) first_grad = grad;
          const double rate = static_cast<double>(p) * static_cast<double>(n) / tm.median_s;
          double frac = 0, frac_slot = 0;
          if (const auto it = peaks.find(t); it != peaks.end()) {
            frac = rate / fb::flop_limit(cost, it->second.flops_per_s, it->second.exps_per_s);
            frac_slot = rate / fb::slot_limit(cost, it->second.flops_per_s, it->second.exps_per_s);
          }
          if (json) {
            std::printf(
                "{\"impl\":\"fuzzycsg\",\"P\":%d,\"N\":%d,\"threads\":%d,\"median_s\":%.6g,"
                "\"leaf_points_per_s\":%.6g,\"fraction_of_peak\":%.4g,"
                "\"fraction_of_slot_peak\":%.4g,\"reps\":%d,\"loss\":%.9g,"
                "\"same_grad_as_first_thread_count\":%s}\n",
                p, n, t, tm.median_s, rate, frac, frac_slot, tm.reps, tm.loss,
                deterministic ? "true" : "false");
          } else {
            std::printf("%6d %7d %7d %12.6f %6d %14.4g %9.3f %9.3f %5s\n", p, n, t, tm.median_s,
                        tm.reps, rate, frac, frac_slot, deterministic ? "yes" : "NO");
          }
          std::fflush(stdout);
        }
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "eval_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
