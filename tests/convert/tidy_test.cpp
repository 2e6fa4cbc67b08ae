// The tidy stage of convert: angles and numbers rounded where the error allows.

#include <gtest/gtest.h>

#include <cmath>

#include "convert/program.hpp"
#include "convert/search.hpp"
#include "convert/tidy.hpp"
#include "fuzzycsg/core/tree_builder.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg::convert {
namespace {

// A unit normal tilted `ay` degrees from z and turned `az` about it (rotate([0, ay, az])).
Eigen::Vector3d normal_at(double ay, double az) {
  const double y = ay / kDegreesPerRadian, z = az / kDegreesPerRadian;
  return {std::sin(y) * std::cos(z), std::sin(y) * std::sin(z), std::cos(y)};
}

Tree box_cut_by(const Eigen::Vector3d& n, const Eigen::Matrix3d& box_rotation) {
  Solid box;
  box.kind = SolidKind::kBox;
  box.rotation = box_rotation;
  box.size = {1.2, 1.0, 0.8};
  Solid cut;
  cut.kind = SolidKind::kHalfSpace;
  cut.rotation = rotation_with_z(n);
  cut.size = {0.1, 0, 0};
  TreeBuilder b(3);
  const int root = b.op(OpKind::kIntersection, {add_leaf(b, box), add_leaf(b, cut)});
  return std::move(b).finish(root, "test");
}

// A half-space and a box a few ten-thousandths of a degree off round angles come back on them:
// the half-space as the tilt and turn the export writes, the box as its Euler angles.
TEST(ConvertTidy, AnglesOffByAHairAreRounded) {
  const Eigen::Matrix3d turned = rotation_from_euler_degrees({10, 0, 25});
  const Tree round = box_cut_by(normal_at(85, -108.3), turned);
  const Tree off = box_cut_by(normal_at(85.0004, -108.3003),
                              rotation_from_euler_degrees({10.0003, 0.0002, 24.9996}));
  const std::unique_ptr<Target> target = tree_target(round, "round");
  const LabelGrid grid = make_label_grid(
      *target, Eigen::Matrix3d::Identity(),
      Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.9), Eigen::Vector3d::Constant(0.9)), 48, 1);
  TidyOptions options;
  options.threads = 2;
  options.points = 200'000;
  const TidyResult r = tidy_solids(off, Similarity{}, *target, grid, options);
  ASSERT_EQ(r.solids.size(), 2u);
  EXPECT_EQ(r.angles_rounded, 2);
  const Eigen::Vector3d e = euler_xyz_degrees(r.solids[0].rotation);
  EXPECT_NEAR(e[0], 10, 1e-9);
  EXPECT_NEAR(e[1], 0, 1e-9);
  EXPECT_NEAR(e[2], 25, 1e-9);
  EXPECT_LT((r.solids[1].normal() - normal_at(85, -108.3)).norm(), 1e-12);
  EXPECT_LE(r.error_after, r.error_before + static_cast<long long>(0.004 * 200'000));
}

}  // namespace
}  // namespace fuzzycsg::convert
