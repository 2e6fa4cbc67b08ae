// Silhouette antialiasing: blending only along silhouettes, the projection's Jacobian, and the
// gradient to vertex positions against central finite differences.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "fuzzycsg/diffcsg/antialias.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::diffcsg {
namespace {

Image shade(const Frame& f) {
  Image img{f.width, f.height, 3, std::vector<float>(f.primitive.size() * 3, 0.0f)};
  for (std::size_t p = 0; p < f.primitive.size(); ++p) {
    if (f.primitive[p] < 0) continue;
    const float c[2][3] = {{1.0f, 0.5f, 0.25f}, {0.2f, 0.9f, 0.4f}};
    for (int k = 0; k < 3; ++k) img.at(p)[k] = c[f.primitive[p] % 2][k];
  }
  return img;
}

Scene rotated_boxes(bool two) {
  std::string text = R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": )";
  const std::string a = R"({"type": "box", "size": [1, 0.8, 0.6], "rotate": [20, 35, 10]})";
  const std::string b =
      R"({"type": "box", "size": [0.5, 0.5, 1.4], "translate": [0.3, 0.1, 0.2], "rotate": [5, 10, 30]})";
  text += two ? R"({"op": "union", "children": [)" + a + ", " + b + "]}" : a;
  text += "}";
  return scene_from_tree(io::read_tree_string(text), "boxes");
}

TEST(DiffcsgAntialias, ProjectionJacobianMatchesDifferences) {
  const Camera cam = Camera::orbit({0, 0, 0}, 30, 20, 4, 64, 48, 35);
  const Vec3 p{0.3, -0.2, 0.4};
  const Projection pr = project(cam, p);
  // The ray through the projected point's pixel position passes through p.
  for (int k = 0; k < 3; ++k) {
    Vec3 a = p, b = p;
    a[static_cast<std::size_t>(k)] += 1e-6;
    b[static_cast<std::size_t>(k)] -= 1e-6;
    const Projection pa = project(cam, a), pb = project(cam, b);
    EXPECT_NEAR((pa.sx - pb.sx) / 2e-6, pr.jacobian[static_cast<std::size_t>(k)], 1e-4);
    EXPECT_NEAR((pa.sy - pb.sy) / 2e-6, pr.jacobian[3 + static_cast<std::size_t>(k)], 1e-4);
  }
  // Consistent with the camera's rays: the centre pixel's ray projects to its centre.
  const Vec3 d = cam.ray(20, 30);
  const Projection on =
      project(cam, {cam.eye[0] + 3 * d[0], cam.eye[1] + 3 * d[1], cam.eye[2] + 3 * d[2]});
  EXPECT_NEAR(on.sx, 20.5, 1e-9);
  EXPECT_NEAR(on.sy, 30.5, 1e-9);
}

TEST(DiffcsgAntialias, BlendsOnlyAcrossSilhouettes) {
  const Scene scene = rotated_boxes(false);
  const Topology topo = opposite_vertices(scene);
  for (const auto& t : topo[0]) {
    for (const int v : t) EXPECT_GE(v, 0);
  }
  const Camera cam = Camera::orbit({0, 0, 0}, 30, 20, 4, 48, 48, 35);
  const Frame f = render_visibility(scene, cam, 1);
  const Image c = shade(f);
  std::vector<AaPair> pairs;
  const Image out = antialias(scene, topo, cam, f, c, &pairs);
  ASSERT_FALSE(pairs.empty());
  for (const AaPair& p : pairs) {
    // Every blended pair has the box on one side and the background on the other: the box's
    // inner edges (between its own faces) are no silhouettes.
    EXPECT_NE(f.primitive[p.p0] < 0, f.primitive[p.p1] < 0);
    EXPECT_LE(std::abs(p.alpha), 0.5);
  }
  // Values stay between the two colours.
  for (const float v : out.data) {
    EXPECT_GE(v, -1e-6f);
    EXPECT_LE(v, 1.0f + 1e-6f);
  }
}

double loss(const Scene& scene, const Camera& cam, const std::vector<float>& weights) {
  const Frame f = render_visibility(scene, cam, 1);
  const Image out = antialias(scene, opposite_vertices(scene), cam, f, shade(f));
  double l = 0;
  for (std::size_t k = 0; k < out.data.size(); ++k) l += weights[k] * out.data[k];
  return l;
}

TEST(DiffcsgAntialias, VertexGradientsMatchCentralDifferences) {
  for (const bool two : {false, true}) {
    SCOPED_TRACE(two ? "two boxes" : "one box");
    const Scene scene = rotated_boxes(two);
    const Camera cam = Camera::orbit({0, 0, 0}, 30, 20, 4, 48, 48, 35);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<float> weights(48 * 48 * 3);
    for (float& x : weights) x = u(rng);
    const Frame f = render_visibility(scene, cam, 1);
    const Image c = shade(f);
    std::vector<AaPair> pairs;
    antialias(scene, opposite_vertices(scene), cam, f, c, &pairs);
    Image grad_out{48, 48, 3, weights};
    Image grad_colour;
    std::vector<std::vector<Vec3>> grad;
    antialias_backward(scene, cam, c, pairs, grad_out, grad_colour, grad);
    int compared = 0, agreed = 0;
    double largest = 0;
    for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
      for (std::size_t v = 0; v < scene.primitives[p].mesh.vertices.size(); ++v) {
        for (int k = 0; k < 3; ++k) {
          const double eps = 1e-5;
          Scene a = scene, b = scene;
          a.primitives[p].mesh.vertices[v][static_cast<std::size_t>(k)] += eps;
          b.primitives[p].mesh.vertices[v][static_cast<std::size_t>(k)] -= eps;
          const double fd = (loss(a, cam, weights) - loss(b, cam, weights)) / (2 * eps);
          const double an = grad[p][v][static_cast<std::size_t>(k)];
          largest = std::max(largest, std::abs(fd));
          if (std::abs(fd) < 1e-9 && std::abs(an) < 1e-9) continue;
          ++compared;
          agreed += std::abs(fd - an) <= 0.03 * std::max(std::abs(fd), std::abs(an)) + 1e-3;
        }
      }
    }
    EXPECT_GT(largest, 1.0) << "the silhouette should move the loss";
    EXPECT_GE(compared, 12);
    // All but a pixel centre that an edge crosses within the step (visibility changes).
    EXPECT_GE(agreed, compared - 1) << agreed << " of " << compared;
    std::printf("%d of %d gradient components agree\n", agreed, compared);
  }
}

}  // namespace
}  // namespace fuzzycsg::diffcsg

