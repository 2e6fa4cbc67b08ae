// Metrics against analytic balls, whose MSE, IoU, Chamfer and Hausdorff distances are known in
// closed form (or by a one-dimensional integral), and against a tree file as its own target.
#include "fuzzycsg/target/metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "fit/fit_support.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/transform.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg {
namespace {

using testing::BallTarget;

Tree sphere(double radius, double x, const std::string& step) {
  return io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root":
      {"type": "sphere", "radius": )" +
                              std::to_string(radius) + R"(, "translate": [)" + std::to_string(x) +
                              ", 0, 0], " + step + "}}");
}

Tree circle(double radius, const std::string& step) {
  return io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2, "root":
      {"type": "circle", "radius": )" +
                              std::to_string(radius) + ", " + step + "}}");
}

MetricsOptions metrics_options(std::size_t points, bool chamfer = false) {
  MetricsOptions o;
  o.points = points;
  o.seed = 5;
  o.threads = 2;
  o.chamfer = chamfer;
  o.chamfer_resolution = 64;
  o.chamfer_samples = 50000;
  return o;
}

Metrics measure_tree(const Tree& tree, const Target& target, const MetricsOptions& o) {
  return measure(tree, tree.params.values(), target, o);
}

TEST(Metrics, CrispSphereAgainstTheSameBall) {
  const BallTarget ball(3, {0, 0, 0}, 0.5);
  // More points than one batch, and not a multiple of it.
  const Metrics m =
      measure_tree(sphere(0.5, 0, R"("step": "crisp")"), ball, metrics_options(300001));
  EXPECT_EQ(m.points, 300001u);
  EXPECT_LT(m.mse, 1e-5);
  EXPECT_GT(m.iou, 0.9999);
  EXPECT_FALSE(m.chamfer.has_value());  // not asked for
  EXPECT_FALSE(m.hausdorff.has_value());
}

TEST(Metrics, SigmoidSphereMseIsTheSmoothingError) {
  // o = 1 / (1 + exp(s (rho - r))) against the indicator of rho < r: the mean over the cube
  // [-1, 1]^3 of (o - t)^2 is (1/8) * int 4 pi rho^2 (o - t)^2 drho (the tail beyond rho = 1,
  // where shells leave the cube, is below 1e-8 at s = 20, r = 0.5).
  const double r = 0.5, s = 20.0;
  double integral = 0.0;
  const int steps = 200000;
  const double h = 1.0 / steps;
  for (int i = 0; i < steps; ++i) {
    const double rho = (i + 0.5) * h;
    const double o = 1.0 / (1.0 + std::exp(s * (rho - r)));
    const double d = o - (rho < r ? 1.0 : 0.0);
    integral += 4.0 * std::numbers::pi * rho * rho * d * d * h;
  }
  const double expected = integral / 8.0;
  const BallTarget ball(3, {0, 0, 0}, r);
  const Metrics m = measure_tree(sphere(r, 0, R"("sharpness": 20)"), ball, metrics_options(400000));
  EXPECT_NEAR(m.mse, expected, 0.03 * expected) << "expected " << expected;
  EXPECT_GT(m.iou, 0.999);  // the 0.5 level set is the sphere itself
}

TEST(Metrics, IouOfShiftedBallsIsTheLensRatio) {
  // Two balls of radius R at distance d meet in a lens of volume pi (4R + d)(2R - d)^2 / 12.
  const double R = 0.5, d = 0.3;
  const double lens = std::numbers::pi * (4 * R + d) * (2 * R - d) * (2 * R - d) / 12.0;
  const double ball = 4.0 / 3.0 * std::numbers::pi * R * R * R;
  const double expected = lens / (2 * ball - lens);
  const BallTarget target(3, {0, 0, 0}, R);
  const Metrics m =
      measure_tree(sphere(R, d, R"("step": "crisp")"), target, metrics_options(500000));
  // About 47,000 points fall in the union: the standard error of the ratio is about 0.002.
  EXPECT_NEAR(m.iou, expected, 0.008);
  // Crisp on both sides: the MSE is the volume fraction of the symmetric difference.
  EXPECT_NEAR(m.mse, 2 * (ball - lens) / 8.0, 0.004);
}

