// fuzzycsg refine MODEL --target (MODEL | MESH | VIEWS.json) -o OUTDIR [--shading normals|colours]
//                 [--loss l1|l2|tanh] [--views N] [--size N] [--iters N] [--lr F] [--stop F]
//                 [--random-views K] [--no-intersection-aa] ...
//
// DiffCSG's image-based refinement (fuzzycsg/diffcsg/refine.hpp): the continuous parameters of
// MODEL (a 3D tree file, or an OpenSCAD model in its flattened .csg form) are optimised so that
// its renderings match the target's, without any mesh boolean. The target is another model
// (tree file or .csg), a mesh (OBJ, STL, PLY, OFF), or a views file of images with their
// cameras (diffcsg/targets.hpp). Writes tree.json and model.scad (refined), report.json
// (settings, loss curve, the check view's error, time per step split into visibility, edges,
// antialiasing and backward, every parameter before and after) and before.png, after.png,
// target.png (the check view, view 0).

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diffcsg/openscad_csg.hpp"
#include "fuzzycsg/diffcsg/refine.hpp"
#include "fuzzycsg/diffcsg/refine_target.hpp"
#include "fuzzycsg/diffcsg/report.hpp"
#include "fuzzycsg/diffcsg/targets.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/scad/scad.hpp"

