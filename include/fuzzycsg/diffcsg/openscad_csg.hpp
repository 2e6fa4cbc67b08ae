#pragma once
// OpenSCAD models through the flattened CSG form that `openscad -o model.csg model.scad`
// writes, as a Scene of meshed primitives (scene.hpp).
//
// Nodes: cube(size, center), sphere(r | d), cylinder(h, r | r1, r2 | d | d1, d2, center),
// multmatrix(m), union(), difference() (the first child less all the others), intersection(),
// group() (a union), and the pass-through color() and render(). Several top-level statements
// are a union. The modifiers # and ! keep their node, % and * remove it. Spheres and cylinders are
// tessellated as OpenSCAD 2021.01 does: $fn, $fa and $fs give the number of fragments
// (get_fragments_from_r), a sphere is (fragments + 1) / 2 rings of latitude with capping polygons,
// a cylinder two circles of that many points (a cone's apex is one point). Any other node
// (linear_extrude, polyhedron, import, ...) is refused with one line naming the file, the line and
// the node.
//
// Limits, so that a few bytes cannot exhaust the stack or the memory: statements and vectors
// nested more than 512 deep are refused, as are a sphere or cylinder of more than
// kMaxFragments fragments and a model of more than `max_triangles` triangles in all (counted as
// parse_openscad_csg tessellates it), each naming the line, by both readers and before any
// tessellation is made.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include "fuzzycsg/diffcsg/scene.hpp"

namespace fuzzycsg::diffcsg {

// The most triangles of a model by default: two spheres at the limit of fragments (a sphere of
// 4096 fragments has 16777212 triangles), about a gigabyte of meshes.
inline constexpr std::size_t kMaxOpenscadTriangles = std::size_t{1} << 25;

Scene read_openscad_csg(const std::filesystem::path& path);
// `source` names the text in messages.
Scene parse_openscad_csg(std::string_view text, const std::string& source,
                         std::size_t max_triangles = kMaxOpenscadTriangles);

// The model as a tree file, for refinement: each primitive's accumulated multmatrix becomes the
// leaf's translate and rotate (Euler angles), its scales folded into the primitive's fields (a
// sphere scaled unevenly becomes an ellipsoid, a cylinder with r1 != r2 a cone, an uncentred
// primitive is moved by half its size); a shearing matrix, or one that scales a cylinder
// differently across its axis, is refused naming the line. A difference of several children
// becomes the first less the union of the others. Leaves are crisp and named "<node> line <n>";
// the tessellation keeps OpenSCAD's fragments for every sphere and cylinder.
struct OpenscadModel {
  Tree tree;
  TessellationOptions tessellation;
};
OpenscadModel read_openscad_csg_tree(const std::filesystem::path& path);
OpenscadModel parse_openscad_csg_tree(std::string_view text, const std::string& source,
                                      std::size_t max_triangles = kMaxOpenscadTriangles);

// OpenSCAD's get_fragments_from_r, saturated at the largest int. The readers above refuse a
// primitive with more than kMaxFragments, naming its line.
int openscad_fragments(double r, double fn, double fs, double fa);

}  // namespace fuzzycsg::diffcsg
