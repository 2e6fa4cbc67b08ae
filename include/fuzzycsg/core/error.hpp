#pragma once
// Errors of fuzzycsg.
//
// InputError is bad input from a user (a file, a JSON field, a flag, a parameter range). Its
// message is one line that names the place and the field, e.g.
//   tree.json: root.children[1].radius: must be > 0 (got -0.2)
// The command-line program prints it and exits with status 2.
//
// FUZZYCSG_ASSERT checks internal invariants; it is on in Debug and sanitizer builds.

#include <stdexcept>
#include <string>
#include <utility>

namespace fuzzycsg {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class InputError : public Error {
 public:
  using Error::Error;
};

// A setting of one of the library's options structs that is out of its range. It names the
// field as the struct spells it ("prims", "sampling.near_distance", "metrics.points") and the
// problem; what() is "FIELD: PROBLEM". A program maps the field to its own name for it (the
// fuzzycsg program to its flag, "--prims: must be a power of two ...").
class OptionError : public InputError {
 public:
  OptionError(std::string field, std::string problem)
      : InputError(field + ": " + problem),
        field_(std::move(field)),
        problem_(std::move(problem)) {}
  const std::string& field() const { return field_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string field_, problem_;
};

[[noreturn]] void assertion_failed(const char* expr, const char* file, int line);

}  // namespace fuzzycsg

#if defined(FUZZYCSG_ENABLE_ASSERTS)
#define FUZZYCSG_ASSERT(expr) \
  ((expr) ? static_cast<void>(0) : ::fuzzycsg::assertion_failed(#expr, __FILE__, __LINE__))
#else
#define FUZZYCSG_ASSERT(expr) static_cast<void>(0)
#endif
