#pragma once
// CSG of meshed primitives (Yuan et al. 2024, DiffCSG): each leaf of a 3D tree becomes a closed
// triangle mesh of fixed tessellation, placed in the world by the leaf's translate, rotate and
// scale, and the tree's operators become crisp booleans over those solids.
//
// Tessellations (local coordinates, outward normals by the right-hand rule):
//   box        [-1/2, 1/2]^3 scaled by `size`: 12 triangles;
//   sphere     an icosahedron subdivided `sphere_subdivisions` times (default 2: 320
//              triangles), vertices on the sphere of radius `radius`;
//   ellipsoid  the sphere's mesh scaled by `radii`;
//   cylinder   axis z, z in [-height/2, height/2], `cylinder_segments` (default 16) sides, the
//              rings' vertices on the circle of `radius`: 4 * segments triangles;
//   cone       the cylinder's mesh with the bottom ring on the circle of `radius1` and the top
//              ring on that of `radius2` (DiffCSG's tapered cylinder); a radius that is 0 when
//              the scene is built is an apex (one vertex) instead of a ring;
//   extrude    the profile's polygon (core/bezier.hpp, kBezierSamples points per Bézier
//              segment) as two rings at z = -height/2 and +height/2, the walls between them
//              (smooth, but sharp where the profile turns by more than 30 degrees) and the caps
//              triangulated by ear clipping.
// The meshes are inscribed in the analytic shapes (a sphere's mesh lies inside its sphere).
//
// Every vertex is a function of the tree's parameters, v = t + s R l: t, R, s the leaf's
// placement and the local position l linear in the leaf's own fields (a box corner is
// (±size_x, ±size_y, ±size_z) / 2, a profile sample a Bernstein combination of control points).
// Scene::bindings records these maps, so that gradients with respect to vertices become
// gradients with respect to parameters (refine.hpp) without tessellating again.
//
// Leaves read from an OpenSCAD model (openscad_csg.hpp) keep OpenSCAD's tessellation: spheres as
// its rings of latitude, cylinders and cones as its polygons, with its number of fragments
// (TessellationOptions::openscad_fragments).
//
// Operators: union and intersection (two or more children), difference (exactly two), each of
// any logic family or unified (snapped to its largest weight), read as the crisp boolean.

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "fuzzycsg/core/bezier.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/core/triangle_mesh.hpp"

namespace fuzzycsg::diffcsg {

using Vec3 = std::array<double, 3>;

inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// A primitive's closed mesh (core's TriangleMesh: its vertices are Vec3) and how it is shaded.
struct PrimitiveMesh {
  TriangleMesh mesh;
  // Per triangle, a smoothing group (>= 0: normals are averaged over the triangles of the group
  // around each vertex) or -1 (flat: the face's own normal). Empty: all flat.
  std::vector<int> smoothing;
};

// Unit meshes (sizes 1; the sphere of radius 1, the cylinder of radius 1 and height 1), with
// their smoothing groups.
PrimitiveMesh unit_box();
PrimitiveMesh unit_sphere(int subdivisions);
PrimitiveMesh unit_cylinder(int segments);
// OpenSCAD 2021.01's sphere of radius 1 with `fragments` fragments: (fragments + 1) / 2 rings
// of latitude, capped by polygons.
PrimitiveMesh openscad_sphere(int fragments);

// The most fragments a sphere or cylinder may have (a sphere of n fragments has about n^2
// triangles): more is refused, by the .csg readers and by scene_from_tree alike.
inline constexpr int kMaxFragments = 4096;

struct TessellationOptions {
  int sphere_subdivisions = 2;
  int cylinder_segments = 16;
  // Leaves (tree node index) tessellated as OpenSCAD does, with this many fragments: spheres
  // and ellipsoids as openscad_sphere(), cylinders and cones with that many sides.
  std::map<int, int> openscad_fragments;
  // Extrude leaves (tree node index) whose caps keep this triangulation of the profile's
  // polygon, whatever its points become (fixed_tessellation()); others are triangulated anew.
  std::map<int, std::vector<PolygonTriangle>> cap_triangles;
};

// `options` with the caps of every extrude leaf of `tree` triangulated at the tree's present
// values, so that the meshes keep their connectivity while the parameters change (a
// refinement). InputError naming the node if a profile cannot be triangulated.
TessellationOptions fixed_tessellation(const Tree& tree, const std::string& source,
                                       TessellationOptions options);

// The CSG expression over the primitives: node 0.. with children; leaves name a primitive.
struct CsgNode {
  enum class Kind : std::uint8_t { kPrimitive, kUnion, kIntersection, kDifference } kind;
  int primitive = -1;         // kPrimitive
  std::vector<int> children;  // operators
};

// How a primitive's vertices follow the tree's parameters: v = t + s R l with
// l = sum over the vertex's terms of coefficient * value(param).
struct LocalTerm {
  ParamRef param;
  Vec3 coefficient;
};
struct PrimitiveBinding {
  std::vector<std::uint32_t> offsets;  // vertex v's terms: [offsets[v], offsets[v + 1])
  std::vector<LocalTerm> terms;
  std::vector<Vec3> local;  // l of each vertex (at the parameters the scene was built with)
  std::vector<ParamRef> translate, rotate;
  std::optional<ParamRef> scale;
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // R, row-major
  double scale_value = 1;
};

struct Scene {
  std::vector<PrimitiveMesh> primitives;  // world coordinates
  std::vector<int> tree_node;             // the Tree node of each primitive
  std::vector<CsgNode> nodes;
  int root = -1;
  // One per primitive when the scene was built from a tree (scene_from_tree), else empty.
  std::vector<PrimitiveBinding> bindings;

  // Whether a point inside exactly the primitives p with inside[p] != 0 is inside the solid.
  bool solid(const std::vector<std::uint8_t>& inside) const;
  std::size_t triangle_count() const;
  // The bounding box of every primitive's vertices (lo, hi); throws if there are none.
  std::array<Vec3, 2> bounds() const;
};

// Throws InputError naming `source` and the node path for a tree that is not 3D, a leaf that
// is not a box, sphere, ellipsoid, cylinder, cone or extrude, an extrude whose profile cannot
// be triangulated (self-intersecting), or an operator that is not union, intersection, difference
// or unified.
Scene scene_from_tree(const Tree& tree, const std::string& source,
                      const TessellationOptions& options = {});

// A closed mesh as a scene of one primitive (a target to render). Normals are averaged across
// edges whose faces meet at less than `crease_degrees`; sharper edges stay sharp.
Scene scene_from_mesh(TriangleMesh mesh, double crease_degrees = 30);

}  // namespace fuzzycsg::diffcsg
