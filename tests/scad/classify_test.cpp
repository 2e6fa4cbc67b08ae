// Classification of quadric leaves: hand-made quadrics of every kind under random rotations,
// translations and scales of the coefficients (negated too), the quadrics that are none of the
// kinds, the tolerance and the numerical validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/scad/scad.hpp"
#include "scad_support.hpp"

namespace fuzzycsg {
namespace {

using scad::QuadricClass;
using scad::QuadricKind;
using scad_test::make_quadric2;
using scad_test::make_quadric3;
using scad_test::quadric_value;

// Fraction of uniform samples of [-1, 1]^dim where the class and the quadric agree in sign
// (other samples than the classifier's own).
double sign_agreement(const QuadricClass& c, std::span<const double> q, int dim) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int agree = 0;
  const int n = 20000;
  for (int s = 0; s < n; ++s) {
    const double x[3] = {u(rng), u(rng), dim == 3 ? u(rng) : 0.0};
    agree += (quadric_value(q, x) < 0) == (c.value(x) < 0) ? 1 : 0;
  }
  return static_cast<double>(agree) / n;
}

Eigen::Vector3d column(const QuadricClass& c, int k) {
  return {c.rotation[static_cast<std::size_t>(k)], c.rotation[static_cast<std::size_t>(3 + k)],
          c.rotation[static_cast<std::size_t>(6 + k)]};
}
Eigen::Vector3d center(const QuadricClass& c) { return {c.center[0], c.center[1], c.center[2]}; }

std::vector<double> sorted(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v;
}

void expect_near_all(const std::vector<double>& a, const std::vector<double>& b, double tol) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], tol) << "entry " << i;
}

