#pragma once
// The solids that convert builds its trees of: CAD primitives with a rigid placement, tested
// crisply and written as tree leaves.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <numbers>
#include <string>
#include <vector>

#include "fuzzycsg/core/transform.hpp"
#include "fuzzycsg/core/tree_builder.hpp"

namespace fuzzycsg::convert {

inline constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

enum class SolidKind { kBox, kCylinder, kCone, kSphere, kTorus, kHalfSpace, kPrism };

std::string_view solid_kind_name(SolidKind kind);  // "box", "cylinder", ...

// A primitive in world coordinates: p is inside when local = rotation^T (p - centre) is inside
// the primitive in its own frame, which is that of the tree's family (box centred with full
// extents `size`; cylinder and cone along z, centred; torus in the xy plane; prism: the polygon
// `polygon` of the xy plane extruded over z in [-h/2, h/2]). A half-space is
// {p : normal . p <= offset} with normal = rotation.col(2) and offset = size[0]; its centre is
// not used.
struct Solid {
  SolidKind kind = SolidKind::kBox;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // columns: the local axes
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  // box: full extents; cylinder: (radius, -, height); cone: (radius at -h/2, radius at +h/2,
  // height); sphere: (radius, -, -); torus: (major, minor, -); half-space: (offset, -, -);
  // prism: (-, -, height).
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  // Prism: the vertices of a simple polygon in the solid's xy plane, counter-clockwise. Written
  // as an `extrude` leaf with straight sides (OpenSCAD: linear_extrude of a polygon).
  std::vector<Eigen::Vector2d> polygon;

  Eigen::Vector3d normal() const { return rotation.col(2); }  // half-spaces
  bool contains(const Eigen::Vector3d& p) const;
  // Corners of a box in the solid's own frame that bound it (half-spaces: none).
  Eigen::AlignedBox3d local_bounds() const;
  // The same solid after p -> m(p) (rotation unchanged, lengths times m.scale).
  Solid mapped(const Similarity& m) const;
  // One line: "box 30 x 15 x 15 at (0, 0, 0)".
  std::string describe() const;
};

// Euler angles in degrees [ax, ay, az] of the tree's rotate field (R = Rz(az) Ry(ay) Rx(ax)),
// for a rotation matrix.
Eigen::Vector3d euler_xyz_degrees(const Eigen::Matrix3d& rotation);
// The rotation of the tree's rotate field.
Eigen::Matrix3d rotation_from_euler_degrees(const Eigen::Vector3d& angles);
// A rotation whose third column is the unit vector `axis` (the first two completed
// deterministically, as close to the world axes as the axis allows).
Eigen::Matrix3d rotation_with_z(const Eigen::Vector3d& axis);

// The solid as a leaf of the builder's tree: the family's fields, translate and rotate where
// they are not the identity (rotations within `angle_tolerance_deg` of none are dropped), and a
// crisp step, or a sigmoid step of the given sharpness when `sharpness` > 0.
int add_leaf(TreeBuilder& builder, const Solid& solid, double sharpness = 0.0);

// The solid a leaf of a tree describes (its family, translate and rotate; no scale), or
// nullopt for leaves of other families or with a scale.
std::optional<Solid> solid_of_leaf(const Tree& tree, std::span<const double> params, int node);

}  // namespace fuzzycsg::convert
