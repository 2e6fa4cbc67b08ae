// fuzzycsg raster MODEL -o OUT.png [--camera AZ,EL,DIST] [--size W[,H]] [--fov DEG]
//                  [--normals | --colors]
//
// A 3D tree of boxes, spheres and cylinders, or an OpenSCAD model in its flattened .csg form
// (diffcsg/openscad_csg.hpp), drawn as CSG of meshed primitives (DiffCSG's forward pass): the
// visible surface of every pixel found by rays through all primitives' meshes
// (fuzzycsg/diffcsg/visibility.hpp), written as a normal map (the default; RGB = (n + 1) / 2) or in
// each primitive's colour; background transparent.

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
#include "fuzzycsg/diffcsg/visibility.hpp"
#include "fuzzycsg/io/png.hpp"
#include "fuzzycsg/io/points.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::app {

namespace {

struct RasterArgs {
  std::string model, out;
  std::vector<double> camera{30, 25, 0};
  std::vector<int> size{512};
  double fov = 30;
  bool colors = false, normals = false, quiet = false;
  int sphere_subdivisions = 2, cylinder_segments = 16, threads = 0;
};

int run_raster(const RasterArgs& a) {
  if (a.camera.size() != 3) throw InputError("--camera: three numbers AZ,EL,DIST expected");
  if (a.size.empty() || a.size.size() > 2 || a.size[0] < 1 || a.size.back() < 1 ||
      a.size[0] > 8192 || a.size.back() > 8192) {
    throw InputError("--size: W or W,H in [1, 8192] expected");
  }
  if (!(a.fov > 0 && a.fov < 180)) throw InputError("--fov: must be in (0, 180) degrees");
  diffcsg::TessellationOptions t;
  t.sphere_subdivisions = a.sphere_subdivisions;
  t.cylinder_segments = a.cylinder_segments;
  const bool openscad = std::filesystem::path(a.model).extension() == ".csg";
  const diffcsg::Scene scene =
      openscad ? diffcsg::read_openscad_csg(a.model)
               : diffcsg::scene_from_tree(io::read_tree_file(a.model), a.model, t);
  // Aimed at the centre of the primitives' bounding box; by default far enough for its
  // bounding sphere to fill the view.
  diffcsg::Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const diffcsg::TriMesh& m : scene.primitives) {
    for (const diffcsg::Vec3& v : m.vertices) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], v[k]);
        hi[k] = std::max(hi[k], v[k]);
      }
    }
  }
  const diffcsg::Vec3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  double diagonal = 0;
  for (int k = 0; k < 3; ++k) diagonal += (hi[k] - lo[k]) * (hi[k] - lo[k]);
  diagonal = std::sqrt(diagonal);
  const double distance =
      a.camera[2] > 0 ? a.camera[2]
                      : diagonal / 2 / std::sin(a.fov * 3.14159265358979323846 / 360) * 1.05;
  const int w = a.size[0], h = a.size.back();
  const diffcsg::Camera cam =
      diffcsg::Camera::orbit(centre, a.camera[0], a.camera[1], distance, w, h, a.fov);
  const auto start = std::chrono::steady_clock::now();
  const diffcsg::Frame f = diffcsg::render_visibility(scene, cam, a.threads);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<unsigned char> rgba(static_cast<std::size_t>(w) * h * 4, 0);
  for (std::size_t p = 0; p < f.primitive.size(); ++p) {
    if (f.primitive[p] < 0) continue;
    unsigned char* o = &rgba[p * 4];
    if (a.colors) {
      const std::array<float, 3> c = diffcsg::primitive_colour(f.primitive[p]);
      // Shaded by the normal's facing, so that faces of one primitive stay apart.
      const diffcsg::Vec3 d = cam.ray(static_cast<int>(p % static_cast<std::size_t>(w)),
                                      static_cast<int>(p / static_cast<std::size_t>(w)));
      const double facing =
          std::abs(d[0] * f.normal[p][0] + d[1] * f.normal[p][1] + d[2] * f.normal[p][2]);
      for (int k = 0; k < 3; ++k) {
        o[k] = static_cast<unsigned char>(
            std::lround(255 * c[static_cast<std::size_t>(k)] * (0.35 + 0.65 * facing)));
      }
    } else {
      for (int k = 0; k < 3; ++k) {
        o[k] = static_cast<unsigned char>(std::lround((f.normal[p][k] + 1) * 127.5));
      }
    }
    o[3] = 255;
  }
  io::write_text_file_atomic(a.out, encode_png(w, h, 4, rgba));
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
      "raster",
      "A 3D tree of boxes, spheres and cylinders drawn as CSG of meshes (normals or "
      "colours)");
  cmd->add_option("model", a->model,
                  "Tree file (3D; box, sphere, cylinder leaves) or OpenSCAD .csg")
      ->required();
  cmd->add_option("-o,--output", a->out, "Output PNG")->required();
  cmd->add_option("--camera", a->camera,
                  "AZ,EL,DIST: degrees about +z from +x, degrees above the xy plane, distance "
                  "from the primitives' centre (0: they fill the view)")
      ->delimiter(',')
      ->expected(3);
  cmd->add_option("--size", a->size, "W or W,H pixels")->delimiter(',')->expected(1, 2);
  cmd->add_option("--fov", a->fov, "Vertical field of view, degrees")->capture_default_str();
  auto* colors = cmd->add_flag("--colors", a->colors, "Each primitive in its colour");
  cmd->add_flag("--normals", a->normals, "The normal map (the default)")->excludes(colors);
  cmd->add_option("--sphere-subdivisions", a->sphere_subdivisions,
                  "Icosahedron subdivisions of spheres (20 * 4^n triangles)")
      ->capture_default_str();
  cmd->add_option("--cylinder-segments", a->cylinder_segments, "Sides of cylinders")
      ->capture_default_str();
  cmd->add_option("--threads", a->threads, "Threads (0: all)")->capture_default_str();
  cmd->add_flag("-q,--quiet", a->quiet, "No summary line");
  return {cmd, [a] { return run_raster(*a); }};
}

}  // namespace fuzzycsg::app
