#include "fuzzycsg/optim/schedule.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fuzzycsg::optim {

double cosine_lr(double lr, double end_fraction, double f) {
  f = std::clamp(f, 0.0, 1.0);
  return lr * (end_fraction + (1.0 - end_fraction) * 0.5 * (1.0 + std::cos(std::numbers::pi * f)));
}

double geometric(double start, double end, double f) { return start * std::pow(end / start, f); }

double geometric_ramp(double start, double end, double ramp_steps, long step) {
  if (ramp_steps <= 0 || static_cast<double>(step) >= ramp_steps) return end;
  return geometric(start, end, static_cast<double>(step) / ramp_steps);
}

}  // namespace fuzzycsg::optim
