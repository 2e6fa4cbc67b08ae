#include "convert/surface_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace fuzzycsg::convert::detail {

namespace {

using Eigen::Vector3d;

// The component of v perpendicular to the unit d, and its length.
Vector3d perpendicular(const Vector3d& v, const Vector3d& d) { return v - v.dot(d) * d; }

// A unit vector perpendicular to the unit d.
Vector3d any_perpendicular(const Vector3d& d) {
  Vector3d u, w;
  orthonormal_basis(d, u, w);
  return u;
}

int parameter_count(SurfaceKind kind) {
  switch (kind) {
    case SurfaceKind::kSphere:
      return 4;
    case SurfaceKind::kCylinder:
      return 5;
    case SurfaceKind::kCone:
      return 6;
    case SurfaceKind::kTorus:
      return 7;
    case SurfaceKind::kPlane:
      break;
  }
  return 0;
}

// Whether parameter j of the kind is a length (else an angle or a direction's tangent step).
bool is_length(SurfaceKind kind, int j) {
  switch (kind) {
    case SurfaceKind::kSphere:
      return true;
    case SurfaceKind::kCylinder:
      return j >= 2;
    case SurfaceKind::kCone:
      return j >= 2 && j <= 4;
    case SurfaceKind::kTorus:
      return j >= 2;
    case SurfaceKind::kPlane:
      break;
  }
  return true;
}

// `base` moved by the parameter step x (parameter_count(kind) values): the axis turned in the
// tangent plane of its direction, the point moved, the radii and angle changed.
Surface step(const Surface& base, const double* x) {
  Surface s = base;
  if (base.kind == SurfaceKind::kSphere) {
    s.point += Vector3d(x[0], x[1], x[2]);
    s.radius += x[3];
    return s;
  }
  Vector3d u, w;
  orthonormal_basis(base.direction, u, w);
  s.direction = (base.direction + x[0] * u + x[1] * w).normalized();
  switch (base.kind) {
    case SurfaceKind::kCylinder:
      s.point += x[2] * u + x[3] * w;
      s.radius += x[4];
      break;
    case SurfaceKind::kCone:
      s.point += Vector3d(x[2], x[3], x[4]);
      s.half_angle += x[5];
      break;
    case SurfaceKind::kTorus:
      s.point += Vector3d(x[2], x[3], x[4]);
      s.radius += x[5];
      s.minor_radius += x[6];
      break;
    default:
      break;
  }
  return s;
}

double weighted_cost(const Surface& s, const WeightedPoints& data, Eigen::VectorXd& residuals) {
  const std::size_t n = data.points.size();
  residuals.resize(static_cast<Eigen::Index>(n));
  double cost = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = signed_distance(s, data.points[i]);
    residuals[static_cast<Eigen::Index>(i)] = r;
    cost += data.weights[i] * r * r;
  }
  return cost;
}

bool valid(const Surface& s, double length) {
  const bool finite = s.point.allFinite() && s.direction.allFinite() && std::isfinite(s.radius) &&
                      std::isfinite(s.minor_radius) && std::isfinite(s.half_angle);
  if (!finite) return false;
  constexpr double kTenth = 0.1 * std::numbers::pi / 180;
  switch (s.kind) {
    case SurfaceKind::kSphere:
    case SurfaceKind::kCylinder:
      return s.radius > 0 && s.radius < 1000 * length;
    case SurfaceKind::kCone:
      return s.half_angle > kTenth && s.half_angle < std::numbers::pi / 2 - kTenth &&
             s.point.norm() < 1e6 * length;
    case SurfaceKind::kTorus:
      return s.radius > 0 && s.minor_radius > 0 && s.radius < 1000 * length &&
             s.minor_radius < 1000 * length;
    case SurfaceKind::kPlane:
      return true;
  }
  return false;
}

}  // namespace

void orthonormal_basis(const Vector3d& d, Vector3d& u, Vector3d& w) {
  // The axis least aligned with d, made perpendicular.
  Vector3d a = Vector3d::UnitX();
  if (std::abs(d.y()) < std::abs(d.x()) && std::abs(d.y()) <= std::abs(d.z())) {
    a = Vector3d::UnitY();
  } else if (std::abs(d.z()) < std::abs(d.x()) && std::abs(d.z()) < std::abs(d.y())) {
    a = Vector3d::UnitZ();
  }
  u = perpendicular(a, d).normalized();
  w = d.cross(u);
}

double signed_distance(const Surface& s, const Vector3d& x) {
  const Vector3d v = x - s.point;
  switch (s.kind) {
    case SurfaceKind::kPlane:
      return v.dot(s.direction);
    case SurfaceKind::kSphere:
      return v.norm() - s.radius;
    case SurfaceKind::kCylinder:
      return perpendicular(v, s.direction).norm() - s.radius;
    case SurfaceKind::kCone: {
      const double h = v.dot(s.direction);
      const double rho = (v - h * s.direction).norm();
      return rho * std::cos(s.half_angle) - h * std::sin(s.half_angle);
    }
    case SurfaceKind::kTorus: {
      const double h = v.dot(s.direction);
      const double rho = (v - h * s.direction).norm();
      return std::hypot(rho - s.radius, h) - s.minor_radius;
    }
  }
  return 0;
}

