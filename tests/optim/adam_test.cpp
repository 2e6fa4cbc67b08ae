// Adam: the first steps on a quadratic match the bias-corrected update worked by hand, it
// minimises the quadratic, log coordinates keep a positive parameter positive, projection keeps
// values in their ranges, rates scale or freeze a parameter, and a step into other vectors is
// the step in place.
#include "fuzzycsg/optim/adam.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::optim {
namespace {

// f(x) = 1.5 x^2, f'(x) = 3 x.
double quadratic_grad(double x) { return 3 * x; }

TEST(Adam, FirstStepsOnAQuadraticAreTheBiasCorrectedUpdate) {
  const Adam adam(1);
  std::vector<double> x{2.0}, m{0.0}, v{0.0}, g{quadratic_grad(2.0)};
  adam.step(1, 0.1, g, AdamState{x, m, v});
  // m1 = 0.1 * 6 = 0.6, v1 = 0.001 * 36 = 0.036; corrected, m = 6 and v = 36, so the first
  // step is lr * 6 / (6 + eps): about lr, whatever the gradient's size. Uncorrected it would
  // be 0.1 * 0.6 / sqrt(0.036) = 0.316.
  EXPECT_NEAR(m[0], 0.6, 1e-15);
  EXPECT_NEAR(v[0], 0.036, 1e-15);
  EXPECT_NEAR(x[0], 2.0 - 0.1 * 6.0 / (6.0 + 1e-8), 1e-15);
  EXPECT_NEAR(x[0], 1.9, 1e-9);

  // Second step at x1 = 1.9 (up to 1e-10): g2 = 5.7, m2 = 0.9 * 0.6 + 0.1 * 5.7 = 1.11,
  // v2 = 0.999 * 0.036 + 0.001 * 32.49 = 0.068454; c1 = 0.19, c2 = 0.001999.
  // u = 0.1 * (1.11 / 0.19) / sqrt(0.068454 / 0.001999) = 0.0998335...
  g[0] = quadratic_grad(x[0]);
  adam.step(2, 0.1, g, AdamState{x, m, v});
  EXPECT_NEAR(m[0], 1.11, 1e-9);
  EXPECT_NEAR(v[0], 0.068454, 1e-9);
  const double u = 0.1 * (1.11 / 0.19) / std::sqrt(0.068454 / 0.001999);
  EXPECT_NEAR(u, 0.0998335, 1e-7);
  EXPECT_NEAR(x[0], 1.9 - u, 1e-8);
}

TEST(Adam, MinimisesAQuadratic) {
  const Adam adam(2);
  std::vector<double> x{2.0, -5.0}, m(2, 0.0), v(2, 0.0), g(2);
  for (long k = 1; k <= 3000; ++k) {
    for (std::size_t i = 0; i < 2; ++i) g[i] = quadratic_grad(x[i]);
    adam.step(k, 0.05, g, AdamState{x, m, v});
  }
  EXPECT_NEAR(x[0], 0.0, 1e-3);
  EXPECT_NEAR(x[1], 0.0, 1e-3);
}

TEST(Adam, LogCoordinatesKeepAPositiveParameterPositive) {
  // A sharpness-like parameter pushed down hard: a direct step of about lr = 1 would take 1e-3
  // to about -1; in log coordinates it shrinks by the factor exp(-1).
  Adam adam(2);
  adam.set_log(0, true);
  std::vector<double> x{1e-3, 1e-3}, m(2, 0.0), v(2, 0.0), g{1e6, 1e6};
  adam.step(1, 1.0, g, AdamState{x, m, v});
  EXPECT_GT(x[0], 0.0);
  EXPECT_NEAR(x[0], 1e-3 * std::exp(-1.0), 1e-12);
  EXPECT_LT(x[1], 0.0);
  // The moments are those of dL/du = x dL/dx = 1e3.
  EXPECT_NEAR(m[0], 0.1 * 1e3, 1e-9);
  EXPECT_NEAR(m[1], 0.1 * 1e6, 1e-6);
  for (long k = 2; k <= 200; ++k) {
    adam.step(k, 1.0, g, AdamState{x, m, v});
    ASSERT_GT(x[0], 0.0) << "step " << k;
  }
}

TEST(Adam, ProjectionKeepsValuesInTheirRanges) {
  Adam adam(4);
  adam.set_range(0, Range::positive());
  adam.set_range(1, Range::closed(-1.0, 1.0));
  adam.set_range(2, Range::closed(-1.0, 1.0));
  // 3 stays in Range::any() and moves freely.
  std::vector<double> x{0.5, 0.95, -0.95, 0.5}, m(4, 0.0), v(4, 0.0), g{1.0, -1.0, 1.0, 1.0};
  for (long k = 1; k <= 20; ++k) adam.step(k, 0.1, g, AdamState{x, m, v});
  EXPECT_GT(x[0], 0.0);
  EXPECT_EQ(x[0], 1e-6);  // an open bound is kept 1e-6 inside
  EXPECT_EQ(x[1], 1.0);
  EXPECT_EQ(x[2], -1.0);
  EXPECT_NEAR(x[3], 0.5 - 20 * 0.1, 1e-6);
}

TEST(Adam, ProjectOnItsOwn) {
  EXPECT_EQ(project(0.5, Range::closed(0.0, 1.0)), 0.5);
  EXPECT_EQ(project(-3.0, Range::closed(0.0, 1.0)), 0.0);
  EXPECT_EQ(project(3.0, Range::closed(0.0, 1.0)), 1.0);
  EXPECT_EQ(project(0.0, Range::positive()), 1e-6);
  EXPECT_EQ(project(-1.0, Range::greater_than(-1.0)), -1.0 + 1e-6);
  // Far from 0 the margin is relative, so that it is not lost in rounding.
  EXPECT_EQ(project(1e12, Range::greater_than(1e12)), 1e12 + 1e6);
  EXPECT_GT(project(1e12, Range::greater_than(1e12)), 1e12);
  EXPECT_EQ(project(2.0, Range{0.0, 1.0, false, true}), 1.0 - 1e-6);
  EXPECT_TRUE(std::isnan(project(std::nan(""), Range::closed(0.0, 1.0))));
  EXPECT_EQ(project(-1e300, Range::any()), -1e300);
}

TEST(Adam, RatesScaleTheStepAndZeroFreezesTheValue) {
  Adam adam(3);
  adam.set_rate(0, 0.0);
  adam.set_rate(1, 2.0);
  std::vector<double> x{1.0, 1.0, 1.0}, m(3, 0.0), v(3, 0.0), g{4.0, 4.0, 4.0};
  for (long k = 1; k <= 5; ++k) adam.step(k, 0.01, g, AdamState{x, m, v});
  EXPECT_EQ(x[0], 1.0);
  // The moments still follow the gradient, so that a rate raised later starts from them.
  EXPECT_GT(m[0], 0.0);
  EXPECT_EQ(m[0], m[2]);
  EXPECT_NEAR(1.0 - x[1], 2 * (1.0 - x[2]), 1e-12);
  EXPECT_NEAR(1.0 - x[2], 5 * 0.01, 1e-8);
}

TEST(Adam, AParameterThatIsNotFreeKeepsItsValueAndMoments) {
  Adam adam(2);
  adam.set_free(0, false);
  std::vector<double> x{1.0, 1.0}, m{0.25, 0.25}, v{0.5, 0.5}, g{4.0, 4.0};
  adam.step(3, 0.01, g, AdamState{x, m, v});
  EXPECT_EQ(x[0], 1.0);
  EXPECT_EQ(m[0], 0.25);
  EXPECT_EQ(v[0], 0.5);
  EXPECT_NE(x[1], 1.0);
  EXPECT_NE(m[1], 0.25);
}

TEST(Adam, NonFiniteGradientsAreSkippedOnlyWhenAsked) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  AdamOptions o;
  o.skip_non_finite = true;
  const Adam skipping(2, o);
  std::vector<double> x{1.0, 1.0}, m(2, 0.0), v(2, 0.0), g{nan, 1.0};
  skipping.step(1, 0.1, g, AdamState{x, m, v});
  EXPECT_EQ(x[0], 1.0);
  EXPECT_EQ(m[0], 0.0);
  EXPECT_EQ(v[0], 0.0);
  EXPECT_NEAR(x[1], 0.9, 1e-7);

