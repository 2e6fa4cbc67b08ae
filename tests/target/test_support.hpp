#pragma once
// Shared by the target tests: data files, temporary files, errors, fractions.

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg::test {

namespace fs = std::filesystem;

// A file of tests/data. A missing file throws, which fails the test: these tests never skip.
inline std::string data_file(const std::string& relative) {
  const fs::path path = fs::path(FUZZYCSG_TEST_DATA_DIR) / relative;
  if (!fs::is_regular_file(path)) {
    throw std::runtime_error("missing test data file " + path.string());
  }
  return path.string();
}

// A fresh directory, removed with the object.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() / ("fuzzycsg_target_test." + std::to_string(::getpid()) +
                                         "." + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::string write(const std::string& name, std::string_view bytes) const {
    const std::string path = file(name);
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("cannot write " + path);
    return path;
  }

 private:
  fs::path path_;
};

// The message of the InputError load_target throws, or "no error".
inline std::string load_error(const std::string& path, const TargetOptions& options = {}) {
  try {
    load_target(path, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// Fraction of n uniform points in [-1, 1]^dim that the target says are inside.
inline double inside_fraction(const Target& target, std::size_t n, std::uint64_t seed) {
  Rng rng(seed);
  const std::vector<float> points = uniform_points(target.dim(), n, rng);
  std::vector<float> occ(n);
  target.occupancy(points, occ);
  double inside = 0;
  for (float o : occ) inside += o;
  return inside / static_cast<double>(n);
}

// Four standard errors of a fraction p estimated from n samples, plus `extra`.
inline double tolerance(double p, std::size_t n, double extra = 0.0) {
  return 4.0 * std::sqrt(p * (1.0 - p) / static_cast<double>(n)) + extra;
}

}  // namespace fuzzycsg::test
