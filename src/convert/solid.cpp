#include "convert/solid.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <numbers>

#include "fuzzycsg/core/placement.hpp"

namespace fuzzycsg::convert {

namespace {

std::string number(double v) { return fmt::format("{:.4g}", v); }

// Even-odd rule: the polygon's inside, for any simple polygon.
bool in_polygon(const std::vector<Eigen::Vector2d>& polygon, double x, double y) {
  bool inside = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[j];
    if ((a.y() > y) != (b.y() > y) && x < (b.x() - a.x()) * (y - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

}  // namespace

std::string_view solid_kind_name(SolidKind kind) {
  switch (kind) {
    case SolidKind::kBox:
      return "box";
    case SolidKind::kCylinder:
      return "cylinder";
    case SolidKind::kCone:
      return "cone";
    case SolidKind::kSphere:
      return "sphere";
    case SolidKind::kTorus:
      return "torus";
    case SolidKind::kHalfSpace:
      return "half-space";
    case SolidKind::kPrism:
      return "prism";
  }
  return "?";
}

bool Solid::contains(const Eigen::Vector3d& p) const {
  if (kind == SolidKind::kHalfSpace) return normal().dot(p) <= size[0];
  const Eigen::Vector3d q = rotation.transpose() * (p - centre);
  switch (kind) {
    case SolidKind::kBox:
      return std::abs(q[0]) <= 0.5 * size[0] && std::abs(q[1]) <= 0.5 * size[1] &&
             std::abs(q[2]) <= 0.5 * size[2];
    case SolidKind::kCylinder:
      return std::abs(q[2]) <= 0.5 * size[2] && q[0] * q[0] + q[1] * q[1] <= size[0] * size[0];
    case SolidKind::kCone: {
      if (std::abs(q[2]) > 0.5 * size[2]) return false;
      const double r = size[0] + (size[1] - size[0]) * (q[2] / size[2] + 0.5);
      return q[0] * q[0] + q[1] * q[1] <= r * r;
    }
    case SolidKind::kSphere:
      return q.squaredNorm() <= size[0] * size[0];
    case SolidKind::kTorus: {
      const double rho = std::hypot(q[0], q[1]) - size[0];
      return rho * rho + q[2] * q[2] <= size[1] * size[1];
    }
    case SolidKind::kPrism:
      return std::abs(q[2]) <= 0.5 * size[2] && in_polygon(polygon, q[0], q[1]);
    case SolidKind::kHalfSpace:
      break;
  }
  return false;
}

Eigen::AlignedBox3d Solid::local_bounds() const {
  Eigen::Vector3d h = Eigen::Vector3d::Zero();
  switch (kind) {
    case SolidKind::kBox:
      h = 0.5 * size;
      break;
    case SolidKind::kCylinder:
      h = {size[0], size[0], 0.5 * size[2]};
      break;
    case SolidKind::kCone: {
      const double r = std::max(size[0], size[1]);
      h = {r, r, 0.5 * size[2]};
      break;
    }
    case SolidKind::kSphere:
      h.setConstant(size[0]);
      break;
    case SolidKind::kTorus:
      h = {size[0] + size[1], size[0] + size[1], size[1]};
      break;
    case SolidKind::kPrism: {
      Eigen::AlignedBox3d box;
      for (const Eigen::Vector2d& v : polygon) {
        box.extend(Eigen::Vector3d(v.x(), v.y(), -0.5 * size[2]));
        box.extend(Eigen::Vector3d(v.x(), v.y(), 0.5 * size[2]));
      }
      return box;
    }
    case SolidKind::kHalfSpace:
      return {};
  }
  return {-h, h};
}

Solid Solid::mapped(const Similarity& m) const {
  Solid s = *this;
  const Eigen::Vector3d t(m.translate[0], m.translate[1], m.translate[2]);
  if (kind == SolidKind::kHalfSpace) {
    // n . p <= d  with p = (q - t) / scale:  n . q <= scale d + n . t
    s.size[0] = m.scale * size[0] + normal().dot(t);
    return s;
  }
  s.centre = m.scale * centre + t;
  s.size = m.scale * size;
  for (Eigen::Vector2d& v : s.polygon) v *= m.scale;
  return s;
}

std::string Solid::describe() const {
  const auto at = [&] {
    return fmt::format(" at ({}, {}, {})", number(centre[0]), number(centre[1]), number(centre[2]));
  };
  const Eigen::Vector3d z = rotation.col(2);
  const auto axis = [&] {
    return fmt::format(" axis ({}, {}, {})", number(z[0]), number(z[1]), number(z[2]));
  };
  switch (kind) {
    case SolidKind::kBox:
      return fmt::format("box {} x {} x {}", number(size[0]), number(size[1]), number(size[2])) +
             at();
    case SolidKind::kCylinder:
      return fmt::format("cylinder r {} h {}", number(size[0]), number(size[2])) + at() + axis();
    case SolidKind::kCone:
      return fmt::format("cone r {} to {} h {}", number(size[0]), number(size[1]),
                         number(size[2])) +
             at() + axis();
    case SolidKind::kSphere:
      return fmt::format("sphere r {}", number(size[0])) + at();
    case SolidKind::kTorus:
      return fmt::format("torus {} / {}", number(size[0]), number(size[1])) + at() + axis();
    case SolidKind::kHalfSpace:
      return fmt::format("half-space n ({}, {}, {}) . p <= {}", number(z[0]), number(z[1]),
                         number(z[2]), number(size[0]));
    case SolidKind::kPrism:
      return fmt::format("prism of {} sides h {}", polygon.size(), number(size[2])) + at() + axis();
  }
  return "?";
}

Eigen::Vector3d euler_xyz_degrees(const Eigen::Matrix3d& r) {
  // R = Rz(c) Ry(b) Rx(a): R(2,0) = -sin b, R(2,1) = cos b sin a, R(2,2) = cos b cos a,
  // R(1,0) = sin c cos b, R(0,0) = cos c cos b.
  const double sb = std::clamp(-r(2, 0), -1.0, 1.0);
  const double b = std::asin(sb);
  double a = 0, c = 0;
  if (std::abs(sb) < 1.0 - 1e-12) {
    a = std::atan2(r(2, 1), r(2, 2));
    c = std::atan2(r(1, 0), r(0, 0));
  } else {
    // Gimbal lock: only a - c (b = 90°) or a + c (b = -90°) is determined; take c = 0.
    a = std::atan2(-r(1, 2), r(1, 1));
  }
  return {a * kDegreesPerRadian, b * kDegreesPerRadian, c * kDegreesPerRadian};
}

Eigen::Matrix3d rotation_from_euler_degrees(const Eigen::Vector3d& angles) {
  const std::array<double, 9> m = placement::rotation_3d(angles[0], angles[1], angles[2]);
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r(i, j) = m[static_cast<std::size_t>(i * 3 + j)];
  }
  return r;
}

Eigen::Matrix3d rotation_with_z(const Eigen::Vector3d& axis) {
  const Eigen::Vector3d z = axis.normalized();
  // The world axis least aligned with z gives x; y completes a right-handed frame.
  Eigen::Index k = 0;
  z.cwiseAbs().minCoeff(&k);
  Eigen::Vector3d helper = Eigen::Vector3d::Zero();
  helper[k] = 1.0;
  // Axis-aligned z: keep the frame a permutation of the world's (x stays x where it can).
  if (std::abs(z[0]) < 1e-12 && std::abs(z[1]) < 1e-12) helper = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d x = (helper - helper.dot(z) * z).normalized();
  Eigen::Matrix3d r;
  r.col(0) = x;
  r.col(1) = z.cross(x);
  r.col(2) = z;
  return r;
}

int add_leaf(TreeBuilder& builder, const Solid& s, double sharpness) {
  int leaf = -1;
  const auto numbers = [](std::initializer_list<double> values) {
    return std::vector<Number>(values.begin(), values.end());
  };
  switch (s.kind) {
    case SolidKind::kBox:
      leaf = builder.leaf(PrimitiveType::kBox, numbers({s.size[0], s.size[1], s.size[2]}));
      break;
    case SolidKind::kCylinder:
      leaf = builder.leaf(PrimitiveType::kCylinder, numbers({s.size[0], s.size[2]}));
      break;
    case SolidKind::kCone:
      leaf = builder.leaf(PrimitiveType::kCone, numbers({s.size[0], s.size[1], s.size[2]}));
      break;
    case SolidKind::kSphere:
      leaf = builder.leaf(PrimitiveType::kSphere, numbers({s.size[0]}));
      break;
    case SolidKind::kTorus:
      leaf = builder.leaf(PrimitiveType::kTorus, numbers({s.size[0], s.size[1]}));
      break;
    case SolidKind::kHalfSpace: {
      const Eigen::Vector3d n = s.normal();
      leaf = builder.leaf(PrimitiveType::kPlane, numbers({n[0], n[1], n[2], s.size[0]}));
      break;
    }
    case SolidKind::kPrism: {
      // Straight sides: each segment's Bézier controls at its thirds.
      std::vector<Number> profile;
      const std::size_t n = s.polygon.size();
      for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector2d& a = s.polygon[i];
        const Eigen::Vector2d& b = s.polygon[(i + 1) % n];
        for (const double t : {0.0, 1.0 / 3.0, 2.0 / 3.0}) {
          const Eigen::Vector2d p = a + t * (b - a);
          profile.push_back(p.x());
          profile.push_back(p.y());
        }
      }
      profile.push_back(s.size[2]);
      leaf = builder.leaf(PrimitiveType::kExtrude, std::move(profile));
      break;
    }
  }
  if (s.kind != SolidKind::kHalfSpace) {
    if (!s.centre.isZero(0.0)) {
      builder.translate(leaf, numbers({s.centre[0], s.centre[1], s.centre[2]}));
    }
    const Eigen::Vector3d angles = euler_xyz_degrees(s.rotation);
    if (s.kind != SolidKind::kSphere && angles.cwiseAbs().maxCoeff() > 1e-9) {
      builder.rotate(leaf, numbers({angles[0], angles[1], angles[2]}));
    }
  }
  if (sharpness > 0.0) {
    builder.sigmoid(leaf, sharpness);
  } else {
    builder.crisp(leaf);
  }
  return leaf;
}

std::optional<Solid> solid_of_leaf(const Tree& tree, std::span<const double> params, int node) {
  const Node& n = tree.node(node);
  if (n.kind != NodeKind::kPrimitive || n.placement.scale) return std::nullopt;
  const auto value = [&](std::size_t i) { return params[n.intrinsic.at(i).index]; };
  Solid s;
  switch (n.shape.type) {
    case PrimitiveType::kBox:
      s.kind = SolidKind::kBox;
      s.size = {value(0), value(1), value(2)};
      break;
    case PrimitiveType::kCylinder:
      s.kind = SolidKind::kCylinder;
      s.size = {value(0), value(0), value(1)};
      break;
    case PrimitiveType::kCone:
      s.kind = SolidKind::kCone;
      s.size = {value(0), value(1), value(2)};
      break;
    case PrimitiveType::kSphere:
      s.kind = SolidKind::kSphere;
      s.size = {value(0), 0, 0};
      break;
    case PrimitiveType::kTorus:
      s.kind = SolidKind::kTorus;
      s.size = {value(0), value(1), 0};
      break;
    case PrimitiveType::kExtrude: {
      // The segments' end points: a straight-sided profile's polygon.
      const std::size_t count = n.intrinsic.size();
      if (count < 1 + 2 * 3 * 3) return std::nullopt;  // at least three segments
      s.kind = SolidKind::kPrism;
      for (std::size_t i = 0; i + 1 < count; i += 6) s.polygon.emplace_back(value(i), value(i + 1));
      s.size = {0, 0, value(count - 1)};
      break;
    }
    case PrimitiveType::kPlane: {
      s.kind = SolidKind::kHalfSpace;
      const Eigen::Vector3d normal(value(0), value(1), value(2));
      const double length = normal.norm();
      if (!(length > 0.0)) return std::nullopt;
      s.rotation = rotation_with_z(normal / length);
      s.size = {value(3) / length, 0, 0};
      return s;
    }
    default:
      return std::nullopt;
  }
  if (!n.placement.translate.empty()) {
    for (int i = 0; i < 3; ++i) s.centre[i] = params[n.placement.translate[i].index];
  }
  if (!n.placement.rotate.empty()) {
    s.rotation = rotation_from_euler_degrees({params[n.placement.rotate[0].index],
                                              params[n.placement.rotate[1].index],
                                              params[n.placement.rotate[2].index]});
  }
  return s;
}

}  // namespace fuzzycsg::convert
