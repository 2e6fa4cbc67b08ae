// fuzzycsg raster MODEL -o OUT.png [--camera AZ,EL,DIST] [--size W[,H]] [--fov DEG]
//                  [--normals | --colors | --shaded] [--save-views VIEWS.json]
//                  [--gradient PARAM [--target T] [--finite-difference H]]
//
// A 3D tree of meshed primitives, or an OpenSCAD model in its flattened .csg form
// (diffcsg/openscad_csg.hpp), drawn as CSG of meshed primitives by DiffCSG's forward pass: the
// visible surface of every pixel found by rays through all primitives' meshes, shaded and
// antialiased along silhouettes and intersection edges (fuzzycsg/diffcsg/pipeline.hpp):
//   --normals (default)  the normal image refine matches: RGB = (n + 1) / 2
//   --colors             each primitive's flat colour, the colour image refine matches
//   --shaded             each primitive's colour shaded by how the surface faces the camera
// Background transparent. --save-views writes a views file (diffcsg/targets.hpp) naming the
// PNG and its camera, so that the picture, edited or not, can be a target of refine.
//
// --gradient PARAM draws the image of one parameter's gradient (DiffCSG Fig. 1 and 9), pixel by
// pixel: without --target, d(sum of the image's channels)/dθ; with a target (a model or a
// views file), the derivative of each pixel's loss term. Blue is negative, red positive;
// --finite-difference H draws the same by central differences of step H instead.

#include <fmt/format.h>

#include <algorithm>
#include <array>
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
#include "fuzzycsg/diffcsg/targets.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/png.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::app {

