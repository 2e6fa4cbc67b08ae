#pragma once
// What refinement can match, read from files: a mesh (drawn by the same renderer as the model),
// and images with their cameras. Images are PNG: a normal map stores RGB = (n + 1) / 2, a colour
// map the primitives' colours; covered pixels are opaque and the background transparent (0 in
// every channel when read).
//
// A set of views is a JSON file:
//   { "format": "fuzzycsg-views", "version": 1, "shading": "normals",
//     "views": [ { "image": "view0.png", "eye": [x, y, z], "target": [x, y, z],
//                  "up": [0, 0, 1], "fov": 30 } ] }
// Image paths are relative to the file. "up" defaults to +z and "fov" (vertical, degrees) to
// 30; an optional "size": [w, h] must agree with the PNG. The camera is Camera's pinhole (pixel
// (i, j), row j from the top, sampled at its centre).

#include <filesystem>
#include <string>
#include <vector>

#include "fuzzycsg/diffcsg/pipeline.hpp"

namespace fuzzycsg::diffcsg {

// A closed mesh file (OBJ, STL, PLY, OFF) as a scene of one primitive with outward normals,
// smooth across edges sharper than `crease_degrees` (scene_from_mesh). InputError naming the
// file for what cannot be read, and for a mesh that encloses no volume.
Scene read_mesh_scene(const std::filesystem::path& path, double crease_degrees = 30);

// PNG bytes of a 3-channel image in the given shading, the background (0 in every channel)
// transparent; and back. InputError naming the file.
std::string encode_image_png(const Image& image, Shading shading);
Image read_image_png(const std::filesystem::path& path, Shading shading);

struct ViewSet {
  Shading shading = Shading::kNormals;
  std::vector<Camera> cameras;
  std::vector<Image> images;
};
// InputError naming the file and the field (views[2].eye: three numbers expected).
ViewSet read_views(const std::filesystem::path& path);
// The views file for `cameras` whose images are `image_files` (relative to the file).
std::string views_json(Shading shading, const std::vector<Camera>& cameras,
                       const std::vector<std::string>& image_files);

// Whether a JSON file is a views file (its "format" is "fuzzycsg-views").
bool is_views_file(const std::filesystem::path& path);

}  // namespace fuzzycsg::diffcsg
