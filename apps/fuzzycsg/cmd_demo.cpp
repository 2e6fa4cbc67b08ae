// fuzzycsg demo: the product's main job on a built-in mechanical part (a bracket: a plate and a
// boss, with a bore and two bolt holes). Writes the part as a tree file and as a mesh, converts
// the mesh back to a CSG program of CAD primitives and writes every output of `fuzzycsg convert`.
//
// fuzzycsg demo --fit: the paper's inverse CSG on the same part instead: fits 32 quadrics with
// unified operators to the tree, prunes, measures and writes every output of `fuzzycsg fit`.
//
// fuzzycsg demo --gradient: the evaluator's demonstration instead: a box with a cylindrical
// hole, its volume from integrating the soft occupancy and the derivatives of that volume with
// respect to the parameters from one backward pass, each beside its analytic value.

#include <fmt/format.h>
#include <stdlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/mesh/mesh.hpp"

namespace fuzzycsg::app {

namespace {

constexpr const char* kExample = R"({
  "format": "fuzzycsg-tree", "version": 1, "dim": 3,
  "root": { "op": "difference", "children": [
    { "type": "box", "size": [1.2, 0.8, 0.4], "sharpness": 80 },
    { "type": "cylinder", "radius": 0.15, "height": 1.0, "rotate": [90, 0, 0] } ] }
})";

// Units: the domain is [-1, 1]^3; the part spans about [-0.7, 0.7] x [-0.55, 0.45] x [-0.5, 0.5].
// The leaves' steps are steep sigmoids rather than crisp, so that the mesh of the part's 0.5 level
// set finds its faces between grid points (a crisp step puts them on the points, in stairs).
constexpr const char* kPart = R"({
  "format": "fuzzycsg-tree", "version": 1, "dim": 3,
  "root": { "op": "difference", "children": [
    { "op": "union", "children": [
      { "name": "plate", "sharpness": 400, "type": "box", "size": [1.4, 0.2, 1.0], "translate": [0, -0.45, 0] },
      { "name": "boss", "sharpness": 400, "type": "cylinder", "radius": 0.32, "height": 0.9,
        "rotate": [90, 0, 0], "translate": [0, -0.1, 0] } ] },
    { "op": "union", "children": [
      { "name": "bore", "sharpness": 400, "type": "cylinder", "radius": 0.16, "height": 2.0, "rotate": [90, 0, 0] },
      { "name": "bolt hole", "sharpness": 400, "type": "cylinder", "radius": 0.09, "height": 1.0,
        "rotate": [90, 0, 0], "translate": [0.5, -0.45, 0] },
      { "name": "bolt hole", "sharpness": 400, "type": "cylinder", "radius": 0.09, "height": 1.0,
        "rotate": [90, 0, 0], "translate": [-0.5, -0.45, 0] } ] } ] }
})";

struct DemoArgs {
  int resolution = 128;
  int threads = 0;
  bool gradient = false;
  bool fit = false;
  std::string out = "fuzzycsg-demo";
  long iters = 20000;
  int prims = 32;
  std::uint64_t seed = 0;
};

// Writes the built-in part into the output directory as part.json; returns its path.
std::filesystem::path write_part(const DemoArgs& a) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(a.out, ec);
  if (ec) {
    throw InputError(fmt::format("{}: cannot create output directory ({})", a.out, ec.message()));
  }
  const fs::path part = fs::path(a.out) / "part.json";
  io::write_tree_file(io::read_tree_string(kPart, "built-in part"), part);
  return part;
}

int run_convert_demo(const DemoArgs& a) {
  namespace fs = std::filesystem;
  // The part is written beside its conversion, as one set with it; it is converted from a
  // scratch copy of its mesh.
  std::string scratch_template = (fs::temp_directory_path() / "fuzzycsg-demo.XXXXXX").string();
  if (::mkdtemp(scratch_template.data()) == nullptr) {
    throw InputError(fmt::format("{}: cannot create a scratch folder", scratch_template));
  }
  const fs::path scratch(scratch_template);
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{scratch};
  const Tree tree = io::read_tree_string(kPart, "built-in part");
  MeshOptions mo;
  mo.resolution = 160;
  mo.threads = a.threads;
  const fs::path mesh = scratch / "part.obj";
  write_mesh(extract_mesh(tree, tree.params.values(), mo), mesh);
  fmt::print(
      "demo: the target is a bracket built from 6 primitives ({}), as a mesh ({}); converted "
      "below to a CSG program\n",
      (fs::path(a.out) / "part.json").string(), (fs::path(a.out) / "part.obj").string());
  ConvertJob job;
  job.target = mesh.string();
  job.out_dir = a.out;
  job.options.seed = a.seed;
  job.options.threads = a.threads;
  job.options.metrics.threads = a.threads;
  job.options.metrics.seed = a.seed;
  job.also_write = {{"part.json", io::write_tree_string(tree)}, {"part.obj", io::read_file(mesh)}};
  return run_convert_job(job);
}

int run_fit_demo(const DemoArgs& a) {
  const std::filesystem::path part = write_part(a);
  fmt::print(
      "demo: the target is a bracket built from 6 primitives ({}), fitted below with {} "
      "quadrics\n",
      part.string(), a.prims);
  FitJob job;
  job.target = part.string();
  job.out_dir = a.out;
  job.options.prims = a.prims;
  job.options.iters = a.iters;
  job.options.seed = a.seed;
  job.options.threads = a.threads;
  job.options.lr = 3e-3;
  job.options.metrics.points = 1'000'000;
  job.checkpoint_every = 0;
  job.command_line = command_line();
  return run_fit_job(job);
}

int run_gradient_demo(const DemoArgs& a) {
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
  CLI::App* cmd = app.add_subcommand(
      "demo",
      "Convert a built-in mechanical part's mesh to a CSG program (--fit: fit it with fuzzy CSG; "
      "--gradient: evaluate one)");
  cmd->add_option("-o,--output", args->out, "Output directory")->capture_default_str();
  cmd->add_flag("--fit", args->fit,
                "Instead: fit quadrics with unified operators to the part (the paper's protocol)");
  cmd->add_option("--iters", args->iters, "--fit: optimisation steps")
      ->capture_default_str()
      ->check(CLI::Range(0L, 10'000'000L));
  cmd->add_option("--prims", args->prims, "--fit: quadrics (a power of two)")
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Random seed")
      ->capture_default_str()
      ->check(unsigned_number());
  cmd->add_flag("--gradient", args->gradient,
                "Instead: evaluate a box with a hole, its volume and gradient");
  cmd->add_option("--resolution", args->resolution, "--gradient: grid cells per axis")
      ->check(CLI::Range(8, 512));
  add_threads_option(cmd, args->threads);
  return {cmd, [args] {
            if (args->gradient) return run_gradient_demo(*args);
            return args->fit ? run_fit_demo(*args) : run_convert_demo(*args);
          }};
}

}  // namespace fuzzycsg::app
