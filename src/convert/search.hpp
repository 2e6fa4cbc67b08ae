#pragma once
// The crisp structure search of convert: on a grid of cells labelled inside or outside the
// target, a chain of boolean moves ((((A ∪ B) \ C) ∩ D) ...) of candidate solids chosen
// greedily by the number of cells each move puts right, in the manner of Gibson et al.'s
// discrete search (1997) but in 3D and over solids proposed from the target's surfaces.
//
// Boxes aligned with the grid's frame are not listed one by one: their faces are taken from
// offsets along each axis (the detected planes), every pair of offsets per axis, and a box's
// gain is read from summed-area tables of the move's per-cell gains in O(1). Other solids
// (cylinders, spheres, cones, tori, half-spaces, boxes in other frames) are listed with the
// cells whose centres they contain.

#include <Eigen/Core>
#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "convert/solid.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg::convert {

// Cells of a box laid along a frame. A cell's label: 0 outside the target, 1 inside, 2 not
// counted (another component's).
struct LabelGrid {
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();  // columns: the grid's axes (world)
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();     // frame coordinates of the low corner
  double cell = 1.0;
  std::array<int, 3> n{0, 0, 0};
  std::vector<std::uint8_t> label;  // x fastest

  std::size_t size() const { return label.size(); }
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(n[1]) +
            static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(n[0]) +
           static_cast<std::size_t>(i);
  }
  Eigen::Vector3d centre_frame(int i, int j, int k) const {
    return origin + cell * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
  }
  Eigen::Vector3d centre_world(int i, int j, int k) const { return frame * centre_frame(i, j, k); }
  std::size_t count(std::uint8_t value) const;
};

// The grid over `bounds` (frame coordinates) grown by `margin_cells` on every side, with
// `resolution` cells along its longest side, labelled by the target's occupancy at cell
// centres.
LabelGrid make_label_grid(const Target& target, const Eigen::Matrix3d& frame,
                          const Eigen::AlignedBox3d& bounds, int resolution, int margin_cells);

// The components of the inside cells (6-connected) of at least `min_cells` cells, each as a
// grid of its own: its box of cells grown by `margin_cells`, where the cells of the other
// components are not counted. Components smaller than min_cells are dropped; their cells are
// counted in `dropped_cells`.
std::vector<LabelGrid> split_components(const LabelGrid& grid, std::size_t min_cells,
                                        int margin_cells, std::size_t& dropped_cells);

// What the search chooses from.
struct Candidates {
  // Frame coordinates of box faces along each axis of the grid's frame.
  std::array<std::vector<double>, 3> box_offsets;
  std::vector<Solid> solids;  // world coordinates
};

enum class Move { kUnion, kDifference, kIntersection };
std::string_view move_name(Move move);

struct ChainStep {
  Move move = Move::kUnion;
  Solid solid;
  long long gain = 0;  // cells put right when the step was chosen
};

struct Chain {
  std::vector<ChainStep> steps;
  long long error = 0;   // counted cells labelled differently from the chain's solid
  long long inside = 0;  // counted inside cells
};

struct SearchOptions {
  int max_steps = 32;            // moves in a chain
  double min_gain = 5e-4;        // a move must put right this fraction of the inside cells ...
  long long min_gain_cells = 8;  // ... and at least this many
  // Restarts after the first, greedy, one: each picks at random among the moves within
  // `tolerance` of the best gain.
  int restarts = 7;
  double tolerance = 0.15;
  int top_moves = 4;  // the moves a restart chooses among
  // Descents that start from each of this many first moves (the unions of the listed solids and
  // of the best frame box, best first), whatever their gain.
  int first_moves = 16;
  // A difference or intersection may take away at most this fraction of the target's cells
  // that the chain holds (more undoes the chain instead of carving it).
  double max_loss = 0.5;
  std::uint64_t seed = 0;
  // No step starts after this time (the first step of the greedy descent excepted): the chains
  // end where they are. Set, the result depends on the machine's speed.
  std::optional<std::chrono::steady_clock::time_point> deadline;
};

// The best chain over the restarts (fewest wrong cells plus min_gain cells a step), with steps
// that no longer pay for themselves removed. Deterministic for a seed, whatever the threads.
Chain search_chain(const LabelGrid& grid, const Candidates& candidates,
                   const SearchOptions& options);

// The counted cells a chain gets wrong on a grid.
long long chain_error(const LabelGrid& grid, const std::vector<ChainStep>& steps);

}  // namespace fuzzycsg::convert
