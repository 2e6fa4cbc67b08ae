#pragma once
// Image-based refinement of a CSG program's continuous parameters (DiffCSG §3.4): the model's
// renderings (per-primitive colour images, antialiased along silhouettes and intersection
// edges, antialias.hpp) are matched to target images by Adam on the tree's free parameters,
// through the vertices' dependence on each leaf's translate, rotate, scale and size fields.
// No mesh boolean is ever computed.

#include <array>
#include <vector>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/diffcsg/antialias.hpp"

namespace fuzzycsg::diffcsg {

// dL/d(tree parameters) (the parameter table's order) from dL/d(world vertices) of the scene
// scene_from_tree(tree, ...) built: through v = t + s R (size * u) for each leaf's unit mesh u.
std::vector<double> parameter_gradient(const Tree& tree, const Scene& scene,
                                       const std::vector<std::vector<Vec3>>& grad_vertices,
                                       const TessellationOptions& options = {});

// The colour of primitive p in colour images (Tableau's ten colours, cycled), in [0, 1].
std::array<float, 3> primitive_colour(int p);
// The per-primitive colour image of a frame (background 0).
Image colour_image(const Frame& frame);

struct RefineOptions {
  int iterations = 300;
  double lr = 0.01;
  double beta1 = 0.9, beta2 = 0.999, eps = 1e-8;
  bool intersection_aa = true;
  double stop_loss = 5e-4;  // mean squared error over pixels and channels
  int threads = 0;
};

struct RefineResult {
  Tree tree;                 // the refined model
  std::vector<double> loss;  // per step, mean over views
  int steps = 0;
  bool converged = false;  // loss below stop_loss
  bool vanished = false;   // the model left every view
  double seconds_visibility = 0, seconds_edges = 0, seconds_antialias = 0, seconds_backward = 0;
};

// Refines `model` (unified operators are snapped first) so that its colour images from
// `cameras` match `targets` (one per camera, the cameras' sizes, 3 channels).
RefineResult refine_to_images(const Tree& model, const std::vector<Camera>& cameras,
                              const std::vector<Image>& targets, const RefineOptions& options = {},
                              const TessellationOptions& tessellation = {});

}  // namespace fuzzycsg::diffcsg
