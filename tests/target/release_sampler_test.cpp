// The 2D sampler of the authors' release (SamplingScheme::kRelease): its distance field against
// brute force, the density of its points against the formula on a disc, determinism, errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/signed_distance_grid.hpp"
#include "fuzzycsg/target/target.hpp"
#include "mesh_support.hpp"
#include "test_support.hpp"

namespace fuzzycsg::test {
namespace {

// The release's weight, written out here as utils/sample_image_points.py has it:
// exp(1 / (|sdf| / softness + 0.2)) with softness 5 and the sdf in pixels.
double weight(double d) { return std::exp(1.0 / (std::abs(d) / 5.0 + 0.2)); }

// An n x n mask, row 0 at the top, of the disc of centre (cx, cy) and radius r in [-1, 1]^2.
std::vector<std::uint8_t> disc_mask(int n, double cx, double cy, double r) {
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(n) * n);
  const double h = 2.0 / n;
  for (int row = 0; row < n; ++row) {
    for (int col = 0; col < n; ++col) {
      const double x = -1 + (col + 0.5) * h, y = 1 - (row + 0.5) * h;
      mask[static_cast<std::size_t>(row) * n + col] = std::hypot(x - cx, y - cy) < r ? 1 : 0;
    }
  }
  return mask;
}

// The mask as a binary PGM (inside black), which the image target reads pixel for pixel at
// image_resolution n.
std::string write_pgm(const TempDir& dir, const std::string& name,
                      const std::vector<std::uint8_t>& mask, int n) {
  std::string bytes = "P5\n" + std::to_string(n) + " " + std::to_string(n) + "\n255\n";
  for (std::uint8_t m : mask) bytes.push_back(static_cast<char>(m ? 0 : 255));
  return dir.write(name, bytes);
}

SamplingOptions release() {
  SamplingOptions o;
  o.scheme = SamplingScheme::kRelease;
  return o;
}

TEST(SamplingScheme, Names) {
  EXPECT_EQ(sampling_scheme_name(SamplingScheme::kAppendixA), "appendix-a");
  EXPECT_EQ(sampling_scheme_name(SamplingScheme::kRelease), "release");
  EXPECT_EQ(sampling_scheme_from_name("appendix-a"), SamplingScheme::kAppendixA);
  EXPECT_EQ(sampling_scheme_from_name("release"), SamplingScheme::kRelease);
  EXPECT_EQ(sampling_scheme_from_name("Release"), std::nullopt);
  EXPECT_EQ(sampling_scheme_from_name(""), std::nullopt);
  EXPECT_EQ(SamplingOptions{}.scheme, SamplingScheme::kAppendixA);
}

// At the pixel centres: + the distance in pixels to the nearest inside centre outside, - the
// distance to the nearest outside centre inside (scipy's distance_transform_edt), by brute
// force; bilinear between the centres and constant beyond the outermost ones.
TEST(SignedDistanceGrid, CentreDistanceIsTheReleaseField) {
  Rng rng(4);
  for (const double density : {0.05, 0.4}) {
    const int n = 23;
    std::vector<std::uint8_t> mask(n * n);
    for (auto& m : mask) m = (rng() % 1000) < density * 1000 ? 1 : 0;
    mask[0] = 1;
    mask[1] = 0;
    const SignedDistanceGrid grid(mask, n);
    const double h = grid.cell();
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c) {
        const bool in = mask[r * n + c] != 0;
        double best = std::numeric_limits<double>::infinity();
        for (int r2 = 0; r2 < n; ++r2) {
          for (int c2 = 0; c2 < n; ++c2) {
            if ((mask[r2 * n + c2] != 0) != in) best = std::min(best, std::hypot(r - r2, c - c2));
          }
        }
        const double expected = in ? -best : best;
        ASSERT_NEAR(grid.centre_distance_at(r, c), expected, 1e-4) << r << " " << c;
        const double x = -1 + (c + 0.5) * h, y = 1 - (r + 0.5) * h;
        ASSERT_NEAR(grid.centre_distance(x, y), expected, 1e-4);
      }
    }
    // Bilinear: the middle of a cell is the mean of its corners, a point a quarter along an
    // edge three quarters of one corner and one of the other.
    for (int r = 0; r + 1 < n; r += 3) {
      for (int c = 0; c + 1 < n; c += 2) {
        const double x = -1 + (c + 1) * h, y = 1 - (r + 1) * h;
        const double mean =
            (grid.centre_distance_at(r, c) + grid.centre_distance_at(r, c + 1) +
             grid.centre_distance_at(r + 1, c) + grid.centre_distance_at(r + 1, c + 1)) /
            4;
        EXPECT_NEAR(grid.centre_distance(x, y), mean, 1e-4);
        const double xq = -1 + (c + 0.75) * h, yq = 1 - (r + 0.5) * h;
        EXPECT_NEAR(grid.centre_distance(xq, yq),
                    0.75 * grid.centre_distance_at(r, c) + 0.25 * grid.centre_distance_at(r, c + 1),
                    1e-4);
      }
    }
    // Beyond the outermost centres: the value at the nearest one.
    EXPECT_NEAR(grid.centre_distance(-1.0, 1.0), grid.centre_distance_at(0, 0), 1e-6);
    EXPECT_NEAR(grid.centre_distance(1.0, -1.0), grid.centre_distance_at(n - 1, n - 1), 1e-6);
  }
}

