// fuzzycsg prune TREE --target TARGET -o OUT [--threshold F] [--max-primitives K] [--points N]
//                [--sampling S]
//
// Snaps unified operators to crisp booleans and removes redundant nodes (Liu et al. 2024 App. A,
// after Tilove 1984), judging redundancy on points drawn uniformly (as the authors' release) or
// from the target's training distribution, then, with --max-primitives, reduces the tree
// greedily to that many primitives; reports node counts and the fit to the target before and
// after.

#include <fmt/format.h>

#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/snap.hpp"
#include "fuzzycsg/core/transform.hpp"
#include "fuzzycsg/fit/prune.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/target/metrics.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg::app {

namespace {

struct PruneArgs {
  std::string tree, target, out;
  double threshold = 1e-3;
  int max_primitives = 0;
  std::size_t points = 65536;
  std::string sampling = "uniform";
  std::uint64_t seed = 0;
  double padding = 0.2;
  int image_resolution = 256;
  std::size_t metric_points = 2'000'000;
  bool no_metrics = false;
  int threads = 0;
};

int run_prune(const PruneArgs& a) {
  const Tree given = io::read_tree_file(a.tree);
  TargetOptions to;
  to.padding = a.padding;
  to.image_resolution = a.image_resolution;
  to.threads = a.threads;
  const std::unique_ptr<Target> target = load_target(a.target, to);
  if (target->dim() != given.dim) {
    throw InputError(fmt::format("{}: the tree is {}D but the target {} is {}D", a.tree, given.dim,
                                 a.target, target->dim()));
  }
  // The tree is in the target's coordinates (as `fit` writes it); pruning judges it in the
  // target's normalised box, and the result goes back.
  const Similarity normalisation = target->normalisation();
  const Tree tree = transformed(given, normalisation);
  if (!(a.threshold >= 0)) throw InputError("--threshold: must be >= 0");

  Rng rng(a.seed);
  std::vector<float> points;
  if (a.sampling == "uniform") {
    points = uniform_points(tree.dim, a.points, rng);
  } else {
    points = draw_samples(*target, a.points, SamplingOptions{}, rng).points;
  }
  const Tree snapped = snap_operators(tree);
  PruneOptions po;
  po.threshold = a.threshold;
  po.threads = a.threads;
  po.max_primitives = a.max_primitives;
  PruneReport report;
  const Tree pruned = prune(snapped, points, po, &report);
  const std::string text = io::write_tree_string(transformed(pruned, normalisation.inverse()));

  fmt::print("prune: {}+{} -> {}+{} nodes (primitives+operators)\n", report.primitives_before,
             report.operators_before, report.primitives_after, report.operators_after);
  if (!a.no_metrics) {
    MetricsOptions mo;
    mo.points = a.metric_points;
    mo.threads = a.threads;
    mo.seed = a.seed;
    const Metrics before = measure(tree, tree.params.values(), *target, mo);
    const Metrics after = measure(pruned, pruned.params.values(), *target, mo);
    for (const auto& [what, m] : {std::pair{"before", before}, std::pair{"after", after}}) {
      fmt::print("prune: {:<6} MSE {:.5f}  IoU {:.4f}{}{}\n", what, m.mse, m.iou,
                 m.chamfer ? fmt::format("  Chamfer {:.5f}", *m.chamfer) : "",
                 m.hausdorff ? fmt::format("  Hausdorff {:.5f}", *m.hausdorff) : "");
    }
  }
  io::write_text_file_atomic(a.out, text);
  return 0;
}

}  // namespace

Verb register_prune(CLI::App& app) {
  auto a = std::make_shared<PruneArgs>();
  CLI::App* cmd = app.add_subcommand(
      "prune", "Snap unified operators and remove redundant nodes of a fitted tree");
  cmd->add_option("tree", a->tree, "Tree file")->required();
  cmd->add_option("--target", a->target, "The shape the tree was fitted to")->required();
  cmd->add_option("-o,--output", a->out, "Pruned tree file")->required();
  cmd->add_option("--threshold", a->threshold,
                  "Mean squared occupancy change below which a node is redundant")
      ->capture_default_str();
  cmd->add_option("--max-primitives", a->max_primitives,
                  "Then keep at most this many primitives, removing subtrees greedily by the "
                  "least change of the output per primitive (0: no limit)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1 << 30));
  cmd->add_option("--points", a->points, "Points on which redundancy is judged")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 26));
  cmd->add_option("--sampling", a->sampling,
                  "Where those points lie: uniform (as the authors' release) or target (40% on, "
                  "40% near the surface, 20% uniform)")
      ->capture_default_str()
      ->check(CLI::IsMember({"uniform", "target"}));
  cmd->add_option("--seed", a->seed, "Random seed")
      ->capture_default_str()
      ->check(unsigned_number());
  cmd->add_option("--padding", a->padding, "Meshes: margin around the normalised shape")
      ->capture_default_str();
  cmd->add_option("--image-resolution", a->image_resolution,
                  "Pictures: resampled to this square size (0: native)")
      ->capture_default_str();
  cmd->add_option("--metric-points", a->metric_points, "Uniform points for MSE and IoU")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 28));
  cmd->add_flag("--no-metrics", a->no_metrics, "Skip measuring before and after");
  add_threads_option(cmd, a->threads);
  return {cmd, [a] { return run_prune(*a); }};
}

}  // namespace fuzzycsg::app
