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

#include <string>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/trace/csg.hpp"

namespace fuzzycsg::trace {

// The tree file's text (format "fuzzycsg-tree", version 1).
std::string to_tree_json(const CsgTree& tree, int width, int height);
// The same, read back as a validated Tree.
Tree to_tree(const CsgTree& tree, int width, int height);

}  // namespace fuzzycsg::trace
