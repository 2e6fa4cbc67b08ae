#include "fuzzycsg/target/nearest.hpp"

#include <cstdint>
#include <nanoflann.hpp>
#include <utility>

namespace fuzzycsg {

namespace nearest_detail {

// A row-major n x dim point array as nanoflann's dataset.
struct Cloud {
  const std::vector<float>* points;
  std::size_t dim;
  std::size_t kdtree_get_point_count() const { return points->size() / dim; }
  float kdtree_get_pt(std::size_t i, std::size_t d) const { return (*points)[i * dim + d]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud, -1>;

}  // namespace nearest_detail

using nearest_detail::Cloud;
using nearest_detail::KdTree;

struct NearestPoints::Impl {
  std::vector<float> points;
  Cloud cloud;
  KdTree index;
  Impl(std::vector<float> p, int dim)
      : points(std::move(p)), cloud{&points, static_cast<std::size_t>(dim)}, index(dim, cloud) {}
};

NearestPoints::NearestPoints(std::vector<float> points, int dim)
    : impl_(std::make_unique<Impl>(std::move(points), dim)) {}
NearestPoints::~NearestPoints() = default;
NearestPoints::NearestPoints(NearestPoints&&) noexcept = default;
NearestPoints& NearestPoints::operator=(NearestPoints&&) noexcept = default;

NearestPoints::Hit NearestPoints::nearest(const float* point) const {
  std::uint32_t index = 0;
  float d2 = 0.0f;
  impl_->index.knnSearch(point, 1, &index, &d2);
  return {index, d2};
}

int NearestPoints::dim() const { return static_cast<int>(impl_->cloud.dim); }
std::size_t NearestPoints::size() const { return impl_->cloud.kdtree_get_point_count(); }
const float* NearestPoints::point(std::size_t i) const {
  return &impl_->points[i * impl_->cloud.dim];
}

}  // namespace fuzzycsg
