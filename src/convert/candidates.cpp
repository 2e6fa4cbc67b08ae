#include "convert/candidates.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fuzzycsg::convert {

namespace {

Eigen::Vector3d vec(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

// Extent of the mesh along a unit direction, from a point.
std::pair<double, double> extent_along(const TriangleMesh& mesh, const Eigen::Vector3d& point,
                                       const Eigen::Vector3d& direction) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& v : mesh.vertices) {
    const double t = direction.dot(vec(v) - point);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  return {lo, hi};
}

struct Direction {
  Eigen::Vector3d axis;
  double weight = 0;
};

// Directions up to sign, weighted by the area of the surfaces that give them.
std::vector<Direction> directions(const std::vector<Surface>& surfaces, double cos_tol) {
  std::vector<Direction> out;
  for (const Surface& s : surfaces) {
    if (s.kind == SurfaceKind::kSphere) continue;
    Eigen::Vector3d d = s.direction.normalized();
    bool merged = false;
    for (Direction& o : out) {
      if (std::abs(o.axis.dot(d)) >= cos_tol) {
        o.weight += s.area;
        merged = true;
        break;
      }
    }
    if (!merged) out.push_back({d, s.area});
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Direction& a, const Direction& b) { return a.weight > b.weight; });
  return out;
}

// The closest offsets below `t0` and above `t1` among `offsets` (within `slack` inside).
void caps_from_planes(const std::vector<double>& offsets, double t0, double t1, double slack,
                      std::vector<double>& lows, std::vector<double>& highs) {
  double below = -std::numeric_limits<double>::infinity();
  double above = std::numeric_limits<double>::infinity();
  for (const double t : offsets) {
    if (t <= t0 + slack && t > below) below = t;
    if (t >= t1 - slack && t < above) above = t;
  }
  if (std::isfinite(below)) lows.push_back(below);
  if (std::isfinite(above)) highs.push_back(above);
}

void dedupe(std::vector<double>& v, double eps) {
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  for (const double x : v) {
    if (out.empty() || x - out.back() > eps) out.push_back(x);
  }
  v = std::move(out);
}

// Cylinders or cones around an axis surface, with caps at the support's ends, at the nearest
// planes across the axis and through the whole part.
void axial_solids(const Surface& s, const TriangleMesh& mesh, const std::vector<Surface>& planes,
                  double cos_tol, double margin, std::vector<Solid>& out) {
  const Eigen::Vector3d axis = s.direction.normalized();
  std::vector<double> across;
  for (const Surface& p : planes) {
    if (std::abs(p.direction.normalized().dot(axis)) >= cos_tol)
      across.push_back(axis.dot(p.point - s.point));
  }
  const auto [m0, m1] = extent_along(mesh, s.point, axis);
  std::vector<double> lows{s.axial_min, m0 - margin}, highs{s.axial_max, m1 + margin};
  caps_from_planes(across, s.axial_min, s.axial_max, 0.05 * (s.axial_max - s.axial_min), lows,
                   highs);
  const double eps = 1e-6 * std::max(1.0, m1 - m0);
  dedupe(lows, eps);
  dedupe(highs, eps);
  for (const double t0 : lows) {
    for (const double t1 : highs) {
      if (t1 - t0 <= eps) continue;
      Solid c;
      c.rotation = rotation_with_z(axis);
      c.centre = s.point + 0.5 * (t0 + t1) * axis;
      if (s.kind == SurfaceKind::kCylinder) {
        c.kind = SolidKind::kCylinder;
        c.size = {s.radius, s.radius, t1 - t0};
      } else {
        // A cone opens along +axis from its apex at s.point: r(t) = t tan(half_angle).
        const double a0 = std::max(t0, 0.0), k = std::tan(s.half_angle);
        if (t1 - a0 <= eps) continue;
        c.kind = SolidKind::kCone;
        c.centre = s.point + 0.5 * (a0 + t1) * axis;
        c.size = {a0 * k, t1 * k, t1 - a0};
      }
      out.push_back(c);
    }
  }
}

}  // namespace

std::string describe_surface(const Surface& s) {
  const auto v = [](const Eigen::Vector3d& x) {
    return fmt::format("({:.4g}, {:.4g}, {:.4g})", x[0], x[1], x[2]);
  };
  std::string text(surface_kind_name(s.kind));
  switch (s.kind) {
    case SurfaceKind::kPlane:
      text += fmt::format(" normal {} offset {:.4g}", v(s.direction), s.direction.dot(s.point));
      break;
    case SurfaceKind::kCylinder:
      text += fmt::format(" r {:.4g} axis {} through {}", s.radius, v(s.direction), v(s.point));
      break;
    case SurfaceKind::kSphere:
      text += fmt::format(" r {:.4g} centre {}", s.radius, v(s.point));
      break;
    case SurfaceKind::kCone:
      text += fmt::format(" half-angle {:.4g} deg axis {} apex {}",
                          s.half_angle * 180.0 / std::numbers::pi, v(s.direction), v(s.point));
      break;
    case SurfaceKind::kTorus:
      text += fmt::format(" r {:.4g} / {:.4g} axis {} centre {}", s.radius, s.minor_radius,
                          v(s.direction), v(s.point));
      break;
  }
  if (s.kind != SurfaceKind::kPlane && !s.outward) text += ", inward";
  text += fmt::format(", area {:.4g}", s.area);
  return text;
}

