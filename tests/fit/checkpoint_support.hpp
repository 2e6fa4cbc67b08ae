#pragma once
// Shared by the tests of the settings in checkpoints: a small checkpoint and the error that
// reading one gives.

#include <string>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "fuzzycsg/fit/report.hpp"

namespace fuzzycsg::testing {

// A checkpoint of two parameters with `options`, for a target `target` of dimension `dim`.
inline Checkpoint small_checkpoint(const FitOptions& options, int dim, const std::string& target) {
  Checkpoint ck;
  ck.target = target;
  ck.dim = dim;
  ck.options = options;
  ck.state.params = {1, 2};
  ck.state.m = {0, 0};
  ck.state.v = {0, 0};
  return ck;
}

// The message of the InputError that reading the checkpoint at `path` throws, or "no error".
inline std::string checkpoint_read_error(const std::string& path) {
  try {
    (void)read_checkpoint(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace fuzzycsg::testing
