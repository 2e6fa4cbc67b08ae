#pragma once
// convert on pictures (PNG, JPEG, PBM, PGM): a crisp 2D tree of circles and rectangles by the
// bitmap tracer of Gibson et al. 1997 (trace::search, primitives made dearer until
// ConvertOptions::max_primitives holds) and its refinement by gradient descent on the tree's
// fuzzy relaxation (trace::refine, ConvertOptions::refine_steps Adam steps), in the picture's
// pixel units (y up, as trace writes trees), measured against the picture at its own
// resolution. The grid, restarts, padding and tidy settings of the 3D pipeline do not apply.

#include <string>

#include "fuzzycsg/convert/convert.hpp"

namespace fuzzycsg::convert {

// Whether convert reads the file as a picture (by its extension).
bool is_picture(const std::string& path);

ConvertResult convert_picture(const std::string& path, const ConvertOptions& options,
                              const ConvertHooks& hooks);

}  // namespace fuzzycsg::convert