namespace {

struct RasterArgs {
  std::string model, out, save_views, gradient, target, loss = "l2";
  std::vector<double> camera{30, 25, 0};
  std::vector<int> size{512};
  double fov = 30, finite_difference = 0, gradient_scale = 0;
  bool colors = false, normals = false, shaded = false, quiet = false, no_intersection_aa = false;
  int sphere_subdivisions = 2, cylinder_segments = 16, threads = 0;
};

// Per-pixel values as a diverging picture: blue negative, white 0, red positive, saturating at
// `scale`.
std::string gradient_png(const std::vector<double>& values, int w, int h, double scale) {
  std::vector<unsigned char> rgb(values.size() * 3);
  for (std::size_t p = 0; p < values.size(); ++p) {
    const double x = std::clamp(values[p] / scale, -1.0, 1.0);
    const double keep = 1 - std::abs(x);  // the other two channels
    const unsigned char fade = static_cast<unsigned char>(std::lround(255 * keep));
    unsigned char* o = &rgb[p * 3];
    o[0] = x > 0 ? 255 : fade;
    o[1] = fade;
    o[2] = x < 0 ? 255 : fade;
  }
  return encode_png(w, h, 3, rgb);
}

// Each pixel's share of the loss (image_loss's sum split by pixel).
std::vector<double> pixel_losses(const diffcsg::Image& img, const diffcsg::Image& target,
                                 diffcsg::Loss loss) {
  const std::size_t pixels = static_cast<std::size_t>(img.width) * img.height;
  std::vector<double> out(pixels, 0.0);
  for (std::size_t p = 0; p < pixels; ++p) {
    double e = 0, l1 = 0;
    for (int c = 0; c < 3; ++c) {
      const double d = img.at(p)[c] - target.at(p)[c];
      e += d * d;
      l1 += std::abs(d);
    }
    out[p] = loss == diffcsg::Loss::kTanh ? std::tanh(10 * e) / static_cast<double>(pixels)
             : loss == diffcsg::Loss::kL1 ? l1 / (3.0 * static_cast<double>(pixels))
                                          : e / (3.0 * static_cast<double>(pixels));
  }
  return out;
}

int run_raster(const RasterArgs& a) {
  if (a.camera.size() != 3) throw InputError("--camera: three numbers AZ,EL,DIST expected");
  if (a.size.empty() || a.size.size() > 2 || a.size[0] < 1 || a.size.back() < 1 ||
      a.size[0] > 8192 || a.size.back() > 8192) {
    throw InputError("--size: W or W,H in [1, 8192] expected");
  }
  if (!(a.fov > 0 && a.fov < 180)) throw InputError("--fov: must be in (0, 180) degrees");
  const bool gradient = !a.gradient.empty();
  if (!gradient && (!a.target.empty() || a.finite_difference != 0)) {
    throw InputError("--target and --finite-difference: only with --gradient");
  }
  if (a.finite_difference < 0) throw InputError("--finite-difference: must be > 0");
  if (gradient && a.shaded) throw InputError("--gradient: of --normals or --colors images");
  if (!a.save_views.empty() && (a.shaded || gradient)) {
    throw InputError("--save-views: of --normals or --colors images");
  }
  const auto loss = diffcsg::loss_from_name(a.loss);
  if (!loss) throw InputError("--loss: l1, l2 or tanh");
  const diffcsg::Shading shading =
      a.colors ? diffcsg::Shading::kColours : diffcsg::Shading::kNormals;
  diffcsg::TessellationOptions t;
  t.sphere_subdivisions = a.sphere_subdivisions;
  t.cylinder_segments = a.cylinder_segments;
  // A gradient needs the model as a tree (its parameters); a plain picture of a .csg model
  // takes OpenSCAD's transforms as they are.
  std::optional<diffcsg::OpenscadModel> model;
  if (gradient || !has_extension(a.model, {".csg"})) {
    model = has_extension(a.model, {".csg"})
                ? diffcsg::read_openscad_csg_tree(a.model)
                : diffcsg::OpenscadModel{io::read_tree_file(a.model), t};
  }
  const diffcsg::Scene scene =
      model ? diffcsg::scene_from_tree(model->tree, a.model, model->tessellation)
            : diffcsg::read_openscad_csg(a.model);
  // Aimed at the centre of the primitives' bounding box; by default far enough for its
  // bounding sphere to fill the view.
  const auto [lo, hi] = scene.bounds();
  const diffcsg::Vec3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  const double distance =
      a.camera[2] > 0 ? a.camera[2] : diffcsg::framing_distance(scene, centre, a.fov);
  const int w = a.size[0], h = a.size.back();
  const diffcsg::Camera cam =
      diffcsg::Camera::orbit(centre, a.camera[0], a.camera[1], distance, w, h, a.fov);
  const auto start = std::chrono::steady_clock::now();
  const diffcsg::PreparedScene prepared = diffcsg::prepare_scene(scene, !a.no_intersection_aa);
  const diffcsg::ViewPass pass = diffcsg::render_view(prepared, cam, shading, a.threads);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const diffcsg::Frame& f = pass.frame;

  if (gradient) {
    const auto param = model->tree.params.find(a.gradient);
    if (!param) {
      std::string names;
      for (std::size_t k = 0; k < model->tree.params.size() && k < 4; ++k) {
        names += (k ? ", " : "") + model->tree.params.at(k).name;
      }
      throw InputError(fmt::format("--gradient: {} has no parameter \"{}\" (it has {}: {}{})",
                                   a.model, a.gradient, model->tree.params.size(), names,
                                   model->tree.params.size() > 4 ? ", ..." : ""));
    }
    std::optional<diffcsg::Image> target;
    if (!a.target.empty()) {
      if (std::filesystem::path(a.target).extension() == ".json" &&
          diffcsg::is_views_file(a.target)) {
        const diffcsg::ViewSet set = diffcsg::read_views(a.target);
        if (set.shading != shading) throw InputError(fmt::format("{}: other shading", a.target));
        if (set.images[0].width != w || set.images[0].height != h) {
          throw InputError(fmt::format("{}: view 0's image is {}x{}, --size {}x{}", a.target,
                                       set.images[0].width, set.images[0].height, w, h));
        }
        target = set.images[0];
      } else {
        const diffcsg::OpenscadModel tm =
            has_extension(a.target, {".csg"})
                ? diffcsg::read_openscad_csg_tree(a.target)
                : diffcsg::OpenscadModel{io::read_tree_file(a.target), t};
        target = diffcsg::render_image(
            diffcsg::prepare_scene(diffcsg::scene_from_tree(tm.tree, a.target, tm.tessellation),
                                   !a.no_intersection_aa),
            cam, shading, a.threads);
      }
    }
    const std::size_t pixels = static_cast<std::size_t>(w) * h;
    std::vector<double> values(pixels, 0.0);
    std::string method;
    if (a.finite_difference > 0) {
      method = fmt::format("central differences, step {}", a.finite_difference);
      const auto image_at = [&](double delta) {
        Tree tree = model->tree;
        tree.params[*param].value += delta;
        const diffcsg::Image img = diffcsg::render_image(
            diffcsg::prepare_scene(diffcsg::scene_from_tree(tree, a.model, model->tessellation),
                                   !a.no_intersection_aa),
            cam, shading, a.threads);
        if (target) return pixel_losses(img, *target, *loss);
        std::vector<double> sum(pixels, 0.0);
        for (std::size_t p = 0; p < pixels; ++p)
          sum[p] = img.at(p)[0] + img.at(p)[1] + img.at(p)[2];
        return sum;
      };
      const std::vector<double> up = image_at(a.finite_difference),
                                down = image_at(-a.finite_difference);
      for (std::size_t p = 0; p < pixels; ++p) {
        values[p] = (up[p] - down[p]) / (2 * a.finite_difference);
      }
    } else {
      method = "analytic";
      diffcsg::Image g;
      if (target) {
        diffcsg::image_loss(pass.image, *target, *loss, &g);
      } else {
        g = pass.image;
        std::fill(g.data.begin(), g.data.end(), 1.0f);
      }
      const auto tangent = diffcsg::vertex_tangent(model->tree, prepared.scene, param->index);
      diffcsg::VertexGradient vg;
      vg.tangent = &tangent;
      vg.per_pixel = &values;
      diffcsg::render_view_backward(prepared, cam, shading, pass, g, vg);
    }
    double total = 0;
    std::vector<double> magnitude;
    for (const double v : values) {
      total += v;
      if (v != 0) magnitude.push_back(std::abs(v));
    }
    double scale = a.gradient_scale;
    if (!(scale > 0)) {
      scale = 1;
      if (!magnitude.empty()) {
        const std::size_t k = magnitude.size() * 99 / 100;
        std::nth_element(magnitude.begin(), magnitude.begin() + static_cast<std::ptrdiff_t>(k),
                         magnitude.end());
        scale = magnitude[k];
      }
    }
    io::write_text_file_atomic(a.out, gradient_png(values, w, h, scale));
    if (!a.quiet) {
      fmt::print(
          "raster: gradient of {} ({}): total {:.6g}, {} pixels non-zero, colour scale "
          "{:.3g}, to {}\n",
          a.gradient, method, total, magnitude.size(), scale, a.out);
    }
    return 0;
  }

  std::string png;
  if (a.shaded) {
    std::vector<unsigned char> rgba(static_cast<std::size_t>(w) * h * 4, 0);
    for (std::size_t p = 0; p < f.primitive.size(); ++p) {
      if (f.primitive[p] < 0) continue;
      unsigned char* o = &rgba[p * 4];
      const std::array<float, 3> c = diffcsg::primitive_colour(f.primitive[p]);
      // Shaded by the normal's facing, so that faces of one primitive stay apart.
      const diffcsg::Vec3 d = cam.ray(static_cast<int>(p % static_cast<std::size_t>(w)),
                                      static_cast<int>(p / static_cast<std::size_t>(w)));
      const double facing =
          std::abs(d[0] * f.normal[p][0] + d[1] * f.normal[p][1] + d[2] * f.normal[p][2]);
      for (std::size_t k = 0; k < 3; ++k) {
        o[k] = static_cast<unsigned char>(std::lround(255 * c[k] * (0.35 + 0.65 * facing)));
      }
      o[3] = 255;
    }
    png = encode_png(w, h, 4, rgba);
  } else {
    png = diffcsg::encode_image_png(pass.image, shading);
  }
  io::write_text_file_atomic(a.out, png);
  if (!a.save_views.empty()) {
    const std::filesystem::path views(a.save_views), image(a.out);
    const std::filesystem::path rel = std::filesystem::absolute(image).lexically_relative(
        std::filesystem::absolute(views).parent_path());
    io::write_text_file_atomic(views, diffcsg::views_json(shading, {cam}, {rel.generic_string()}));
  }
  if (f.visible_pixels() == 0) {
    fmt::print(stderr, "raster: warning: {}: the camera sees nothing of the model\n", a.out);
  }
  if (!a.quiet) {
    fmt::print("raster: {} primitives, {} triangles, {}x{} pixels ({} covered) in {:.3f} s to {}\n",
               scene.primitives.size(), scene.triangle_count(), w, h, f.visible_pixels(), seconds,
               a.out);
  }
  return 0;
}

}  // namespace

