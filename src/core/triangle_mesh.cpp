#include "fuzzycsg/core/triangle_mesh.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>

namespace fuzzycsg {

double signed_volume(const TriangleMesh& mesh) {
  double v = 0.0;
  for (const auto& t : mesh.triangles) {
    const auto& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const auto& b = mesh.vertices[static_cast<std::size_t>(t[1])];
    const auto& c = mesh.vertices[static_cast<std::size_t>(t[2])];
    v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
          a[2] * (b[0] * c[1] - b[1] * c[0])) /
         6.0;
  }
  return v;
}

std::array<std::array<double, 3>, 2> bounding_box(const TriangleMesh& mesh) {
  std::array<double, 3> lo, hi;
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (const auto& v : mesh.vertices) {
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], v[k]);
      hi[k] = std::max(hi[k], v[k]);
    }
  }
  return {lo, hi};
}

}  // namespace fuzzycsg
