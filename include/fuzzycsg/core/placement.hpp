#pragma once
// Rigid placement of a leaf: the world point p maps to the local point
//   p_local = R^T (p - t) / s,   f_world(p) = s * f_local(p_local)
// with R built from Euler angles in degrees: in 3D rotate([ax, ay, az]) turns about x, then y,
// then z (OpenSCAD's convention), R = Rz(az) Ry(ay) Rx(ax); in 2D one counter-clockwise angle.

#include <array>
#include <span>

namespace fuzzycsg::placement {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

// Row-major 3x3 (3D) or 2x2 (2D) rotation matrix.
std::array<double, 9> rotation_3d(double ax_deg, double ay_deg, double az_deg);
std::array<double, 4> rotation_2d(double angle_deg);

// Given G = dL/dR (row-major, same shape as R), returns dL/dangles (per degree).
std::array<double, 3> rotation_3d_vjp(double ax_deg, double ay_deg, double az_deg,
                                      const std::array<double, 9>& g);
double rotation_2d_vjp(double angle_deg, const std::array<double, 4>& g);

}  // namespace fuzzycsg::placement
