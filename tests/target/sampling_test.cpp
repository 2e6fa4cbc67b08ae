// The training distribution (draw_samples), uniform points, and the choice of loader.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/target.hpp"
#include "mesh_support.hpp"
#include "test_support.hpp"

namespace fuzzycsg::test {
namespace {

TEST(UniformPoints, RangeAndDeterminism) {
  for (int dim : {2, 3}) {
    Rng a(1), b(1), c(2);
    const std::vector<float> p = uniform_points(dim, 50000, a);
    ASSERT_EQ(p.size(), 50000u * dim);
    EXPECT_EQ(p, uniform_points(dim, 50000, b));
    EXPECT_NE(p, uniform_points(dim, 50000, c));
    double mean = 0, below = 0;
    for (float x : p) {
      ASSERT_LE(std::abs(x), 1.0f);
      mean += x / p.size();
      below += x < -0.5f;
    }
    EXPECT_NEAR(mean, 0.0, 4 * std::sqrt(1.0 / 3 / p.size()));
    EXPECT_NEAR(below / p.size(), 0.25, tolerance(0.25, p.size()));
  }
  Rng rng(1);
  EXPECT_TRUE(uniform_points(3, 0, rng).empty());
  EXPECT_THROW(uniform_points(0, 5, rng), InputError);
}

// A 2 x 1 x 1 box mesh: normalised to half-extents 0.8, 0.4, 0.4 (padding 0.2) or 1, 0.5, 0.5
// (padding 0). Boundary samples lie exactly on a face plane (a float coordinate equal to the
// half-extent); no other point does.
class DrawSamples : public ::testing::Test {
 protected:
  std::unique_ptr<Target> box(double padding) {
    return load_target(dir_.write("box.off", to_off(test::box({0, 0, 0}, {2, 1, 1}))),
                       TargetOptions{padding, 256, 0});
  }
  static bool on_face(const float* p, const Vec3& half) {
    bool in = true, on = false;
    for (int k = 0; k < 3; ++k) {
      in = in && std::abs(p[k]) <= static_cast<float>(half[k]);
      on = on || std::abs(p[k]) == static_cast<float>(half[k]);
    }
    return in && on;
  }
  // Distance from p to the surface of the box, inside or out.
  static double distance(const float* p, const Vec3& half) {
    double outside = 0, inside = 1e9;
    for (int k = 0; k < 3; ++k) {
      const double q = std::abs(p[k]) - half[k];
      outside += std::max(q, 0.0) * std::max(q, 0.0);
      inside = std::min(inside, -q);
    }
    return outside > 0 ? std::sqrt(outside) : inside;
  }
  TempDir dir_;
};

TEST_F(DrawSamples, ProportionsLabelsAndShuffle) {
  const auto target = box(0.2);
  const Vec3 half = {0.8, 0.4, 0.4};
  Rng rng(7);
  const std::size_t n = 10000;
  const SampleSet set = draw_samples(*target, n, SamplingOptions{}, rng);
  EXPECT_EQ(set.dim, 3);
  ASSERT_EQ(set.size(), n);
  ASSERT_EQ(set.points.size(), 3 * n);
  std::vector<float> labels(n);
  target->occupancy(set.points, labels);
  EXPECT_EQ(set.occupancy, labels);

  int surface = 0, band = 0, surface_in_first_tenth = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &set.points[3 * i];
    for (int k = 0; k < 3; ++k) ASSERT_LE(std::abs(p[k]), 1.0f);
    if (on_face(p, half)) {
      ++surface;
      surface_in_first_tenth += i < n / 10;
    } else if (distance(p, half) <= 0.1 + 1e-6) {
      ++band;
    }
  }
  EXPECT_EQ(surface, 4000);
  // The 4000 near points, and the uniform points that fall in the band within 0.1 of the
  // surface: (1.8 * 1.0 * 1.0 - 1.4 * 0.6 * 0.6) / 8 of the cube.
  const double share = (1.8 - 1.4 * 0.6 * 0.6) / 8;
  EXPECT_NEAR(band, 4000 + 2000 * share, 4 * std::sqrt(2000 * share * (1 - share)));
  EXPECT_NEAR(surface_in_first_tenth, 400, 4 * std::sqrt(1000 * 0.4 * 0.6));  // shuffled
}

TEST_F(DrawSamples, OtherProportionsAndClipping) {
  const auto target = box(0.0);  // the box touches x = +-1
  const Vec3 half = {1.0, 0.5, 0.5};
  Rng rng(8);
  const SampleSet set = draw_samples(*target, 5000, SamplingOptions{0.1, 0.7, 0.05}, rng);
  int surface = 0, band = 0, clipped = 0;
  for (std::size_t i = 0; i < 5000; ++i) {
    const float* p = &set.points[3 * i];
    for (int k = 0; k < 3; ++k) ASSERT_LE(std::abs(p[k]), 1.0f);
    if (on_face(p, half)) {
      ++surface;
      clipped += std::abs(p[1]) < 0.5f && std::abs(p[2]) < 0.5f;  // on x = +-1, maybe clipped
    } else if (distance(p, half) <= 0.05 + 1e-6) {
      ++band;
    }
  }
  // Near points pushed beyond x = +-1 are clipped back onto the faces x = +-1: half of those
  // drawn on these faces (area 2 of 10), so 0.7 * 5000 * 0.2 / 2 = 350.
  EXPECT_NEAR(surface, 500 + 350, 4 * std::sqrt(350.0));
  EXPECT_GT(clipped, 350);
  const double share = (2.0 * 1.1 * 1.1 - 1.9 * 0.9 * 0.9) / 8 / 2;  // the band inside the cube
  EXPECT_NEAR(band, 3500 - 350 + 1000 * share, 4 * std::sqrt(350.0 + 1000 * share));

  // All on the surface; nothing at all.
  Rng r2(9);
  const SampleSet all = draw_samples(*target, 1000, SamplingOptions{1.0, 0.0, 0.1}, r2);
  for (std::size_t i = 0; i < 1000; ++i) EXPECT_TRUE(on_face(&all.points[3 * i], half));
  EXPECT_EQ(draw_samples(*target, 0, SamplingOptions{}, r2).size(), 0u);
}

TEST_F(DrawSamples, DeterministicForASeed) {
  const auto target = box(0.2);
  Rng a(5), b(5), c(6);
  const SampleSet sa = draw_samples(*target, 3000, SamplingOptions{}, a);
  const SampleSet sb = draw_samples(*target, 3000, SamplingOptions{}, b);
  const SampleSet sc = draw_samples(*target, 3000, SamplingOptions{}, c);
  EXPECT_EQ(sa.points, sb.points);
  EXPECT_EQ(sa.occupancy, sb.occupancy);
  EXPECT_NE(sa.points, sc.points);
}

TEST_F(DrawSamples, BadOptions) {
  const auto target = box(0.2);
  Rng rng(1);
  const auto error = [&](SamplingOptions o) -> std::string {
    try {
      draw_samples(*target, 10, o, rng);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(error({-0.1, 0.4, 0.1}), "draw_samples: surface must be in [0, 1] (got -0.1)");
  EXPECT_EQ(error({0.4, 1.5, 0.1}), "draw_samples: near must be in [0, 1] (got 1.5)");
  EXPECT_EQ(error({0.6, 0.6, 0.1}), "draw_samples: surface + near must be <= 1 (got 1.2)");
  EXPECT_EQ(error({0.4, 0.4, -1}), "draw_samples: near_distance must be finite and >= 0 (got -1)");
  EXPECT_EQ(error({0.4, 0.4, NAN}),
            "draw_samples: near_distance must be finite and >= 0 (got nan)");
}

TEST(LoadTarget, ChoosesByExtension) {
  TempDir dir;
  EXPECT_EQ(load_error(dir.write("shape.xyz", "1 2 3")),
            dir.file("shape.xyz") +
                ": unknown kind of target (extension \".xyz\"; expected .obj .stl .ply .off, .png "
                ".jpg .jpeg .pbm .pgm or .json)");
  EXPECT_EQ(load_error(dir.write("shape", "1 2 3")),
            dir.file("shape") +
                ": unknown kind of target (no extension; expected .obj .stl .ply .off, .png .jpg "
                ".jpeg .pbm .pgm or .json)");
  const std::string tree =
      dir.write("T.JSON", R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,)"
                          R"( "root": {"type": "circle", "radius": 0.5}})");
  EXPECT_EQ(load_target(tree)->kind(), "tree");
  EXPECT_EQ(load_target(dir.write("b.Off", to_off(box({0, 0, 0}, {1, 1, 1}))))->kind(), "mesh");
  EXPECT_EQ(load_target(dir.write("p.Pbm", "P1 2 1 1 0"))->kind(), "image");
}

}  // namespace
}  // namespace fuzzycsg::test
