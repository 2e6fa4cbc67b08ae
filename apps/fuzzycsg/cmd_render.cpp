// fuzzycsg render TREE -o OUT.png [--size W H] [--camera EX EY EZ TX TY TZ] [--fov F]
//                 [--views N] [--up [-]x|y|z] [--resolution N] [--threads N]
//
// A shaded picture of a 3D tree's 0.5 level set, from a camera or from default cameras that
// frame the shape (several side by side with --views); of a 2D tree, its occupancy with a
// colour scale and the 0.5 contour.

#include <fmt/format.h>

#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/points.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/render/render.hpp"

namespace fuzzycsg::app {

namespace {

struct RenderArgs {
  std::string tree, out;
  std::vector<int> size{800, 600};
  std::vector<double> camera;
  double fov = 30.0;
  std::string up = "z";
  RenderOptions options;
};

int run_render(RenderArgs a) {
  const Tree tree = io::read_tree_file(a.tree);
  if (tree.dim == 2) {
    // The occupancy with a colour scale and the 0.5 contour; --size W: the longer side.
    std::string png;
    try {
      png = plot_2d_png(tree, tree.params.values(), a.size[0], a.options.threads);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", a.tree, e.what()));
    }
    io::write_text_file_atomic(a.out, png);
    return 0;
  }
  a.options.width = a.size[0];
  a.options.height = a.size[1];
  const double sign = a.up[0] == '-' ? -1.0 : 1.0;
  const char axis = a.up.back();
  a.options.up = {axis == 'x' ? sign : 0.0, axis == 'y' ? sign : 0.0, axis == 'z' ? sign : 0.0};
  if (!a.camera.empty()) {
    Camera c;
    c.eye = {a.camera[0], a.camera[1], a.camera[2]};
    c.target = {a.camera[3], a.camera[4], a.camera[5]};
    c.up = a.options.up;
    c.fov_deg = a.fov;
    a.options.camera = c;
  }
  std::string png;
  try {
    png = render_png(tree, tree.params.values(), a.options);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", a.tree, e.what()));
  }
  io::write_text_file_atomic(a.out, png);
  return 0;
}

}  // namespace

Verb register_render(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand(
      "render", "A picture (PNG): a 3D tree shaded, a 2D tree's occupancy and 0.5 contour");
  cmd->add_option("tree", a->tree, "Tree file")->required();
  cmd->add_option("-o,--output", a->out, "PNG file")->required();
  cmd->add_option("--size", a->size, "Width and height of one view in pixels")
      ->expected(2)
      ->capture_default_str()
      ->check(CLI::Range(1, 8192));
  cmd->add_option("--camera", a->camera, "Eye and target: EX EY EZ TX TY TZ (default: framing)")
      ->expected(6);
  cmd->add_option("--fov", a->fov, "Vertical field of view of --camera, degrees")
      ->capture_default_str();
  cmd->add_option("--views", a->options.views, "Default views around the shape, side by side")
      ->capture_default_str()
      ->check(CLI::Range(1, 8));
  cmd->add_option("--up", a->up, "The axis that points up")
      ->capture_default_str()
      ->check(CLI::IsMember({"x", "y", "z", "-x", "-y", "-z"}));
  cmd->add_option("--resolution", a->options.resolution, "Grid cells of the mesh rendered")
      ->capture_default_str()
      ->check(CLI::Range(1, kMaxMeshResolution));
  cmd->add_option("--threads", a->options.threads, "Threads (0: all cores)")
      ->check(CLI::Range(0, 1024));
  return {cmd, [a] { return run_render(*a); }};
}

}  // namespace fuzzycsg::app
