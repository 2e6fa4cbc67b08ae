#pragma once
// Field schemas: which numbers each node kind has, their names in the tree file, their ranges
// and defaults. The tree reader, the writer, validation, parameter naming and `info` all read
// these tables, so a family is described once.

#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace fuzzycsg {

// An interval constraint on a number, printed in error messages as "must be > 0",
// "must be in [0, 1]", ...
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  static constexpr Range any() { return {}; }
  static constexpr Range positive() {
    return {0.0, std::numeric_limits<double>::infinity(), true, false};
  }
  static constexpr Range non_negative() {
    return {0.0, std::numeric_limits<double>::infinity(), false, false};
  }
  static constexpr Range greater_than(double v) {
    return {v, std::numeric_limits<double>::infinity(), true, false};
  }
  static constexpr Range closed(double a, double b) { return {a, b, false, false}; }
  static constexpr Range left_open(double a, double b) { return {a, b, true, false}; }

  bool contains(double v) const;
  // "must be > 0", "must be in (0, 1]", ... (empty for any()).
  std::string describe() const;
};

// How many numbers a field holds.
enum class Arity {
  kScalar,   // one number: "radius": 0.5
  kFixed,    // a fixed-length array: "size": [1, 2, 3]
  kList,     // a list of numbers whose length depends on other fields (MLP weights)
  kPoints2,  // a list of [x, y] pairs (polygon vertices, an extrude's profile); its count
             // follows from the number of intrinsic parameters (fields::variable_count)
};

struct FieldSpec {
  std::string_view name;
  Arity arity = Arity::kScalar;
  int length = 1;  // for kFixed
  Range range;
  std::optional<double> default_value;  // optional field when set
  bool default_fixed = false;           // a plain number here is fixed (temperature, omega)
};

}  // namespace fuzzycsg
