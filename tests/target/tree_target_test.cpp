// Tree targets: spheres and circles written here against their analytic boundary (labels,
// boundary points, normals, uniformity), domains, crisp steps, the examples, bad trees.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/target.hpp"
#include "test_support.hpp"

namespace fuzzycsg::test {
namespace {

std::string tree_json(int dim, const std::string& root, const std::string& extra = "") {
  return R"({"format": "fuzzycsg-tree", "version": 1, "dim": )" + std::to_string(dim) + extra +
         R"(, "root": )" + root + "}";
}

constexpr double kRadius = 0.5;
const double kC[3] = {0.1, -0.2, 0.05};  // the sphere's centre

const std::string kSphere =
    R"({"type": "sphere", "radius": 0.5, "translate": [0.1, -0.2, 0.05], "sharpness": 50})";

TEST(TreeTarget, Sphere) {
  TempDir dir;
  const auto target = load_target(dir.write("sphere.json", tree_json(3, kSphere)));
  EXPECT_EQ(target->kind(), "tree");
  EXPECT_EQ(target->dim(), 3);
  EXPECT_EQ(target->describe(), "tree sphere.json: 3D, 1 primitive, 0 operators");

  // A sigmoid step is 0.5 exactly where the distance is 0: the crisp target is the ball.
  Rng rng(1);
  const std::size_t n = 200000;
  const std::vector<float> points = uniform_points(3, n, rng);
  std::vector<float> occ(n);
  target->occupancy(points, occ);
  double inside = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double d =
        std::hypot(points[3 * i] - kC[0], points[3 * i + 1] - kC[1], points[3 * i + 2] - kC[2]) -
        kRadius;
    if (std::abs(d) > 1e-5) {
      ASSERT_EQ(occ[i], d < 0 ? 1.0f : 0.0f) << d;
    }
    inside += occ[i];
  }
  const double ball = 4.0 / 3.0 * std::numbers::pi * kRadius * kRadius * kRadius / 8;
  EXPECT_NEAR(inside / n, ball, tolerance(ball, n));

