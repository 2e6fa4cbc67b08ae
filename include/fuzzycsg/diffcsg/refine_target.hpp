#pragma once
// What `refine` reads: the model (a tree file or an OpenSCAD .csg) and the target (another
// model or a mesh drawn from cameras orbiting it, or a views file of images with their cameras),
// as the fuzzycsg program and the Python module both load them.

#include <filesystem>
#include <string>

#include "fuzzycsg/diffcsg/openscad_csg.hpp"
#include "fuzzycsg/diffcsg/refine.hpp"
#include "fuzzycsg/diffcsg/scene.hpp"

namespace fuzzycsg::diffcsg {

// A tree file, or an OpenSCAD .csg read as one with OpenSCAD's tessellation (`tessellation`
// is the tree file's).
OpenscadModel read_refine_model(const std::filesystem::path& path,
                                const TessellationOptions& tessellation = {});

// The cameras about a model or mesh target, and how its images are drawn.
struct TargetViewOptions {
  Shading shading = Shading::kNormals;
  int views = 4;            // cameras orbiting the target, in [1, 64]
  int size = 256;           // pixels (square), in [8, 4096]
  bool size_given = false;  // a views file's images must then be `size` square
  double elevation = 25;    // degrees
  double distance = 0;      // 0: the target fills the view
  double fov = 30;          // vertical, degrees, in (0, 180)
  int random_views = 0;     // refine's random_view_every (not for a views file)
  bool intersection_aa = true;
  int threads = 0;
};

struct LoadedTarget {
  RefineTarget target;
  std::string kind;  // "views", "mesh" or "model"
};

// The target at `path`: a views file (.json with "format": "fuzzycsg-views"), a mesh (OBJ, STL,
// PLY, OFF) or a model (tree file or .csg). `model_scene` is the model being refined: colour
// images need the same number of primitives. Throws OptionError naming the field of `options`
// for a setting out of range or at odds with the target, InputError naming the file otherwise.
LoadedTarget load_refine_target(const std::filesystem::path& path, const TargetViewOptions& options,
                                const TessellationOptions& tessellation, const Scene& model_scene);

}  // namespace fuzzycsg::diffcsg