namespace fuzzycsg::diffcsg {
namespace {

TEST(DiffcsgIntersectionAa, EdgePlanePointVjpMatchesDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    Vec3 pts[5];
    for (Vec3& p : pts) p = {u(rng), u(rng), u(rng)};
    pts[0][2] = 1 + std::abs(pts[0][2]);  // the edge crosses the plane z ~ 0 of the triangle
    pts[1][2] = -1 - std::abs(pts[1][2]);
    for (int k = 2; k < 5; ++k) pts[k][2] *= 0.1;
    const Vec3 g{u(rng), u(rng), u(rng)};
    Vec3 grads[5] = {};
    edge_plane_point_vjp(pts[0], pts[1], pts[2], pts[3], pts[4], g, grads[0], grads[1], grads[2],
                         grads[3], grads[4]);
    for (int which = 0; which < 5; ++which) {
      for (int k = 0; k < 3; ++k) {
        Vec3 a[5], b[5];
        for (int j = 0; j < 5; ++j) a[j] = b[j] = pts[j];
        a[which][static_cast<std::size_t>(k)] += 1e-6;
        b[which][static_cast<std::size_t>(k)] -= 1e-6;
        const Vec3 pa = edge_plane_point(a[0], a[1], a[2], a[3], a[4]);
        const Vec3 pb = edge_plane_point(b[0], b[1], b[2], b[3], b[4]);
        const double fd = (dot(g, pa) - dot(g, pb)) / 2e-6;
        EXPECT_NEAR(grads[which][static_cast<std::size_t>(k)], fd, 1e-5 * (1 + std::abs(fd)));
      }
    }
  }
}

Scene model(const std::string& root) {
  return scene_from_tree(
      io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": )" +
                           root + "}"),
      "model");
}

