// fuzzycsg refine MODEL --target MODEL -o OUTDIR [--views N] [--size N] [--iters N] [--lr F]
//                 [--no-intersection-aa] [--stop F]
//
// DiffCSG's image-based refinement (fuzzycsg/diffcsg/refine.hpp): the continuous parameters of
// MODEL (a 3D tree file of boxes, spheres and cylinders) are optimised so that its
// per-primitive colour images from N views match those of the target model (a tree file of
// the same program: primitive k of one is primitive k of the other), without any mesh boolean.
// Writes tree.json and model.scad (refined), report.json (settings, loss curve, time split into
// visibility, edges, antialiasing and backward) and before.png, after.png, target.png (view 0).

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diffcsg/refine.hpp"
#include "fuzzycsg/io/png.hpp"
#include "fuzzycsg/io/points.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/scad/scad.hpp"

namespace fuzzycsg::app {

namespace {

struct RefineArgs {
  std::string model, target, out;
  int views = 4, size = 128, iters = 300, threads = 0;
  double lr = 0.01, stop = 5e-4, elevation = 25, distance = 0;
  bool no_intersection_aa = false, quiet = false;
};

std::string png_of(const diffcsg::Image& img) {
  std::vector<unsigned char> px(static_cast<std::size_t>(img.width) * img.height * 3);
  for (std::size_t k = 0; k < px.size(); ++k) {
    px[k] = static_cast<unsigned char>(std::lround(std::clamp(img.data[k], 0.0f, 1.0f) * 255));
  }
  return encode_png(img.width, img.height, 3, px);
}

diffcsg::Image render(const diffcsg::Scene& scene, const diffcsg::Camera& cam, int threads) {
  const diffcsg::Frame f = diffcsg::render_visibility(scene, cam, threads);
  const std::vector<diffcsg::IntersectionEdge> edges = diffcsg::intersection_edges(scene);
  return diffcsg::antialias(scene, diffcsg::opposite_vertices(scene), cam, f,
                            diffcsg::colour_image(f), nullptr, &edges);
}

int run_refine(const RefineArgs& a) {
  if (a.views < 1 || a.views > 64) throw InputError("--views: must be in [1, 64]");
  if (a.size < 8 || a.size > 2048) throw InputError("--size: must be in [8, 2048]");
  if (a.iters < 0) throw InputError("--iters: must not be negative");
  if (!(a.lr > 0)) throw InputError("--lr: must be > 0");
  const Tree model = io::read_tree_file(a.model);
  const Tree target = io::read_tree_file(a.target);
  const diffcsg::Scene model_scene = diffcsg::scene_from_tree(model, a.model);
  const diffcsg::Scene target_scene = diffcsg::scene_from_tree(target, a.target);
  if (model_scene.primitives.size() != target_scene.primitives.size()) {
    throw InputError(
        fmt::format("{}: {} primitives, the model {}: the target must be the same "
                    "program (primitive k for primitive k)",
                    a.target, target_scene.primitives.size(), model_scene.primitives.size()));
  }
  prepare_output_dir(a.out);
  // Cameras around the target's bounding box, evenly in azimuth.
  diffcsg::Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const diffcsg::TriMesh& m : target_scene.primitives) {
    for (const diffcsg::Vec3& v : m.vertices) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], v[k]);
        hi[k] = std::max(hi[k], v[k]);
      }
    }
  }
  const diffcsg::Vec3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  const double diagonal =
      std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
  const double distance = a.distance > 0
                              ? a.distance
                              : diagonal / 2 / std::sin(15 * 3.14159265358979323846 / 180) * 1.2;
  std::vector<diffcsg::Camera> cams;
  std::vector<diffcsg::Image> targets;
  for (int v = 0; v < a.views; ++v) {
    cams.push_back(diffcsg::Camera::orbit(centre, 30 + 360.0 * v / a.views, a.elevation, distance,
                                          a.size, a.size, 30));
    targets.push_back(render(target_scene, cams.back(), a.threads));
  }
  diffcsg::RefineOptions o;
  o.iterations = a.iters;
  o.lr = a.lr;
  o.stop_loss = a.stop;
  o.intersection_aa = !a.no_intersection_aa;
  o.threads = a.threads;
  const auto start = std::chrono::steady_clock::now();
  const diffcsg::RefineResult r = diffcsg::refine_to_images(model, cams, targets, o);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::filesystem::path out(a.out);
  io::write_text_file_atomic(out / "before.png", png_of(render(model_scene, cams[0], a.threads)));
  io::write_text_file_atomic(out / "target.png", png_of(targets[0]));
  io::write_text_file_atomic(
      out / "after.png",
      png_of(render(diffcsg::scene_from_tree(r.tree, "refined"), cams[0], a.threads)));
  io::write_tree_file(r.tree, out / "tree.json");
  scad::write_scad(r.tree, r.tree.params.values(), out / "model.scad");
  nlohmann::json report;
  report["format"] = "fuzzycsg-refine-report";
  report["version"] = 1;
  report["command_line"] = command_line();
  report["model"] = a.model;
  report["target"] = a.target;
  report["settings"] = {{"views", a.views},         {"size", a.size},
                        {"iters", a.iters},         {"lr", a.lr},
                        {"stop", a.stop},           {"intersection_aa", !a.no_intersection_aa},
                        {"elevation", a.elevation}, {"distance", distance}};
  report["steps"] = r.steps;
  report["converged"] = r.converged;
  report["vanished"] = r.vanished;
  report["loss"] = r.loss;
  report["seconds"] = seconds;
  report["seconds_per_step"] = {{"visibility", r.seconds_visibility / std::max(1, r.steps + 1)},
                                {"edges", r.seconds_edges / std::max(1, r.steps + 1)},
                                {"antialias", r.seconds_antialias / std::max(1, r.steps + 1)},
                                {"backward", r.seconds_backward / std::max(1, r.steps + 1)}};
  io::write_text_file_atomic(out / "report.json", report.dump(2) + "\n");
  if (r.vanished) {
    fmt::print(stderr, "refine: the model vanished from every view at step {}; stopped\n", r.steps);
  }
  if (!a.quiet) {
    fmt::print(
        "refine: loss {:.3g} -> {:.3g} in {} steps ({:.1f} s{}); wrote {}/{{tree.json, "
        "model.scad, report.json, before.png, after.png, target.png}}\n",
        r.loss.front(), r.loss.back(), r.steps, seconds, r.converged ? ", converged" : "", a.out);
  }
  return 0;
}

}  // namespace

