// Prisms of convert: proposed from flat walls off the frame (a slanted hole), and found by the
// whole pipeline as one cutter.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "convert/candidates.hpp"
#include "convert/program.hpp"
#include "convert/test_meshes.hpp"
#include "fuzzycsg/convert/convert.hpp"
#include "fuzzycsg/convert/detect.hpp"
#include "fuzzycsg/mesh/mesh.hpp"

namespace fuzzycsg::convert {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// A rhombus around the origin: every side off the box's axes.
const std::vector<Vector2d> kRhombus{{0.5, 0}, {0, 0.3}, {-0.5, 0}, {0, -0.3}};

Candidates candidates_of(const TriangleMesh& mesh) {
  const std::vector<Surface> surfaces = detect_surfaces(mesh, {});
  const Eigen::Matrix3d frame = dominant_frame(surfaces);
  return propose_candidates(surfaces, mesh, frame);
}

TEST(ConvertPrism, RhombusHoleIsProposedAsAPrismThroughThePart) {
  const TriangleMesh mesh = test_meshes::box_with_polygon_hole_mesh(1.0, kRhombus, 1.0);
  const Candidates c = candidates_of(mesh);
  int hole_prisms = 0;
  for (const Solid& s : c.solids) {
    if (s.kind != SolidKind::kPrism) continue;
    // The hole: inside near its corners, outside just beyond its sides, along the whole height.
    const bool hole = s.contains({0, 0, 0.5}) && s.contains({0.45, 0, 0.02}) &&
                      s.contains({-0.45, 0, 0.98}) && s.contains({0, 0.27, 0.5}) &&
                      !s.contains({0, 0.33, 0.5}) && !s.contains({0.55, 0, 0.5}) &&
                      !s.contains({0.3, 0.15, 0.5});
    hole_prisms += hole ? 1 : 0;
  }
  EXPECT_GE(hole_prisms, 1);
}

TEST(ConvertPrism, WallsOnTheFrameGiveNoPrism) {
  const std::vector<Vector2d> square{{0.3, 0.3}, {-0.3, 0.3}, {-0.3, -0.3}, {0.3, -0.3}};
  const Candidates c = candidates_of(test_meshes::box_with_polygon_hole_mesh(1.0, square, 1.0));
  for (const Solid& s : c.solids) EXPECT_NE(s.kind, SolidKind::kPrism) << s.describe();
  EXPECT_FALSE(c.solids.empty() && c.box_offsets[0].empty());
}

// The whole pipeline: a box less one prism, written as an extrude leaf.
TEST(ConvertPrism, BoxWithRhombusHoleIsABoxLessAPrism) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("fuzzycsg-prism-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path path = dir / "rhombus.ply";
  write_mesh(test_meshes::box_with_polygon_hole_mesh(10.0, {{5, 0}, {0, 3}, {-5, 0}, {0, -3}}, 8.0),
             path);
  ConvertOptions options;
  options.threads = 2;
  options.resolution = 64;
  options.restarts = 2;
  options.refine_steps = 100;
  options.metrics.points = 200'000;
  const ConvertResult result = convert(path.string(), options);
  std::filesystem::remove_all(dir);
  EXPECT_GE(result.metrics.iou, 0.98);
  EXPECT_EQ(result.primitives, 2);
  int extrudes = 0;
  for (const Node& n : result.tree.nodes) {
    extrudes += n.kind == NodeKind::kPrimitive && n.shape.type == PrimitiveType::kExtrude ? 1 : 0;
  }
  EXPECT_EQ(extrudes, 1);
  // In the mesh's units: the prism's polygon is the rhombus.
  for (const Solid& s : tree_solids(result.tree)) {
    if (s.kind != SolidKind::kPrism) continue;
    EXPECT_TRUE(s.contains({4.5, 0, 4}));
    EXPECT_FALSE(s.contains({0, 3.4, 4}));
    EXPECT_FALSE(s.contains({3, 1.6, 4}));
  }
}

}  // namespace
}  // namespace fuzzycsg::convert
