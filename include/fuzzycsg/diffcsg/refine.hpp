#pragma once
// Image-based refinement of a CSG program's continuous parameters (DiffCSG §3.4): the model's
// renderings (normal or per-primitive colour images, antialiased along silhouettes and
// intersection edges: pipeline.hpp) are matched to target images by Adam on the tree's free
// parameters, through the vertices' dependence on each leaf's placement and fields
// (Scene::bindings). No mesh boolean is ever computed.

#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/diffcsg/pipeline.hpp"

namespace fuzzycsg::diffcsg {

// dL/d(tree parameters) (the parameter table's order) from dL/d(world vertices) of the scene
// scene_from_tree(tree, ...) built, through its bindings.
std::vector<double> parameter_gradient(const Tree& tree, const Scene& scene,
                                       const std::vector<std::vector<Vec3>>& grad_vertices);

// dv/dθ of every world vertex ([primitive][vertex]) for parameter `param` (table index) of the
// tree the scene was built from: the direction in which the vertices move.
std::vector<std::vector<Vec3>> vertex_tangent(const Tree& tree, const Scene& scene,
                                              std::size_t param);

// The per-primitive colour image of a frame (background 0).
Image colour_image(const Frame& frame);

// Image losses, means over pixels: L1 and L2 over pixels and channels; tanh, DiffCSG's released
// loss on normals: the mean over pixels of tanh(10 * sum over channels of the squared
// difference).
enum class Loss { kL1, kL2, kTanh };
std::string_view loss_name(Loss l);  // "l1", "l2", "tanh"
std::optional<Loss> loss_from_name(std::string_view name);
// The loss of `image` against `target` (same size), and dL/d(image) into `grad` if given.
double image_loss(const Image& image, const Image& target, Loss loss, Image* grad = nullptr);
// Mean squared difference over pixels and channels.
double image_mse(const Image& image, const Image& target);

// What to match: images from fixed views, and, for targets that can be drawn again (a model
// or a mesh), a way to draw them from any view.
struct RefineTarget {
  std::vector<Camera> cameras;  // the fixed views; cameras[0] is the check view
  std::vector<Image> images;    // the target images of the fixed views
  Shading shading = Shading::kNormals;
  std::function<Image(const Camera&)> render;  // may be empty (images)
};

// Each parameter's natural scale, for steps relative to it: its magnitude, or where it is 0,
// 10 degrees for an angle (a name ending in rotate[k]) and 5% of the model's extent otherwise.
std::vector<double> parameter_scales(const Tree& tree,
                                     const TessellationOptions& tessellation = {});

// Adam on the gradients of the differentiable renderer (DiffCSG), or CMA-ES on the loss alone
// (optim/cmaes.hpp, DiffCSG §4.3's derivative-free baseline): it minimises the mean loss over the
// fixed views, counts one step per evaluation (a render of every fixed view), and searches
// every free parameter from steps of cmaes_sigma times its natural scale (parameter_scales).
enum class Method { kAdam, kCmaes };
std::string_view method_name(Method m);  // "adam", "cmaes"
std::optional<Method> method_from_name(std::string_view name);

struct RefineOptions {
  Method method = Method::kAdam;
  double cmaes_sigma = 0.1;
  int iterations = 1000;
  double lr = 0.01;
  // If > 0, each parameter's learning rate is lr_relative times its natural scale
  // (parameter_scales) instead of lr: one setting for models in any unit.
  double lr_relative = 0;
  double beta1 = 0.9, beta2 = 0.999, eps = 1e-8;
  Loss loss = Loss::kL2;
  bool intersection_aa = true;
  // Success: the check view's mean squared error below stop_mse, checked every check_every
  // steps (DiffCSG's protocol: 5e-4, every 10 steps).
  double stop_mse = 5e-4;
  int check_every = 10;
  // 0: train on the fixed views at every step. k > 0: train on one random view about the
  // target, drawn anew every k steps (needs RefineTarget::render), as DiffCSG does.
  int random_view_every = 0;
  std::uint64_t seed = 1;
  int threads = 0;
  // Called after every step with the step and its loss; return false to stop.
  std::function<bool(int, double)> progress;
};

struct RefineResult {
  Tree tree;                 // the refined model
  std::vector<double> loss;  // per step: the training loss, mean over its views
  std::vector<std::pair<int, double>> check_mse;  // (step, the check view's MSE)
  int steps = 0;                                  // Adam steps taken
  bool converged = false;                         // check MSE below stop_mse
  bool vanished = false;                          // the model left every training view
  std::vector<int> unseen_primitives;             // tree nodes no fixed view shows at the end
  double seconds_visibility = 0, seconds_edges = 0, seconds_antialias = 0, seconds_backward = 0;
  double seconds = 0;
};

// Refines `model` (unified operators are snapped first). Throws InputError for targets whose
// images do not match their cameras' sizes, and for random views without a way to render.
RefineResult refine(const Tree& model, const RefineTarget& target,
                    const RefineOptions& options = {},
                    const TessellationOptions& tessellation = {});

}  // namespace fuzzycsg::diffcsg
