#include "fuzzycsg/diffcsg/refine_target.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <memory>
#include <utility>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diffcsg/pipeline.hpp"
#include "fuzzycsg/diffcsg/shade.hpp"
#include "fuzzycsg/diffcsg/targets.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::diffcsg {

namespace {

bool has_extension(const std::filesystem::path& path, std::initializer_list<const char*> exts) {
  std::string e = path.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return std::any_of(exts.begin(), exts.end(), [&](const char* x) { return e == x; });
}

void check(const TargetViewOptions& o) {
  if (o.views < 1 || o.views > 64) throw OptionError("views", "must be in [1, 64]");
  if (o.size < 8 || o.size > 4096) throw OptionError("size", "must be in [8, 4096]");
  if (o.random_views < 0) throw OptionError("random_views", "must not be negative");
  if (!(o.fov > 0 && o.fov < 180)) throw OptionError("fov", "must be in (0, 180) degrees");
  if (!(o.distance >= 0)) throw OptionError("distance", "must not be negative");
}

// A views file's cameras and images, checked against the options.
void read_view_set(const std::filesystem::path& path, const TargetViewOptions& o,
                   RefineTarget& target) {
  ViewSet set = read_views(path);
  if (set.shading != o.shading) {
    throw OptionError("shading", fmt::format("{}'s images are {}, not {}", path.string(),
                                             shading_name(set.shading), shading_name(o.shading)));
  }
  if (o.random_views > 0) {
    throw OptionError("random_views", "the target's images cannot be drawn from other views");
  }
  if (o.size_given) {
    for (std::size_t v = 0; v < set.images.size(); ++v) {
      if (set.images[v].width != o.size || set.images[v].height != o.size) {
        throw OptionError("size",
                          fmt::format("{}: view {}'s image is {}x{}, not {}", path.string(), v,
                                      set.images[v].width, set.images[v].height, o.size));
      }
    }
  }
  target.cameras = std::move(set.cameras);
  target.images = std::move(set.images);
}

}  // namespace

OpenscadModel read_refine_model(const std::filesystem::path& path,
                                const TessellationOptions& tessellation) {
  if (has_extension(path, {".csg"})) return read_openscad_csg_tree(path);
  return {io::read_tree_file(path), tessellation};
}

LoadedTarget load_refine_target(const std::filesystem::path& path, const TargetViewOptions& o,
                                const TessellationOptions& tessellation, const Scene& model_scene) {
  check(o);
  LoadedTarget loaded;
  RefineTarget& target = loaded.target;
  target.shading = o.shading;
  if (has_extension(path, {".json"}) && is_views_file(path)) {
    loaded.kind = "views";
    read_view_set(path, o, target);
    return loaded;
  }
  Scene scene;
  if (has_extension(path, {".obj", ".stl", ".ply", ".off"})) {
    loaded.kind = "mesh";
    if (o.shading == Shading::kColours) {
      throw OptionError("shading", "colours: a mesh has no primitives to colour; use normals");
    }
    scene = read_mesh_scene(path);
  } else {
    loaded.kind = "model";
    const OpenscadModel m = read_refine_model(path, tessellation);
    scene = scene_from_tree(m.tree, path.string(), m.tessellation);
    if (o.shading == Shading::kColours &&
        scene.primitives.size() != model_scene.primitives.size()) {
      throw InputError(fmt::format(
          "{}: {} primitives, the model {}: colour images need the same program (primitive k "
          "for primitive k)",
          path.string(), scene.primitives.size(), model_scene.primitives.size()));
    }
  }
  const auto prepared =
      std::make_shared<const PreparedScene>(prepare_scene(std::move(scene), o.intersection_aa));
  const auto [lo, hi] = prepared->scene.bounds();
  const Vec3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  const double distance =
      o.distance > 0 ? o.distance : framing_distance(prepared->scene, centre, o.fov, 1.2);
  target.cameras = orbit_views(centre, distance, o.views, o.elevation, o.size, o.size, o.fov);
  const Shading shading = o.shading;
  const int threads = o.threads;
  target.render = [prepared, shading, threads](const Camera& c) {
    return render_image(*prepared, c, shading, threads);
  };
  for (const Camera& c : target.cameras) target.images.push_back(target.render(c));
  return loaded;
}

}  // namespace fuzzycsg::diffcsg
