#pragma once
// The differentiable renderer of CSG of meshed primitives, whole (DiffCSG Fig. 3): visibility
// by rays (visibility.hpp), shading (shade.hpp), intersection edges (edges.hpp) and
// antialiasing of silhouettes and intersection edges (antialias.hpp); forward, and backward to
// the world vertices. Never a mesh boolean.

#include <vector>

#include "fuzzycsg/diffcsg/antialias.hpp"
#include "fuzzycsg/diffcsg/edges.hpp"
#include "fuzzycsg/diffcsg/shade.hpp"
#include "fuzzycsg/diffcsg/visibility.hpp"

namespace fuzzycsg::diffcsg {

// What a scene needs for every view: its edges' topology, shading normals and intersection
// edges (none with intersection_aa false: silhouettes only, DiffCSG's ablation).
struct PreparedScene {
  Scene scene;
  Topology topology;
  CornerNormals normals;
  std::vector<IntersectionEdge> edges;
  bool intersection_aa = true;
  double seconds_edges = 0;  // finding the intersection edges
};
PreparedScene prepare_scene(Scene scene, bool intersection_aa = true);

// One view's forward pass, kept for the backward pass.
struct ViewPass {
  Frame frame;
  ShadeRecord record;
  Image shaded;  // before antialiasing
  std::vector<AaPair> pairs;
  Image image;                                           // the result
  double seconds_visibility = 0, seconds_antialias = 0;  // antialias: shading included
  mutable Image grad_shaded;  // the backward pass's scratch, kept to reuse its memory
};

ViewPass render_view(const PreparedScene& scene, const Camera& camera, Shading shading,
                     int threads = 0);
// The same into `pass`, reusing its memory (a refinement draws the same views again and again).
void render_view(const PreparedScene& scene, const Camera& camera, Shading shading, int threads,
                 ViewPass& pass);

// Given dL/d(pass.image), adds dL/d(world vertices).
void render_view_backward(const PreparedScene& scene, const Camera& camera, Shading shading,
                          const ViewPass& pass, const Image& grad, VertexGradient& grad_vertices);

// The image alone.
Image render_image(const PreparedScene& scene, const Camera& camera, Shading shading,
                   int threads = 0);

// Cameras. `orbit_views`: n views on a ring about `centre` at `elevation` degrees, from
// azimuth 30 degrees on, evenly spaced. `random_view`: a view from a point drawn uniformly in
// angle on the sphere of `distance` about `centre` (polar angle in [0, pi], azimuth in
// [0, 2 pi), as DiffCSG's random views).
std::vector<Camera> orbit_views(const Vec3& centre, double distance, int n, double elevation,
                                int width, int height, double fov_deg);
Camera random_view(const Vec3& centre, double distance, double u1, double u2, int width, int height,
                   double fov_deg);
// The distance at which a sphere about `centre` through the scene's bounding box fills a
// field of view of `fov_deg` (with a margin of `margin`).
double framing_distance(const Scene& scene, const Vec3& centre, double fov_deg,
                        double margin = 1.05);

}  // namespace fuzzycsg::diffcsg
