#pragma once
// Images of the differentiable renderer, and where their gradients go.

#include <cstddef>
#include <vector>

#include "fuzzycsg/diffcsg/scene.hpp"

namespace fuzzycsg::diffcsg {

// An image of `channels` floats per pixel, row-major, row 0 at the top.
struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> data;
  float* at(std::size_t pixel) { return data.data() + pixel * static_cast<std::size_t>(channels); }
  const float* at(std::size_t pixel) const {
    return data.data() + pixel * static_cast<std::size_t>(channels);
  }
};

// dL/d(world vertex) of every primitive, filled by the backward passes (shade.hpp,
// antialias.hpp). With `tangent` (dv/dθ of every vertex for one parameter θ) and `per_pixel`
// (one entry per pixel), each contribution g to vertex v that the pass draws from pixel q also
// adds g · tangent[v] to per_pixel[q]: the image of that parameter's gradient, pixel by pixel
// (DiffCSG Fig. 1 and 9).
struct VertexGradient {
  std::vector<std::vector<Vec3>> g;  // [primitive][vertex]
  const std::vector<std::vector<Vec3>>* tangent = nullptr;
  std::vector<double>* per_pixel = nullptr;

  // Sized for `scene` (existing values kept).
  void resize(const Scene& scene) {
    g.resize(scene.primitives.size());
    for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
      g[p].resize(scene.primitives[p].mesh.vertices.size(), Vec3{0, 0, 0});
    }
  }
  void add(int primitive, int vertex, const Vec3& grad, std::size_t pixel) {
    Vec3& out = g[static_cast<std::size_t>(primitive)][static_cast<std::size_t>(vertex)];
    for (std::size_t k = 0; k < 3; ++k) out[k] += grad[k];
    if (tangent && per_pixel) {
      (*per_pixel)[pixel] += dot(
          grad, (*tangent)[static_cast<std::size_t>(primitive)][static_cast<std::size_t>(vertex)]);
    }
  }
};

}  // namespace fuzzycsg::diffcsg
