#pragma once
// CSG visibility by rays (DiffCSG's Goldfeather pass, exact): every hit of the pixel's ray with
// every primitive's mesh is collected (Embree 3), the hits are walked in depth order keeping
// each primitive's winding number along the ray (+1 where a face's outward normal opposes the
// ray, -1 where it follows it; the camera's own from the whole ray's sum, so a camera inside a
// primitive is handled), and the first hit at which the tree's solid turns from outside to
// inside is the visible surface. This is the image the Goldfeather algorithm draws, and it is
// also correct for non-convex closed primitives, and for rays through a mesh's edges. Hits
// within 1e-6 of each other (relative to the ray's length, at least 1) are taken together
// (coplanar faces, shared edges). Meshes must be closed with outward normals (scene.hpp's are).
//
// The rays go to Embree in packets of 4 x 4 pixels over tiles of 16 x 16 (one task each);
// pixels outside every primitive's rectangle on the screen are not traced, and rays within
// float rounding of a triangle's edge on the screen are traced alone (Embree's packet and
// single-ray kernels may decide such a hit differently). The frame is, to the bit, the one of
// tracing every pixel's ray alone (tests/diffcsg/visibility_reference.hpp).

#include <array>
#include <cstdint>
#include <vector>

#include "fuzzycsg/diffcsg/scene.hpp"

namespace fuzzycsg::diffcsg {

// A pinhole camera at `eye` looking at `target`, `up` giving the image's up direction,
// vertical field of view `fov_deg`, `width` x `height` pixels; pixel (i, j), row j from the
// top, is sampled at its centre.
struct Camera {
  Vec3 eye{0, -4, 0}, target{0, 0, 0}, up{0, 0, 1};
  double fov_deg = 30;
  int width = 512, height = 512;

  // On a sphere of `distance` about `target`: `azimuth` degrees about +z from +x, `elevation`
  // degrees above the xy plane; z up.
  static Camera orbit(const Vec3& target, double azimuth, double elevation, double distance,
                      int width, int height, double fov_deg = 30);
  // The unit direction of the ray through the centre of pixel (i, j).
  Vec3 ray(int i, int j) const;
  // The camera's unit axes: forward (to the target), right and up (the image's).
  void axes(Vec3& forward, Vec3& right, Vec3& true_up) const;
};

// Per pixel (index j * width + i); primitive -1 where no surface is visible.
struct Frame {
  int width = 0, height = 0;
  std::vector<int> primitive, triangle;
  std::vector<float> depth;                       // distance along the ray
  std::vector<std::array<float, 2>> barycentric;  // (u, v): the hit is (1-u-v) a + u b + v c
  std::vector<std::array<float, 3>> normal;       // the solid's outward normal (faces the camera)
  int visible_pixels() const;
};

Frame render_visibility(const Scene& scene, const Camera& camera, int threads = 0);
// The same into `frame`, reusing its buffers (no allocation when it already has the size).
void render_visibility(const Scene& scene, const Camera& camera, Frame& frame, int threads = 0);

}  // namespace fuzzycsg::diffcsg
