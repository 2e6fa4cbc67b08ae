#pragma once
// Shading of the visible surface, with gradients (DiffCSG §3.4 and §4.2: the images matched are
// per-pixel normals or per-primitive colours).
//
// Normals: each pixel interpolates the shading normals of its visible triangle's three corners
// with the perspective-correct barycentrics of the pixel centre, computed from the corners'
// clip coordinates as nvdiffrast does (../shared/notes/diffcsg.md §1.4), not renormalised. A
// corner's normal is the face's own normal on flat triangles (PrimitiveMesh::smoothing -1), or the
// normalised area-weighted sum of the face normals of its smoothing group around the vertex,
// so it is a function of the world vertices. Where the visible surface is a back face (inside
// of a subtracted primitive), the normal is turned over: the solid's outward normal. The
// gradient reaches the vertices twice: through the corner normals, and through the barycentrics
// (which triangle points land where), the interior signal of §4.2.
//
// Colours: each primitive's flat colour (primitive_colour), which carries no gradient inside
// the primitive: only the antialiased edges move it.
//
// Background pixels are 0 in every channel.

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "fuzzycsg/diffcsg/image.hpp"
#include "fuzzycsg/diffcsg/visibility.hpp"

namespace fuzzycsg::diffcsg {

enum class Shading { kNormals, kColours };
std::string_view shading_name(Shading s);  // "normals", "colours"
// "normals"; "colours" or "colors".
std::optional<Shading> shading_from_name(std::string_view name);

// The colour of primitive p in colour images (Tableau's ten colours, cycled), in [0, 1].
std::array<float, 3> primitive_colour(int p);

// The shading normals of every triangle corner, and how they were formed.
struct CornerNormals {
  struct Primitive {
    std::vector<std::array<int, 3>> corner_slot;   // per triangle corner: its normal's slot
    std::vector<std::vector<int>> slot_triangles;  // the faces summed in each slot
    std::vector<Vec3> slot_sum;                    // their area-weighted normal sum
    std::vector<Vec3> slot_normal;                 // normalised (0 if the sum is 0)
  };
  std::vector<Primitive> primitives;
  const Vec3& at(int primitive, int triangle, int corner) const {
    const Primitive& p = primitives[static_cast<std::size_t>(primitive)];
    return p.slot_normal[static_cast<std::size_t>(
        p.corner_slot[static_cast<std::size_t>(triangle)][static_cast<std::size_t>(corner)])];
  }
};
CornerNormals corner_normals(const Scene& scene);

// What the backward pass needs of the forward one.
struct ShadeRecord {
  std::vector<std::int8_t> flip;  // per pixel: -1 where a back face is seen
};

// The 3-channel image of the frame's visible surface; the second form writes into `out`,
// reusing its memory.
Image shade(const Scene& scene, const CornerNormals& normals, const Camera& camera,
            const Frame& frame, Shading shading, ShadeRecord* record = nullptr);
void shade(const Scene& scene, const CornerNormals& normals, const Camera& camera,
           const Frame& frame, Shading shading, Image& out, ShadeRecord* record);

// Given dL/d(shaded image), adds dL/d(world vertices) (nothing for colours).
void shade_backward(const Scene& scene, const CornerNormals& normals, const Camera& camera,
                    const Frame& frame, Shading shading, const ShadeRecord& record,
                    const Image& grad, VertexGradient& grad_vertices);

// The perspective-correct barycentrics of the centre of pixel (i, j) on triangle (a, b, c)
// (world coordinates), and their vector-Jacobian product: given g = dL/db, adds dL/da, dL/db,
// dL/dc.
std::array<double, 3> pixel_barycentrics(const Camera& camera, int i, int j, const Vec3& a,
                                         const Vec3& b, const Vec3& c);
void pixel_barycentrics_vjp(const Camera& camera, int i, int j, const Vec3& a, const Vec3& b,
                            const Vec3& c, const std::array<double, 3>& g, Vec3& ga, Vec3& gb,
                            Vec3& gc);

}  // namespace fuzzycsg::diffcsg
