#pragma once
// The optim module: optimisers the engines share.
//
//   cmaes.hpp  cmaes_minimize: CMA-ES (Hansen), the derivative-free baseline of DiffCSG.

#include "fuzzycsg/optim/cmaes.hpp"
