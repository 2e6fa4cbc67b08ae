#pragma once
// The render module: pictures of trees, 3D by ray casting their mesh, 2D as plots and SVG
// outlines. This header is all of its interface.
//
// Pictures of trees. 3D: the 0.5 level set (mesh.hpp) ray cast with Embree and shaded (two
// directional lights and an ambient term on smooth vertex normals, 2x2 samples a pixel), from a
// given camera or from default cameras that frame the shape. 2D: the occupancy with a colour
// scale and the 0.5 contour (PNG, SVG or PDF); the primitives' outlines over the result (SVG).

#include <array>
#include <optional>
#include <span>
#include <string>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/io/canvas.hpp"
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

struct PlotOptions {
  int size = 600;  // pixels along the domain's longer side (16..8192)
  PictureFormat format = PictureFormat::kPng;
  int threads = 0;
};

// A 2D tree's occupancy over its domain as a picture (PNG, SVG or PDF; io/canvas.hpp), in the
// style of the papers' figures: a colour scale (viridis) from 0 to 1, the 0.5 contour (contours
// from mesh.hpp) in white, and a labelled colour bar. The occupancy is an image of one pixel a
// sample, in SVG and PDF too.
std::string plot_2d(const Tree& tree, std::span<const double> params,
                    const PlotOptions& options = {});

struct OutlineOptions {
  int size = 512;        // pixels along the domain's longer side (64..8192)
  int resolution = 256;  // grid cells of the contours along the domain's longer side
  int threads = 0;
};

// A 2D tree as an SVG figure in the style of the papers': the domain's frame, the result (the
// whole tree's 0.5 contours, filled with the even-odd rule so that holes show) and over it each
// leaf's own outline (the leaf alone, its 0.5 contour clipped to the domain) as a thin stroke
// in a colour of its own, numbered in leaf order (left to right) at its highest point, with a
// legend (index, family, name). Pixel coordinates, y down. Structure for tools: one
// <path class="result">, one <g class="outline" data-leaf="i" data-node="node path"> a leaf
// (an empty path when the leaf has no edge in the domain), <rect class="frame">.
std::string outlines_svg(const Tree& tree, std::span<const double> params,
                         const OutlineOptions& options = {});

}  // namespace fuzzycsg
