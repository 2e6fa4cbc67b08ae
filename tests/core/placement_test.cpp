#include "fuzzycsg/core/placement.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace fuzzycsg::placement {
namespace {

TEST(Placement, RotationMatchesOpenScadOrder) {
  // rotate([90, 0, 0]) takes the z axis to -y; rotate([0, 0, 90]) takes x to y.
  const auto r = rotation_3d(90, 0, 0);
  EXPECT_NEAR(r[0 * 3 + 2], 0.0, 1e-12);
  EXPECT_NEAR(r[1 * 3 + 2], -1.0, 1e-12);
  EXPECT_NEAR(r[2 * 3 + 2], 0.0, 1e-12);
  const auto rz = rotation_3d(0, 0, 90);
  EXPECT_NEAR(rz[1 * 3 + 0], 1.0, 1e-12);
  // x first, then y, then z: R = Rz Ry Rx.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-180, 180);
  for (int t = 0; t < 20; ++t) {
    const double a = u(rng), b = u(rng), c = u(rng);
    const Eigen::Matrix3d e = (Eigen::AngleAxisd(c * kDegree, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(b * kDegree, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(a * kDegree, Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    const auto m = rotation_3d(a, b, c);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(m[i * 3 + j], e(i, j), 1e-12);
    }
  }
}

TEST(Placement, VectorJacobianProductsMatchFiniteDifferences) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-180, 180), g(-1, 1);
  for (int t = 0; t < 20; ++t) {
    const double ang[3] = {u(rng), u(rng), u(rng)};
    std::array<double, 9> w{};
    for (double& v : w) v = g(rng);
    const auto vjp = rotation_3d_vjp(ang[0], ang[1], ang[2], w);
    for (int k = 0; k < 3; ++k) {
      double p[3] = {ang[0], ang[1], ang[2]}, m[3] = {ang[0], ang[1], ang[2]};
      const double h = 1e-5;
      p[k] += h;
      m[k] -= h;
      const auto rp = rotation_3d(p[0], p[1], p[2]), rm = rotation_3d(m[0], m[1], m[2]);
      double fd = 0.0;
      for (int i = 0; i < 9; ++i) fd += w[i] * (rp[i] - rm[i]) / (2 * h);
      EXPECT_NEAR(vjp[k], fd, 1e-8);
    }
    std::array<double, 4> w2{g(rng), g(rng), g(rng), g(rng)};
    const double h = 1e-5;
    const auto rp = rotation_2d(ang[0] + h), rm = rotation_2d(ang[0] - h);
    double fd = 0.0;
    for (int i = 0; i < 4; ++i) fd += w2[i] * (rp[i] - rm[i]) / (2 * h);
    EXPECT_NEAR(rotation_2d_vjp(ang[0], w2), fd, 1e-8);
  }
}

}  // namespace
}  // namespace fuzzycsg::placement
