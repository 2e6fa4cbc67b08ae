#include "convert/tidy.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <utility>

namespace fuzzycsg::convert {

namespace {

// The world axis (0, 1, 2) and sign that `v` (unit) is within `max_deg` of, if any.
std::optional<std::pair<int, double>> near_axis(const Eigen::Vector3d& v, double max_deg) {
  int axis = 0;
  v.cwiseAbs().maxCoeff(&axis);
  const double angle = std::acos(std::min(1.0, std::abs(v[axis]))) * kDegreesPerRadian;
  if (angle > max_deg) return std::nullopt;
  return std::pair{axis, v[axis] < 0 ? -1.0 : 1.0};
}

// The solid with the given rotation; a prism's polygon keeps its place in the world (its
// vertices in the new frame, their height dropped).
Solid turned(const Solid& s, const Eigen::Matrix3d& rotation) {
  Solid out = s;
  out.rotation = rotation;
  if (s.kind == SolidKind::kPrism) {
    const Eigen::Matrix3d turn = rotation.transpose() * s.rotation;
    for (Eigen::Vector2d& v : out.polygon) {
      v = (turn * Eigen::Vector3d(v.x(), v.y(), 0.0)).head<2>();
    }
  }
  return out;
}

// The solid with its axes on the world's, or nullopt when they are not within `max_deg`.
std::optional<Solid> axis_snapped(const Solid& s, double max_deg) {
  Solid out = s;
  switch (s.kind) {
    case SolidKind::kBox: {
      std::array<bool, 3> used{false, false, false};
      for (int c = 0; c < 3; ++c) {
        const auto a = near_axis(s.rotation.col(c), max_deg);
        if (!a || used[static_cast<std::size_t>(a->first)]) return std::nullopt;
        used[static_cast<std::size_t>(a->first)] = true;
        out.size[a->first] = s.size[c];
      }
      out.rotation.setIdentity();
      break;
    }
    case SolidKind::kCylinder:
    case SolidKind::kCone:
    case SolidKind::kTorus:
    case SolidKind::kHalfSpace: {
      const auto a = near_axis(s.rotation.col(2), max_deg);
      if (!a) return std::nullopt;
      double sign = a->second;
      // A cylinder's or a torus's axis has no direction; a cone's radii swap ends instead.
      if (s.kind == SolidKind::kCone && sign < 0) std::swap(out.size[0], out.size[1]);
      if (s.kind != SolidKind::kHalfSpace) sign = 1.0;
      out.rotation = rotation_with_z(sign * Eigen::Vector3d::Unit(a->first));
      break;
    }
    case SolidKind::kPrism: {
      const auto a = near_axis(s.rotation.col(2), max_deg);
      if (!a) return std::nullopt;
      const Eigen::Vector3d axis = a->second * Eigen::Vector3d::Unit(a->first);
      if ((s.rotation.col(2) - axis).norm() < 1e-12) return std::nullopt;
      return turned(s, rotation_with_z(axis));
    }
    case SolidKind::kSphere:
      return std::nullopt;
  }
  if (out.rotation.isApprox(s.rotation, 1e-12)) return std::nullopt;  // already on the axes
  return out;
}

// The numbers of a solid that are rounded: pointers into it, with whether each must stay > 0.
std::vector<std::pair<double*, bool>> numbers_of(Solid& s) {
  std::vector<std::pair<double*, bool>> out;
  switch (s.kind) {
    case SolidKind::kBox:
      for (int a = 0; a < 3; ++a) out.emplace_back(&s.size[a], true);
      break;
    case SolidKind::kCylinder:
      out.emplace_back(&s.size[0], true);
      out.emplace_back(&s.size[2], true);
      break;
    case SolidKind::kCone:
      out.emplace_back(&s.size[0], false);
      out.emplace_back(&s.size[1], false);
      out.emplace_back(&s.size[2], true);
      break;
    case SolidKind::kSphere:
      out.emplace_back(&s.size[0], true);
      break;
    case SolidKind::kTorus:
      out.emplace_back(&s.size[0], true);
      out.emplace_back(&s.size[1], true);
      break;
    case SolidKind::kPrism:
      out.emplace_back(&s.size[2], true);
      for (Eigen::Vector2d& v : s.polygon) {
        out.emplace_back(&v.x(), false);
        out.emplace_back(&v.y(), false);
      }
      break;
    case SolidKind::kHalfSpace:
      out.emplace_back(&s.size[0], false);
      return out;  // no centre
  }
  for (int a = 0; a < 3; ++a) out.emplace_back(&s.centre[a], false);
  return out;
}

// The solid turned so that the angles OpenSCAD reads are multiples of `quantum` degrees: a
// half-space's normal as the tilt from z and the turn about it that the export writes
// (rotate([0, ay, az])), another solid's Euler angles (rotate([ax, ay, az])). nullopt for a
// sphere, a solid on the world's axes, or angles already on the quantum.
std::optional<Solid> angles_rounded(const Solid& s, double quantum) {
  const auto round = [&](double a) { return std::round(a / quantum) * quantum; };
  if (s.kind == SolidKind::kSphere) return std::nullopt;
  if (s.kind == SolidKind::kHalfSpace) {
    const Eigen::Vector3d n = s.normal();
    const double ay = std::acos(std::clamp(n[2], -1.0, 1.0)) * kDegreesPerRadian;
    const double az = std::atan2(n[1], n[0]) * kDegreesPerRadian;
    const double ry = round(ay) / kDegreesPerRadian, rz = round(az) / kDegreesPerRadian;
    const Eigen::Vector3d m(std::sin(ry) * std::cos(rz), std::sin(ry) * std::sin(rz), std::cos(ry));
    if ((m - n).norm() < 1e-12) return std::nullopt;
    return turned(s, rotation_with_z(m));
  }
  const Eigen::Vector3d e = euler_xyz_degrees(s.rotation);
  const Eigen::Vector3d r(round(e[0]), round(e[1]), round(e[2]));
  if ((r - e).cwiseAbs().maxCoeff() < 1e-9) return std::nullopt;
  return turned(s, rotation_from_euler_degrees(r));
}

class Tidier {
 public:
  Tidier(const Tree& tree, const Similarity& normalisation, const Target& target,
         const LabelGrid& grid, const TidyOptions& options)
      : tree_(tree),
        normalisation_(normalisation),
        scorer_(sample_scorer(target, grid, options.points, options.seed)),
        options_(options) {
    const long long inside = static_cast<long long>(scorer_.inside());
    step_ = static_cast<long long>(options.step_tolerance * static_cast<double>(inside));
    total_ = static_cast<long long>(options.total_tolerance * static_cast<double>(inside));
  }