TEST(Classify, EveryKindUnderRandomPlacementAndScaledNegatedCoefficients) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto uni = [&](double a, double b) { return a + (b - a) * u(rng); };
  const std::vector<QuadricKind> kinds{
      QuadricKind::kSphere, QuadricKind::kEllipsoid,  QuadricKind::kCylinder, QuadricKind::kCone,
      QuadricKind::kPlane,  QuadricKind::kParaboloid, QuadricKind::kSlab};
  for (const QuadricKind kind : kinds) {
    for (int trial = 0; trial < 10; ++trial) {
      SCOPED_TRACE(std::string(scad::kind_name(kind, 3)) + " trial " + std::to_string(trial));
      const Eigen::Matrix3d r = scad_test::random_rotation(rng);
      const Eigen::Vector3d c(uni(-0.3, 0.3), uni(-0.3, 0.3), uni(-0.3, 0.3));
      // Coefficients scaled by 1e-3 .. 1e3, negated on odd trials.
      const double s = (trial % 2 ? -1.0 : 1.0) * std::pow(10.0, uni(-3, 3));
      Eigen::Matrix3d g = Eigen::Matrix3d::Zero();
      Eigen::Vector3d h = Eigen::Vector3d::Zero();
      double k0 = 0.0;
      Eigen::Vector3d axes(1, 1, 1);
      switch (kind) {
        case QuadricKind::kSphere:
          g.setIdentity();
          k0 = -1;
          axes.setConstant(uni(0.2, 0.6));
          break;
        case QuadricKind::kEllipsoid:
          g.setIdentity();
          k0 = -1;
          axes = Eigen::Vector3d(uni(0.2, 0.3), uni(0.35, 0.5), uni(0.55, 0.7));
          break;
        case QuadricKind::kCylinder:
          g.diagonal() << 1, 1, 0;
          k0 = -1;
          axes = Eigen::Vector3d(uni(0.2, 0.35), uni(0.4, 0.6), 1.0);
          break;
        case QuadricKind::kCone:
          g.diagonal() << 1, 1, -1;
          axes = Eigen::Vector3d(uni(0.3, 0.6), uni(0.7, 1.2), 1.0);
          break;
        case QuadricKind::kPlane:
          h << 0, 0, 1;
          break;
        case QuadricKind::kParaboloid:
          g.diagonal() << 1, 1, 0;
          h << 0, 0, -1;
          axes = Eigen::Vector3d(uni(0.3, 0.5), uni(0.6, 0.9), uni(0.5, 2.0));
          break;
        case QuadricKind::kSlab:
          g.diagonal() << 0, 0, 1;
          k0 = -1;
          axes = Eigen::Vector3d(1, 1, uni(0.1, 0.5));
          break;
        default:
          FAIL();
      }
      const std::vector<double> q = make_quadric3(g, h, k0, r, axes, c, s);
      const QuadricClass cls = scad::classify_quadric(3, q, Domain{});
      ASSERT_EQ(cls.kind, kind) << cls.note;
      // A negated plane is the other half-space; every other kind turns inside out.
      EXPECT_EQ(cls.outside, s < 0 && kind != QuadricKind::kPlane);
      EXPECT_GT(cls.agreement, 0.999);
      EXPECT_GT(sign_agreement(cls, q, 3), 0.999);
      EXPECT_NEAR(column(cls, 0).cross(column(cls, 1)).dot(column(cls, 2)), 1.0, 1e-9);
      const double tol = 1e-6;
      const Eigen::Vector3d axis = column(cls, 2), expected_axis = r.col(2);
      switch (kind) {
        case QuadricKind::kSphere:
        case QuadricKind::kEllipsoid:
          expect_near_all(sorted({cls.axes[0], cls.axes[1], cls.axes[2]}),
                          sorted({axes[0], axes[1], axes[2]}), tol);
          EXPECT_LT((center(cls) - c).norm(), tol);
          break;
        case QuadricKind::kCylinder:
          expect_near_all(sorted({cls.axes[0], cls.axes[1]}), sorted({axes[0], axes[1]}), tol);
          EXPECT_NEAR(std::abs(axis.dot(expected_axis)), 1.0, tol);
          EXPECT_LT((center(cls) - c).cross(axis).norm(), tol);  // on the axis
          break;
        case QuadricKind::kCone:
          expect_near_all(sorted({cls.axes[0], cls.axes[1]}), sorted({axes[0], axes[1]}), tol);
          EXPECT_NEAR(std::abs(axis.dot(expected_axis)), 1.0, tol);
          EXPECT_LT((center(cls) - c).norm(), tol);  // the apex
          break;
        case QuadricKind::kPlane:
          EXPECT_NEAR(axis.dot(expected_axis), s > 0 ? 1.0 : -1.0, tol);
          EXPECT_NEAR((center(cls) - c).dot(axis), 0.0, tol);
          break;
        case QuadricKind::kParaboloid:
          expect_near_all(sorted({cls.axes[0], cls.axes[1]}),
                          sorted({axes[0] / std::sqrt(axes[2]), axes[1] / std::sqrt(axes[2])}),
                          tol);
          EXPECT_NEAR(axis.dot(expected_axis), 1.0, tol);  // opens the same way
          EXPECT_LT((center(cls) - c).norm(), tol);        // the apex
          break;
        case QuadricKind::kSlab:
          EXPECT_NEAR(cls.axes[2], axes[2], tol);
          EXPECT_NEAR(std::abs(axis.dot(expected_axis)), 1.0, tol);
          EXPECT_NEAR((center(cls) - c).dot(axis), 0.0, tol);
          break;
        default:
          break;
      }
      // The affine map takes the canonical unit set's boundary onto the quadric's zero set.
      const auto m = cls.affine();
      const Eigen::Vector3d v = kind == QuadricKind::kPlane        ? Eigen::Vector3d(0.3, -0.2, 0)
                                : kind == QuadricKind::kCone       ? Eigen::Vector3d(0.6, 0.8, 1)
                                : kind == QuadricKind::kParaboloid ? Eigen::Vector3d(0.6, 0.8, 1)
                                : kind == QuadricKind::kSlab       ? Eigen::Vector3d(0.4, 0.1, 1)
                                : kind == QuadricKind::kCylinder   ? Eigen::Vector3d(0.6, 0.8, 0.3)
                                                                   : Eigen::Vector3d(0.6, 0, 0.8);
      double x[3];
      for (int i = 0; i < 3; ++i) {
        x[i] = m[static_cast<std::size_t>(4 * i + 3)];
        for (int k = 0; k < 3; ++k) x[i] += m[static_cast<std::size_t>(4 * i + k)] * v[k];
      }
      EXPECT_NEAR(quadric_value(q, x) / std::abs(s), 0.0, 1e-6);
    }
  }
}

