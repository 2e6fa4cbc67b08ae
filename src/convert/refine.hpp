#pragma once
// Refinement of a tree of solids by fuzzy gradient descent (Liu et al. 2024): the leaves'
// crisp steps become sigmoids whose sharpness rises geometrically over the steps (stepped as
// its logarithm of a schedule, so that the tree ends effectively crisp), the booleans become
// unified operators B_c leaning towards the boolean the search chose, and Adam descends the mean
// squared error of the occupancy against the target's labels at points drawn near its surface.

#include <chrono>
#include <cstdint>
#include <optional>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg::convert {

struct RefineOptions {
  int steps = 400;
  int batch = 16384;
  std::size_t pool = 262144;  // points drawn once, cycled through in batches
  double lr = 2e-3;           // lengths (the normalised domain); cosine down to lr_end of it
  double lr_end = 0.05;
  double rotation_rate = 20.0;  // rotations (degrees) step this multiple of lr
  double logit_rate = 2.0;      // operator logits
  double sharpness_start = 60.0, sharpness_end = 2000.0;
  double near_distance = 0.03;  // half-width of the band around the surface where points are drawn
  std::uint64_t seed = 0;
  int threads = 0;
  // No step starts after this time; the schedule is not shortened, the refinement just ends.
  std::optional<std::chrono::steady_clock::time_point> deadline;
};

struct RefineResult {
  Tree tree;  // the soft tree after the last step (unified operators, sigmoid steps)
  double loss_first = 0, loss_last = 0;  // mean loss of the first and last tenth of the steps
  bool stopped = false;                  // ended at the deadline
};

// `tree`: a tree of solids with sigmoid steps and unified operators (chains_tree with
// BuildOptions{sharpness, unified}) in the target's normalised coordinates.
RefineResult refine_fuzzy(const Tree& tree, const Target& target, const RefineOptions& options);

}  // namespace fuzzycsg::convert