  // Boundary points on the sphere, normals radial; uniform on the sphere: by Archimedes, each
  // coordinate is uniform on [c - r, c + r], so each quarter of that range gets a quarter.
  const std::size_t m = 20000;
  std::vector<float> b, nrm;
  target->sample_boundary(m, rng, b, nrm);
  ASSERT_EQ(b.size(), 3 * m);
  ASSERT_EQ(nrm.size(), 3 * m);
  std::array<std::array<int, 4>, 3> quarter{};
  for (std::size_t s = 0; s < m; ++s) {
    double u[3], r = 0;
    for (int k = 0; k < 3; ++k) u[k] = b[3 * s + k] - kC[k], r += u[k] * u[k];
    r = std::sqrt(r);
    EXPECT_NEAR(r, kRadius, 2e-5);
    double dot = 0, len = 0;
    for (int k = 0; k < 3; ++k)
      dot += nrm[3 * s + k] * u[k] / r, len += nrm[3 * s + k] * nrm[3 * s + k];
    EXPECT_NEAR(len, 1.0, 1e-5);
    EXPECT_GT(dot, 0.9999);
    for (int k = 0; k < 3; ++k) {
      ++quarter[k][std::clamp(static_cast<int>((u[k] / kRadius + 1) * 2), 0, 3)];
    }
  }
  for (int k = 0; k < 3; ++k) {
    for (int q = 0; q < 4; ++q) EXPECT_NEAR(quarter[k][q] / double(m), 0.25, tolerance(0.25, m));
  }
}

// 2D: a circle united with a rectangle; boundary points on the union's boundary, outward.
TEST(TreeTarget, CircleAndRectangle) {
  TempDir dir;
  const std::string root = R"({"op": "union", "logic": "godel", "children": [
      {"type": "circle", "radius": 0.4, "translate": [-0.3, 0.1], "sharpness": 100},
      {"type": "rectangle", "size": [0.8, 0.5], "translate": [0.4, -0.2], "sharpness": 100}]})";
  const auto target = load_target(dir.write("shape.json", tree_json(2, root)));
  EXPECT_EQ(target->describe(), "tree shape.json: 2D, 2 primitives, 1 operator");
  EXPECT_EQ(target->dim(), 2);
  const auto circle = [](double x, double y) { return std::hypot(x + 0.3, y - 0.1) - 0.4; };
  const auto rectangle = [](double x, double y) {
    const double qx = std::abs(x - 0.4) - 0.4, qy = std::abs(y + 0.2) - 0.25;
    return std::hypot(std::max(qx, 0.0), std::max(qy, 0.0)) + std::min(std::max(qx, qy), 0.0);
  };
  const auto sdf = [&](double x, double y) { return std::min(circle(x, y), rectangle(x, y)); };
  Rng rng(2);
  const std::size_t m = 20000;
  std::vector<float> b, nrm;
  target->sample_boundary(m, rng, b, nrm);
  ASSERT_EQ(b.size(), 2 * m);
  int on_circle = 0;
  std::vector<float> probes;
  for (std::size_t s = 0; s < m; ++s) {
    const double x = b[2 * s], y = b[2 * s + 1];
    EXPECT_LT(std::abs(sdf(x, y)), 2e-5);
    on_circle += std::abs(circle(x, y)) < 1e-4;
    for (float sign : {1.0f, -1.0f}) {
      probes.push_back(b[2 * s] + sign * 1e-3f * nrm[2 * s]);
      probes.push_back(b[2 * s + 1] + sign * 1e-3f * nrm[2 * s + 1]);
    }
  }
  std::vector<float> labels(2 * m);
  target->occupancy(probes, labels);
  int good = 0;
  for (std::size_t s = 0; s < m; ++s) good += labels[2 * s] == 0 && labels[2 * s + 1] == 1;
  EXPECT_GT(good, 0.99 * m);
  // Uniform by length: the share of the circle's arc in the union's boundary, measured on a
  // fine polygon of the boundary.
  double arc = 0;
  for (int k = 0; k < 100000; ++k) {
    const double a0 = 2 * std::numbers::pi * k / 100000,
                 a1 = 2 * std::numbers::pi * (k + 1) / 100000;
    const double x = -0.3 + 0.4 * std::cos((a0 + a1) / 2), y = 0.1 + 0.4 * std::sin((a0 + a1) / 2);
    if (rectangle(x, y) > 0) arc += 0.4 * (a1 - a0);
  }
  double total = arc;
  for (int k = 0; k < 100000; ++k) {            // the rectangle's perimeter outside the circle
    const double t = (k + 0.5) / 100000 * 2.6;  // 0.8 + 0.5 + 0.8 + 0.5
    double x, y;
    if (t < 0.8)
      x = t, y = -0.45;
    else if (t < 1.3)
      x = 0.8, y = -0.45 + (t - 0.8);
    else if (t < 2.1)
      x = 0.8 - (t - 1.3), y = 0.05;
    else
      x = 0.0, y = 0.05 - (t - 2.1);
    if (circle(x, y) > 0) total += 2.6 / 100000;
  }
  const double share = arc / total;
  EXPECT_NEAR(on_circle / double(m), share, tolerance(share, m));

  const std::vector<float> points = uniform_points(2, 100000, rng);
  std::vector<float> occ(100000);
  target->occupancy(points, occ);
  for (std::size_t i = 0; i < 100000; ++i) {
    const double d = sdf(points[2 * i], points[2 * i + 1]);
    if (std::abs(d) > 1e-5) {
      ASSERT_EQ(occ[i], d < 0 ? 1.0f : 0.0f) << d;
    }
  }
}

// The tree's domain is what [-1, 1]^dim stands for: centred, scaled by its largest half-extent.
TEST(TreeTarget, Domain) {
  TempDir dir;
  const std::string json =
      tree_json(3, R"({"type": "sphere", "radius": 1, "translate": [3, 1, 1], "sharpness": 50})",
                R"(, "domain": {"min": [1, 0, 0], "max": [5, 2, 2]})");
  const auto target = load_target(dir.write("domain.json", json));
  // Centre (3, 1, 1), half-extent 2: a sphere of radius 0.5 about the origin.
  std::vector<float> occ(3);
  target->occupancy(std::vector<float>{0, 0, 0, 0.45f, 0, 0, 0, 0.55f, 0}, occ);
  EXPECT_EQ(occ, (std::vector<float>{1, 1, 0}));
  Rng rng(3);
  std::vector<float> b, nrm;
  target->sample_boundary(1000, rng, b, nrm);
  for (std::size_t s = 0; s < 1000; ++s) {
    EXPECT_NEAR(std::hypot(b[3 * s], b[3 * s + 1], b[3 * s + 2]), 0.5, 2e-5);
    EXPECT_GT(b[3 * s] * nrm[3 * s] + b[3 * s + 1] * nrm[3 * s + 1] + b[3 * s + 2] * nrm[3 * s + 2],
              0.49);
  }
}

