#pragma once
// Extrude profiles for the primitive and Bézier tests.

#include <cstddef>
#include <vector>

namespace fuzzycsg::test {

// The profile of the closed polygon `corners` ([x0, y0, x1, y1, ...]) with each edge a straight
// Bézier segment (its controls at the edge's thirds).
inline std::vector<double> straight_profile(const std::vector<double>& corners) {
  const std::size_t n = corners.size() / 2;
  std::vector<double> c;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t m = (k + 1) % n;
    for (int j = 0; j < 3; ++j) {
      c.push_back(corners[2 * k] + j * (corners[2 * m] - corners[2 * k]) / 3.0);
      c.push_back(corners[2 * k + 1] + j * (corners[2 * m + 1] - corners[2 * k + 1]) / 3.0);
    }
  }
  return c;
}

}  // namespace fuzzycsg::test
