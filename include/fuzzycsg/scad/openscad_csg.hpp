#pragma once
// OpenSCAD import: models through the flattened CSG form that `openscad -o model.csg model.scad`
// writes, read as a checked model of primitives and booleans, and as a tree.
//
// Nodes: cube(size, center), sphere(r | d), cylinder(h, r | r1, r2 | d | d1, d2, center),
// multmatrix(m), union(), difference() (the first child less all the others), intersection(),
// group() (a union), and the pass-through color() and render(). Several top-level statements
// are a union. The modifiers # and ! keep their node, % and * remove it. $fn, $fa and $fs give
// a sphere's or cylinder's number of fragments as OpenSCAD 2021.01 computes it
// (get_fragments_from_r). Any other node (linear_extrude, polyhedron, import, ...) is refused
// with one line naming the file, the line and the node.
//
// Limits, so that a few bytes cannot exhaust the stack or the memory: statements and vectors
// nested more than 512 deep are refused, as are a sphere or cylinder of more than
// kMaxFragments fragments and a model of more than `max_triangles` triangles in all (counted
// as OpenSCAD tessellates the primitives, in the order they are read), each naming the line,
// before anything is tessellated.

#include <array>
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg::scad {

// The most fragments of a sphere or cylinder.
inline constexpr int kMaxFragments = 4096;
// The most triangles of a model by default: 2^22, a sphere of 2048 fragments (4192252
// triangles), about 130 MB of meshes, which DiffCSG draws in minutes on two cores; a sphere at
// the limit of fragments (4096: 16777212 triangles) took 258 s and 6.6 GB to draw once.
inline constexpr std::size_t kMaxOpenscadTriangles = std::size_t{1} << 22;

// OpenSCAD's get_fragments_from_r, saturated at the largest int.
int openscad_fragments(double r, double fn, double fs, double fa);

// A primitive's arguments, checked.
struct CsgPrimitive {
  enum class Kind { kCube, kSphere, kCylinder } kind = Kind::kCube;
  std::array<double, 3> size{1, 1, 1};  // cube
  double r = 1;                         // sphere
  double h = 1, r1 = 1, r2 = 1;         // cylinder (r1 at z = 0 or -h/2)
  bool center = false;
  int fragments = 3;  // sphere, cylinder
};

// A node of the model: a primitive with the matrix that places it in the world (every
// multmatrix above it multiplied in), or a boolean over its children (group, color, render and
// multmatrix are unions).
struct CsgItem {
  enum class Kind { kPrimitive, kUnion, kIntersection, kDifference } kind = Kind::kUnion;
  std::string name;  // the statement's name: "cube", "multmatrix", ...
  int line = 0;
  CsgPrimitive primitive;
  std::array<double, 16> matrix{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // row-major
  std::vector<CsgItem> children;
  // The triangles of this primitive as OpenSCAD tessellates it (0 for operators).
  std::size_t triangle_count() const;
};

struct CsgModel {
  std::string source;          // names the model in messages
  std::vector<CsgItem> items;  // the top-level statements, a union
};

// Throws InputError with one line naming `source`, the line and the node for what the reader
// refuses (see above).
CsgModel parse_csg(std::string_view text, const std::string& source,
                   std::size_t max_triangles = kMaxOpenscadTriangles);
CsgModel read_csg(const std::filesystem::path& path);

// Throws InputError "source: line L: name: problem", as the reader's messages about a node read.
[[noreturn]] void fail_at(const CsgModel& model, const CsgItem& item, const std::string& problem);

// The model as a tree: each primitive's matrix becomes the leaf's translate and rotate (Euler
// angles), its scales folded into the primitive's fields (a sphere scaled unevenly becomes an
// ellipsoid, a cylinder with r1 != r2 a cone, an uncentred primitive is moved by half its
// size); a shearing matrix, or one that scales a cylinder differently across its axis, is
// refused naming the line. A difference of several children becomes the first less the union
// of the others. Leaves are crisp and named "<node> line <n>"; `fragments` gives OpenSCAD's
// fragments of every sphere and cylinder leaf, by node index.
struct CsgTree {
  Tree tree;
  std::map<int, int> fragments;
};
CsgTree csg_tree(const CsgModel& model);

}  // namespace fuzzycsg::scad
