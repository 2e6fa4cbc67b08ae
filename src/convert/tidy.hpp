#pragma once
// The last stage before the program is written: the solids' numbers made regular where that
// costs (almost) nothing on the grid. Axes within a few degrees of the world's are snapped to
// them (boxes then lose their rotation), and every length and coordinate is rounded in the
// mesh's own units: to the coarsest of 1, 5, 10, 50 ... times a power of ten that keeps the
// error at uniform samples within a tolerance, and never finer than a thousandth of the part's
// size.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "convert/program.hpp"
#include "convert/search.hpp"
#include "convert/solid.hpp"
#include "fuzzycsg/core/transform.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg::convert {

struct TidyOptions {
  bool enabled = true;  // false: the solids as they are, only moved to the mesh's coordinates
  double snap_angle_deg = 2.0;  // axes this close to a world axis are snapped to it
  // Each change may add at most `step_tolerance` of the inside cells to the wrong ones, and all
  // changes together at most `total_tolerance`.
  double step_tolerance = 0.001;
  double total_tolerance = 0.004;
  std::size_t points = std::size_t{1} << 20;  // uniform samples over the grid's box
  std::uint64_t seed = 0;
  int threads = 0;
  // After this time numbers get the finest quantum only (no more trials).
  std::optional<std::chrono::steady_clock::time_point> deadline;
};

struct TidyResult {
  std::vector<Solid> solids;  // in the mesh's coordinates, in the tree's leaf order
  long long error_before = 0, error_after = 0;  // wrong samples
  int axes_snapped = 0;
  int values_rounded = 0;  // numbers that became coarser than the finest quantum
  int angles_rounded = 0;  // solids turned to angles of whole, half or tenth degrees
  bool stopped = false;    // the deadline passed before every number was tried
};

// The free ends of the solids that chains cut away (cylinders along their axis, boxes along
// each of their axes) pushed `distance` further out wherever that leaves the error on the grid
// as it is: a hole cut through the part with room to spare, as a CAD user draws it, rather than
// one that ends on the part's face, which fuzzy refinement would blur into a skin.
// Returns the number of ends moved.
int extend_cutters(std::vector<Chain>& chains, const LabelGrid& grid, double distance,
                   int threads = 0);

// `tree`: crisp, its leaves solids in the normalised box (normalisation: mesh -> box), judged
// against `target` at uniform samples over `grid`'s box (both in the same box).
TidyResult tidy_solids(const Tree& tree, const Similarity& normalisation, const Target& target,
                       const LabelGrid& grid, const TidyOptions& options = {});

}  // namespace fuzzycsg::convert
