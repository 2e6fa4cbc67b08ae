#pragma once
// The nearest of a set of points (a k-d tree, nanoflann), built once and queried from any number
// of threads: the distances of the metrics and the initialisation of a fit from its target.

#include <cstddef>
#include <memory>
#include <vector>

namespace fuzzycsg {

class NearestPoints {
 public:
  // n points of `dim` coordinates, row-major (n x dim).
  NearestPoints(std::vector<float> points, int dim);
  ~NearestPoints();
  NearestPoints(NearestPoints&&) noexcept;
  NearestPoints& operator=(NearestPoints&&) noexcept;

  struct Hit {
    std::size_t index = 0;  // of the nearest point
    float squared_distance = 0;
  };
  // The nearest point to `point` (dim coordinates). The set must not be empty.
  Hit nearest(const float* point) const;

  int dim() const;
  std::size_t size() const;
  const float* point(std::size_t i) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fuzzycsg
