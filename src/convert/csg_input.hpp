#pragma once
// OpenSCAD models as convert's input: a `.csg` file (what `openscad -o model.csg` writes) read as
// a tree of solids, which is the true solid that the result is measured against, and a mesh of
// it for surface detection.

#include <string>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/core/triangle_mesh.hpp"

namespace fuzzycsg::convert {

struct CsgInput {
  // The model's tree, crisp, in its own units, over the cube around its solid whose largest
  // half-extent grown by 1 / (1 - padding) is the cube's: as a target, it is normalised as a
  // mesh of it would be.
  Tree solid;
  // The 0.5 level set of the same tree with sigmoid steps about a grid cell wide and min/max
  // booleans, which is the solid's surface to within the marching cubes' error (flat faces stay
  // flat, edges are cut by less than a cell), in the model's units.
  TriangleMesh mesh;
};

// A crisp tree of solids with sigmoid steps of the given sharpness and min/max booleans, over
// the same domain: its occupancy is the sigmoid of the booleans' signed distance, so its 0.5
// level set is the crisp tree's boundary, and marching cubes on a grid of cells about
// 2 / sharpness wide place it smoothly (no steps of the grid on slanted and curved faces).
Tree smooth_tree(const Tree& tree, double sharpness);

// Throws InputError naming the file: what scad::read_csg and scad::csg_tree refuse, a leaf
// that is not one of convert's solids (an ellipsoid: a sphere scaled unevenly), a model with no
// volume.
CsgInput read_csg_input(const std::string& path, double padding, int resolution, int threads);

}  // namespace fuzzycsg::convert
