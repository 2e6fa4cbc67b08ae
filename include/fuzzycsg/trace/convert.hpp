#pragma once
// Trees of the tracer as the project's trees (fuzzycsg::Tree, docs/tree-format.md).
//
// A W x H bitmap becomes the 2D domain [0, W] x [0, H]: pixels are unit squares and, by the
// tree-file convention, pixel (i, j) (row j from the top) has its centre at
// (i + 1/2, H - j - 1/2). A primitive at (x, y) in pixel units (y down) is translated to
// (x, H - y); a rectangle's angle theta (clockwise on screen) becomes rotate = -theta (counter-
// clockwise, y up). Leaves are crisp ("step": "crisp"); the operators keep the default product
// logic, which on crisp occupancies is the boolean operator. Evaluated at a pixel centre, the
// tree gives 1 exactly where the tracer's bitmap is set (except at centres on a primitive's
// boundary, where a crisp leaf is 1/2).
//
// With a sharpness s > 0 the leaves are soft instead ("step": "sigmoid", occupancy
// 1 / (1 + exp(s f)), f the signed distance in pixels), the sharpness a fixed parameter: the
// positions, sizes and angles are the tree's free parameters, for gradient descent
// (trace/refine.hpp). As s grows the occupancy at every pixel centre off a boundary tends to the
// crisp one.
//
// from_tree() is the inverse: it reads circles and rectangles back into a CsgTree.

#include <string>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/trace/csg.hpp"

namespace fuzzycsg::trace {

// The tracer's tree as a validated, canonical Tree (write it with io/tree_json.hpp). sharpness
// 0: crisp leaves; > 0: sigmoid leaves of that fixed sharpness (per pixel).
Tree to_tree(const CsgTree& tree, int width, int height, double sharpness = 0);

// A 2D tree of circles and rectangles (any step, placement by translate and rotate, and scale)
// combined by union, intersection (two or more children, folded left) and difference, with the
// current values of its parameter table, as a CsgTree in pixel units of a bitmap `height`
// pixels high (y = height - translate[1], theta = -rotate; a scale multiplies the sizes). Leaves
// come out in the same left-to-right order. The logic family of an operator is not read (every
// t-norm is the boolean operator on crisp occupancies). Throws InputError naming the node for a
// 3D tree, other primitive families (ellipse, polygon, ...) and other operators (complement,
// unified, spline). `width` is checked (>= 1) but not otherwise used.
CsgTree from_tree(const Tree& tree, int width, int height);

}  // namespace fuzzycsg::trace
