#pragma once
// Pictures of trees. 3D: the 0.5 level set (mesh.hpp) ray cast with Embree and shaded (two
// directional lights and an ambient term on smooth vertex normals, 2x2 samples a pixel), from a
// given camera or from default cameras that frame the shape. 2D: the occupancy with a colour
// scale and the 0.5 contour.

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

// A 2D tree's occupancy over its domain as a PNG, in the style of the papers' figures: a
// colour scale (viridis) from 0 to 1, the 0.5 contour (contours from mesh.hpp) in white, and a
// labelled colour bar. `size`: pixels along the domain's longer side (16..8192).
std::string plot_2d_png(const Tree& tree, std::span<const double> params, int size = 600,
                        int threads = 0);

}  // namespace fuzzycsg