Vector3d radial_normal(const Surface& s, const Vector3d& x) {
  const Vector3d v = x - s.point;
  switch (s.kind) {
    case SurfaceKind::kPlane:
      return s.direction;
    case SurfaceKind::kSphere: {
      const double n = v.norm();
      return n > 0 ? Vector3d(v / n) : Vector3d::UnitZ();
    }
    case SurfaceKind::kCylinder: {
      const Vector3d p = perpendicular(v, s.direction);
      const double n = p.norm();
      return n > 0 ? Vector3d(p / n) : any_perpendicular(s.direction);
    }
    case SurfaceKind::kCone: {
      const Vector3d p = perpendicular(v, s.direction);
      const double n = p.norm();
      const Vector3d e = n > 0 ? Vector3d(p / n) : any_perpendicular(s.direction);
      return std::cos(s.half_angle) * e - std::sin(s.half_angle) * s.direction;
    }
    case SurfaceKind::kTorus: {
      const double h = v.dot(s.direction);
      const Vector3d p = v - h * s.direction;
      const double n = p.norm();
      const Vector3d e = n > 0 ? Vector3d(p / n) : any_perpendicular(s.direction);
      const Vector3d q = (n - s.radius) * e + h * s.direction;
      const double qn = q.norm();
      return qn > 0 ? Vector3d(q / qn) : e;
    }
  }
  return Vector3d::UnitZ();
}

Surface fit_plane(const WeightedPoints& data, const Vector3d& hint) {
  double total = 0;
  Vector3d centroid = Vector3d::Zero();
  for (std::size_t i = 0; i < data.points.size(); ++i) {
    total += data.weights[i];
    centroid += data.weights[i] * data.points[i];
  }
  centroid /= total;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < data.points.size(); ++i) {
    const Vector3d v = data.points[i] - centroid;
    covariance += data.weights[i] * v * v.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Vector3d normal = solver.eigenvectors().col(0).normalized();
  if (normal.dot(hint) < 0) normal = -normal;
  Surface s;
  s.kind = SurfaceKind::kPlane;
  s.point = centroid;
  s.direction = normal;
  return s;
}

bool refine_fit(Surface& s, const WeightedPoints& data, double length) {
  const int k = parameter_count(s.kind);
  if (k == 0 || data.points.empty()) return false;
  const auto n = static_cast<Eigen::Index>(data.points.size());
  Eigen::VectorXd weights(n);
  for (Eigen::Index i = 0; i < n; ++i) weights[i] = data.weights[static_cast<std::size_t>(i)];

  Eigen::VectorXd residuals, trial_residuals, shifted;
  double cost = weighted_cost(s, data, residuals);
  double lambda = 1e-3;
  Eigen::MatrixXd jacobian(n, k);
  double x[7] = {0, 0, 0, 0, 0, 0, 0};
  for (int iteration = 0; iteration < 60; ++iteration) {
    // Forward differences, the steps scaled to lengths or angles.
    for (int j = 0; j < k; ++j) {
      const double h = is_length(s.kind, j) ? 1e-7 * length : 1e-7;
      std::fill(x, x + 7, 0.0);
      x[j] = h;
      weighted_cost(step(s, x), data, shifted);
      jacobian.col(j) = (shifted - residuals) / h;
    }
    const Eigen::MatrixXd jtw = jacobian.transpose() * weights.asDiagonal();
    const Eigen::MatrixXd normal_matrix = jtw * jacobian;
    const Eigen::VectorXd gradient = jtw * residuals;
    bool accepted = false;
    double previous = cost;
    for (int attempt = 0; attempt < 12 && !accepted; ++attempt) {
      Eigen::MatrixXd damped = normal_matrix;
      for (int j = 0; j < k; ++j) {
        damped(j, j) += lambda * normal_matrix(j, j) + 1e-15 * (1 + normal_matrix(j, j));
      }
      const Eigen::VectorXd delta = damped.ldlt().solve(-gradient);
      if (!delta.allFinite()) {
        lambda *= 10;
        continue;
      }
      for (int j = 0; j < k; ++j) x[j] = delta[j];
      const Surface trial = step(s, x);
      const double trial_cost = weighted_cost(trial, data, trial_residuals);
      if (std::isfinite(trial_cost) && trial_cost < cost) {
        s = trial;
        cost = trial_cost;
        residuals = trial_residuals;
        lambda = std::max(lambda * 0.3, 1e-12);
        accepted = true;
      } else {
        lambda *= 10;
      }
    }
    if (!accepted || previous - cost <= 1e-14 * previous + 1e-300) break;
  }
  if (s.kind == SurfaceKind::kTorus) s.minor_radius = std::abs(s.minor_radius);
  return valid(s, length);
}

}  // namespace fuzzycsg::convert::detail
