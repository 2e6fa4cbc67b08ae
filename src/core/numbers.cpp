// Printing numbers for people and files.
#include "fuzzycsg/core/numbers.hpp"

#include <array>
#include <charconv>
#include <cmath>

namespace fuzzycsg {

std::string shortest_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), v);
  return std::string(buffer.data(), result.ptr);
}

}  // namespace fuzzycsg
