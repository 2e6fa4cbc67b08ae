#pragma once
// Pictures a fit writes: the loss curve and the slices (drawn on io's Canvas, Cairo), and 2D
// occupancies (PNG through stb_image_write).

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg {

// The loss curve on a log10 axis against the step, with axes, ticks and a title.
std::string loss_curve_png(std::span<const LossPoint> curve, std::string_view title,
                           int width = 800, int height = 500);

// Occupancy of a 2D tree at the pixel centres of a res x res grid over [-1, 1]^2, row 0 at
// y = +1 (as the image targets are read).
std::vector<float> occupancy_grid_2d(const Tree& tree, int res, int threads = 0);

// Three axis-aligned cross-sections through the origin of a 3D target (top row) and a tree's
// occupancy (bottom row), res x res pixels each, inside black.
std::string slices_png(const Target& target, const Tree& tree, int res = 256, int threads = 0);

// Greyscale picture of occupancies in [0, 1]: 1 (inside) black, 0 white, as the pictures fitted.
std::string occupancy_png(std::span<const float> values, int width, int height);

}  // namespace fuzzycsg
