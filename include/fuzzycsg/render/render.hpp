#pragma once
// Pictures of a 3D tree: its 0.5 level set (mesh.hpp) ray cast with Embree and shaded
// (two directional lights and an ambient term on smooth vertex normals, 2x2 samples a pixel),
// from a given camera or from default cameras that frame the shape.

#include <array>
#include <optional>
#include <span>
#include <string>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/mesh/mesh.hpp"

namespace fuzzycsg {

struct Camera {
  std::array<double, 3> eye{3, -4, 2.5};
  std::array<double, 3> target{0, 0, 0};
  std::array<double, 3> up{0, 0, 1};
  double fov_deg = 30.0;  // vertical field of view
};

struct RenderOptions {
  int width = 800, height = 600;  // of one view
  std::optional<Camera> camera;   // none: default cameras framing the mesh
  int views = 1;                  // default cameras around the shape, side by side
  std::array<double, 3> up{0, 0, 1};
  int resolution = 192;  // of the mesh rendered
  int threads = 0;
};

// A camera looking at the mesh's bounding sphere from azimuth/elevation (degrees, about `up`),
// at the distance that fits the sphere in the view.
Camera framing_camera(const TriangleMesh& mesh, double azimuth_deg, double elevation_deg,
                      const std::array<double, 3>& up, double aspect, double fov_deg = 30.0);

// PNG bytes. Throws InputError when the level set is empty, a camera is degenerate (eye at the
// target, up along the view) or its eye lies inside the shape, and when sizes are out of range
// (1..8192 pixels a side, 1..8 views).
std::string render_png(const Tree& tree, std::span<const double> params,
                       const RenderOptions& options);

}  // namespace fuzzycsg