Verb register_refine(CLI::App& app) {
  auto a = std::make_shared<RefineArgs>();
  CLI::App* cmd = app.add_subcommand(
      "refine", "Refine a CSG program's parameters so that its renderings match a target's");
  cmd->add_option("model", a->model, "Tree file (3D; box, sphere, cylinder leaves)")->required();
  cmd->add_option("--target", a->target, "Tree file of the same program, the target")->required();
  cmd->add_option("-o,--output", a->out, "Output directory")->required();
  cmd->add_option("--views", a->views, "Cameras around the target")->capture_default_str();
  cmd->add_option("--size", a->size, "Image size (pixels, square)")->capture_default_str();
  cmd->add_option("--iters", a->iters, "Adam steps at most")->capture_default_str();
  cmd->add_option("--lr", a->lr, "Learning rate")->capture_default_str();
  cmd->add_option("--stop", a->stop, "Stop below this mean squared error")->capture_default_str();
  cmd->add_option("--elevation", a->elevation, "Cameras' elevation, degrees")
      ->capture_default_str();
  cmd->add_option("--distance", a->distance, "Cameras' distance (0: the target fills the view)")
      ->capture_default_str();
  cmd->add_flag("--no-intersection-aa", a->no_intersection_aa,
                "Antialias silhouettes only (DiffCSG's ablation)");
  cmd->add_option("--threads", a->threads, "Threads (0: all)")->capture_default_str();
  cmd->add_flag("-q,--quiet", a->quiet, "No summary line");
  return {cmd, [a] { return run_refine(*a); }};
}

}  // namespace fuzzycsg::app
