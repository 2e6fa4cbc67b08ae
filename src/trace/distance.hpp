#pragma once
// The Euclidean distance map of a bitmap and its extrema, which the global search's ADD
// operator uses to place primitives (Gibson et al. 1997).
//
// Exact distances between pixel centres (Felzenszwalb and Huttenlocher's transform,
// fuzzycsg/target/signed_distance_grid.hpp), in pixels:
//   inside[p]  at a set pixel, the distance to the nearest clear pixel centre, the picture
//              being surrounded by clear pixels (so a shape that touches the border is 1 there);
//              0 at clear pixels;
//   outside[p] at a clear pixel, the distance to the nearest set pixel centre (+infinity when
//              the bitmap has none); 0 at set pixels.
// Index p = row * width + col.

#include <vector>

#include "fuzzycsg/trace/bitmap.hpp"

namespace fuzzycsg::trace {

struct DistanceMap {
  int width = 0, height = 0;
  std::vector<double> inside, outside;
  double inside_at(int col, int row) const { return inside[index(col, row)]; }
  double outside_at(int col, int row) const { return outside[index(col, row)]; }
  std::size_t index(int col, int row) const {
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(width) +
           static_cast<std::size_t>(col);
  }
};

DistanceMap distance_map(const Bitmap& b);

// A pixel where a distance map has a local maximum, and the map's value there.
struct Extremum {
  int col = 0, row = 0;
  double distance = 0;
};

// The pixels whose value is positive and finite and at least that of each of their 8
// neighbours (neighbours outside the bitmap do not count); a plateau gives all its pixels.
// Ordered by decreasing distance, then row, then column.
std::vector<Extremum> local_maxima(const std::vector<double>& map, int width, int height);

// The ADD operator's positions: local maxima of the inside map (where a unioned primitive
// adds to the shape) and the "local minima" of the signed map, i.e. local maxima of the outside
// map (where a differenced primitive cuts away).
struct Extrema {
  std::vector<Extremum> maxima, minima;
};
Extrema distance_extrema(const DistanceMap& d);

}  // namespace fuzzycsg::trace
