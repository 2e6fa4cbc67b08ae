#include "fuzzycsg/core/placement.hpp"

#include <cmath>

namespace fuzzycsg::placement {

namespace {

using Mat3 = std::array<double, 9>;

Mat3 mul(const Mat3& a, const Mat3& b) {
  Mat3 c{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k) s += a[i * 3 + k] * b[k * 3 + j];
      c[i * 3 + j] = s;
    }
  }
  return c;
}

// Rotation about one axis and its derivative wrt the angle (radians).
Mat3 rx(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {1, 0, 0, 0, c, -s, 0, s, c};
}
Mat3 ry(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c, 0, s, 0, 1, 0, -s, 0, c};
}
Mat3 rz(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c, -s, 0, s, c, 0, 0, 0, 1};
}
Mat3 drx(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {0, 0, 0, 0, -s, -c, 0, c, -s};
}
Mat3 dry(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {-s, 0, c, 0, 0, 0, -c, 0, -s};
}
Mat3 drz(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {-s, -c, 0, c, -s, 0, 0, 0, 0};
}

double dot(const Mat3& a, const Mat3& b) {
  double s = 0.0;
  for (int i = 0; i < 9; ++i) s += a[i] * b[i];
  return s;
}

}  // namespace

std::array<double, 9> rotation_3d(double ax_deg, double ay_deg, double az_deg) {
  return mul(rz(az_deg * kDegree), mul(ry(ay_deg * kDegree), rx(ax_deg * kDegree)));
}

std::array<double, 4> rotation_2d(double angle_deg) {
  const double c = std::cos(angle_deg * kDegree), s = std::sin(angle_deg * kDegree);
  return {c, -s, s, c};
}

std::array<double, 3> rotation_3d_vjp(double ax_deg, double ay_deg, double az_deg,
                                      const std::array<double, 9>& g) {
  const double a = ax_deg * kDegree, b = ay_deg * kDegree, c = az_deg * kDegree;
  const Mat3 dx = mul(rz(c), mul(ry(b), drx(a)));
  const Mat3 dy = mul(rz(c), mul(dry(b), rx(a)));
  const Mat3 dz = mul(drz(c), mul(ry(b), rx(a)));
  return {dot(g, dx) * kDegree, dot(g, dy) * kDegree, dot(g, dz) * kDegree};
}

double rotation_2d_vjp(double angle_deg, const std::array<double, 4>& g) {
  const double a = angle_deg * kDegree;
  const double c = std::cos(a), s = std::sin(a);
  return (g[0] * -s + g[1] * -c + g[2] * c + g[3] * -s) * kDegree;
}

}  // namespace fuzzycsg::placement
