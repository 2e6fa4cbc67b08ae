#pragma once
// Pictures of a traced tree (the trace and morph verbs): the result over the target as a PNG,
// the primitives' outlines over both as an SVG, and the tree as an expression.

#include <string>

#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/csg.hpp"

namespace fuzzycsg::trace {

// The colours of result_png (RGB).
inline constexpr unsigned char kInsideRgb[3] = {64, 64, 64};       // tree and target set
inline constexpr unsigned char kOutsideRgb[3] = {255, 255, 255};   // both clear
inline constexpr unsigned char kExcessRgb[3] = {220, 50, 40};      // tree set, target clear
inline constexpr unsigned char kUncoveredRgb[3] = {40, 100, 220};  // target set, tree clear

// The tree's bitmap `result` over `target` (the same size), each pixel coloured as above,
// scaled up `scale` times (nearest); a legend strip below when the picture is at least 200
// pixels wide. PNG bytes.
std::string result_png(const Bitmap& result, const Bitmap& target, int scale);

// A bitmap alone (set: dark grey, clear: white), scaled up `scale` times. PNG bytes.
std::string bitmap_png(const Bitmap& b, int scale);

// An SVG of the target (light grey pixels), the result (translucent dark pixels over it) and
// every primitive's outline in pixel coordinates (clipped to the picture), numbered 1, 2, ...
// in leaf order, in a colour of its own: dashed when it is subtracted (on the right of an odd
// number of differences), solid otherwise; each outline's class says "added", "subtracted" or
// "intersected" (leaf_polarity). A legend below gives the tree as an expression of those
// numbers. Drawn `scale` screen pixels per bitmap pixel.
std::string primitives_svg(const CsgTree& tree, const Bitmap& result, const Bitmap& target,
                           int scale);

// The tree as an expression of its leaves numbered 1, 2, ... in leaf order: "(1 | 2) - 3"
// ("|" union, "&" intersection, "-" difference; every operator in parentheses but the root's).
std::string expression(const CsgTree& tree);

// How each leaf acts on the shape (in leaf order): +1 adds (union-like), -1 is subtracted,
// 0 intersects (only removes where it is clear).
std::vector<int> leaf_polarity(const CsgTree& tree);

}  // namespace fuzzycsg::trace
