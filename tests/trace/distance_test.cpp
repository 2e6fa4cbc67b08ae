// The distance map against brute force, and its extrema on known shapes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fuzzycsg/trace/evaluate.hpp"
#include "trace/distance.hpp"

namespace fuzzycsg::trace {
namespace {

TEST(TraceDistance, MatchesBruteForceOnSmallRandomBitmaps) {
  Rng rng(21);
  for (int trial = 0; trial < 200; ++trial) {
    const int w = 1 + static_cast<int>(rng() % 17), h = 1 + static_cast<int>(rng() % 13);
    const double density = uniform01(rng);
    Bitmap b(w, h);
    for (int j = 0; j < h; ++j) {
      for (int i = 0; i < w; ++i) b.set(i, j, uniform01(rng) < density);
    }
    const DistanceMap d = distance_map(b);
    for (int j = 0; j < h; ++j) {
      for (int i = 0; i < w; ++i) {
        double to_clear = std::numeric_limits<double>::infinity();
        double to_set = std::numeric_limits<double>::infinity();
        // Clear pixels: those of the bitmap and the frame of clear pixels around it.
        for (int y = -1; y <= h; ++y) {
          for (int x = -1; x <= w; ++x) {
            const bool in_image = x >= 0 && y >= 0 && x < w && y < h;
            const double dist = std::hypot(x - i, y - j);
            if (!in_image || !b.get(x, y)) to_clear = std::min(to_clear, dist);
            if (in_image && b.get(x, y)) to_set = std::min(to_set, dist);
          }
        }
        if (b.get(i, j)) {
          ASSERT_NEAR(d.inside_at(i, j), to_clear, 1e-12) << trial << " " << i << " " << j;
          ASSERT_EQ(d.outside_at(i, j), 0.0);
        } else {
          ASSERT_EQ(d.inside_at(i, j), 0.0);
          if (std::isinf(to_set)) {
            ASSERT_TRUE(std::isinf(d.outside_at(i, j)));
          } else {
            ASSERT_NEAR(d.outside_at(i, j), to_set, 1e-12) << trial << " " << i << " " << j;
          }
        }
      }
    }
  }
}

TEST(TraceDistance, DiscCentreIsTheMaximum) {
  const int n = 101;
  Bitmap b(n, n);
  const double r = 30;
  scan_convert(Primitive{Shape::kCircle, 50.5, 50.5, r}, b);
  const DistanceMap d = distance_map(b);
  const Extrema e = distance_extrema(d);
  ASSERT_FALSE(e.maxima.empty());
  EXPECT_EQ(e.maxima[0].col, 50);
  EXPECT_EQ(e.maxima[0].row, 50);
  EXPECT_NEAR(e.maxima[0].distance, r, 1.0);
  // The centre alone reaches that depth.
  ASSERT_GE(e.maxima.size(), 1u);
  if (e.maxima.size() > 1) {
    EXPECT_LT(e.maxima[1].distance, e.maxima[0].distance);
  }
  // Outside, the maxima are the corners of the image, furthest from the disc.
  ASSERT_FALSE(e.minima.empty());
  EXPECT_NEAR(e.minima[0].distance, std::hypot(50.0, 50.0) - r, 1.0);
  const int c = e.minima[0].col, row = e.minima[0].row;
  EXPECT_TRUE((c == 0 || c == n - 1) && (row == 0 || row == n - 1));
}

TEST(TraceDistance, AHoleIsAnOutsideMaximum) {
  // A ring: a disc of radius 30 less one of radius 10; the hole's centre is a local maximum of
  // the outside map (a "local minimum" of the shape) with d ~ 10.
  const int n = 80;
  Bitmap disc(n, n), hole(n, n);
  scan_convert(Primitive{Shape::kCircle, 40.5, 40.5, 30}, disc);
  scan_convert(Primitive{Shape::kCircle, 40.5, 40.5, 10}, hole);
  Bitmap ring(n, n);
  for (std::size_t i = 0; i < ring.words().size(); ++i) {
    ring.words()[i] = disc.words()[i] & ~hole.words()[i];
  }
  const Extrema e = distance_extrema(distance_map(ring));
  bool found = false;
  for (const Extremum& m : e.minima) {
    if (m.col == 40 && m.row == 40) {
      found = true;
      EXPECT_NEAR(m.distance, 10.0, 1.0);
    }
  }
  EXPECT_TRUE(found);
  // And the ring's medial circle (radius 20) carries the inside maxima, d ~ 10.
  ASSERT_FALSE(e.maxima.empty());
  for (const Extremum& m : e.maxima) {
    EXPECT_NEAR(std::hypot(m.col + 0.5 - 40.5, m.row + 0.5 - 40.5), 20.0, 2.5);
    EXPECT_NEAR(m.distance, 10.0, 1.5);
  }
}

TEST(TraceDistance, EmptyAndFullBitmaps) {
  const Bitmap empty(5, 4);
  const DistanceMap d = distance_map(empty);
  EXPECT_TRUE(std::isinf(d.outside_at(2, 2)));
  const Extrema e = distance_extrema(d);
  EXPECT_TRUE(e.maxima.empty());
  EXPECT_TRUE(e.minima.empty());
  Bitmap full(5, 5);
  for (int j = 0; j < 5; ++j) full.set_span(j, 0, 5);
  const DistanceMap f = distance_map(full);
  EXPECT_DOUBLE_EQ(f.inside_at(2, 2), 3.0);  // to the frame
  EXPECT_DOUBLE_EQ(f.inside_at(0, 0), 1.0);
  const Extrema fe = distance_extrema(f);
  ASSERT_EQ(fe.maxima.size(), 1u);
  EXPECT_EQ(fe.maxima[0].col, 2);
}

}  // namespace
}  // namespace fuzzycsg::trace
