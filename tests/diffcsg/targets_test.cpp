// Targets of refinement: image losses and their gradients, images and views files through
// PNG, meshes from files drawn as the model is; and refinement against them: a sphere's radius
// from normal images without intersection antialiasing (DiffCSG Fig. 11), a box against a mesh
// file, random views, a single edited image.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diffcsg/refine.hpp"
#include "fuzzycsg/diffcsg/targets.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::diffcsg {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("fuzzycsg_targets_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

Tree tree_of(const std::string& root) {
  return io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": )" +
                              root + "}");
}

TEST(DiffcsgTargets, LossGradientsMatchCentralDifferences) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-1, 1);
  Image a{5, 4, 3, std::vector<float>(60)}, b = a;
  for (float& x : a.data) x = u(rng);
  for (float& x : b.data) x = u(rng);
  for (const Loss loss : {Loss::kL1, Loss::kL2, Loss::kTanh}) {
    Image g;
    const double l = image_loss(a, b, loss, &g);
    EXPECT_GT(l, 0);
    for (std::size_t k = 0; k < a.data.size(); ++k) {
      Image p = a, m = a;
      p.data[k] += 1e-3f;
      m.data[k] -= 1e-3f;
      const double fd = (image_loss(p, b, loss) - image_loss(m, b, loss)) / 2e-3;
      EXPECT_NEAR(g.data[k], fd, 2e-4) << loss_name(loss) << " " << k;
    }
    EXPECT_EQ(image_loss(a, a, loss), 0.0);
  }
  EXPECT_EQ(loss_from_name("tanh"), Loss::kTanh);
  EXPECT_FALSE(loss_from_name("l3"));
}

TEST(DiffcsgTargets, ImagesAndViewsRoundTripThroughPng) {
  const fs::path dir = temp_dir("views");
  const Tree tree = tree_of(
      R"({"op": "difference", "children": [{"type": "box", "size": [1, 1, 1]},
         {"type": "sphere", "radius": 0.6, "translate": [0.4, 0.3, 0.5]}]})");
  const PreparedScene ps = prepare_scene(scene_from_tree(tree, "t"));
  std::vector<Camera> cams = orbit_views({0, 0, 0}, 4, 2, 25, 48, 40, 30);
  std::vector<std::string> files;
  for (std::size_t v = 0; v < cams.size(); ++v) {
    files.push_back("view" + std::to_string(v) + ".png");
    write(dir / files.back(),
          encode_image_png(render_image(ps, cams[v], Shading::kNormals, 1), Shading::kNormals));
  }
  write(dir / "views.json", views_json(Shading::kNormals, cams, files));
  ASSERT_TRUE(is_views_file(dir / "views.json"));
  const ViewSet set = read_views(dir / "views.json");
  ASSERT_EQ(set.cameras.size(), 2u);
  for (std::size_t v = 0; v < 2; ++v) {
    EXPECT_EQ(set.cameras[v].width, 48);
    EXPECT_EQ(set.cameras[v].height, 40);
    for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(set.cameras[v].eye[k], cams[v].eye[k], 1e-12);
    // 8-bit normals: within half a step of 2 / 255.
    const Image again = render_image(ps, cams[v], Shading::kNormals, 1);
    EXPECT_LT(image_mse(set.images[v], again), 2e-5);
    EXPECT_GT(image_mse(set.images[v], Image{48, 40, 3, std::vector<float>(48 * 40 * 3)}), 0.01);
  }
  // Errors name the file and the field.
  const auto refused = [&](const std::string& text, const std::string& expect) {
    write(dir / "bad.json", text);
    try {
      read_views(dir / "bad.json");
      ADD_FAILURE() << "accepted " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
    }
  };
  refused(R"({"format": "fuzzycsg-views", "version": 1, "views": [{"image": "view0.png",
      "eye": [1, 2], "target": [0, 0, 0]}]})",
          "bad.json: views[0].eye: three numbers expected");
  refused(R"({"format": "fuzzycsg-views", "version": 1, "views": [{"image": "view0.png",
      "eye": [4, 0, 0], "target": [0, 0, 0], "size": [64, 64]}]})",
          "views[0].size: 64x64, but");
  refused(R"({"format": "fuzzycsg-views", "version": 1, "views": [{"image": "missing.png",
      "eye": [4, 0, 0], "target": [0, 0, 0]}]})",
          "missing.png");
  refused(R"({"format": "fuzzycsg-views", "version": 1, "shading": "depth", "views": []})",
          "shading");
  fs::remove_all(dir);
}

