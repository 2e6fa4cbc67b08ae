#pragma once
// Antialiasing of silhouette edges with gradients to vertex positions (Laine et al. 2020's
// nvdiffrast antialias, as DiffCSG uses it; the exact formulas are in
// ../shared/notes/diffcsg.md §1.6).
//
// For every pair of horizontally or vertically adjacent pixels showing different triangles,
// the triangle in front (or the only one) is taken; where one of its silhouette edges crosses
// the segment between the two pixel centres, the pixel the edge covers less is blended towards
// the other's colour by α = s (1/2 - t), t the crossing's position along the segment. α is a
// function of the edge's projected endpoints, so the image's gradient reaches the vertices.
//
// Screen coordinates: pixel (i, j), row j from the top, is centred at (i + 1/2, j + 1/2); a
// point P projects to (W/2 (1 + x_c / (z_c h a)), H/2 (1 - y_c / (z_c h))) with (x_c, y_c, z_c)
// its camera coordinates (right, up, forward), h = tan(fov / 2), a = W / H.

#include <array>
#include <vector>

#include "fuzzycsg/diffcsg/edges.hpp"
#include "fuzzycsg/diffcsg/image.hpp"
#include "fuzzycsg/diffcsg/visibility.hpp"

namespace fuzzycsg::diffcsg {

// For each primitive, triangle t and edge k (between vertices k + 1 and k + 2, mod 3): the
// vertex of the neighbouring triangle across that edge that is not on it (the triangle's own
// vertex k where the edge has no neighbour).
using Topology = std::vector<std::vector<std::array<int, 3>>>;
Topology opposite_vertices(const Scene& scene);

// A point's screen position and its Jacobian d(sx, sy)/dP.
struct Projection {
  double sx = 0, sy = 0;
  std::array<double, 6> jacobian{};  // row-major 2 x 3
};
Projection project(const Camera& camera, const Vec3& p);

// One blended pair, kept for the backward pass.
struct AaPair {
  std::size_t p0 = 0, p1 = 0, target = 0;  // target: the pixel blended
  int primitive = -1, triangle = -1, edge = -1;
  int s = 1;
  bool vertical = false;
  double alpha = 0;
  int intersection = -1;  // blended across this intersection edge (index), not a silhouette
};

// The antialiased image of `colour` (the shaded visible surface, `frame`'s size). With
// `edges` (intersection_edges() of the scene), a pair of pixels showing triangles of two
// primitives that no silhouette separates is also blended across the intersection edge of
// exactly those two triangles, if it crosses the segment between their centres: DiffCSG's
// intersection-edge antialiasing (only visible edges count: the two triangles are the ones the
// pixels show).
Image antialias(const Scene& scene, const Topology& topology, const Camera& camera,
                const Frame& frame, const Image& colour, std::vector<AaPair>* pairs = nullptr,
                const std::vector<IntersectionEdge>* edges = nullptr);
// The same into `out`, reusing its memory.
void antialias(const Scene& scene, const Topology& topology, const Camera& camera,
               const Frame& frame, const Image& colour, Image& out, std::vector<AaPair>* pairs,
               const std::vector<IntersectionEdge>* edges);

// Given dL/d(antialiased image), adds dL/dcolour (sized like colour) and dL/dvertex (world
// coordinates, [primitive][vertex]) through α's dependence on the edges' endpoints; for an
// intersection edge, through its endpoints' dependence on the six vertices of its two
// triangles. `edges` as given to antialias().
void antialias_backward(const Scene& scene, const Camera& camera, const Image& colour,
                        const std::vector<AaPair>& pairs, const Image& grad_out, Image& grad_colour,
                        VertexGradient& grad_vertices,
                        const std::vector<IntersectionEdge>* edges = nullptr);
void antialias_backward(const Scene& scene, const Camera& camera, const Image& colour,
                        const std::vector<AaPair>& pairs, const Image& grad_out, Image& grad_colour,
                        std::vector<std::vector<Vec3>>& grad_vertices,
                        const std::vector<IntersectionEdge>* edges = nullptr);

}  // namespace fuzzycsg::diffcsg