TEST(Classify, EveryKindIn2D) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto uni = [&](double a, double b) { return a + (b - a) * u(rng); };
  const std::vector<QuadricKind> kinds{QuadricKind::kSphere, QuadricKind::kEllipsoid,
                                       QuadricKind::kPlane, QuadricKind::kParaboloid,
                                       QuadricKind::kSlab};
  for (const QuadricKind kind : kinds) {
    for (int trial = 0; trial < 10; ++trial) {
      SCOPED_TRACE(std::string(scad::kind_name(kind, 2)) + " trial " + std::to_string(trial));
      const double angle = uni(0, 6.3);
      const Eigen::Vector2d c(uni(-0.3, 0.3), uni(-0.3, 0.3));
      const double s = (trial % 2 ? -1.0 : 1.0) * std::pow(10.0, uni(-3, 3));
      Eigen::Matrix2d g = Eigen::Matrix2d::Zero();
      Eigen::Vector2d h = Eigen::Vector2d::Zero();
      double k0 = 0.0;
      Eigen::Vector2d axes(1, 1);
      switch (kind) {
        case QuadricKind::kSphere:
          g.setIdentity();
          k0 = -1;
          axes.setConstant(uni(0.2, 0.6));
          break;
        case QuadricKind::kEllipsoid:
          g.setIdentity();
          k0 = -1;
          axes = Eigen::Vector2d(uni(0.2, 0.35), uni(0.45, 0.7));
          break;
        case QuadricKind::kPlane:
          h << 0, 1;
          break;
        case QuadricKind::kParaboloid:
          g.diagonal() << 1, 0;
          h << 0, -1;
          axes = Eigen::Vector2d(uni(0.3, 0.6), uni(0.5, 2.0));
          break;
        case QuadricKind::kSlab:
          g.diagonal() << 0, 1;
          k0 = -1;
          axes = Eigen::Vector2d(1, uni(0.1, 0.5));
          break;
        default:
          FAIL();
      }
      const std::vector<double> q = make_quadric2(g, h, k0, angle, axes, c, s);
      const QuadricClass cls = scad::classify_quadric(2, q, Domain{});
      ASSERT_EQ(cls.kind, kind) << cls.note;
      EXPECT_EQ(cls.outside, s < 0 && kind != QuadricKind::kPlane);
      EXPECT_GT(sign_agreement(cls, q, 2), 0.999);
      if (kind == QuadricKind::kSphere) {
        EXPECT_NEAR(cls.axes[0], axes[0], 1e-6);
      }
      if (kind == QuadricKind::kEllipsoid) {
        expect_near_all(sorted({cls.axes[0], cls.axes[1]}), sorted({axes[0], axes[1]}), 1e-6);
      }
      if (kind == QuadricKind::kSlab) {
        EXPECT_NEAR(cls.axes[1], axes[1], 1e-6);
      }
      if (kind == QuadricKind::kParaboloid) {
        EXPECT_NEAR(cls.axes[0], axes[0] / std::sqrt(axes[1]), 1e-6);
      }
    }
  }
}

TEST(Classify, HyperboloidsSaddlesAndOtherQuadricsAreNotClassified) {
  std::mt19937_64 rng(3);
  struct Case {
    Eigen::Vector3d g, h;
    double k0;
    const char* note;
  };
  const std::vector<Case> cases{
      {{1, 1, -1}, {0, 0, 0}, -0.1, "hyperboloid of one sheet"},
      {{1, 1, -1}, {0, 0, 0}, 0.1, "hyperboloid of two sheets"},
      {{1, -1, 0}, {0, 0, 1}, 0.0, "saddle"},
      {{1, -1, 0}, {0, 0, 0}, -0.1, "hyperbolic cylinder"},
      {{1, -1, 0}, {0, 0, 0}, 0.0, "crossing planes"},
      {{1, 0, 0}, {0, 1, 0}, 0.0, "parabolic cylinder"},
  };
  for (const Case& cs : cases) {
    for (int trial = 0; trial < 6; ++trial) {
      SCOPED_TRACE(std::string(cs.note) + " trial " + std::to_string(trial));
      const double s = (trial % 2 ? -1.0 : 1.0) * std::pow(10.0, trial - 3);
      const Eigen::Vector3d c(0.1 * trial - 0.2, 0.05, -0.1);
      const std::vector<double> q =
          make_quadric3(Eigen::Matrix3d(cs.g.asDiagonal()), cs.h, cs.k0,
                        scad_test::random_rotation(rng), Eigen::Vector3d(0.5, 0.7, 0.6), c, s);
      const QuadricClass cls = scad::classify_quadric(3, q, Domain{});
      EXPECT_EQ(cls.kind, QuadricKind::kNone) << scad::kind_name(cls.kind, 3);
      // Negated or not, the surface is the same.
      const std::string want = cs.note;
      EXPECT_NE(cls.note.find(want), std::string::npos) << cls.note;
    }
  }
  // 2D: hyperbolas and crossing lines.
  for (const double k0 : {-0.1, 0.0}) {
    const std::vector<double> q =
        make_quadric2(Eigen::Vector2d(1, -1).asDiagonal().toDenseMatrix(), Eigen::Vector2d::Zero(),
                      k0, 0.4, Eigen::Vector2d(0.5, 0.3), Eigen::Vector2d(0.1, 0), -20.0);
    const QuadricClass cls = scad::classify_quadric(2, q, Domain{});
    EXPECT_EQ(cls.kind, QuadricKind::kNone);
    EXPECT_NE(cls.note.find(k0 == 0 ? "crossing lines" : "hyperbola"), std::string::npos)
        << cls.note;
  }
}

