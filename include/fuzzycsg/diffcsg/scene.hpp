#pragma once
// CSG of meshed primitives (Yuan et al. 2024, DiffCSG): each leaf of a 3D tree becomes a closed
// triangle mesh of fixed tessellation, placed in the world by the leaf's translate, rotate and
// scale, and the tree's operators become crisp booleans over those solids.
//
// Tessellations (local coordinates, outward normals by the right-hand rule):
//   box       [-1/2, 1/2]^3 scaled by `size`: 12 triangles;
//   sphere    an icosahedron subdivided `sphere_subdivisions` times (default 2: 320
//             triangles), vertices on the sphere of radius `radius`;
//   cylinder  axis z, z in [-height/2, height/2], `cylinder_segments` (default 16) sides, the
//             rings' vertices on the circle of `radius`: 4 * segments triangles.
// The meshes are inscribed in the analytic shapes (a sphere's mesh lies inside its sphere).
//
// Operators: union and intersection (two or more children), difference (exactly two), each of
// any logic family or unified (snapped to its largest weight), read as the crisp boolean.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg::diffcsg {

using Vec3 = std::array<double, 3>;

inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

struct TriMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
};

// Six times the signed volume enclosed (positive for outward normals).
double signed_volume6(const TriMesh& m);

TriMesh unit_box();
TriMesh unit_sphere(int subdivisions);
TriMesh unit_cylinder(int segments);

struct TessellationOptions {
  int sphere_subdivisions = 2;
  int cylinder_segments = 16;
};

// The CSG expression over the primitives: node 0.. with children; leaves name a primitive.
struct CsgNode {
  enum class Kind : std::uint8_t { kPrimitive, kUnion, kIntersection, kDifference } kind;
  int primitive = -1;         // kPrimitive
  std::vector<int> children;  // operators
};

struct Scene {
  std::vector<TriMesh> primitives;  // world coordinates
  std::vector<int> tree_node;       // the Tree node of each primitive
  std::vector<CsgNode> nodes;
  int root = -1;

  // Whether a point inside exactly the primitives p with inside[p] != 0 is inside the solid.
  bool solid(const std::vector<std::uint8_t>& inside) const;
  std::size_t triangle_count() const;
};

// Throws InputError naming `source` and the node path for a tree that is not 3D, a leaf that
// is not a box, sphere or cylinder, or an operator that is not union, intersection, difference
// or unified.
Scene scene_from_tree(const Tree& tree, const std::string& source,
                      const TessellationOptions& options = {});

}  // namespace fuzzycsg::diffcsg
