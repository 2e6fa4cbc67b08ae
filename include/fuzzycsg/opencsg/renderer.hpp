#pragma once
// An independent renderer of the same scenes as diffcsg::render_visibility, for comparison:
// OpenCSG (Kirsch and Döllner's image-based CSG on OpenGL) drawing the very same triangles
// (Scene::primitives, world coordinates) through the same camera, headless in an OpenGL context
// of Mesa's surfaceless EGL platform (llvmpipe on a machine without a GPU), into a framebuffer
// object.
//
// The tree is drawn as its sum of products (diffcsg/products.hpp): for each product OpenCSG
// fills the depth buffer with the product's visible surface, then each of its primitives is
// drawn in a colour of its own with the depth test GL_EQUAL (front faces of intersected
// primitives, back faces of subtracted ones), as OpenSCAD's preview does; the colours read back
// name the primitive visible at each pixel centre.

#include <memory>
#include <string>
#include <vector>

#include "fuzzycsg/diffcsg/scene.hpp"
#include "fuzzycsg/diffcsg/visibility.hpp"

namespace fuzzycsg::opencsg {

enum class Algorithm {
  kGoldfeather,  // any closed primitives, each with its convexity (1 for convex meshes)
  kScs,          // convex primitives only
};

class Renderer {
 public:
  // Creates the context and a width x height framebuffer; throws Error with one line saying
  // what failed when no context can be made.
  Renderer(int width, int height);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Uploads the scene's meshes (world coordinates, as they are) and its tree as a sum of
  // products; each primitive's convexity is found here.
  void set_scene(const diffcsg::Scene& scene);

  // Draws the scene as the camera (of the renderer's size) sees it and waits for OpenGL to
  // finish. Throws InputError when the camera's size differs or kScs is asked for a scene with
  // a non-convex primitive.
  void draw(const diffcsg::Camera& camera, Algorithm algorithm);
  // The primitive visible at each pixel of the last draw (index j * width + i, row 0 at the
  // top), -1 where none is.
  std::vector<int> read_primitives() const;
  // draw() then read_primitives().
  std::vector<int> render(const diffcsg::Camera& camera, Algorithm algorithm);

  // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Compatibility
  // Profile) Mesa 22.3.6".
  std::string description() const;
  // Each primitive's convexity as given to OpenCSG: 1 for convex meshes.
  std::vector<int> convexity() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace fuzzycsg::opencsg
