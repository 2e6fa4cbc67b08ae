#pragma once
// The triangle mesh every module shares: the level set that mesh extracts and writes, the mesh
// files that target reads, the tessellated leaves of diffcsg's scenes. Vertices in double,
// triangles as three indices into them. What a module adds (diffcsg's smoothing groups, the
// float buffers a ray tracer wants) it keeps beside the mesh, not in it.
//
// Coordinates keep what their producer computed: extract_mesh() computes its vertices in float
// and stores those values exactly (a float converts to double without rounding), so that files
// written with float coordinates hold the same numbers.

#include <array>
#include <vector>

namespace fuzzycsg {

struct TriangleMesh {
  std::vector<std::array<double, 3>> vertices;
  // Indices into `vertices`. In an oriented mesh the corners run counter-clockwise seen from
  // outside (normals by the right-hand rule point out).
  std::vector<std::array<int, 3>> triangles;
};

// The signed volume enclosed (divergence theorem): the sum over the triangles (a, b, c), in their
// order, of det(a, b, c) / 6, computed in double. Positive when the triangles of a closed mesh
// face outwards, negative when they all face inwards.
double signed_volume(const TriangleMesh& mesh);

// The smallest box that holds every vertex, {lo, hi} (whether or not a triangle uses it). A mesh
// without vertices gives lo = +infinity and hi = -infinity on every axis.
std::array<std::array<double, 3>, 2> bounding_box(const TriangleMesh& mesh);

}  // namespace fuzzycsg
