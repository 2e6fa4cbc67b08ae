// The solids of convert, their leaves, and the crisp structure search on a tree target.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "convert/program.hpp"
#include "convert/search.hpp"
#include "convert/solid.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg::convert {
namespace {

Solid cylinder_along(const Eigen::Vector3d& axis, double r, double h, const Eigen::Vector3d& c) {
  Solid s;
  s.kind = SolidKind::kCylinder;
  s.rotation = rotation_with_z(axis);
  s.centre = c;
  s.size = {r, r, h};
  return s;
}

TEST(ConvertSolid, EulerAnglesRoundTrip) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> angle(-170, 170);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d a(angle(rng), 0.5 * angle(rng), angle(rng));
    const Eigen::Matrix3d r = rotation_from_euler_degrees(a);
    const Eigen::Matrix3d back = rotation_from_euler_degrees(euler_xyz_degrees(r));
    EXPECT_LT((r - back).norm(), 1e-9) << a.transpose();
  }
  // Gimbal lock: the rotation is still reproduced.
  const Eigen::Matrix3d lock = rotation_from_euler_degrees({30, 90, 0});
  EXPECT_LT((lock - rotation_from_euler_degrees(euler_xyz_degrees(lock))).norm(), 1e-9);
}

TEST(ConvertSolid, RotationWithZIsARightHandedFrame) {
  for (const Eigen::Vector3d& axis : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 0),
                                      Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(1, 2, 3)}) {
    const Eigen::Matrix3d r = rotation_with_z(axis);
    EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
    EXPECT_LT((r.col(2) - axis.normalized()).norm(), 1e-12);
  }
  EXPECT_LT((rotation_with_z({0, 0, 1}) - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

// A crisp tree of each kind of solid, evaluated by the kernel, agrees with Solid::contains.
TEST(ConvertSolid, LeavesAgreeWithContains) {
  std::vector<Solid> solids;
  Solid box;
  box.kind = SolidKind::kBox;
  box.rotation = rotation_from_euler_degrees({20, -35, 50});
  box.centre = {0.1, -0.2, 0.05};
  box.size = {0.9, 0.5, 0.3};
  solids.push_back(box);
  solids.push_back(cylinder_along({1, 1, 0}, 0.3, 0.8, {0, 0.1, 0}));
  Solid cone = cylinder_along({0, 1, 2}, 0.4, 0.9, {-0.1, 0, 0.1});
  cone.kind = SolidKind::kCone;
  cone.size = {0.4, 0.1, 0.9};
  solids.push_back(cone);
  Solid ball;
  ball.kind = SolidKind::kSphere;
  ball.centre = {0.2, 0.2, -0.3};
  ball.size = {0.45, 0, 0};
  solids.push_back(ball);
  Solid torus = cylinder_along({1, 0, 1}, 0, 0, {0, 0, 0});
  torus.kind = SolidKind::kTorus;
  torus.size = {0.5, 0.15, 0};
  solids.push_back(torus);
  Solid half;
  half.kind = SolidKind::kHalfSpace;
  half.rotation = rotation_with_z({1, -1, 0.5});
  half.size = {0.2, 0, 0};
  solids.push_back(half);
  // A prism over an L-shaped (not convex) polygon, tilted.
  Solid prism = cylinder_along({0.2, -1, 0.4}, 0, 1.2, {0.05, 0, -0.1});
  prism.kind = SolidKind::kPrism;
  prism.size = {0, 0, 1.2};
  prism.polygon = {{-0.6, -0.5}, {0.5, -0.5}, {0.5, -0.1}, {-0.2, -0.1}, {-0.2, 0.6}, {-0.6, 0.6}};
  solids.push_back(prism);

  std::mt19937_64 rng(11);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> points(3 * 4000);
  for (float& x : points) x = u(rng);
  for (const Solid& s : solids) {
    TreeBuilder b(3);
    const Tree tree = std::move(b).finish(add_leaf(b, s), "test");
    const std::optional<Solid> back = solid_of_leaf(tree, tree.params.values(), tree.root);
    ASSERT_TRUE(back.has_value()) << s.describe();
    std::vector<float> occupancy(4000);
    Evaluator(tree).forward(tree.params.values(), points, occupancy);
    int disagree = 0, inside = 0;
    for (std::size_t i = 0; i < 4000; ++i) {
      const Eigen::Vector3d p(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
      const bool in = s.contains(p);
      inside += in ? 1 : 0;
      disagree += (occupancy[i] >= 0.5f) != in ? 1 : 0;
      EXPECT_EQ(back->contains(p), in) << s.describe();
    }
    EXPECT_GT(inside, 40) << s.describe();
    EXPECT_LE(disagree, 2) << s.describe();  // points within rounding of the surface
  }
}

TEST(ConvertSolid, MappedSolidsFollowTheMap) {
  const Similarity m{{1.0, -2.0, 0.5}, 3.0};
  Solid half;
  half.kind = SolidKind::kHalfSpace;
  half.rotation = rotation_with_z({0.3, 0.4, -1});
  half.size = {0.1, 0, 0};
  const Solid cyl = cylinder_along({0, 1, 0}, 0.2, 0.5, {0.1, 0.2, 0.3});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    const auto q = m.apply({p[0], p[1], p[2]});
    const Eigen::Vector3d mp(q[0], q[1], q[2]);
    EXPECT_EQ(half.contains(p), half.mapped(m).contains(mp));
    EXPECT_EQ(cyl.contains(p), cyl.mapped(m).contains(mp));
  }
}

// A box with a hole through it, as a tree target: the search finds the box and the hole.
TEST(ConvertSearch, FindsABoxWithAHole) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "fuzzycsg_convert_search";
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "box_hole.json";
  std::ofstream(file) << R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3,
    "root": {"op": "difference", "children": [
      {"type": "box", "size": [1.2, 0.8, 0.4], "step": "crisp"},
      {"type": "cylinder", "radius": 0.15, "height": 1.0, "rotate": [90, 0, 0], "step": "crisp"}]}})";
  const std::unique_ptr<Target> target = load_target(file.string());
  const Eigen::AlignedBox3d bounds(Eigen::Vector3d(-0.6, -0.4, -0.2),
                                   Eigen::Vector3d(0.6, 0.4, 0.2));
  const LabelGrid grid = make_label_grid(*target, Eigen::Matrix3d::Identity(), bounds, 64, 2);
  ASSERT_GT(grid.count(1), 1000u);

  Candidates c;
  c.box_offsets = {std::vector<double>{-0.6, 0.6, -0.3, 0.3, -0.7, 0.7},
                   std::vector<double>{-0.4, 0.4, -0.5, 0.5}, std::vector<double>{-0.2, 0.2, 0.0}};
  c.solids.push_back(cylinder_along({0, 1, 0}, 0.15, 1.0, {0, 0, 0}));
  c.solids.push_back(cylinder_along({1, 0, 0}, 0.15, 1.0, {0, 0, 0}));  // a decoy
  SearchOptions o;
  o.restarts = 3;
  const Chain chain = search_chain(grid, c, o);
  ASSERT_EQ(chain.steps.size(), 2u);
  EXPECT_EQ(chain.steps[0].move, Move::kUnion);
  EXPECT_EQ(chain.steps[0].solid.kind, SolidKind::kBox);
  EXPECT_NEAR(chain.steps[0].solid.size[0], 1.2, 1e-9);
  EXPECT_EQ(chain.steps[1].move, Move::kDifference);
  EXPECT_EQ(chain.steps[1].solid.kind, SolidKind::kCylinder);
  EXPECT_NEAR(std::abs(chain.steps[1].solid.normal()[1]), 1.0, 1e-9);
  EXPECT_EQ(chain.error, chain_error(grid, chain.steps));
  EXPECT_LT(chain.error, static_cast<long long>(grid.count(1) / 100));

  // The chain as a tree gets the same cells wrong as the chain.
  const Tree tree = chains_tree({chain});
  EXPECT_LE(std::abs(tree_error(tree, grid) - chain.error), 4);
  // Same seed: the same chain.
  const Chain again = search_chain(grid, c, o);
  ASSERT_EQ(again.steps.size(), chain.steps.size());
  EXPECT_EQ(again.error, chain.error);
}

