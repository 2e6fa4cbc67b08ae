// Shading with gradients: the normal image's interior gradient (corner normals and
// perspective-correct barycentrics) and the whole pipeline's parameter gradient against
// central differences; barycentrics reproduce the hit point; the per-pixel gradient image sums
// to the parameter's gradient.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "fuzzycsg/diffcsg/refine.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::diffcsg {
namespace {

Tree ball_and_box(double radius, double tx) {
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {"op": "difference",
      "children": [{"type": "box", "size": [1, 0.8, 0.7], "rotate": [20, 35, 10], "scale": 1.1},
        {"type": "sphere", "radius": %.9f, "translate": [%.9f, 0.1, 0.3]}]}})",
                radius, tx);
  return io::read_tree_string(buf);
}

double weighted(const Tree& tree, const Camera& cam, const std::vector<float>& w, Shading shading,
                bool aa, const TessellationOptions& tess = {}) {
  const PreparedScene ps = prepare_scene(scene_from_tree(tree, "t", tess), aa);
  const Image out = render_image(ps, cam, shading, 1);
  double l = 0;
  for (std::size_t k = 0; k < out.data.size(); ++k) l += w[k] * out.data[k];
  return l;
}

TEST(DiffcsgShade, BarycentricsReproduceTheHitAndTheirGradientMatchesDifferences) {
  const Camera cam = Camera::orbit({0, 0, 0}, 30, 20, 4, 64, 48, 35);
  const Vec3 a{0.2, -0.3, 0.1}, b{-0.4, 0.2, 0.3}, c{0.3, 0.4, -0.2};
  // The pixel whose ray passes through a point of the triangle gets that point's weights.
  const std::array<double, 3> w{0.2, 0.5, 0.3};
  const Vec3 p{w[0] * a[0] + w[1] * b[0] + w[2] * c[0], w[0] * a[1] + w[1] * b[1] + w[2] * c[1],
               w[0] * a[2] + w[1] * b[2] + w[2] * c[2]};
  const Projection pr = project(cam, p);
  const int i = static_cast<int>(pr.sx), j = static_cast<int>(pr.sy);
  const std::array<double, 3> bary = pixel_barycentrics(cam, i, j, a, b, c);
  EXPECT_NEAR(bary[0] + bary[1] + bary[2], 1, 1e-12);
  // The barycentric point lies on the pixel centre's ray.
  const Vec3 q{bary[0] * a[0] + bary[1] * b[0] + bary[2] * c[0],
               bary[0] * a[1] + bary[1] * b[1] + bary[2] * c[1],
               bary[0] * a[2] + bary[1] * b[2] + bary[2] * c[2]};
  const Projection pq = project(cam, q);
  EXPECT_NEAR(pq.sx, i + 0.5, 1e-9);
  EXPECT_NEAR(pq.sy, j + 0.5, 1e-9);
  // VJP against central differences for every coordinate of every vertex.
  const std::array<double, 3> g{0.7, -1.3, 0.4};
  Vec3 ga{}, gb{}, gc{};
  pixel_barycentrics_vjp(cam, i, j, a, b, c, g, ga, gb, gc);
  const Vec3* grads[3] = {&ga, &gb, &gc};
  for (int v = 0; v < 3; ++v) {
    for (std::size_t k = 0; k < 3; ++k) {
      Vec3 t[3] = {a, b, c}, u[3] = {a, b, c};
      t[v][k] += 1e-6;
      u[v][k] -= 1e-6;
      const auto bt = pixel_barycentrics(cam, i, j, t[0], t[1], t[2]);
      const auto bu = pixel_barycentrics(cam, i, j, u[0], u[1], u[2]);
      double fd = 0;
      for (std::size_t m = 0; m < 3; ++m) fd += g[m] * (bt[m] - bu[m]) / 2e-6;
      EXPECT_NEAR((*grads[v])[k], fd, 1e-5 * std::max(1.0, std::abs(fd))) << v << " " << k;
    }
  }
}