  long long error(const std::vector<Solid>& mesh_solids) const {
    std::vector<Solid> box;
    box.reserve(mesh_solids.size());
    for (const Solid& s : mesh_solids) box.push_back(s.mapped(normalisation_));
    return scorer_.error(tree_with_solids(tree_, box, tree_.domain_or_default()), options_.threads);
  }

  // Keeps `candidate` in place of solids[i] when the error allows it.
  bool try_solid(std::vector<Solid>& solids, std::size_t i, const Solid& candidate) {
    const Solid old = solids[i];
    solids[i] = candidate;
    const long long e = error(solids);
    if (e <= current_ + step_ && e <= before_ + total_) {
      current_ = e;
      return true;
    }
    solids[i] = old;
    return false;
  }

  void set_before(long long e) { before_ = current_ = e; }
  long long current() const { return current_; }

 private:
  const Tree& tree_;
  Similarity normalisation_;
  GridScorer scorer_;
  TidyOptions options_;
  long long step_ = 0, total_ = 0, before_ = 0, current_ = 0;
};

}  // namespace

int extend_cutters(std::vector<Chain>& chains, const LabelGrid& grid, double distance,
                   int threads) {
  const GridScorer scorer(grid);
  long long error = scorer.error(chains_tree(chains), threads);
  int moved = 0;
  for (Chain& chain : chains) {
    for (ChainStep& step : chain.steps) {
      if (step.move != Move::kDifference) continue;
      const SolidKind kind = step.solid.kind;
      if (kind != SolidKind::kCylinder && kind != SolidKind::kBox && kind != SolidKind::kPrism) {
        continue;
      }
      // Local axes that have ends: a cylinder's and a prism's own; a box's three.
      const int first = kind == SolidKind::kBox ? 0 : 2;
      for (int axis = first; axis < 3; ++axis) {
        for (const double side : {-1.0, 1.0}) {
          const Solid old = step.solid;
          step.solid.size[axis] += distance;
          step.solid.centre += 0.5 * distance * side * old.rotation.col(axis);
          const long long e = scorer.error(chains_tree(chains), threads);
          if (e <= error) {
            error = e;
            ++moved;
          } else {
            step.solid = old;
          }
        }
      }
    }
  }
  return moved;
}

TidyResult tidy_solids(const Tree& tree, const Similarity& normalisation, const Target& target,
                       const LabelGrid& grid, const TidyOptions& options) {
  TidyResult result;
  const Similarity to_mesh = normalisation.inverse();
  for (const Solid& s : tree_solids(tree)) result.solids.push_back(s.mapped(to_mesh));
  std::vector<Solid>& solids = result.solids;

  Tidier tidier(tree, normalisation, target, grid, options);
  result.error_before = tidier.error(solids);
  tidier.set_before(result.error_before);
  result.error_after = result.error_before;
  if (!options.enabled) return result;

  for (std::size_t i = 0; i < solids.size(); ++i) {
    if (const std::optional<Solid> s = axis_snapped(solids[i], options.snap_angle_deg)) {
      result.axes_snapped += tidier.try_solid(solids, i, *s) ? 1 : 0;
    }
  }
  // Angles off the axes: to whole degrees where the error allows, else halves, tenths, and a
  // thousandth of a degree at least.
  for (std::size_t i = 0; i < solids.size(); ++i) {
    bool done = false;
    for (const double quantum : {1.0, 0.5, 0.1}) {
      const std::optional<Solid> s = angles_rounded(solids[i], quantum);
      if (!s || tidier.try_solid(solids, i, *s)) {
        result.angles_rounded += s ? 1 : 0;
        done = true;
        break;
      }
    }
    if (!done) {
      if (const std::optional<Solid> s = angles_rounded(solids[i], 0.001)) solids[i] = *s;
    }
  }

  // The quanta, coarse to fine, from a tenth of the part's size (the grid's long side) down.
  const double extent = grid.cell *
                        static_cast<double>(std::max({grid.n[0], grid.n[1], grid.n[2]})) /
                        normalisation.scale;
  const double top = std::pow(10.0, std::floor(std::log10(extent)) - 1.0);
  const std::array<double, 5> quanta{top, top / 2, top / 10, top / 20, top / 100};
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const std::size_t count = numbers_of(solids[i]).size();
    for (std::size_t k = 0; k < count; ++k) {
      bool done = false;
      const bool late = options.deadline && std::chrono::steady_clock::now() > *options.deadline;
      result.stopped = result.stopped || late;
      for (std::size_t q = 0; q + 1 < quanta.size() && !done && !late; ++q) {
        Solid candidate = solids[i];
        const auto [value, positive] = numbers_of(candidate)[k];
        const double rounded = std::round(*value / quanta[q]) * quanta[q];
        if (positive && rounded <= 0) continue;
        if (rounded == *value) {
          done = true;
          break;
        }
        *value = rounded;
        if (tidier.try_solid(solids, i, candidate)) {
          ++result.values_rounded;
          done = true;
        }
      }
      if (done) continue;
      // The finest quantum always: a thousandth of the part, far below the grid's cell.
      const auto [value, positive] = numbers_of(solids[i])[k];
      const double rounded = std::round(*value / quanta.back()) * quanta.back();
      if (!positive || rounded > 0) *value = rounded;
    }
  }
  result.error_after = tidier.error(solids);
  return result;
}

}  // namespace fuzzycsg::convert