TEST(Classify, ToleranceIsRelativeToTheCoefficientScale) {
  const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero(), c(0.1, -0.2, 0.05);
  for (const double s : {1e-4, 1.0, 1e4}) {
    // Radii equal within the tolerance: a sphere; 10% apart: an ellipsoid.
    EXPECT_EQ(
        scad::classify_quadric(
            3, make_quadric3(id, zero, -1, id, Eigen::Vector3d(0.5, 0.5, 0.50001), c, s), Domain{})
            .kind,
        QuadricKind::kSphere);
    EXPECT_EQ(
        scad::classify_quadric(
            3, make_quadric3(id, zero, -1, id, Eigen::Vector3d(0.5, 0.5, 0.55), c, s), Domain{})
            .kind,
        QuadricKind::kEllipsoid);
    // An eigenvalue 1e-6 of the others: a cylinder.
    Eigen::Matrix3d g = id;
    g(2, 2) = 1e-6;
    EXPECT_EQ(scad::classify_quadric(
                  3, make_quadric3(g, zero, -1, id, Eigen::Vector3d(0.4, 0.3, 1), c, s), Domain{})
                  .kind,
              QuadricKind::kCylinder);
    // A hyperboloid whose neck is within the tolerance is a cone; with a smaller tolerance not.
    Eigen::Matrix3d cone = id;
    cone(2, 2) = -1;
    const std::vector<double> q =
        make_quadric3(cone, zero, -2e-4, id, Eigen::Vector3d(0.5, 0.5, 1), c, s);
    const QuadricClass near_cone = scad::classify_quadric(3, q, Domain{});
    EXPECT_EQ(near_cone.kind, QuadricKind::kCone);
    EXPECT_GT(near_cone.agreement, 0.995);
    scad::ClassifyOptions strict;
    strict.tolerance = 1e-5;
    const QuadricClass hyperboloid = scad::classify_quadric(3, q, Domain{}, strict);
    EXPECT_EQ(hyperboloid.kind, QuadricKind::kNone);
    EXPECT_NE(hyperboloid.note.find("one sheet"), std::string::npos) << hyperboloid.note;
  }
}

TEST(Classify, ValidationRefusesASnapThatChangesTheShape) {
  // An ellipsoid whose long axis has an eigenvalue a sixth of the others: with tolerance 0.3
  // the eigenvalue snaps to 0 (a cylinder), which the samples refuse (the cylinder holds ~4% of
  // the domain more); the exact classification, an ellipsoid, is kept.
  const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
  const std::vector<double> q =
      make_quadric3(id, Eigen::Vector3d::Zero(), -1, id, Eigen::Vector3d(0.5, 0.5, 1.2),
                    Eigen::Vector3d::Zero(), 1.0);
  scad::ClassifyOptions loose;
  loose.tolerance = 0.3;
  const QuadricClass cls = scad::classify_quadric(3, q, Domain{}, loose);
  EXPECT_EQ(cls.kind, QuadricKind::kEllipsoid);
  EXPECT_NEAR(*std::max_element(cls.axes.begin(), cls.axes.end()), 1.2, 1e-9);
  // Without the validation's thresholds the snap is taken: the samples are what decides.
  loose.min_agreement = 0.9;
  loose.max_relative_error = 1.0;
  const QuadricClass snapped = scad::classify_quadric(3, q, Domain{}, loose);
  EXPECT_EQ(snapped.kind, QuadricKind::kCylinder);
  EXPECT_LT(snapped.agreement, 0.99);
}