Eigen::Matrix3d dominant_frame(const std::vector<Surface>& surfaces, double tolerance_deg) {
  const double tol = tolerance_deg * std::numbers::pi / 180.0;
  const std::vector<Direction> dirs = directions(surfaces, std::cos(tol));
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
  if (dirs.empty()) return frame;
  const Eigen::Vector3d d1 = dirs[0].axis;
  Eigen::Vector3d d2 = Eigen::Vector3d::Zero();
  for (std::size_t i = 1; i < dirs.size(); ++i) {
    if (std::abs(dirs[i].axis.dot(d1)) <= std::sin(tol)) {
      d2 = dirs[i].axis;
      break;
    }
  }
  if (d2.isZero()) {
    // No second direction across the first: the world axis most across it.
    Eigen::Index k = 0;
    d1.cwiseAbs().minCoeff(&k);
    d2 = Eigen::Vector3d::Unit(k);
  }
  d2 = (d2 - d2.dot(d1) * d1).normalized();
  frame.col(0) = d1;
  frame.col(1) = d2;
  frame.col(2) = d1.cross(d2);
  // Within the tolerance of the world's axes (up to order and sign): the world's.
  bool world = true;
  for (int c = 0; c < 3; ++c) world = world && frame.col(c).cwiseAbs().maxCoeff() >= std::cos(tol);
  if (world) return Eigen::Matrix3d::Identity();
  // Order the axes as the world's closest ones, so that boxes read naturally.
  Eigen::Matrix3d ordered = frame;
  for (int c = 0; c < 3; ++c) {
    Eigen::Index k = 0;
    frame.col(c).cwiseAbs().maxCoeff(&k);
    ordered.col(k) = frame.col(c) * (frame(k, c) < 0 ? -1.0 : 1.0);
  }
  if (std::abs(ordered.determinant() - 1.0) < 1e-6) return ordered;
  return frame;
}

Eigen::AlignedBox3d frame_bounds(const TriangleMesh& mesh, const Eigen::Matrix3d& frame) {
  Eigen::AlignedBox3d box;
  for (const auto& v : mesh.vertices) box.extend(frame.transpose() * vec(v));
  return box;
}

Candidates propose_candidates(const std::vector<Surface>& surfaces, const TriangleMesh& mesh,
                              const Eigen::Matrix3d& frame, const CandidateOptions& options) {
  const double cos_tol = std::cos(options.tolerance_deg * std::numbers::pi / 180.0);
  const Eigen::AlignedBox3d bounds = frame_bounds(mesh, frame);
  const double size = bounds.sizes().maxCoeff();
  const double margin = options.through * size;
  Candidates c;
  std::vector<Surface> planes;
  for (const Surface& s : surfaces) {
    if (s.kind == SurfaceKind::kPlane) planes.push_back(s);
  }
  for (int a = 0; a < 3; ++a) {
    auto& offsets = c.box_offsets[static_cast<std::size_t>(a)];
    offsets = {bounds.min()[a], bounds.max()[a], bounds.min()[a] - margin,
               bounds.max()[a] + margin};
  }
  for (const Surface& p : planes) {
    const Eigen::Vector3d n = p.direction.normalized();
    bool aligned = false;
    for (int a = 0; a < 3; ++a) {
      if (std::abs(n.dot(frame.col(a))) >= cos_tol) {
        c.box_offsets[static_cast<std::size_t>(a)].push_back(frame.col(a).dot(p.point));
        aligned = true;
      }
    }
    if (!aligned) {
      Solid h;
      h.kind = SolidKind::kHalfSpace;
      h.rotation = rotation_with_z(n);
      h.size = {n.dot(p.point), 0, 0};
      c.solids.push_back(h);
    }
  }
  for (auto& offsets : c.box_offsets) dedupe(offsets, 1e-6 * size);
  for (const Surface& s : surfaces) {
    switch (s.kind) {
      case SurfaceKind::kPlane:
        break;
      case SurfaceKind::kCylinder:
      case SurfaceKind::kCone:
        axial_solids(s, mesh, planes, cos_tol, margin, c.solids);
        break;
      case SurfaceKind::kSphere: {
        Solid b;
        b.kind = SolidKind::kSphere;
        b.centre = s.point;
        b.size = {s.radius, 0, 0};
        c.solids.push_back(b);
        break;
      }
      case SurfaceKind::kTorus: {
        Solid t;
        t.kind = SolidKind::kTorus;
        t.rotation = rotation_with_z(s.direction);
        t.centre = s.point;
        t.size = {s.radius, s.minor_radius, 0};
        c.solids.push_back(t);
        break;
      }
    }
  }
  prism_solids(surfaces, mesh, frame, bounds, margin, cos_tol, c.solids);
  return c;
}

}  // namespace fuzzycsg::convert
