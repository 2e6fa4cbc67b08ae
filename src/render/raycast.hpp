#pragma once
// A triangle mesh ray cast with Embree and shaded: the views that render_png (a tree's level set),
// render_mesh_png (a mesh) and render_comparison_png (a mesh beside a tree) are made of; and the
// arena they run in. Private to the render module.

#include <tbb/task_arena.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <memory>

#include "fuzzycsg/core/limits.hpp"
#include "fuzzycsg/core/triangle_mesh.hpp"
#include "fuzzycsg/render/render.hpp"

namespace fuzzycsg::render_detail {

using Vec = std::array<double, 3>;
inline constexpr double kPi = 3.14159265358979323846;

inline Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec add(const Vec& a, const Vec& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec scale(const Vec& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec& a) { return std::sqrt(dot(a, a)); }
inline Vec normalized(const Vec& a) {
  const double n = norm(a);
  return n > 0 ? scale(a, 1.0 / n) : a;
}

// Throws InputError for a camera whose eye is at its target (or not finite), whose up direction
// lies along the view, or whose field of view is outside (0, 180) degrees. Whether the eye is
// inside the shape is the caller's to check.
void check_camera_geometry(const Camera& camera);

// The mesh in an Embree scene, with area-weighted vertex normals for smooth shading: two
// directional lights fixed to the view and an ambient term, outside faces blue-grey, faces seen
// from behind red, on a soft vertical grey gradient; 2x2 samples a pixel. With a crease angle
// below 180 degrees, a corner's normal averages only the triangles at its vertex whose normals
// lie within that angle of its own triangle's: the edges of a CAD part's few flat faces stay
// sharp instead of shading its faces as if they were curved.
class MeshShader {
 public:
  // The mesh must outlive the shader. Throws Error when Embree fails.
  explicit MeshShader(const TriangleMesh& mesh, double crease_deg = 180);
  ~MeshShader();
  MeshShader(const MeshShader&) = delete;
  MeshShader& operator=(const MeshShader&) = delete;

  // The view from `camera`, width x height pixels (aspect width / height), RGB bytes, row 0 at
  // the top, written from `rgb` on with `stride` bytes from one row to the next. Rows are shaded
  // in parallel (oneTBB, in the calling arena); the pixels do not depend on the thread count.
  void shade(const Camera& camera, int width, int height, unsigned char* rgb,
             std::size_t stride) const;

 private:
  class Scene;
  std::unique_ptr<Scene> scene_;
};

// f() in an arena of `threads` threads (0: the default one).
template <class F>
auto in_arena(int threads, const F& f) {
  check_threads(threads);
  if (threads > 0) {
    tbb::task_arena arena(threads);
    return arena.execute(f);
  }
  return f();
}

}  // namespace fuzzycsg::render_detail