TEST(DiffcsgShade, NormalImagesFaceTheCameraAndAreSmoothOnSpheres) {
  const Tree tree = io::read_tree_string(
      R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {"type": "sphere", "radius": 0.8}})");
  const Camera cam = Camera::orbit({0, 0, 0}, 10, 15, 4, 64, 64, 35);
  const PreparedScene ps = prepare_scene(scene_from_tree(tree, "t"));
  const ViewPass pass = render_view(ps, cam, Shading::kNormals, 1);
  int covered = 0, facing = 0;
  double smooth = 0, flat = 0;  // mean angle defects against the true sphere's normal
  for (std::size_t p = 0; p < pass.frame.primitive.size(); ++p) {
    if (pass.frame.primitive[p] < 0) continue;
    ++covered;
    const float* n = pass.shaded.at(p);
    const Vec3 d = cam.ray(static_cast<int>(p % 64), static_cast<int>(p / 64));
    facing += n[0] * d[0] + n[1] * d[1] + n[2] * d[2] < 0;
    const double t = pass.frame.depth[p];
    const Vec3 hit{cam.eye[0] + t * d[0], cam.eye[1] + t * d[1], cam.eye[2] + t * d[2]};
    const double len = std::sqrt(dot(hit, hit));
    // (Interpolated normals are not renormalised, as nvdiffrast's: compare directions.)
    const double nn = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    smooth += 1 - (n[0] * hit[0] + n[1] * hit[1] + n[2] * hit[2]) / (len * nn);
    const auto& f = pass.frame.normal[p];
    flat += 1 - (f[0] * hit[0] + f[1] * hit[1] + f[2] * hit[2]) / len;
  }
  ASSERT_GT(covered, 500);
  // Interpolated normals face the camera except at a few grazing pixels of the silhouette.
  EXPECT_GT(facing, covered * 0.97);
  // And follow the sphere far better than the facets' own normals.
  std::printf("mean 1 - cos: interpolated %g, flat %g\n", smooth / covered, flat / covered);
  EXPECT_LT(smooth, 0.3 * flat);
}

// A D-shaped plate (straight back, a Bézier curve in front) less a tapered hole, tilted.
Tree plate_with_hole() {
  return io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {
      "op": "difference", "children": [
        {"type": "extrude", "profile": [[-0.6, -0.5], [-0.2, -0.5], [0.2, -0.5],
                                        [0.5, -0.5], [0.9, -0.3], [0.9, 0.3],
                                        [0.5, 0.5], [0.2, 0.5], [-0.2, 0.5],
                                        [-0.6, 0.5], [-0.6, 0.2], [-0.6, -0.2]],
         "height": 0.4, "rotate": [25, -10, 15]},
        {"type": "cone", "radius1": 0.25, "radius2": 0.15, "height": 1.2,
         "translate": [0.2, 0.05, 0], "rotate": [25, -10, 15]}]}})");
}

void check_parameter_gradient(Shading shading, bool aa, int min_compared,
                              const Tree& tree = ball_and_box(0.45, 0.25)) {
  const Camera cam = Camera::orbit({0, 0, 0}, 30, 25, 4, 48, 48, 35);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> w(48 * 48 * 3);
  for (float& x : w) x = u(rng);
  // Extrude caps keep their triangulation, as in a refinement.
  const TessellationOptions tess = fixed_tessellation(tree, "t", {});
  const PreparedScene ps = prepare_scene(scene_from_tree(tree, "t", tess), aa);
  const ViewPass pass = render_view(ps, cam, shading, 1);
  Image g{48, 48, 3, w};
  VertexGradient gv;
  render_view_backward(ps, cam, shading, pass, g, gv);
  const std::vector<double> grad = parameter_gradient(tree, ps.scene, gv.g);
  int compared = 0, agreed = 0;
  for (std::size_t k = 0; k < grad.size(); ++k) {
    const double eps = 1e-5 * std::max(1.0, std::abs(tree.params.at(k).value));
    Tree a = tree, b = tree;
    a.params.at(k).value += eps;
    b.params.at(k).value -= eps;
    const double fd =
        (weighted(a, cam, w, shading, aa, tess) - weighted(b, cam, w, shading, aa, tess)) /
        (2 * eps);
    if (std::abs(fd) < 1e-9 && std::abs(grad[k]) < 1e-9) continue;
    ++compared;
    const bool ok =
        std::abs(fd - grad[k]) <= 0.03 * std::max(std::abs(fd), std::abs(grad[k])) + 2e-3;
    agreed += ok;
    if (!ok) std::printf("%s: fd %g analytic %g\n", tree.params.at(k).name.c_str(), fd, grad[k]);
  }
  std::printf("%s: %d of %d parameter gradients agree\n",
              std::string(shading_name(shading)).c_str(), agreed, compared);
  EXPECT_GE(compared, min_compared);
  EXPECT_GE(agreed, compared - 1);
}

