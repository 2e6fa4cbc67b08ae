#pragma once
// Shared by the fit tests: analytic targets with exact occupancy and exact boundary samples,
// random points, tree evaluation and temporary files.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg::testing {

// Writes `text` to the test's temporary directory as `name`; returns the path.
inline std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write " + path);
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error("cannot write " + path);
  return path;
}

// The ball (3D) or disc (2D) of radius `radius` about `center`.
class BallTarget : public Target {
 public:
  BallTarget(int dim, std::vector<double> center, double radius)
      : dim_(dim), center_(std::move(center)), radius_(radius) {}

  int dim() const override { return dim_; }
  std::string describe() const override { return "ball r=" + std::to_string(radius_); }
  std::string kind() const override { return "ball"; }

  void occupancy(std::span<const float> points, std::span<float> out) const override {
    const auto d = static_cast<std::size_t>(dim_);
    for (std::size_t i = 0; i < out.size(); ++i) {
      double r2 = 0.0;
      for (std::size_t k = 0; k < d; ++k) {
        const double x = points[i * d + k] - center_[k];
        r2 += x * x;
      }
      out[i] = r2 < radius_ * radius_ ? 1.0f : 0.0f;
    }
  }

  // Uniform directions (normalised Gaussian vectors) are uniform on the sphere or circle.
  void sample_boundary(std::size_t n, Rng& rng, std::vector<float>& points,
                       std::vector<float>& normals) const override {
    const auto d = static_cast<std::size_t>(dim_);
    std::normal_distribution<double> g;
    points.resize(n * d);
    normals.resize(n * d);
    for (std::size_t i = 0; i < n; ++i) {
      double v[3] = {0, 0, 0}, len = 0.0;
      while (len < 1e-12) {
        len = 0.0;
        for (std::size_t k = 0; k < d; ++k) {
          v[k] = g(rng);
          len += v[k] * v[k];
        }
      }
      len = std::sqrt(len);
      for (std::size_t k = 0; k < d; ++k) {
        normals[i * d + k] = static_cast<float>(v[k] / len);
        points[i * d + k] = static_cast<float>(center_[k] + radius_ * v[k] / len);
      }
    }
  }

 private:
  int dim_;
  std::vector<double> center_;
  double radius_;
};

inline std::vector<float> random_points(std::size_t n, int dim, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> p(n * static_cast<std::size_t>(dim));
  for (float& v : p) v = u(rng);
  return p;
}

inline std::vector<float> occupancy(const Tree& tree, std::span<const float> points) {
  const Evaluator evaluator(tree, EvalOptions{2});
  std::vector<float> out(points.size() / static_cast<std::size_t>(tree.dim));
  evaluator.forward(tree.params.values(), points, out);
  return out;
}

inline double mse(const std::vector<float>& a, const std::vector<float>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double d = static_cast<double>(a[i]) - b[i];
    s += d * d;
  }
  return s / static_cast<double>(a.size());
}

// The message validate() throws for `o`, or "" when it accepts them.
inline std::string validation_message(const FitOptions& o, int dim) {
  try {
    validate(o, dim);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace fuzzycsg::testing