Verb register_raster(CLI::App& app) {
  auto a = std::make_shared<RasterArgs>();
  CLI::App* cmd = app.add_subcommand(
      "raster", "A 3D tree or OpenSCAD model drawn as CSG of meshes (normals, colours, gradients)");
  cmd->add_option("model", a->model,
                  "Tree file (3D; box, sphere, ellipsoid, cylinder, cone leaves) or OpenSCAD .csg")
      ->required();
  cmd->add_option("-o,--output", a->out, "Output PNG")->required();
  cmd->add_option("--camera", a->camera,
                  "AZ,EL,DIST: degrees about +z from +x, degrees above the xy plane, distance "
                  "from the primitives' centre (0: they fill the view)")
      ->delimiter(',')
      ->expected(3);
  cmd->add_option("--size", a->size, "W or W,H pixels")->delimiter(',')->expected(1, 2);
  cmd->add_option("--fov", a->fov, "Vertical field of view, degrees")->capture_default_str();
  auto* colors = cmd->add_flag("--colors", a->colors, "Each primitive in its flat colour");
  auto* shaded =
      cmd->add_flag("--shaded", a->shaded, "Each primitive's colour shaded by its facing");
  cmd->add_flag("--normals", a->normals, "The normal map (the default)")
      ->excludes(colors)
      ->excludes(shaded);
  colors->excludes(shaded);
  cmd->add_option("--save-views", a->save_views,
                  "Also write a views file (the PNG and its camera), a target for refine");
  cmd->add_option("--gradient", a->gradient,
                  "Draw this parameter's gradient image instead (a name as `info` lists it)");
  cmd->add_option("--target", a->target,
                  "--gradient: of each pixel's loss against this model or views file");
  cmd->add_option("--loss", a->loss, "--gradient with --target: l1, l2 or tanh")
      ->capture_default_str();
  cmd->add_option("--finite-difference", a->finite_difference,
                  "--gradient: by central differences of this step instead");
  cmd->add_option("--gradient-scale", a->gradient_scale,
                  "--gradient: the value drawn at full colour (0: the 99th percentile)");
  cmd->add_flag("--no-intersection-aa", a->no_intersection_aa,
                "Antialias silhouettes only (DiffCSG's ablation)");
  cmd->add_option("--sphere-subdivisions", a->sphere_subdivisions,
                  "Icosahedron subdivisions of spheres (20 * 4^n triangles)")
      ->capture_default_str();
  cmd->add_option("--cylinder-segments", a->cylinder_segments, "Sides of cylinders and cones")
      ->capture_default_str();
  add_threads_option(cmd, a->threads);
  cmd->add_flag("-q,--quiet", a->quiet, "No summary line");
  return {cmd, [a] { return run_raster(*a); }};
}

}  // namespace fuzzycsg::app