// Crisp steps: the occupancy is a step, central differences see it only across the boundary;
// the normals are coarse but point outward.
TEST(TreeTarget, CrispStep) {
  TempDir dir;
  const auto target = load_target(dir.write(
      "crisp.json", tree_json(3, R"({"type": "sphere", "radius": 0.5, "step": "crisp"})")));
  Rng rng(4);
  std::vector<float> b, nrm;
  target->sample_boundary(2000, rng, b, nrm);
  for (std::size_t s = 0; s < 2000; ++s) {
    const double r = std::hypot(b[3 * s], b[3 * s + 1], b[3 * s + 2]);
    EXPECT_NEAR(r, 0.5, 2e-5);
    const double dot =
        (b[3 * s] * nrm[3 * s] + b[3 * s + 1] * nrm[3 * s + 1] + b[3 * s + 2] * nrm[3 * s + 2]) / r;
    EXPECT_GT(dot, 0.5);
  }
}

TEST(TreeTarget, Examples) {
  for (const char* name : {"box_with_hole.json", "cart_2d.json"}) {
    SCOPED_TRACE(name);
    const auto target = load_target(std::string(FUZZYCSG_SOURCE_DIR) + "/examples/" + name);
    Rng rng(5);
    std::vector<float> b, nrm;
    target->sample_boundary(5000, rng, b, nrm);
    const std::size_t d = static_cast<std::size_t>(target->dim());
    std::vector<float> probes;
    for (std::size_t s = 0; s < 5000; ++s) {
      for (float sign : {1.0f, -1.0f}) {
        for (std::size_t k = 0; k < d; ++k)
          probes.push_back(b[s * d + k] + sign * 2e-3f * nrm[s * d + k]);
      }
    }
    std::vector<float> labels(10000);
    target->occupancy(probes, labels);
    int good = 0;
    for (std::size_t s = 0; s < 5000; ++s) good += labels[2 * s] == 0 && labels[2 * s + 1] == 1;
    EXPECT_GT(good, 0.97 * 5000);
  }
}

TEST(TreeTarget, SamplingIsDeterministic) {
  TempDir dir;
  const std::string path = dir.write("sphere.json", tree_json(3, kSphere));
  const auto a = load_target(path, TargetOptions{0.2, 256, 1});
  const auto b = load_target(path, TargetOptions{0.2, 256, 2});
  Rng ra(9), rb(9);
  std::vector<float> pa, na, pb, nb;
  a->sample_boundary(3000, ra, pa, na);
  b->sample_boundary(3000, rb, pb, nb);
  EXPECT_EQ(pa, pb);
  EXPECT_EQ(na, nb);
  EXPECT_EQ(ra(), rb());
}

TEST(TreeTarget, EmptyFullAndBadTrees) {
  TempDir dir;
  const std::string empty = dir.write(
      "empty.json", tree_json(3, R"({"type": "sphere", "radius": 0.2, "translate": [5, 5, 5]})"));
  EXPECT_EQ(load_error(empty),
            empty + ": the tree is empty: no point of a 65x65x65 grid over [-1, 1]^3 is inside");
  const std::string full =
      dir.write("full.json", tree_json(2, R"({"type": "circle", "radius": 3})"));
  EXPECT_EQ(load_error(full),
            full + ": the tree is full: every point of a 257x257 grid over [-1, 1]^2 is inside");
  for (const auto& [name, text] : {std::pair{"blank.json", ""}, std::pair{"garbage.json", "{\x01"},
                                   std::pair{"wrong.json", "{\"format\": \"other\"}"}}) {
    const std::string path = dir.write(name, text);
    const std::string e = load_error(path);
    EXPECT_EQ(e.substr(0, path.size() + 2), path + ": ") << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  const std::string missing = dir.file("missing.json");
  EXPECT_NE(load_error(missing).find("missing.json"), std::string::npos);
}

}  // namespace
}  // namespace fuzzycsg::test
