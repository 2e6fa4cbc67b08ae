// Schedules: the cosine learning rate and the geometric ramps at known fractions and steps.
#include "fuzzycsg/optim/schedule.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace fuzzycsg::optim {
namespace {

TEST(Schedule, CosineLrFromLrDownToItsEndFraction) {
  EXPECT_DOUBLE_EQ(cosine_lr(2e-3, 0.1, 0.0), 2e-3);
  // Half way the cosine term is 1/2: lr (0.1 + 0.9 / 2).
  EXPECT_NEAR(cosine_lr(2e-3, 0.1, 0.5), 2e-3 * 0.55, 1e-15);
  // A quarter of the way: (1 + cos(pi / 4)) / 2 = 0.853553...
  EXPECT_NEAR(cosine_lr(1.0, 0.0, 0.25), 0.5 * (1 + std::sqrt(0.5)), 1e-15);
  EXPECT_NEAR(cosine_lr(2e-3, 0.1, 1.0), 2e-4, 1e-15);
  EXPECT_LT(cosine_lr(2e-3, 0.1, 0.7), cosine_lr(2e-3, 0.1, 0.6));
  // Outside [0, 1] the ends hold.
  EXPECT_EQ(cosine_lr(2e-3, 0.1, 1.5), cosine_lr(2e-3, 0.1, 1.0));
  EXPECT_EQ(cosine_lr(2e-3, 0.1, -0.5), cosine_lr(2e-3, 0.1, 0.0));
  // An end fraction of 1 is a constant rate.
  EXPECT_DOUBLE_EQ(cosine_lr(3e-3, 1.0, 0.4), 3e-3);
}

TEST(Schedule, GeometricInterpolation) {
  EXPECT_DOUBLE_EQ(geometric(1.0, 1000.0, 0.0), 1.0);
  EXPECT_NEAR(geometric(1.0, 1000.0, 0.5), std::sqrt(1000.0), 1e-9);
  EXPECT_NEAR(geometric(10.0, 1000.0, 0.5), 100.0, 1e-9);
  EXPECT_NEAR(geometric(10.0, 1000.0, 1.0), 1000.0, 1e-9);
  // Downwards as well (a sharpness schedule may fall).
  EXPECT_NEAR(geometric(8.0, 2.0, 0.5), 4.0, 1e-12);
}

TEST(Schedule, GeometricRampThenConstant) {
  // Over the first 300 steps from 10 to 1000, then 1000.
  EXPECT_DOUBLE_EQ(geometric_ramp(10.0, 1000.0, 300.0, 0), 10.0);
  EXPECT_NEAR(geometric_ramp(10.0, 1000.0, 300.0, 150), 100.0, 1e-9);
  EXPECT_NEAR(geometric_ramp(10.0, 1000.0, 300.0, 100), 10.0 * std::cbrt(100.0), 1e-9);
  EXPECT_LT(geometric_ramp(10.0, 1000.0, 300.0, 299), 1000.0);
  EXPECT_EQ(geometric_ramp(10.0, 1000.0, 300.0, 300), 1000.0);
  EXPECT_EQ(geometric_ramp(10.0, 1000.0, 300.0, 5000), 1000.0);
  // A fractional length: step 2 is past a ramp of 1.5 steps.
  EXPECT_EQ(geometric_ramp(10.0, 1000.0, 1.5, 2), 1000.0);
  EXPECT_LT(geometric_ramp(10.0, 1000.0, 1.5, 1), 1000.0);
  // No ramp: the end value from the first step.
  EXPECT_EQ(geometric_ramp(10.0, 1000.0, 0.0, 0), 1000.0);
}

}  // namespace
}  // namespace fuzzycsg::optim
