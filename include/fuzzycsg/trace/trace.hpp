#pragma once
// The trace module: bitmaps to crisp CSG trees of circles and rectangles by stochastic search
// (Gibson et al. 1997), morphing between two pictures, and refinement of a traced tree by
// gradient descent on its fuzzy relaxation.
//
//   bitmap.hpp        Bitmap (bit-packed rows), read_bitmap.
//   csg.hpp           CsgTree: crisp trees in pixel units, the tracer's representation.
//   evaluate.hpp      scan conversion, TreeEvaluator (incremental) and the Score.
//   optimize.hpp      the local optimizer (adjust each primitive, prune the idle ones).
//   search.hpp        the global search, its morph and variety forms.
//   refine.hpp        refinement on the fuzzy relaxation (beyond the paper).
//   convert.hpp       to_tree and from_tree: the tracer's trees as the project's trees.
//   morph_frames.hpp  the frames of a morph, and the animated GIF.
//   pictures.hpp      pictures of a traced tree: PNG, SVG outlines, the expression.
//   report.hpp        report.json of a trace and of a morph.

#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/convert.hpp"
#include "fuzzycsg/trace/csg.hpp"
#include "fuzzycsg/trace/evaluate.hpp"
#include "fuzzycsg/trace/morph_frames.hpp"
#include "fuzzycsg/trace/optimize.hpp"
#include "fuzzycsg/trace/pictures.hpp"
#include "fuzzycsg/trace/refine.hpp"
#include "fuzzycsg/trace/report.hpp"
#include "fuzzycsg/trace/search.hpp"