// On a disc of 256^2 pixels: a quarter of the points uniform and the rest with density
// proportional to the release's weight. The expected share of points in each band of signed
// distance d (inside and outside apart) comes from integrating that density over the square on
// a fine grid.
TEST(ReleaseSampler, DensityFollowsTheFormula) {
  const int n = 256;
  const std::vector<std::uint8_t> mask = disc_mask(n, 0.2, -0.1, 0.5);
  TempDir dir;
  const auto target = load_target(write_pgm(dir, "disc.pgm", mask, n), TargetOptions{0.2, n, 2});
  const SignedDistanceGrid grid(mask, n);  // the target's own grid

  const std::vector<double> edges = {-1e9, -32, -16, -8, -4, -2, -1, -0.5, -0.25, 0,
                                     0.25, 0.5, 1,   2,  4,  8,  16, 32,   1e9};
  const std::size_t bands = edges.size() - 1;
  const auto band_of = [&](double d) {
    return static_cast<std::size_t>(std::upper_bound(edges.begin(), edges.end(), d) -
                                    edges.begin() - 1);
  };
  // Area (in units of the square's) and integral of the weight of each band.
  std::vector<double> area(bands, 0.0), mass(bands, 0.0);
  double total_mass = 0;
  const int m = 4096;
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) {
      const double d = grid.centre_distance(-1 + (j + 0.5) * 2.0 / m, 1 - (i + 0.5) * 2.0 / m);
      const std::size_t b = band_of(d);
      area[b] += 1.0 / (static_cast<double>(m) * m);
      mass[b] += weight(d);
      total_mass += weight(d);
    }
  }
  const auto expected_share = [&](std::size_t b, double uniform) {
    return uniform * area[b] + (1 - uniform) * mass[b] / total_mass;
  };

  Rng rng(11);
  std::vector<double> count(bands, 0.0);
  std::size_t points = 0;
  for (int round = 0; round < 200; ++round) {
    const SampleSet set = draw_samples(*target, 1024, release(), rng);
    ASSERT_EQ(set.size(), 1024u);
    ASSERT_EQ(set.dim, 2);
    std::vector<float> labels(set.size());
    target->occupancy(set.points, labels);
    ASSERT_EQ(set.occupancy, labels);
    for (std::size_t i = 0; i < set.size(); ++i) {
      const double x = set.points[2 * i], y = set.points[2 * i + 1];
      ASSERT_LE(std::abs(x), 1.0);
      ASSERT_LE(std::abs(y), 1.0);
      count[band_of(grid.centre_distance(x, y))] += 1;
    }
    points += set.size();
  }
  for (std::size_t b = 0; b < bands; ++b) {
    const double p = expected_share(b, 0.25);
    // Four standard errors, and 0.3% for the integration.
    EXPECT_NEAR(count[b] / points, p, tolerance(p, points, 0.003 * p))
        << "band " << edges[b] << " to " << edges[b + 1] << " pixels";
  }
  // Concentrated at the boundary: within a quarter of a pixel of it the density is more than
  // 30 times that more than 32 pixels away, as the formula says.
  const std::size_t zero = band_of(0.0), far = bands - 1;
  const double ratio = (count[zero] / area[zero]) / (count[far] / area[far]);
  const double formula =
      (expected_share(zero, 0.25) / area[zero]) / (expected_share(far, 0.25) / area[far]);
  EXPECT_GT(formula, 30);
  EXPECT_NEAR(ratio, formula, 0.1 * formula);
  // The test tells a quarter of uniform points from a fifth or a third.
  for (const double other : {0.2, 1.0 / 3}) {
    const double p = expected_share(far, 0.25);
    EXPECT_GT(std::abs(expected_share(far, other) - p), tolerance(p, points, 0.003 * p));
  }
}

