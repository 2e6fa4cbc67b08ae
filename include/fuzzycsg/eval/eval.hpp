#pragma once
// The eval module: the SIMD evaluator of compiled trees, the hot kernel every engine calls.
//
//   evaluator.hpp  Evaluator: occupancy of a tree at a batch of points (forward), the
//                  reverse-mode gradient of a loss by every parameter (backward), and the exact
//                  change of the loss when a node is replaced (edit_loss_changes); results are
//                  the same for any thread count.

#include "fuzzycsg/eval/evaluator.hpp"
