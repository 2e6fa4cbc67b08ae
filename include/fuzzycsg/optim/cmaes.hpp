#pragma once
// CMA-ES, the covariance matrix adaptation evolution strategy (Hansen, Müller and Koumoutsakos
// 2003; the (mu/mu_w, lambda) form of Hansen's tutorial, "The CMA Evolution Strategy", 2016):
// a derivative-free minimiser, DiffCSG's §4.3 baseline. Written here because Debian has no
// C or C++ CMA-ES library; the tutorial's defaults are used throughout, and the eigensystem of
// the covariance comes from Eigen.
//
// The search runs in scaled coordinates: x = x0 + scale * y (per coordinate), y starting at 0
// with step size `sigma`, so that parameters of different units (millimetres, degrees) start
// with comparable steps.

#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace fuzzycsg::optim {

struct CmaesOptions {
  double sigma = 0.3;  // initial step size, in scaled coordinates
  int population = 0;  // lambda; 0: 4 + floor(3 ln n)
  std::uint64_t seed = 1;
  long max_evaluations = 10000;
  double stop_value = -std::numeric_limits<double>::infinity();  // stop at f <= stop_value
  double tol_sigma = 1e-12;  // stop when sigma times the largest axis falls below this
};

struct CmaesResult {
  std::vector<double> best;  // the best point seen
  double best_value = std::numeric_limits<double>::infinity();
  long evaluations = 0;
  int generations = 0;
  std::string stopped_by;  // "value", "evaluations", "sigma", "callback"
};

// Minimises f from x0. `scale` has x0's size (all > 0). `generation`, if given, is called
// after each generation with the best point and value so far; returning false stops.
CmaesResult cmaes_minimize(
    const std::function<double(std::span<const double>)>& f, const std::vector<double>& x0,
    const std::vector<double>& scale, const CmaesOptions& options = {},
    const std::function<bool(std::span<const double>, double)>& generation = nullptr);

}  // namespace fuzzycsg::optim