TEST(ReleaseSampler, DeterministicForASeedAndAnyThreadCount) {
  const int n = 64;
  const std::vector<std::uint8_t> mask = disc_mask(n, -0.1, 0.3, 0.4);
  TempDir dir;
  const std::string path = write_pgm(dir, "disc.pgm", mask, n);
  const auto a = load_target(path, TargetOptions{0.2, n, 1});
  const auto b = load_target(path, TargetOptions{0.2, n, 2});
  Rng ra(5), rb(5), rc(6);
  const SampleSet sa = draw_samples(*a, 2000, release(), ra);
  const SampleSet sb = draw_samples(*b, 2000, release(), rb);
  const SampleSet sc = draw_samples(*a, 2000, release(), rc);
  EXPECT_EQ(sa.points, sb.points);
  EXPECT_EQ(sa.occupancy, sb.occupancy);
  EXPECT_NE(sa.points, sc.points);
  // The generator moves on: the next draw differs from the first.
  EXPECT_NE(draw_samples(*a, 2000, release(), ra).points, sa.points);
  // Shuffled: the uniform quarter is not at either end.
  const SignedDistanceGrid grid(mask, n);
  double far_first = 0, far_last = 0;
  for (std::size_t i = 0; i < 500; ++i) {
    far_first += std::abs(grid.centre_distance(sa.points[2 * i], sa.points[2 * i + 1])) > 10;
    const std::size_t j = 1999 - i;
    far_last += std::abs(grid.centre_distance(sa.points[2 * j], sa.points[2 * j + 1])) > 10;
  }
  EXPECT_GT(far_first, 0);
  EXPECT_GT(far_last, 0);
  EXPECT_LT(far_first, 400);
  EXPECT_LT(far_last, 400);
  // Small sizes.
  EXPECT_EQ(draw_samples(*a, 0, release(), ra).size(), 0u);
  EXPECT_EQ(draw_samples(*a, 1, release(), ra).size(), 1u);
  EXPECT_EQ(draw_samples(*a, 3, release(), ra).points.size(), 6u);
}

TEST(ReleaseSampler, OnlyForPictures) {
  TempDir dir;
  const auto mesh = load_target(dir.write("box.off", to_off(box({0, 0, 0}, {2, 1, 1}))));
  const auto tree =
      load_target(dir.write("t.json", R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,)"
                                      R"( "root": {"type": "circle", "radius": 0.5}})"));
  const auto message = [](const Target& t) -> std::string {
    Rng rng(1);
    try {
      draw_samples(t, 100, release(), rng);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message(*mesh), "sampling.scheme: release: only for pictures (the target is a mesh)");
  EXPECT_EQ(message(*tree), "sampling.scheme: release: only for pictures (the target is a tree)");
  Rng rng(1);
  std::vector<float> points;
  EXPECT_THROW(tree->sample_distance_weighted(10, rng, points), InputError);
  // App. A's sampler still serves both.
  EXPECT_EQ(draw_samples(*tree, 100, SamplingOptions{}, rng).size(), 100u);
}

}  // namespace
}  // namespace fuzzycsg::test
