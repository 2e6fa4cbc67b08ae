#pragma once
// The signed distance field of a binary picture, as the image target uses it: exact Euclidean
// distance transforms of the mask (Felzenszwalb and Huttenlocher 2012), sampled at the pixel
// centres of an n x n grid over [-1, 1]^2 and interpolated bilinearly between them.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace fuzzycsg {

class SignedDistanceGrid {
 public:
  // inside: n * n entries (non-zero: inside), row-major, row 0 at the top (y = +1), column 0 at
  // the left (x = -1); pixel (row, col) has its centre at (-1 + (col + 1/2) h, 1 - (row + 1/2) h)
  // with h = 2 / n. Throws InputError unless n >= 2 and both inside and outside pixels occur.
  //
  // At an outside centre the value is the distance to the nearest inside centre, at an inside
  // centre minus the distance to the nearest outside centre, each less h / 2: the distance to
  // the pixel edges where the two kinds of pixels meet. So values are never 0 at the centres
  // (|value| >= h / 2) and the zero level set runs between the pixels.
  SignedDistanceGrid(std::span<const std::uint8_t> inside, int n);

  int size() const { return n_; }
  double cell() const { return h_; }  // h, the pixel size in domain units
  float at(int row, int col) const {
    return values_[static_cast<std::size_t>(row) * static_cast<std::size_t>(n_) +
                   static_cast<std::size_t>(col)];
  }

  // Bilinear between pixel centres, constant beyond the outermost ones (x, y finite).
  double value(double x, double y) const;
  // The field of the authors' release (scipy's distance_transform_edt of the mask's outside
  // minus that of its inside), in pixels: at an outside centre the distance to the nearest
  // inside centre, at an inside centre minus the distance to the nearest outside centre (so
  // |value| >= 1 at the centres: value() / cell() moved half a pixel away from 0); bilinear
  // between centres and constant beyond the outermost ones, as value(). Its zero level set is
  // value()'s wherever pixels of the two kinds meet along a row or a column.
  double centre_distance(double x, double y) const;
  // centre_distance() at the centre of pixel (row, col).
  double centre_distance_at(int row, int col) const;
  // The unit direction in which value() grows at (x, y), by central differences two pixels
  // either side: on a pixelated circle the exact gradient of the bilinear interpolant swings
  // by up to 45 degrees about the radius at the zero level set, these by about 10 (3 on
  // average). {0, 0} where both differences vanish.
  std::array<double, 2> normal(double x, double y) const;

 private:
  // Bilinear interpolation of corner(row, col) between the pixel centres.
  template <class F>
  double interpolate(double x, double y, F corner) const;

  int n_;
  double h_;
  std::vector<float> values_;
};

// Squared Euclidean distance, in pixels, from each pixel centre of a width x height mask
// (row-major) to the nearest centre whose mask value equals `feature`; infinity where there is
// none.
std::vector<double> squared_distance_transform(std::span<const std::uint8_t> mask, int width,
                                               int height, std::uint8_t feature);

}  // namespace fuzzycsg