TEST(Metrics, ChamferOfConcentricSpheresIsTheRadiusGap) {
  const BallTarget target(3, {0, 0, 0}, 0.6);
  const Metrics m =
      measure_tree(sphere(0.5, 0, R"("sharpness": 50)"), target, metrics_options(10000, true));
  ASSERT_TRUE(m.chamfer.has_value());
  EXPECT_NEAR(*m.chamfer, 0.1, 0.005);
  // Every point of either sphere is 0.1 from the other: the worst place is the average.
  ASSERT_TRUE(m.hausdorff.has_value());
  EXPECT_NEAR(*m.hausdorff, 0.1, 0.01);
  EXPECT_GE(*m.hausdorff, *m.chamfer);
  const Metrics same =
      measure_tree(sphere(0.6, 0, R"("sharpness": 50)"), target, metrics_options(10000, true));
  ASSERT_TRUE(same.chamfer.has_value());
  EXPECT_LT(*same.chamfer, 0.01);
  // The sampling's error alone: a point of the surface is within a grid cell's diagonal
  // (sqrt(3) * 2/64) of a crossing on the cell's edges.
  ASSERT_TRUE(same.hausdorff.has_value());
  EXPECT_LT(*same.hausdorff, std::sqrt(3.0) * 2.0 / 64);
}

TEST(Metrics, HausdorffOfShiftedBallsIsTheShift) {
  // Two balls of radius r, centres d apart: the point of the tree's sphere farthest along the
  // shift is r + d from the target's centre, d from its sphere, and no point is farther. The
  // Chamfer distance, a mean, is well below it (about d / 2).
  const double d = 0.2;
  const BallTarget target(3, {0, 0, 0}, 0.5);
  const Metrics m =
      measure_tree(sphere(0.5, d, R"("sharpness": 50)"), target, metrics_options(10000, true));
  ASSERT_TRUE(m.hausdorff.has_value() && m.chamfer.has_value());
  EXPECT_NEAR(*m.hausdorff, d, 0.01);
  EXPECT_LT(*m.chamfer, 0.7 * d);
  // In 2D the same.
  const BallTarget disc(2, {0.1, 0}, 0.4);
  const Tree shifted = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
      "root": {"type": "circle", "radius": 0.4, "translate": [-0.2, 0], "sharpness": 50}})");
  const Metrics m2 = measure_tree(shifted, disc, metrics_options(10000, true));
  ASSERT_TRUE(m2.hausdorff.has_value());
  EXPECT_NEAR(*m2.hausdorff, 0.3, 0.01);
}

TEST(Metrics, HausdorffOfATreeAgainstItselfIsSmall) {
  // examples/box_with_hole.json's shape (a box less a cylinder, its default domain) as a tree
  // file target: the tree measured against its own 0.5 level set. The Hausdorff distance is the
  // sampling's error alone: a point of the surface is within a cell's diagonal (sqrt(3) * 2/128)
  // of a level-set point on the cell's edges.
  const std::string text = R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
      "root": {"op": "difference", "children": [
        {"type": "box", "size": [1.2, 0.8, 0.4], "sharpness": 80},
        {"type": "cylinder", "radius": 0.15, "height": 1.0, "rotate": [90, 0, 0]}]}})";
  const Tree tree = io::read_tree_string(text);
  const auto target = load_target(testing::write_temp("fuzzycsg_metrics_self.json", text));
  MetricsOptions o = metrics_options(20000, true);
  o.chamfer_resolution = 128;
  const Tree normalised = transformed(tree, target->normalisation());
  const Metrics self = measure_tree(normalised, *target, o);
  ASSERT_TRUE(self.hausdorff.has_value() && self.chamfer.has_value());
  EXPECT_LT(*self.hausdorff, std::sqrt(3.0) * 2.0 / 128);
  EXPECT_LE(*self.chamfer, *self.hausdorff);
  EXPECT_GT(self.iou, 0.99);
  // The same tree moved by 0.1 along x: the distance is the move (the box's end faces), not the
  // sampling's error.
  const Tree moved = transformed(normalised, Similarity{{0.1, 0, 0}, 1.0});
  const Metrics shifted = measure_tree(moved, *target, o);
  ASSERT_TRUE(shifted.hausdorff.has_value());
  EXPECT_NEAR(*shifted.hausdorff, 0.1, 2.0 / 128);
}

