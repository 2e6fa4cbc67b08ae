// CMA-ES: it finds the minima of the tutorial's test functions (sphere, a badly scaled
// ellipsoid, Rosenbrock) to high accuracy, uses the scales it is given, is deterministic for a
// seed, and keeps to its budget.
#include <gtest/gtest.h>

#include <cmath>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/optim/cmaes.hpp"

namespace fuzzycsg::optim {
namespace {

TEST(Cmaes, MinimisesTheSphereAndABadlyScaledEllipsoid) {
  const auto sphere = [](std::span<const double> x) {
    double s = 0;
    for (std::size_t k = 0; k < x.size(); ++k) s += (x[k] - 1) * (x[k] - 1);
    return s;
  };
  CmaesOptions o;
  o.stop_value = 1e-12;
  const CmaesResult a =
      cmaes_minimize(sphere, std::vector<double>(8, 5.0), std::vector<double>(8, 1.0), o);
  EXPECT_EQ(a.stopped_by, "value");
  EXPECT_LE(a.best_value, 1e-12);
  for (const double x : a.best) EXPECT_NEAR(x, 1, 1e-5);
  // Condition number 1e6: the covariance has to learn it.
  const auto ellipsoid = [](std::span<const double> x) {
    double s = 0;
    for (std::size_t k = 0; k < x.size(); ++k) {
      s += std::pow(1e6, static_cast<double>(k) / (x.size() - 1)) * x[k] * x[k];
    }
    return s;
  };
  o.max_evaluations = 20000;
  const CmaesResult b =
      cmaes_minimize(ellipsoid, std::vector<double>(6, 1.0), std::vector<double>(6, 1.0), o);
  EXPECT_LE(b.best_value, 1e-12);
  EXPECT_LT(b.evaluations, 20000);
}

TEST(Cmaes, SolvesRosenbrockAndIsDeterministic) {
  const auto rosenbrock = [](std::span<const double> x) {
    double s = 0;
    for (std::size_t k = 0; k + 1 < x.size(); ++k) {
      s += 100 * std::pow(x[k + 1] - x[k] * x[k], 2) + std::pow(1 - x[k], 2);
    }
    return s;
  };
  CmaesOptions o;
  o.stop_value = 1e-10;
  o.max_evaluations = 40000;
  o.seed = 7;
  const CmaesResult a =
      cmaes_minimize(rosenbrock, std::vector<double>(5, 0.0), std::vector<double>(5, 1.0), o);
  EXPECT_LE(a.best_value, 1e-10);
  for (const double x : a.best) EXPECT_NEAR(x, 1, 1e-3);
  const CmaesResult b =
      cmaes_minimize(rosenbrock, std::vector<double>(5, 0.0), std::vector<double>(5, 1.0), o);
  EXPECT_EQ(a.evaluations, b.evaluations);
  EXPECT_EQ(a.best, b.best);
}

TEST(Cmaes, ScalesBringParametersOfDifferentUnitsTogether) {
  // x0 in metres, x1 in micrometres: with the right scales it is the sphere again.
  const auto f = [](std::span<const double> x) {
    return (x[0] - 2) * (x[0] - 2) + (x[1] * 1e-6 - 3) * (x[1] * 1e-6 - 3);
  };
  CmaesOptions o;
  o.stop_value = 1e-14;
  o.max_evaluations = 3000;
  const CmaesResult r = cmaes_minimize(f, {0, 0}, {1, 1e6}, o);
  EXPECT_EQ(r.stopped_by, "value");
  EXPECT_NEAR(r.best[1], 3e6, 1);
  // The budget: never more evaluations than allowed.
  o.stop_value = -1;
  o.max_evaluations = 50;
  const CmaesResult s = cmaes_minimize(f, {0, 0}, {1, 1e6}, o);
  EXPECT_EQ(s.stopped_by, "evaluations");
  EXPECT_LE(s.evaluations, 50);
  EXPECT_THROW(cmaes_minimize(f, {0, 0}, {1, 0}, o), InputError);
}

}  // namespace
}  // namespace fuzzycsg::optim
