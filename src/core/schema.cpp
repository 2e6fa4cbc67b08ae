#include "fuzzycsg/core/schema.hpp"

#include <cmath>
#include <sstream>

namespace fuzzycsg {

namespace {
std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace

bool Range::contains(double v) const {
  if (std::isnan(v)) return false;
  const bool above = lo_open ? v > lo : v >= lo;
  const bool below = hi_open ? v < hi : v <= hi;
  return above && below;
}

std::string Range::describe() const {
  const bool has_lo = std::isfinite(lo);
  const bool has_hi = std::isfinite(hi);
  if (!has_lo && !has_hi) return "must be a finite number";
  if (has_lo && !has_hi) return std::string("must be ") + (lo_open ? "> " : ">= ") + number(lo);
  if (!has_lo) return std::string("must be ") + (hi_open ? "< " : "<= ") + number(hi);
  return "must be in " + std::string(lo_open ? "(" : "[") + number(lo) + ", " + number(hi) +
         (hi_open ? ")" : "]");
}

}  // namespace fuzzycsg
