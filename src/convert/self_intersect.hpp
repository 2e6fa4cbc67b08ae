#pragma once
// Whether a closed mesh crosses itself: two shells that overlap (a part exported as the union of
// its bodies, not merged), or a surface folded through itself. The inside test of a mesh target
// counts crossings of rays, so the overlap of two shells reads as outside: the part would be
// converted as the exclusive or of its pieces.

#include <cstddef>
#include <optional>

#include "fuzzycsg/core/triangle_mesh.hpp"

namespace fuzzycsg::convert {

// The pairs of triangles that cross each other (those that only share an edge or a corner do
// not count), by CGAL's self_intersections with exact predicates; nullopt when the triangles
// do not make a polygon mesh CGAL can build (an edge in more than two of them as given: such a
// mesh is judged by mesh_defect instead).
std::optional<std::size_t> crossing_triangle_pairs(const TriangleMesh& mesh);

}  // namespace fuzzycsg::convert