TEST(Classify, EmptyFullAndFarAway) {
  const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  const std::vector<double> imaginary =
      make_quadric3(id, zero, 1, id, Eigen::Vector3d(1, 1, 1), zero, 1.0);
  EXPECT_EQ(scad::classify_quadric(3, imaginary, Domain{}).kind, QuadricKind::kEmpty);
  std::vector<double> negated = imaginary;
  for (double& v : negated) v = -v;
  EXPECT_EQ(scad::classify_quadric(3, negated, Domain{}).kind, QuadricKind::kFull);
  const std::vector<double> constant{0, 0, 0, 0, 0, 0, 0, 0, 0, -3};
  EXPECT_EQ(scad::classify_quadric(3, constant, Domain{}).kind, QuadricKind::kFull);
  const std::vector<double> zeros(10, 0.0);
  EXPECT_EQ(scad::classify_quadric(3, zeros, Domain{}).kind, QuadricKind::kEmpty);
  // A small sphere outside the domain is still a sphere (and the samples agree: all outside).
  const std::vector<double> far =
      make_quadric3(id, zero, -1, id, Eigen::Vector3d(0.3, 0.3, 0.3), Eigen::Vector3d(4, 4, 4), 1);
  const QuadricClass cls = scad::classify_quadric(3, far, Domain{});
  EXPECT_EQ(cls.kind, QuadricKind::kSphere);
  EXPECT_NEAR(cls.axes[0], 0.3, 1e-9);
  // The domain matters: a tiny sphere in a tiny domain.
  Domain small;
  small.min = {0.0, 0.0, 0.0};
  small.max = {1e-3, 1e-3, 1e-3};
  const std::vector<double> tiny = make_quadric3(
      id, zero, -1, id, Eigen::Vector3d(2e-4, 2e-4, 2e-4), Eigen::Vector3d(5e-4, 5e-4, 5e-4), 1.0);
  const QuadricClass t = scad::classify_quadric(3, tiny, small);
  EXPECT_EQ(t.kind, QuadricKind::kSphere);
  EXPECT_NEAR(t.axes[0], 2e-4, 1e-12);
  EXPECT_GT(t.agreement, 0.999);
  EXPECT_THROW(scad::classify_quadric(3, std::vector<double>(6, 1.0), Domain{}), InputError);
}

TEST(WorldQuadric, FoldsThePlacementIntoTheCoefficients) {
  for (const int dim : {3, 2}) {
    const std::string leaf =
        dim == 3
            ? R"({"type": "quadric", "coefficients": [1, 2, 0.5, 0.3, -0.2, 0.1, 0.2, -0.1, 0.3, -0.4],
                      "translate": [0.2, -0.3, 0.1], "rotate": [30, -50, 70], "scale": 0.7})"
            : R"({"type": "quadric", "coefficients": [1, 2, 0.3, 0.2, -0.1, -0.4],
                      "translate": [0.2, -0.3], "rotate": 35, "scale": 1.3})";
    const Tree tree = io::read_tree_string(scad_test::tree_text(dim, leaf));
    const std::vector<double> params = tree.params.values();
    const std::vector<double> q = scad::world_quadric(tree, params, tree.root);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int checked = 0;
    for (int s = 0; s < 2000; ++s) {
      const double x[3] = {u(rng), u(rng), dim == 3 ? u(rng) : 0.0};
      // Occupancy 1 / (1 + exp(k f)) with sharpness 1: f = log(1 / o - 1).
      const double o = reference_occupancy(tree, params, x);
      const double f = std::log(1.0 / o - 1.0);
      if (std::abs(f) < 1e-9 || !std::isfinite(f)) continue;
      EXPECT_NEAR(quadric_value(q, x), f, 1e-9 * std::max(1.0, std::abs(f)));
      ++checked;
    }
    EXPECT_GT(checked, 1900);
  }
}

}  // namespace
}  // namespace fuzzycsg
