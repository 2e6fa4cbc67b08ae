#pragma once
// Refinement of a traced tree by gradient descent on its fuzzy relaxation (beyond Gibson et al.
// 1997, with the fuzzy machinery of Liu et al. 2024).
//
// The crisp tree becomes a fuzzycsg::Tree with sigmoid leaves (trace::to_tree with a sharpness):
// the occupancy of a leaf is 1 / (1 + exp(s f)), f the signed distance in pixels, and the
// operators keep product logic on their fixed types (union a + b - ab, intersection ab,
// difference a(1 - b)), which on crisp occupancies is the boolean operator, so the fuzzy tree
// tends to the crisp one as s grows. Only the primitives' positions, sizes and angles are free;
// structure and operators do not change. Adam minimises the mean squared error between the
// occupancy at the pixel centres and the target bitmap (0 or 1), the sum of which tends to
// EXCESS + UNCOVERED as the steps sharpen, while the sharpness rises geometrically from
// `sharpness_start` (soft: every pixel within a few pixels of an edge pulls on it) to
// `sharpness_end` (nearly crisp) and the learning rate falls along a cosine from lr to
// lr * lr_end. Sizes are kept >= min_size. The schedule matters (bench/refine_bench on four
// glyphs): a soft start lets a primitive feel a part of the shape several pixels away (on the
// glyph i it found the dot that a start at 0.5 missed), a sharp end makes the loss the pixel
// count; a constant sharpness, soft or sharp, did worse on every glyph.
//
// Every `check_every` steps (and after the last) the current parameters are read back as a
// crisp CsgTree (trace::from_tree) and scored with TreeEvaluator; the best crisp tree seen is
// the result. It replaces the input only when its score is strictly lower, so refinement never
// makes the crisp score worse. The result keeps the input's node ids: only the primitives'
// fields that define their shapes change (x, y and r; or x, y, w, h and theta).
//
// Cost: one forward and backward pass of the evaluator over the sampled pixels per step. Placed
// circles and rectangles take the evaluator's scalar path (eval/evaluator.hpp vectorises
// quadric leaves only): about 10 ms a step for 8 primitives on 128 x 128 pixels on one core.

#include <cstdint>
#include <vector>

#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/csg.hpp"
#include "fuzzycsg/trace/evaluate.hpp"

namespace fuzzycsg::trace {

struct RefineOptions {
  int iterations = 300;   // Adam steps
  int batch = 0;          // pixel centres per step, drawn at random; 0: every pixel
  double lr = 0.5;        // pixels (and degrees) per step, roughly, at the start
  double lr_end = 0.1;    // the final learning rate as a fraction of lr (cosine decay)
  double angle_lr = 1.0;  // the angles' learning rate as a multiple of lr
  double beta1 = 0.9, beta2 = 0.999, adam_eps = 1e-8;
  double sharpness_start = 0.25;  // per pixel, at the first step
  double sharpness_end = 16.0;    // at the last step
  double min_size = 0.5;          // smallest radius, width or height (pixels)
  int check_every = 10;           // steps between crisp scorings of the current parameters
  double k = 25.0;                // tree-size weight of the score
  std::uint64_t seed = 1;         // the pixel sample (batch > 0)
  int threads = 0;                // evaluator threads; 0: every hardware thread
  double time_limit = 0;          // seconds; 0: none
};

// Throws InputError naming the field for values out of range.
void validate(const RefineOptions& options);

struct RefineResult {
  CsgTree tree;            // the refined tree, or the input when nothing better was found
  Score before, after;     // crisp scores of the input and of `tree`
  int iterations = 0;      // Adam steps made
  int best_iteration = 0;  // steps made when `tree` was scored (0: the input)
  double seconds = 0;
  bool improved = false;     // after.total() < before.total()
  std::vector<double> loss;  // the mean squared error at each step
};

// Refines `tree` against `target`; the tree's pixel units are the target's. Throws InputError
// for an empty tree or target and for options out of range.
RefineResult refine(const CsgTree& tree, const Bitmap& target, const RefineOptions& options = {});

}  // namespace fuzzycsg::trace