// The world triangles of a one-primitive scene as an OFF file.
std::string off_of(const TriangleMesh& m) {
  std::string s = "OFF\n" + std::to_string(m.vertices.size()) + " " +
                  std::to_string(m.triangles.size()) + " 0\n";
  char buf[128];
  for (const Vec3& v : m.vertices) {
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", v[0], v[1], v[2]);
    s += buf;
  }
  for (const auto& t : m.triangles) {
    s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) +
         "\n";
  }
  return s;
}

TEST(DiffcsgTargets, AMeshFileDrawsAsTheModelItCameFrom) {
  const fs::path dir = temp_dir("mesh");
  const Tree tree =
      tree_of(R"({"type": "cylinder", "radius": 0.5, "height": 1.2, "rotate": [30, 10, 0]})");
  const Scene model = scene_from_tree(tree, "t");
  write(dir / "c.off", off_of(model.primitives[0].mesh));
  const Scene mesh = read_mesh_scene(dir / "c.off");
  ASSERT_EQ(mesh.primitives.size(), 1u);
  // The crease angle keeps the caps flat and the side smooth, as the model's groups do.
  std::set<int> groups(mesh.primitives[0].smoothing.begin(), mesh.primitives[0].smoothing.end());
  EXPECT_EQ(groups.size(), 3u);
  for (const double az : {20.0, 140.0}) {
    const Camera cam = Camera::orbit({0, 0, 0}, az, 30, 4, 64, 64, 30);
    const Image a = render_image(prepare_scene(model), cam, Shading::kNormals, 1);
    const Image b = render_image(prepare_scene(mesh), cam, Shading::kNormals, 1);
    EXPECT_LT(image_mse(a, b), 1e-10);
  }
  write(dir / "flat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_THROW(read_mesh_scene(dir / "flat.off"), InputError);
  EXPECT_THROW(read_mesh_scene(dir / "none.off"), InputError);
  fs::remove_all(dir);
}

double radius_of(const Tree& t) {
  for (std::size_t k = 0; k < t.params.size(); ++k) {
    if (t.params.at(k).name.ends_with("radius")) return t.params.at(k).value;
  }
  return NAN;
}

// A block with a ball bitten out of its top face: the ball's radius shows only where the two
// meet (an intersection edge) and on the ball's own curved surface.
Tree bitten(double radius) {
  return tree_of(R"({"op": "difference", "children": [{"type": "box", "size": [1.6, 1.6, 0.6]},
      {"type": "sphere", "radius": )" +
                 std::to_string(radius) + R"(, "translate": [0, 0, 0.45]}]})");
}

RefineTarget target_of(const Tree& goal, Shading shading, int views, int size, bool aa = true) {
  auto ps = std::make_shared<PreparedScene>(prepare_scene(scene_from_tree(goal, "goal"), aa));
  RefineTarget t;
  t.shading = shading;
  t.cameras = orbit_views({0, 0, 0}, 5, views, 40, size, size, 30);
  t.render = [ps, shading](const Camera& c) { return render_image(*ps, c, shading, 2); };
  for (const Camera& c : t.cameras) t.images.push_back(t.render(c));
  return t;
}

TEST(DiffcsgTargets, NormalsCarryASpheresSizeEvenWithoutIntersectionEdges) {
  // DiffCSG Fig. 11: with flat colours and no intersection antialiasing the ball's radius gets
  // no gradient; the ball's interpolated normals give it one, and the first steps take it to
  // the goal. (Left running, the bowl's normals alone widen it further and further: without the
  // rim's antialiasing nothing says how wide the bowl is, where the goal shows a flat top.)
  const Tree start = bitten(0.45), goal = bitten(0.55);
  RefineOptions o;
  o.iterations = 60;
  o.lr = 0.01;
  o.stop_mse = 0;
  o.intersection_aa = false;
  const RefineResult colours = refine(start, target_of(goal, Shading::kColours, 2, 64, false), o);
  o.iterations = 10;
  const RefineResult normals = refine(start, target_of(goal, Shading::kNormals, 2, 64, false), o);
  std::printf(
      "radius 0.45 -> colours %g (60 steps), normals %g (10 steps; goal 0.55), loss "
      "%g -> %g\n",
      radius_of(colours.tree), radius_of(normals.tree), normals.loss.front(), normals.loss.back());
  EXPECT_NEAR(radius_of(colours.tree), 0.45, 1e-9);
  EXPECT_NEAR(radius_of(normals.tree), 0.55, 0.04);
  EXPECT_LT(normals.loss.back(), 0.3 * normals.loss.front());
  o.stop_mse = 5e-4;
  o.iterations = 60;
  // With intersection edges the colours get there too.
  o.intersection_aa = true;
  const RefineResult edges = refine(start, target_of(goal, Shading::kColours, 2, 64), o);
  std::printf("colours with intersection edges: %g (%d steps)\n", radius_of(edges.tree),
              edges.steps);
  EXPECT_TRUE(edges.converged);
  EXPECT_NEAR(radius_of(edges.tree), 0.55, 0.03);
}

// DiffCSG Fig. 10: a block with a notch cut by a box seen only as the notch's walls. The box
// must grow (top) or move (bottom); only intersection edges say so.
Tree notch(double size, double dx) {
  return tree_of(R"({"op": "difference", "children": [{"type": "box", "size": [1.2, 1, 0.8],
      "rotate": [0, 0, 10]}, {"type": "box", "size": [)" +
                 std::to_string(size) + ", " + std::to_string(size) + ", " + std::to_string(size) +
                 R"(], "translate": [)" + std::to_string(0.5 + dx) +
                 R"(, 0.45, 0.35], "rotate": [8, 5, 20]}]})");
}

TEST(DiffcsgTargets, ANotchIsFoundOnlyWithIntersectionEdges) {
  for (const bool grow : {true, false}) {
    SCOPED_TRACE(grow ? "the box grows" : "the box moves");
    const Tree start = notch(0.6, 0), goal = grow ? notch(0.66, 0) : notch(0.6, 0.05);
    for (const bool aa : {true, false}) {
      RefineOptions o;
      o.iterations = 150;
      o.lr = 0.005;
      o.stop_mse = 2e-5;  // well below the notch's own error (about 1e-3)
      o.intersection_aa = aa;
      const RefineResult r = refine(start, target_of(goal, Shading::kColours, 2, 64), o);
      double moved = 0;
      for (std::size_t k = 0; k < start.params.size(); ++k) {
        moved = std::max(moved, std::abs(r.tree.params.at(k).value - start.params.at(k).value));
      }
      std::printf("%s, %s: %d steps, check MSE %g -> %g\n", grow ? "grow" : "move",
                  aa ? "intersection edges" : "silhouettes only", r.steps,
                  r.check_mse.front().second, r.check_mse.back().second);
      if (aa) {
        EXPECT_TRUE(r.converged);
      } else {
        EXPECT_FALSE(r.converged);
        EXPECT_EQ(moved, 0.0);  // no gradient at all: the refinement stalls where it began
      }
    }
  }
}

TEST(DiffcsgTargets, RandomViewsAndAMeshTargetRecoverABox) {
  const fs::path dir = temp_dir("refine_mesh");
  const std::string box = R"({"type": "box", "size": [%g, 0.8, 0.6], "translate": [%g, 0, 0]})";
  char buf[256];
  std::snprintf(buf, sizeof buf, box.c_str(), 1.3, 0.1);
  const Tree goal = tree_of(buf);
  std::snprintf(buf, sizeof buf, box.c_str(), 1.0, 0.0);
  const Tree start = tree_of(buf);
  write(dir / "goal.off", off_of(scene_from_tree(goal, "goal").primitives[0].mesh));
  auto ps = std::make_shared<PreparedScene>(prepare_scene(read_mesh_scene(dir / "goal.off")));
  RefineTarget t;
  t.cameras = orbit_views({0, 0, 0}, 4, 1, 30, 64, 64, 30);
  t.render = [ps](const Camera& c) { return render_image(*ps, c, Shading::kNormals, 2); };
  t.images.push_back(t.render(t.cameras[0]));
  RefineOptions o;
  o.iterations = 300;
  o.lr = 0.01;
  o.random_view_every = 5;
  o.check_every = 10;
  const RefineResult r = refine(start, t, o);
  std::printf("box: %d steps, converged %d, check MSE %g, size x %g, x %g\n", r.steps, r.converged,
              r.check_mse.back().second, r.tree.params.at(0).value, r.tree.params.at(3).value);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.tree.params.at(0).value, 1.3, 0.05);
  // Checked every 10 steps only.
  for (const auto& [step, mse] : r.check_mse) EXPECT_EQ(step % 10, 0);
  fs::remove_all(dir);
}

