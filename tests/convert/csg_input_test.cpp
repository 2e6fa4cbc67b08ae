// convert on OpenSCAD models: the .csg read as its tree (the true solid) and meshed for the
// surfaces.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "convert/program.hpp"
#include "fuzzycsg/convert/convert.hpp"
#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::convert {
namespace {

const std::filesystem::path kModels = std::filesystem::path(FUZZYCSG_TEST_DATA_DIR) / "scad";

ConvertOptions quick() {
  ConvertOptions o;
  o.threads = 2;
  o.resolution = 64;
  o.restarts = 2;
  o.metrics.points = 200'000;
  return o;
}

// example004: a 30 mm cube less a sphere of radius 20, which the model states exactly (its
// mesh, .ref.off, is OpenSCAD's faceted sphere).
TEST(ConvertModel, CubeLessSphereIsTheModelsTwoPrimitives) {
  const std::string path = (kModels / "Old/example004.openscad.csg").string();
  const ConvertResult r = convert(path, quick());
  EXPECT_NE(r.target.find("tree"), std::string::npos) << r.target;
  EXPECT_FALSE(r.target_mesh.triangles.empty());
  EXPECT_GE(r.metrics.iou, 0.98);
  ASSERT_EQ(r.primitives, 2);
  const std::vector<Solid> solids = tree_solids(r.tree);
  ASSERT_EQ(solids.size(), 2u);
  EXPECT_EQ(solids[0].kind, SolidKind::kBox);
  EXPECT_NEAR(solids[0].size.maxCoeff(), 30.0, 0.6);
  EXPECT_EQ(solids[1].kind, SolidKind::kSphere);
  EXPECT_NEAR(solids[1].size[0], 20.0, 0.4);
  EXPECT_LT(solids[1].centre.norm(), 0.4);
}

TEST(ConvertModel, LeavesThatAreNotSolidsAreRefusedNamingTheLine) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("fuzzycsg-model-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::filesystem::path path = dir / "egg.csg";
  std::ofstream(path)
      << "group() {\n"
         "  multmatrix([[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {\n"
         "    sphere(r = 1);\n"
         "  }\n"
         "}\n";
  try {
    convert(path.string(), quick());
    ADD_FAILURE() << "an ellipsoid leaf was taken";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("egg.csg: "), std::string::npos) << message;
    EXPECT_NE(message.find("line 3"), std::string::npos) << message;
    EXPECT_NE(message.find("ellipsoid"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace fuzzycsg::convert