// A plate with a hole, and an arm that crosses the hole and runs out of the plate. The greedy
// descent alone takes the plate, then the cut (it gains most); the arm, united after the cut,
// would fill the hole where it crosses it, so it must be united early: placed before the cut.
TEST(ConvertSearch, UnitesEarlyWhatALaterCutGoesThrough) {
  LabelGrid g;
  g.n = {24, 24, 6};
  g.label.assign(24 * 24 * 6, 0);
  const auto in = [](int v, int lo, int hi) { return v >= lo && v < hi; };
  for (int k = 0; k < 6; ++k) {
    for (int j = 0; j < 24; ++j) {
      for (int i = 0; i < 24; ++i) {
        const bool z = in(k, 1, 5);
        const bool plate = z && in(i, 2, 22) && in(j, 2, 14);
        const bool arm = z && in(i, 10, 14) && in(j, 4, 22);
        const bool hole = in(i, 8, 16) && in(j, 6, 12);
        g.label[g.index(i, j, k)] = (plate || arm) && !hole ? 1 : 0;
      }
    }
  }
  Candidates c;  // the plate's and the hole's faces; the arm only as a listed solid
  c.box_offsets = {std::vector<double>{2, 22, 8, 16}, std::vector<double>{2, 14, 6, 12},
                   std::vector<double>{1, 5, -1, 7}};
  Solid arm;
  arm.kind = SolidKind::kBox;
  arm.centre = {12, 13, 3};
  arm.size = {4, 18, 4};
  c.solids.push_back(arm);
  SearchOptions o;
  o.first_moves = 0;  // no run started from the arm
  o.restarts = 0;
  o.max_steps = 3;  // no second cut to mend a late arm
  const Chain chain = search_chain(g, c, o);
  ASSERT_EQ(chain.steps.size(), 3u);
  EXPECT_EQ(chain.steps[0].solid.size[0], 20);   // the plate
  EXPECT_EQ(chain.steps[1].move, Move::kUnion);  // the arm, before the cut
  EXPECT_EQ(chain.steps[1].solid.size[1], 18);
  EXPECT_EQ(chain.steps[2].move, Move::kDifference);
  EXPECT_EQ(chain.error, 0);
  EXPECT_EQ(chain.error, chain_error(g, chain.steps));
}

// Two separate parts are two components, each counted only on its own grid.
TEST(ConvertSearch, SplitsComponents) {
  LabelGrid g;
  g.n = {10, 4, 4};
  g.label.assign(160, 0);
  for (int k = 1; k < 3; ++k) {
    for (int j = 1; j < 3; ++j) {
      g.label[g.index(1, j, k)] = 1;
      g.label[g.index(2, j, k)] = 1;
      g.label[g.index(7, j, k)] = 1;
    }
  }
  g.label[g.index(5, 0, 0)] = 1;  // a lone cell, dropped
  std::size_t dropped = 0;
  const std::vector<LabelGrid> parts = split_components(g, 2, 1, dropped);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(dropped, 1u);
  EXPECT_EQ(parts[0].count(1), 8u);
  EXPECT_EQ(parts[1].count(1), 4u);
  EXPECT_EQ(parts[0].count(2) + parts[1].count(2), 0u);  // the margins do not reach each other
}

}  // namespace
}  // namespace fuzzycsg::convert