TEST(DiffcsgTargets, CmaesRecoversAMovedBoxWithoutGradients) {
  const std::string box = R"({"type": "box", "size": [%g, 0.8, 0.6], "translate": [%g, 0, 0]})";
  char buf[256];
  std::snprintf(buf, sizeof buf, box.c_str(), 1.2, 0.1);
  const Tree goal = tree_of(buf);
  std::snprintf(buf, sizeof buf, box.c_str(), 1.0, 0.0);
  const Tree start = tree_of(buf);
  RefineTarget t = target_of(goal, Shading::kNormals, 2, 48);
  RefineOptions o;
  o.method = Method::kCmaes;
  o.iterations = 1500;
  const RefineResult r = refine(start, t, o);
  std::printf("CMA-ES: %d evaluations, converged %d, check MSE %g, size x %g, x %g\n", r.steps,
              r.converged, r.check_mse.back().second, r.tree.params.at(0).value,
              r.tree.params.at(3).value);
  EXPECT_TRUE(r.converged);
  EXPECT_LE(r.steps, 1500);
  EXPECT_NEAR(r.tree.params.at(0).value, 1.2, 0.05);
  EXPECT_LT(r.check_mse.back().second, 5e-4);
  // The check is of the best point: its MSE is what the result's tree renders.
  EXPECT_NEAR(image_mse(render_image(prepare_scene(scene_from_tree(r.tree, "r")), t.cameras[0],
                                     Shading::kNormals, 1),
                        t.images[0]),
              r.check_mse.back().second, 1e-9);
}

TEST(DiffcsgTargets, RefinementRefusesTargetsItCannotUse) {
  const Tree start = bitten(0.45);
  RefineTarget t = target_of(start, Shading::kNormals, 1, 32);
  RefineOptions o;
  o.random_view_every = 5;
  RefineTarget images = t;
  images.render = nullptr;
  EXPECT_THROW(refine(start, images, o), InputError);
  RefineTarget wrong = t;
  wrong.images[0] = Image{16, 16, 3, std::vector<float>(16 * 16 * 3)};
  EXPECT_THROW(refine(start, wrong, RefineOptions{}), InputError);
  // A model no camera sees.
  RefineTarget away = t;
  away.cameras[0].target = {100, 100, 100};
  away.cameras[0].eye = {100, 104, 100};
  EXPECT_THROW(refine(start, away, RefineOptions{}), InputError);
}

}  // namespace
}  // namespace fuzzycsg::diffcsg