// A block with a notch cut by a second box: every image edge of the notch is an intersection
// edge (the cutting box is only seen as the notch's walls), as in DiffCSG's Fig. 10.
std::string notch(double dx) {
  return R"({"op": "difference", "children": [{"type": "box", "size": [1.2, 1, 0.8], "rotate": [0, 0, 10]},
      {"type": "box", "size": [0.6, 0.6, 0.6], "translate": [)" +
         std::to_string(0.5 + dx) + R"(, 0.45, 0.35], "rotate": [8, 5, 20]}]})";
}

struct Rendered {
  Frame frame;
  Image colour, out;
  std::vector<AaPair> pairs;
  std::vector<IntersectionEdge> edges;
};

Rendered render(const Scene& scene, const Camera& cam, bool intersection) {
  Rendered r;
  r.frame = render_visibility(scene, cam, 1);
  r.colour = shade(r.frame);
  r.edges = intersection_edges(scene);
  r.out = antialias(scene, opposite_vertices(scene), cam, r.frame, r.colour, &r.pairs,
                    intersection ? &r.edges : nullptr);
  return r;
}

TEST(DiffcsgIntersectionAa, VertexGradientsMatchCentralDifferences) {
  const Camera cam = Camera::orbit({0, 0, 0}, 35, 30, 4, 48, 48, 35);
  for (
      const std::string& root :
      {notch(0),
       std::string(
           R"({"op": "union", "children": [{"type": "box", "size": [1, 0.8, 0.6], "rotate": [20, 35, 10]},
          {"type": "box", "size": [0.5, 0.5, 1.4], "translate": [0.3, 0.1, 0.2], "rotate": [5, 10, 30]}]})")}) {
    const Scene scene = model(root);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<float> w(48 * 48 * 3);
    for (float& x : w) x = u(rng);
    const Rendered r = render(scene, cam, true);
    int crossings = 0;
    for (const AaPair& p : r.pairs) crossings += p.intersection >= 0;
    EXPECT_GT(crossings, 10);
    Image g_out{48, 48, 3, w}, g_colour;
    std::vector<std::vector<Vec3>> grad;
    antialias_backward(scene, cam, r.colour, r.pairs, g_out, g_colour, grad, &r.edges);
    const auto loss_of = [&](const Scene& s) {
      const Rendered x = render(s, cam, true);
      double l = 0;
      for (std::size_t k = 0; k < x.out.data.size(); ++k) l += w[k] * x.out.data[k];
      return l;
    };
    int compared = 0, agreed = 0;
    for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
      for (std::size_t v = 0; v < scene.primitives[p].mesh.vertices.size(); ++v) {
        for (int k = 0; k < 3; ++k) {
          Scene a = scene, b = scene;
          a.primitives[p].mesh.vertices[v][static_cast<std::size_t>(k)] += 1e-5;
          b.primitives[p].mesh.vertices[v][static_cast<std::size_t>(k)] -= 1e-5;
          const double fd = (loss_of(a) - loss_of(b)) / 2e-5;
          const double an = grad[p][v][static_cast<std::size_t>(k)];
          if (std::abs(fd) < 1e-9 && std::abs(an) < 1e-9) continue;
          ++compared;
          agreed += std::abs(fd - an) <= 0.03 * std::max(std::abs(fd), std::abs(an)) + 1e-3;
        }
      }
    }
    std::printf("%d of %d gradient components agree\n", agreed, compared);
    EXPECT_GE(compared, 20);
    EXPECT_GE(agreed, compared - 1) << agreed << " of " << compared;
  }
}

// Fig. 10: the cutting box must move; only the intersection edges say so.
TEST(DiffcsgIntersectionAa, OnlyIntersectionEdgesCarryTheSignalOfANotch) {
  const Camera cam = Camera::orbit({0, 0, 0}, 35, 30, 4, 64, 64, 35);
  const Scene scene = model(notch(0)), target_scene = model(notch(0.04));
  const Rendered target = render(target_scene, cam, true);
  for (const bool intersection : {true, false}) {
    SCOPED_TRACE(intersection ? "with intersection edges" : "without");
    const Rendered r = render(scene, cam, intersection);
    // L = sum (out - target)^2.
    Image g_out = r.out;
    for (std::size_t k = 0; k < g_out.data.size(); ++k) {
      g_out.data[k] = 2 * (r.out.data[k] - target.out.data[k]);
    }
    Image g_colour;
    std::vector<std::vector<Vec3>> grad;
    antialias_backward(scene, cam, r.colour, r.pairs, g_out, g_colour, grad, &r.edges);
    double dx = 0;  // dL / d(the cutting box's x translation)
    for (const Vec3& g : grad[1]) dx += g[0];
    if (intersection) {
      EXPECT_LT(dx, -1e-2) << "moving the box towards the target lowers the loss";
    } else {
      EXPECT_EQ(dx, 0.0);
    }
  }
}

}  // namespace
}  // namespace fuzzycsg::diffcsg