namespace fuzzycsg::app {

namespace {

struct RefineArgs {
  std::string model, target, out, shading = "normals", loss = "l2", method = "adam";
  int views = 4, size = 256, iters = 1000, threads = 0, random_views = 0;
  int sphere_subdivisions = 2, cylinder_segments = 16;
  long long seed = 1;
  double lr = 0.01, stop = 5e-4, elevation = 25, distance = 0, fov = 30, cmaes_sigma = 0.1,
         lr_relative = 0;
  bool no_intersection_aa = false, quiet = false, size_given = false, shared_only = false;
};

// The ranges of the numeric options.
void check_ranges(const RefineArgs& a) {
  if (a.iters < 0) throw InputError("--iters: must not be negative");
  if (!(a.lr > 0)) throw InputError("--lr: must be > 0");
  if (!(a.stop >= 0)) throw InputError("--stop: must not be negative");
}

// The refinement's options (with a progress line every twentieth of --iters unless --quiet).
diffcsg::RefineOptions refine_options(const RefineArgs& a, diffcsg::Method method,
                                      diffcsg::Loss loss) {
  diffcsg::RefineOptions o;
  o.method = method;
  o.cmaes_sigma = a.cmaes_sigma;
  o.iterations = a.iters;
  o.lr = a.lr;
  o.lr_relative = a.lr_relative;
  o.loss = loss;
  o.stop_mse = a.stop;
  o.intersection_aa = !a.no_intersection_aa;
  o.random_view_every = a.random_views;
  o.seed = static_cast<std::uint64_t>(a.seed);
  o.threads = a.threads;
  if (!a.quiet) {
    o.progress = [start = std::chrono::steady_clock::now(), every = std::max(1, a.iters / 20)](
                     int step, double l) {
      if (step % every == 0) {
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        fmt::print("refine: step {:>5}  loss {:.4g}  {:.1f} steps/s\n", step, l,
                   step / std::max(s, 1e-9));
        std::fflush(stdout);
      }
      return true;
    };
  }
  return o;
}

int run_refine(const RefineArgs& a) {
  check_ranges(a);
  const auto shading = diffcsg::shading_from_name(a.shading);
  if (!shading) throw InputError("--shading: normals or colours");
  const auto loss = diffcsg::loss_from_name(a.loss);
  if (!loss) throw InputError("--loss: l1, l2 or tanh");
  const auto method = diffcsg::method_from_name(a.method);
  if (!method) throw InputError("--method: adam or cmaes");
  if (*method == diffcsg::Method::kCmaes && a.random_views > 0) {
    throw InputError("--random-views: not with --method cmaes (it needs one objective)");
  }
  if (!(a.cmaes_sigma > 0)) throw InputError("--cmaes-sigma: must be > 0");
  if (!(a.lr_relative >= 0)) throw InputError("--lr-relative: must not be negative");
  diffcsg::TessellationOptions tess;
  tess.sphere_subdivisions = a.sphere_subdivisions;
  tess.cylinder_segments = a.cylinder_segments;
  diffcsg::OpenscadModel model = diffcsg::read_refine_model(a.model, tess);
  // --shared-only: the program's hyper-parameters alone move (DiffCSG's H-Params).
  std::vector<bool> was_fixed;
  for (std::size_t k = 0; k < model.tree.params.size(); ++k) {
    Parameter& p = model.tree.params.at(k);
    was_fixed.push_back(p.fixed);
    if (a.shared_only && !p.shared) p.fixed = true;
  }
  if (a.shared_only) {
    bool any = false;
    for (const Parameter& p : model.tree.params.entries()) any = any || (p.shared && !p.fixed);
    if (!any)
      throw InputError(fmt::format("--shared-only: {} has no free shared parameters", a.model));
  }
  const diffcsg::Scene model_scene =
      diffcsg::scene_from_tree(model.tree, a.model, model.tessellation);

  diffcsg::TargetViewOptions view_options;
  view_options.shading = *shading;
  view_options.views = a.views;
  view_options.size = a.size;
  view_options.size_given = a.size_given;
  view_options.elevation = a.elevation;
  view_options.distance = a.distance;
  view_options.fov = a.fov;
  view_options.random_views = a.random_views;
  view_options.intersection_aa = !a.no_intersection_aa;
  view_options.threads = a.threads;
  const diffcsg::LoadedTarget loaded =
      diffcsg::load_refine_target(a.target, view_options, tess, model_scene);
  const diffcsg::RefineTarget& target = loaded.target;
  const std::string& target_kind = loaded.kind;
  // Cameras that see nothing of the model are bad input, found before anything is written.
  int seen = 0;
  for (const diffcsg::Camera& c : target.cameras) {
    seen += diffcsg::render_visibility(model_scene, c, a.threads).visible_pixels();
  }
  if (seen == 0) {
    throw InputError(fmt::format("{}: no view sees the model {} (the cameras see nothing of it)",
                                 a.target, a.model));
  }
  prepare_output_dir(a.out);

  const diffcsg::RefineOptions o = refine_options(a, *method, *loss);
  diffcsg::RefineResult r = diffcsg::refine(model.tree, target, o, model.tessellation);
  for (std::size_t k = 0; k < r.tree.params.size(); ++k) {  // as the file had them
    r.tree.params.at(k).fixed = was_fixed[k];
    model.tree.params.at(k).fixed = was_fixed[k];
  }

  const std::filesystem::path out(a.out);
  const diffcsg::Camera& check = target.cameras[0];
  const auto picture = [&](const diffcsg::Scene& s) {
    return diffcsg::encode_image_png(
        diffcsg::render_image(diffcsg::prepare_scene(s, !a.no_intersection_aa), check, *shading,
                              a.threads),
        *shading);
  };
  io::write_text_file_atomic(out / "before.png", picture(model_scene));
  io::write_text_file_atomic(out / "target.png",
                             diffcsg::encode_image_png(target.images[0], *shading));
  io::write_text_file_atomic(
      out / "after.png", picture(diffcsg::scene_from_tree(r.tree, "refined", model.tessellation)));
  io::write_tree_file(r.tree, out / "tree.json");
  scad::write_scad(r.tree, r.tree.params.values(), out / "model.scad");

  const diffcsg::RefineReportContext context{command_line(), a.model, a.target, target_kind,
                                             a.shared_only};
  io::write_text_file_atomic(
      out / "report.json",
      diffcsg::refine_report_json(model.tree, model_scene, target, o, r, context));
  const std::vector<std::string> paths = node_paths(r.tree);
  if (!r.unseen_primitives.empty()) {
    fmt::print(stderr, "refine: warning: {} primitive(s) no longer seen in any view (first {})\n",
               r.unseen_primitives.size(),
               paths[static_cast<std::size_t>(r.unseen_primitives.front())]);
  }
  if (r.vanished) {
    fmt::print(stderr,
               "refine: the model vanished from every view at step {}; stopped (wrote the last "
               "parameters that showed it)\n",
               r.steps);
    return 1;
  }
  if (!a.quiet) {
    const double final_mse = r.check_mse.empty() ? NAN : r.check_mse.back().second;
    fmt::print(
        "refine: loss {:.3g} -> {:.3g} in {} steps ({:.1f} s{}); check-view MSE {:.3g}; wrote "
        "{}/{{tree.json, model.scad, report.json, before.png, after.png, target.png}}\n",
        r.loss.front(), r.loss.back(), r.steps, r.seconds, r.converged ? ", converged" : "",
        final_mse, a.out);
  }
  return 0;
}

}  // namespace

Verb register_refine(CLI::App& app) {
  auto a = std::make_shared<RefineArgs>();
  CLI::App* cmd = app.add_subcommand(
      "refine", "Refine a CSG program's parameters so that its renderings match a target");
  cmd->add_option("model", a->model,
                  "Tree file (3D; box, sphere, ellipsoid, cylinder, cone leaves) or OpenSCAD .csg")
      ->required();
  cmd->add_option("--target", a->target,
                  "A model (tree file or .csg), a mesh (OBJ, STL, PLY, OFF) or a views file "
                  "(images and cameras)")
      ->required();
  cmd->add_option("-o,--output", a->out, "Output directory")->required();
  cmd->add_option("--shading", a->shading, "Images matched: normals or colours (per primitive)")
      ->capture_default_str();
  cmd->add_option("--loss", a->loss, "l1, l2 or tanh")->capture_default_str();
  cmd->add_option("--method", a->method,
                  "adam (gradients of the differentiable renderer) or cmaes (derivative-free; "
                  "--iters counts renders of the views)")
      ->capture_default_str();
  cmd->add_option("--cmaes-sigma", a->cmaes_sigma,
                  "CMA-ES's first steps, relative to each parameter's magnitude")
      ->capture_default_str();
  cmd->add_option("--views", a->views, "Cameras around a model or mesh target")
      ->capture_default_str();
  auto* size =
      cmd->add_option("--size", a->size, "Image size (pixels, square)")->capture_default_str();
  cmd->add_option("--iters", a->iters, "Adam steps at most")->capture_default_str();
  cmd->add_option("--lr", a->lr, "Learning rate (the parameters' units)")->capture_default_str();
  cmd->add_option("--lr-relative", a->lr_relative,
                  "Instead of --lr: each parameter's rate this fraction of its magnitude (at 0: "
                  "of 10 degrees for angles, 5% of the model's extent otherwise)");
  cmd->add_option("--stop", a->stop, "Stop when view 0's mean squared error falls below this")
      ->capture_default_str();
  cmd->add_option("--random-views", a->random_views,
                  "Train on one random view, drawn anew every K steps (model and mesh targets)")
      ->capture_default_str();
  cmd->add_option("--seed", a->seed, "Seed of the random views")
      ->capture_default_str()
      ->check(unsigned_number());
  cmd->add_option("--elevation", a->elevation, "Cameras' elevation, degrees")
      ->capture_default_str();
  cmd->add_option("--distance", a->distance, "Cameras' distance (0: the target fills the view)")
      ->capture_default_str();
  cmd->add_option("--fov", a->fov, "Vertical field of view, degrees")->capture_default_str();
  cmd->add_flag("--no-intersection-aa", a->no_intersection_aa,
                "Antialias silhouettes only (DiffCSG's ablation)");
  cmd->add_flag("--shared-only", a->shared_only,
                "Move only the tree's shared parameters (the program's hyper-parameters)");
  cmd->add_option("--sphere-subdivisions", a->sphere_subdivisions,
                  "Tree models: icosahedron subdivisions of spheres")
      ->capture_default_str();
  cmd->add_option("--cylinder-segments", a->cylinder_segments,
                  "Tree models: sides of cylinders and cones")
      ->capture_default_str();
  add_threads_option(cmd, a->threads);
  cmd->add_flag("-q,--quiet", a->quiet, "No progress or summary lines");
  return {cmd, [a, size] {
            a->size_given = size->count() > 0;
            return run_refine(*a);
          }};
}

}  // namespace fuzzycsg::app