TEST(DiffcsgShade, NormalImageParameterGradientsMatchCentralDifferences) {
  // 3 + 3 + 1 for the box (size, rotate, scale), 1 + 3 for the ball.
  check_parameter_gradient(Shading::kNormals, true, 10);
}

TEST(DiffcsgShade, ExtrudeAndConeGradientsMatchCentralDifferences) {
  // 24 profile numbers, the height, 3 angles; a cone's 3 fields and 6 of its placement: most
  // reach the image.
  check_parameter_gradient(Shading::kNormals, true, 25, plate_with_hole());
}

TEST(DiffcsgShade, ColourImageParameterGradientsMatchCentralDifferences) {
  check_parameter_gradient(Shading::kColours, true, 8);
}

TEST(DiffcsgShade, TheGradientImageSumsToTheParametersGradient) {
  const Tree tree = ball_and_box(0.45, 0.25);
  const Camera cam = Camera::orbit({0, 0, 0}, 30, 25, 4, 40, 40, 35);
  const PreparedScene ps = prepare_scene(scene_from_tree(tree, "t"));
  const ViewPass pass = render_view(ps, cam, Shading::kNormals, 1);
  Image ones = pass.image;
  std::fill(ones.data.begin(), ones.data.end(), 1.0f);
  VertexGradient all;
  render_view_backward(ps, cam, Shading::kNormals, pass, ones, all);
  const std::vector<double> grad = parameter_gradient(tree, ps.scene, all.g);
  int nonzero = 0;
  for (std::size_t k = 0; k < tree.params.size(); ++k) {
    const auto tangent = vertex_tangent(tree, ps.scene, k);
    std::vector<double> image(40 * 40, 0.0);
    VertexGradient vg;
    vg.tangent = &tangent;
    vg.per_pixel = &image;
    render_view_backward(ps, cam, Shading::kNormals, pass, ones, vg);
    double sum = 0;
    for (const double v : image) sum += v;
    EXPECT_NEAR(sum, grad[k], 1e-6 * std::max(1.0, std::abs(grad[k]))) << tree.params.at(k).name;
    nonzero += std::abs(grad[k]) > 1e-6;
  }
  EXPECT_GE(nonzero, 8);
}

TEST(DiffcsgShade, VertexTangentsMatchDifferencesOfTheScene) {
  const Tree tree = ball_and_box(0.45, 0.25);
  const Scene scene = scene_from_tree(tree, "t");
  for (std::size_t k = 0; k < tree.params.size(); ++k) {
    const auto tangent = vertex_tangent(tree, scene, k);
    Tree a = tree, b = tree;
    a.params.at(k).value += 1e-6;
    b.params.at(k).value -= 1e-6;
    const Scene sa = scene_from_tree(a, "a"), sb = scene_from_tree(b, "b");
    for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
      for (std::size_t v = 0; v < scene.primitives[p].mesh.vertices.size(); ++v) {
        for (std::size_t c = 0; c < 3; ++c) {
          const double fd =
              (sa.primitives[p].mesh.vertices[v][c] - sb.primitives[p].mesh.vertices[v][c]) / 2e-6;
          ASSERT_NEAR(tangent[p][v][c], fd, 1e-6) << tree.params.at(k).name;
        }
      }
    }
  }
}

}  // namespace
}  // namespace fuzzycsg::diffcsg
