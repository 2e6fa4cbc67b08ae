#pragma once
// The render module: pictures of trees, 3D by ray casting their mesh, 2D as plots and SVG
// outlines. This header is all of its interface.
//
// Pictures of trees. 3D: the 0.5 level set (mesh.hpp) ray cast with Embree and shaded (two
// directional lights and an ambient term on smooth vertex normals, 2x2 samples a pixel), from a
// given camera or from default cameras that frame the shape; a triangle mesh (core's
// TriangleMesh, a mesh file's) shaded the same way; a mesh and a tree side by side from the same
// cameras (render_comparison_png). 2D: the occupancy with a colour scale and the 0.5 contour
// (PNG, SVG or PDF); the primitives' outlines over the result (SVG).

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

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
  // Normals are averaged over the triangles at a vertex whose normals lie within this angle
  // (degrees, in (0, 180]) of each other; 180: all of them, smooth shading everywhere.
  double crease_deg = 180.0;
  int threads = 0;
};

// A camera looking at the mesh's bounding sphere from azimuth/elevation (degrees, about `up`),
// at the distance that fits the sphere in the view.
Camera framing_camera(const TriangleMesh& mesh, double azimuth_deg, double elevation_deg,
                      const std::array<double, 3>& up, double aspect, double fov_deg = 30.0);
// The same for the sphere around a box {lo, hi} (core's bounding_box).
Camera framing_camera(const std::array<std::array<double, 3>, 2>& box, double azimuth_deg,
                      double elevation_deg, const std::array<double, 3>& up, double aspect,
                      double fov_deg = 30.0);

// PNG bytes. Throws InputError when the level set is empty, a camera is degenerate (eye at the
// target, up along the view) or its eye lies inside the shape, and when sizes are out of range
// (1..8192 pixels a side, 1..8 views, crease_deg in (0, 180]).
std::string render_png(const Tree& tree, std::span<const double> params,
                       const RenderOptions& options);

// A triangle mesh shaded as render_png shades a tree's level set, from options.camera or from
// options.views default cameras framing the mesh (options.resolution is not used): the picture of
// extract_mesh(tree) is render_png's of the tree, bit for bit. There is no occupancy to tell
// whether an eye is inside: an eye inside a closed mesh sees its faces from behind, in red, as it
// sees the inside of an open mesh through a hole. Throws InputError for a mesh without triangles,
// a degenerate camera and sizes out of range, as render_png.
std::string render_mesh_png(const TriangleMesh& mesh, const RenderOptions& options);

// One column of a comparison: the direction the camera looks from, in degrees about `up`.
struct ComparisonView {
  double azimuth_deg = 30.0;
  double elevation_deg = 25.0;
};

struct ComparisonOptions {
  int width = 360, height = 270;  // of one view (16..2048 each)
  // One column each (1..8): three views from above around the shape and one from below, which
  // shows the bottom faces that views from above never see.
  std::vector<ComparisonView> views{{30, 25}, {150, 25}, {270, 25}, {210, -35}};
  std::array<double, 3> up{0, 0, 1};
  int resolution = 192;  // of the tree's mesh (extract_mesh, over the tree's domain)
  // As RenderOptions::crease_deg, for both rows: a CAD part's edges (90 degrees and the like)
  // stay sharp, the small angles between a level set's triangles are smoothed.
  double crease_deg = 60.0;
  std::string target_label = "target";
  std::string result_label = "result";
  int threads = 0;
};

// A target mesh and a result side by side, as one PNG: two rows, the target's label and views
// above the result's, one column per view, each column's caption (azimuth and elevation) above it.
// Both rows are seen from exactly the same cameras (framing_camera of the box around both
// shapes, 30 degrees of vertical field of view), so that a part of the result that is missing,
// extra or moved shows in the same place of the picture as in the row above. Views are shaded as
// render_mesh_png's (both rows with options.crease_deg) and drawn 1:1; a gap of white pixels
// separates them. A result without triangles leaves its row empty, labelled "(empty)", and the
// cameras frame the target alone. Throws InputError for a target without triangles, a 2D tree
// (the tree form), and options out of range (OptionError: sizes, views with an elevation
// outside (-90, 90) degrees, more than 8 views or none, crease_deg).
std::string render_comparison_png(const TriangleMesh& target, const TriangleMesh& result,
                                  const ComparisonOptions& options = {});
// The result is the tree's 0.5 level set, extracted at options.resolution cells along the longest
// side of the tree's domain (extract_mesh): the crisp shape of the tree, steep or crisp steps as
// much as smooth ones. The tree is in the target's coordinates; its domain must hold the target
// for the result to be comparable.
std::string render_comparison_png(const TriangleMesh& target, const Tree& tree,
                                  std::span<const double> params,
                                  const ComparisonOptions& options = {});

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
