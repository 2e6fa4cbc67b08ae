// fuzzycsg render TREE -o OUT.png|OUT.svg|OUT.pdf [--plot] [--size W H] [--camera EX EY EZ TX TY
// TZ]
//                 [--fov F] [--views N] [--up [-]x|y|z] [--resolution N] [--threads N]
//
// A shaded picture of a 3D tree's 0.5 level set (PNG), from a camera or from default cameras
// that frame the shape (several side by side with --views); of a 2D tree, its occupancy with a
// colour scale and the 0.5 contour (PNG, PDF, and SVG with --plot), or (OUT.svg) its
// primitives' outlines over the result. The format follows OUT's extension.

#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/canvas.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/render/render.hpp"

namespace fuzzycsg::app {

namespace {

struct RenderArgs {
  std::string tree, out;
  bool plot = false;
  std::vector<int> size{800, 600};
  std::vector<double> camera;
  double fov = 30.0;
  std::string up = "z";
  RenderOptions options;
};

int run_render(RenderArgs a) {
  const std::optional<PictureFormat> format = picture_format_of(a.out);
  if (!format) {
    throw InputError(
        fmt::format("{}: unknown picture format '{}' (render writes .png, .svg or .pdf)", a.out,
                    std::filesystem::path(a.out).extension().string()));
  }
  const Tree tree = io::read_tree_file(a.tree);
  if (tree.dim != 2) {
    if (a.plot) throw InputError(fmt::format("--plot: {} is a 3D tree (the plot is 2D)", a.tree));
    if (*format != PictureFormat::kPng) {
      throw InputError(fmt::format("{}: {} is for 2D trees (a 3D tree renders to PNG)", a.out,
                                   *format == PictureFormat::kSvg ? "SVG" : "PDF"));
    }
  }
  if (tree.dim == 2 && *format == PictureFormat::kSvg && !a.plot) {
    // The primitives' outlines over the filled result; --size W: the longer side.
    OutlineOptions o;
    o.size = a.size[0];
    o.resolution = a.options.resolution;
    o.threads = a.options.threads;
    std::string svg;
    try {
      svg = outlines_svg(tree, tree.params.values(), o);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", a.tree, e.what()));
    }
    io::write_text_file_atomic(a.out, svg);
    return 0;
  }
  if (tree.dim == 2) {
    // The occupancy with a colour scale and the 0.5 contour; --size W: the longer side.
    PlotOptions p;
    p.size = a.size[0];
    p.format = *format;
    p.threads = a.options.threads;
    std::string picture;
    try {
      picture = plot_2d(tree, tree.params.values(), p);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", a.tree, e.what()));
    }
    io::write_text_file_atomic(a.out, picture);
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
      "render",
      "A picture: a 3D tree shaded (PNG); a 2D tree's occupancy and 0.5 contour (PNG, PDF), or "
      "its primitive outlines over the result (SVG)");
  cmd->add_option("tree", a->tree, "Tree file")->required();
  cmd->add_option("-o,--output", a->out,
                  "Picture file, its format by the extension: .png, .svg (2D) or .pdf (2D)")
      ->required();
  cmd->add_flag("--plot", a->plot,
                "2D: the occupancy plot in any format (an .svg output draws the outlines without "
                "it)");
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
  add_threads_option(cmd, a->options.threads);
  return {cmd, [a] { return run_render(*a); }};
}

}  // namespace fuzzycsg::app