TEST(Metrics, ChamferInTwoDimensions) {
  const BallTarget disc(2, {0, 0}, 0.4);
  const Metrics m =
      measure_tree(circle(0.7, R"("sharpness": 50)"), disc, metrics_options(10000, true));
  ASSERT_TRUE(m.chamfer.has_value());
  EXPECT_NEAR(*m.chamfer, 0.3, 0.005);
  // Crisp leaves put every crossing mid-edge: the error is at most half a cell (1/64).
  const Metrics crisp =
      measure_tree(circle(0.7, R"("step": "crisp")"), disc, metrics_options(10000, true));
  ASSERT_TRUE(crisp.chamfer.has_value());
  EXPECT_NEAR(*crisp.chamfer, 0.3, 1.0 / 64.0);
}

TEST(Metrics, NoLevelSetGivesNoChamfer) {
  // A sphere outside the domain: empty everywhere the metrics look.
  const Tree outside = sphere(0.2, 5.0, R"("step": "crisp")");
  const Metrics m =
      measure_tree(outside, BallTarget(3, {0, 0, 0}, 0.5), metrics_options(100000, true));
  EXPECT_FALSE(m.chamfer.has_value());
  EXPECT_FALSE(m.hausdorff.has_value());
  EXPECT_EQ(m.iou, 0.0);
  EXPECT_NEAR(m.mse, 4.0 / 3.0 * std::numbers::pi * 0.125 / 8.0, 0.003);
  // Both empty: IoU 1 by definition.
  const Metrics none =
      measure_tree(outside, BallTarget(3, {0, 0, 0}, 0.0), metrics_options(1000, true));
  EXPECT_EQ(none.iou, 1.0);
  EXPECT_EQ(none.mse, 0.0);
}

TEST(Metrics, DeterministicGivenTheSeed) {
  const BallTarget target(3, {0.1, 0, 0}, 0.5);
  const Tree t = sphere(0.45, 0, R"("sharpness": 30)");
  MetricsOptions o = metrics_options(300000, true);
  const Metrics a = measure_tree(t, target, o);
  o.threads = 1;
  const Metrics b = measure_tree(t, target, o);
  EXPECT_EQ(a.mse, b.mse);
  EXPECT_EQ(a.iou, b.iou);
  ASSERT_TRUE(a.chamfer && b.chamfer && a.hausdorff && b.hausdorff);
  EXPECT_EQ(*a.chamfer, *b.chamfer);
  EXPECT_EQ(*a.hausdorff, *b.hausdorff);
  o.seed = 6;
  const Metrics c = measure_tree(t, target, o);
  EXPECT_NE(a.mse, c.mse);
  EXPECT_NE(*a.chamfer, *c.chamfer);
  EXPECT_NEAR(a.mse, c.mse, 0.1 * a.mse);
}

TEST(Metrics, RejectsMismatchedInput) {
  const Tree t = sphere(0.5, 0, R"("step": "crisp")");
  EXPECT_THROW(measure_tree(t, BallTarget(2, {0, 0}, 0.5), metrics_options(10)), InputError);
  EXPECT_THROW(measure_tree(t, BallTarget(3, {0, 0, 0}, 0.5), metrics_options(0)), InputError);
  const std::vector<double> wrong(2, 0.0);
  EXPECT_THROW(measure(t, wrong, BallTarget(3, {0, 0, 0}, 0.5), metrics_options(10)), InputError);
}

}  // namespace
}  // namespace fuzzycsg
