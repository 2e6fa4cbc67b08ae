#pragma once
// The optim module: optimisers the engines share.
//
//   adam.hpp      Adam: bias correction, per-parameter rates, log coordinates, projection.
//   schedule.hpp  learning-rate and temperature schedules: cosine_lr, geometric, geometric_ramp.
//   cmaes.hpp     cmaes_minimize: CMA-ES (Hansen), the derivative-free baseline of DiffCSG.

#include "fuzzycsg/optim/adam.hpp"
#include "fuzzycsg/optim/cmaes.hpp"
#include "fuzzycsg/optim/schedule.hpp"
