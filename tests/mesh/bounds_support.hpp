#pragma once
// Containment check shared by the bounds tests: boxes of several sizes anywhere in the domain
// [-1, 1]^dim, points in each (corners included); every point's reference occupancy must lie
// within the box's bounds.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "mesh/bounds.hpp"

namespace fuzzycsg::test {

// Returns the mean width of the bounds (to check they are not trivially [0, 1]); stops at the
// first box that fails.
inline double check_bounds(const Tree& tree, int boxes, unsigned seed) {
  const std::vector<double> params = tree.params.values();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), t(0.0, 1.0);
  const int dim = tree.dim;
  double width = 0.0;
  for (int b = 0; b < boxes; ++b) {
    const double size = std::pow(10.0, -2.0 + 2.0 * t(rng));  // 0.01 .. 1
    double lo[3], hi[3];
    for (int a = 0; a < dim; ++a) {
      lo[a] = std::clamp(u(rng), -1.0, 1.0 - size);
      hi[a] = lo[a] + size;
    }
    const Interval r = occupancy_bounds(tree, params, lo, hi);
    EXPECT_LE(r.lo, r.hi);
    width += r.hi - r.lo;
    for (int s = 0; s < 40; ++s) {
      double p[3];
      for (int a = 0; a < dim; ++a) {
        const double f = s < (1 << dim) ? ((s >> a) & 1) : t(rng);
        p[a] = lo[a] + f * (hi[a] - lo[a]);
      }
      const double o = reference_occupancy(tree, params, p);
      EXPECT_GE(o, r.lo - 1e-12) << "box " << b << " point " << s;
      EXPECT_LE(o, r.hi + 1e-12) << "box " << b << " point " << s;
      if (o < r.lo - 1e-12 || o > r.hi + 1e-12) return width / (b + 1);
    }
  }
  return width / boxes;
}

}  // namespace fuzzycsg::test
