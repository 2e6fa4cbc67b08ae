#pragma once
// The core module: the CSG tree every engine reads and writes, and the mathematics of its nodes.
// It knows nothing of files, threads or SIMD, and depends on the standard library and Eigen only.
//
//   tree.hpp          Tree, Node, ParameterTable: nodes referring to one flat table of named
//                     parameters; validate, node_paths, count.
//   tree_builder.hpp  TreeBuilder (trees built in code) and canonical (the tree as its file
//                     holds it: parameters named by node path, in reading order).
//   snap.hpp          snap_operators: unified operators B_c rewritten as crisp booleans.
//   transform.hpp     transformed: a tree moved and scaled as a whole (Similarity).
//   builders.hpp      make_full_binary_tree: Liu et al.'s full binary trees of P leaves.
//   schema.hpp, fields.hpp   the fields of every node kind: names, ranges, defaults.
//   primitives.hpp    the primitive families: schemas, implicit functions, exact gradients.
//   bezier.hpp        closed Bezier profiles of the extrude family.
//   placement.hpp     translate, rotate and scale of a leaf.
//   steps.hpp         occupancy maps: sigmoid, H_n, crisp.
//   logic.hpp         fuzzy logic: t-norms and t-conorms, complements, Bezier and Li & Tian
//                     operators, the unified operator B_c.
//   bspline.hpp       the basis of the fuzzy spline node.
//   program.hpp       a tree compiled into a post-order tape, as the evaluator runs it.
//   triangle_mesh.hpp TriangleMesh, the triangle mesh every module shares; signed_volume,
//                     bounding_box.
//   numbers.hpp       printing numbers for people and files.
//   error.hpp         Error and InputError (one-line messages naming the source).
//   limits.hpp        threads an option asks for, checked and counted (core starts none), and
//                     saturating deadlines on the steady clock.

#include "fuzzycsg/core/bezier.hpp"
#include "fuzzycsg/core/bspline.hpp"
#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/fields.hpp"
#include "fuzzycsg/core/limits.hpp"
#include "fuzzycsg/core/logic.hpp"
#include "fuzzycsg/core/numbers.hpp"
#include "fuzzycsg/core/placement.hpp"
#include "fuzzycsg/core/primitives.hpp"
#include "fuzzycsg/core/program.hpp"
#include "fuzzycsg/core/schema.hpp"
#include "fuzzycsg/core/snap.hpp"
#include "fuzzycsg/core/steps.hpp"
#include "fuzzycsg/core/transform.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/core/tree_builder.hpp"
#include "fuzzycsg/core/triangle_mesh.hpp"
