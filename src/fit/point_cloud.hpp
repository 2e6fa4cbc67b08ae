#pragma once
// Nearest-neighbour queries over row-major point arrays (nanoflann), shared by the metrics and
// the initialisation from the target.

#include <cstddef>
#include <nanoflann.hpp>
#include <vector>

namespace fuzzycsg::fit_detail {

// A row-major n x dim point array as nanoflann's dataset.
struct Cloud {
  const std::vector<float>& points;
  std::size_t dim;
  std::size_t kdtree_get_point_count() const { return points.size() / dim; }
  float kdtree_get_pt(std::size_t i, std::size_t d) const { return points[i * dim + d]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud, -1>;

}  // namespace fuzzycsg::fit_detail
