#pragma once
// How well a tree reproduces a target: the measures of Liu et al. 2024 (occupancy MSE on 2
// million uniform points) plus IoU of the 0.5 level sets and the Chamfer and Hausdorff distances
// between the tree's 0.5 level set and the target's boundary (2D and 3D).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg {

struct MetricsOptions {
  std::size_t points = 2'000'000;  // uniform in [-1, 1]^dim
  std::uint64_t seed = 0;
  int threads = 0;
  bool chamfer = true;                    // 2D and 3D; the Hausdorff distance too
  int chamfer_resolution = 128;           // grid on which the tree's 0.5 level set is extracted
  std::size_t chamfer_samples = 100'000;  // points drawn on the target's boundary
};

struct Metrics {
  double mse = 0;  // mean (o_tree - o_target)^2 over the uniform points
  double iou = 0;  // |{o_tree >= 0.5} & {target}| / |{o_tree >= 0.5} | {target}| (1 if both empty)
  // Symmetric mean distance between the two boundaries: (mean over the tree's level-set points
  // of the distance to the nearest target boundary sample + the converse) / 2. Absent when not
  // asked for, or when the tree has no 0.5 level set inside [-1, 1]^dim (mse and iou are still
  // reported).
  std::optional<double> chamfer;
  // Symmetric Hausdorff distance between the same two point sets as chamfer: the larger of the
  // two directed maxima (the farthest a level-set point is from every target boundary sample,
  // and the converse). It is the worst place rather than the average: a thin part of the target
  // that the tree misses, or a stray blob of the tree, shows here when it hardly moves chamfer.
  // Sampled, not exact: it may differ from the distance between the surfaces by about the
  // sampling's spacing (a cell of chamfer_resolution's grid, the gaps between chamfer_samples
  // points), either way. Present exactly when chamfer is.
  std::optional<double> hausdorff;
  std::size_t points = 0;
};

Metrics measure(const Tree& tree, std::span<const double> params, const Target& target,
                const MetricsOptions& options = {});

}  // namespace fuzzycsg
