// fuzzycsg demo: evaluates a built-in example tree (a box with a cylindrical hole, the example
// of the tree-file documentation) and prints what it computed: a slice of the occupancy, the
// volume from integrating the soft occupancy, and the derivatives of that volume with respect to
// the parameters from one backward pass, each beside its analytic value.

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::app {

namespace {

constexpr const char* kExample = R"({
  "format": "fuzzycsg-tree", "version": 1, "dim": 3,
  "root": { "op": "difference", "children": [
    { "type": "box", "size": [1.2, 0.8, 0.4], "sharpness": 80 },
    { "type": "cylinder", "radius": 0.15, "height": 1.0, "rotate": [90, 0, 0] } ] }
})";

struct DemoArgs {
  int resolution = 128;
  int threads = 0;
};

int run_demo(const DemoArgs& a) {
  const Tree tree = io::read_tree_string(kExample, "built-in example");
  fmt::print("Example tree (box minus a cylinder along y):\n{}\n\n", kExample);

  // Cell centres of a regular grid over the domain [-1, 1]^3.
  const int r = a.resolution;
  const double h = 2.0 / r;
  std::vector<float> points;
  points.reserve(static_cast<std::size_t>(r) * r * r * 3);
  for (int k = 0; k < r; ++k) {
    for (int j = 0; j < r; ++j) {
      for (int i = 0; i < r; ++i) {
        points.push_back(static_cast<float>(-1.0 + (i + 0.5) * h));
        points.push_back(static_cast<float>(-1.0 + (j + 0.5) * h));
        points.push_back(static_cast<float>(-1.0 + (k + 0.5) * h));
      }
    }
  }
  const std::size_t n = points.size() / 3;
  const Evaluator evaluator(tree, EvalOptions{a.threads});
  const std::vector<double> params = tree.params.values();
  std::vector<double> grad(params.size());
  std::vector<float> occupancy(n);
  const auto t0 = std::chrono::steady_clock::now();
  const double sum = evaluator.backward(params, points, Loss{}, grad, occupancy);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // The slice z = 0 (nearest grid layer), y down the page.
  fmt::print("Occupancy on the slice z = 0 (x across, y down; '#' > 0.9, '+' > 0.5, '.' > 0.1):\n");
  const int kz = r / 2;
  for (int j = r - 1; j >= 0; j -= std::max(1, r / 24)) {
    std::string row;
    for (int i = 0; i < r; i += std::max(1, r / 64)) {
      const float o = occupancy[(static_cast<std::size_t>(kz) * r + j) * r + i];
      row += o > 0.9f ? '#' : o > 0.5f ? '+' : o > 0.1f ? '.' : ' ';
    }
    fmt::print("  |{}|\n", row);
  }

  const double cell = h * h * h;
  const double rad = 0.15, sx = 1.2, sy = 0.8, sz = 0.4;
  const double pi = std::numbers::pi;
  const double volume = sx * sy * sz - pi * rad * rad * sy;
  fmt::print("\n{} points on a {}^3 grid, forward + backward in {:.3f} s ({:.1f} M points/s)\n", n,
             r, seconds, n / seconds * 1e-6);
  fmt::print("\n{:<34}{:>12}{:>12}\n", "quantity", "computed", "analytic");
  fmt::print("{:<34}{:>12.5f}{:>12.5f}\n", "volume (integral of occupancy)", sum * cell, volume);
  struct Row {
    const char* name;
    double analytic;
  };
  const Row rows[] = {
      {"root.children[0].size[0]", sy * sz},
      {"root.children[0].size[1]", sx * sz - pi * rad * rad},
      {"root.children[0].size[2]", sx * sy},
      {"root.children[1].radius", -2.0 * pi * rad * sy},
  };
  for (const Row& row : rows) {
    const auto ref = tree.params.find(row.name);
    fmt::print("{:<34}{:>12.5f}{:>12.5f}\n", fmt::format("dV/d {}", row.name),
               grad[ref->index] * cell, row.analytic);
  }
  fmt::print(
      "\nThe integral of a soft occupancy (sharpness 80) matches the volume of the crisp\n"
      "solid to within the sigmoid's blur, and one backward pass gives every derivative.\n");
  return 0;
}

}  // namespace

Verb register_demo(CLI::App& app) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* cmd = app.add_subcommand("demo", "Evaluate a built-in example tree and its gradient");
  cmd->add_option("--resolution", args->resolution, "Grid cells per axis")
      ->check(CLI::Range(8, 512));
  cmd->add_option("--threads", args->threads, "Threads (0: all cores)")->check(CLI::Range(0, 1024));
  return {cmd, [args] { return run_demo(*args); }};
}

}  // namespace fuzzycsg::app