  const Adam plain(2);
  x = {1.0, 1.0};
  m = {0.0, 0.0};
  v = {0.0, 0.0};
  plain.step(1, 0.1, g, AdamState{x, m, v});
  EXPECT_TRUE(std::isnan(x[0]));
  EXPECT_TRUE(std::isnan(m[0]));
  EXPECT_NEAR(x[1], 0.9, 1e-7);
}

TEST(Adam, AStepIntoOtherVectorsIsTheStepInPlace) {
  Adam adam(4);
  adam.set_log(1, true);
  adam.set_free(2, false);
  adam.set_rate(3, 0.5);
  adam.set_range(3, Range::closed(0.0, 10.0));
  const std::vector<double> x0{0.3, 2.0, -1.0, 0.2}, m0{0.1, -0.2, 0.3, 0.0},
      v0{0.01, 0.02, 0.03, 0.0}, g{1.5, -0.5, 2.0, 3.0};
  std::vector<double> x = x0, m = m0, v = v0;
  adam.step(7, 0.05, g, AdamState{x, m, v});
  std::vector<double> x2(4, -9.0), m2(4, -9.0), v2(4, -9.0);
  adam.step(7, 0.05, g, ConstAdamState{x0, m0, v0}, AdamState{x2, m2, v2});
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(x[i], x2[i]) << i;
    EXPECT_EQ(m[i], m2[i]) << i;
    EXPECT_EQ(v[i], v2[i]) << i;
  }
  EXPECT_EQ(x2[2], -1.0);  // copied through though not free
  EXPECT_EQ(m2[2], 0.3);
}

TEST(Adam, RejectsVectorsOfTheWrongSize) {
  const Adam adam(2);
  std::vector<double> x(2, 0.0), m(2, 0.0), v(3, 0.0), g(2, 1.0);
  EXPECT_THROW(adam.step(1, 0.1, g, AdamState{x, m, v}), Error);
}

}  // namespace
}  // namespace fuzzycsg::optim
