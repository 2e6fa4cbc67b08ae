#pragma once
// A tree moved and scaled as a whole: the similarity x -> scale * x + translate applied to its
// shape, written into the tree itself (its leaves' placements and steps, its domain). Inverse
// CSG trains in a normalised box and gives its trees back in the target's own coordinates with
// this; `prune` moves a tree into the normalised box of its target and back.

#include <array>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg {

// x -> scale * x + translate (translate has dim entries in use; scale > 0).
struct Similarity {
  std::array<double, 3> translate{0, 0, 0};
  double scale = 1.0;

  bool is_identity() const {
    return scale == 1.0 && translate[0] == 0.0 && translate[1] == 0.0 && translate[2] == 0.0;
  }
  Similarity inverse() const {
    return {{-translate[0] / scale, -translate[1] / scale, -translate[2] / scale}, 1.0 / scale};
  }
  std::array<double, 3> apply(const std::array<double, 3>& x) const {
    return {scale * x[0] + translate[0], scale * x[1] + translate[1], scale * x[2] + translate[2]};
  }
};

// The tree whose occupancy at m(x) is `tree`'s occupancy at x, for every point x (up to
// rounding). Each leaf's placement (t, R, s) becomes (m(t), R, m.scale * s) — a leaf without a
// translate or a scale gets one, named by its node path — a sigmoid step's sharpness is divided
// by m.scale and an H_n step's range multiplied by it (f grows with the scale), and the domain
// (the default [-1, 1]^dim when absent) and spline boxes are mapped by m. Operators, logics and
// the leaves' own fields do not change. Throws InputError naming the parameter when a
// placement or step parameter that must change is shared by several fields, or when m is not a
// similarity with a finite, positive scale.
Tree transformed(const Tree& tree, const Similarity& m);

}  // namespace fuzzycsg
