#pragma once
// Intersection edges between primitives (DiffCSG §3.3): where a triangle of one primitive
// crosses a triangle of another, the segment they share. These edges are where the CSG image
// has discontinuities that are no mesh edge; antialiasing them lets gradients reach both
// primitives.
//
// Candidate pairs come from the triangles' bounding boxes (a sweep along x over the
// triangles of different primitives whose boxes overlap), not from all pairs. A pair's segment
// is found by the six edge-against-triangle tests of the notes (../shared/notes/diffcsg.md
// §1.5): each edge of one triangle crossing the other's plane inside it gives a point; a pair
// with exactly two distinct points gives a segment. A vertex in the other triangle's plane
// counts as on its positive side, so that an edge lying in a plane is counted once. Coplanar
// pairs give none.

#include <vector>

#include "fuzzycsg/diffcsg/scene.hpp"

namespace fuzzycsg::diffcsg {

// Where an endpoint comes from: edge `edge` (from vertex edge to vertex edge + 1, mod 3) of
// triangle a crossing triangle b (`of_b` false), or the other way round.
struct EndpointSource {
  bool of_b = false;
  int edge = 0;
};

struct IntersectionEdge {
  Vec3 p, q;
  int primitive_a = -1, triangle_a = -1, primitive_b = -1, triangle_b = -1;  // a < b
  EndpointSource p_source, q_source;
};

// The point where edge (e0, e1) crosses the plane of triangle (a, b, c), and the
// vector-Jacobian product: given g = dL/dpoint, adds dL/d of e0, e1, a, b, c.
Vec3 edge_plane_point(const Vec3& e0, const Vec3& e1, const Vec3& a, const Vec3& b, const Vec3& c);
void edge_plane_point_vjp(const Vec3& e0, const Vec3& e1, const Vec3& a, const Vec3& b,
                          const Vec3& c, const Vec3& g, Vec3& ge0, Vec3& ge1, Vec3& ga, Vec3& gb,
                          Vec3& gc);

std::vector<IntersectionEdge> intersection_edges(const Scene& scene);

// The segment where triangles (a0, a1, a2) and (b0, b1, b2) cross; false if they do not (or
// touch in a point, or are coplanar).
bool triangle_intersection(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                           const Vec3& b1, const Vec3& b2, Vec3& p, Vec3& q,
                           EndpointSource* p_source = nullptr, EndpointSource* q_source = nullptr);

}  // namespace fuzzycsg::diffcsg
