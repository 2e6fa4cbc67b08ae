// Refinement of a program's parameters from images: the parameter gradient against central
// differences, and a perturbed box recovered from three views.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "fuzzycsg/diffcsg/refine.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::diffcsg {
namespace {

std::string two_boxes(double tx, double ty, double tz, double sz) {
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                R"({"format": "fuzzycsg-tree", "version": 1, "dim": 3, "root": {"op": "union",
      "children": [{"type": "box", "size": [1, 0.8, 0.6], "rotate": [20, 35, 10], "scale": 1.1},
        {"type": "box", "size": [0.5, 0.5, %.6f], "translate": [%.6f, %.6f, %.6f],
         "rotate": [5, 10, 30]}]}})",
                sz, tx, ty, tz);
  return buf;
}

std::vector<Camera> views(int n, int size) {
  std::vector<Camera> c;
  for (int k = 0; k < n; ++k)
    c.push_back(Camera::orbit({0, 0, 0}, 30 + 120 * k, 25, 4, size, size, 35));
  return c;
}

double weighted(const Tree& tree, const Camera& cam, const std::vector<float>& w) {
  const Scene scene = scene_from_tree(tree, "t");
  const Frame f = render_visibility(scene, cam, 1);
  const std::vector<IntersectionEdge> edges = intersection_edges(scene);
  const Image out =
      antialias(scene, opposite_vertices(scene), cam, f, colour_image(f), nullptr, &edges);
  double l = 0;
  for (std::size_t k = 0; k < out.data.size(); ++k) l += w[k] * out.data[k];
  return l;
}

TEST(DiffcsgRefine, ParameterGradientMatchesCentralDifferences) {
  const Tree tree = io::read_tree_string(two_boxes(0.3, 0.1, 0.2, 1.4));
  const Camera cam = views(1, 48)[0];
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> w(48 * 48 * 3);
  for (float& x : w) x = u(rng);
  const Scene scene = scene_from_tree(tree, "t");
  const Frame f = render_visibility(scene, cam, 1);
  const Image colour = colour_image(f);
  const std::vector<IntersectionEdge> edges = intersection_edges(scene);
  std::vector<AaPair> pairs;
  antialias(scene, opposite_vertices(scene), cam, f, colour, &pairs, &edges);
  Image g_out{48, 48, 3, w}, g_colour;
  std::vector<std::vector<Vec3>> gv;
  antialias_backward(scene, cam, colour, pairs, g_out, g_colour, gv, &edges);
  const std::vector<double> grad = parameter_gradient(tree, scene, gv);
  ASSERT_EQ(grad.size(), tree.params.size());
  int compared = 0, agreed = 0;
  for (std::size_t k = 0; k < grad.size(); ++k) {
    const double eps = 1e-5 * std::max(1.0, std::abs(tree.params.at(k).value));
    Tree a = tree, b = tree;
    a.params.at(k).value += eps;
    b.params.at(k).value -= eps;
    const double fd = (weighted(a, cam, w) - weighted(b, cam, w)) / (2 * eps);
    if (std::abs(fd) < 1e-9 && std::abs(grad[k]) < 1e-9) continue;
    ++compared;
    const bool ok =
        std::abs(fd - grad[k]) <= 0.03 * std::max(std::abs(fd), std::abs(grad[k])) + 1e-3;
    agreed += ok;
    if (!ok) std::printf("%s: fd %g analytic %g\n", tree.params.at(k).name.c_str(), fd, grad[k]);
  }
  std::printf("%d of %d parameter gradients agree\n", agreed, compared);
  EXPECT_GE(compared, 14);  // 3 + 3 + 1 (first box) and 3 + 3 + 3 (second)
  EXPECT_GE(agreed, compared - 1);
}

TEST(DiffcsgRefine, RecoversAMovedAndStretchedBoxFromThreeViews) {
  const Tree start = io::read_tree_string(two_boxes(0.3, 0.1, 0.2, 1.4));
  const Tree goal = io::read_tree_string(two_boxes(0.38, 0.04, 0.27, 1.55));
  const std::vector<Camera> cams = views(3, 96);
  std::vector<Image> targets;
  const Scene goal_scene = scene_from_tree(goal, "goal");
  const std::vector<IntersectionEdge> edges = intersection_edges(goal_scene);
  for (const Camera& c : cams) {
    const Frame f = render_visibility(goal_scene, c, 2);
    targets.push_back(antialias(goal_scene, opposite_vertices(goal_scene), c, f, colour_image(f),
                                nullptr, &edges));
  }
  RefineOptions o;
  o.iterations = 150;
  o.lr = 0.005;
  o.stop_mse = 0;
  const RefineResult r = refine(start, RefineTarget{cams, targets, Shading::kColours, nullptr}, o);
  ASSERT_FALSE(r.vanished);
  ASSERT_GE(r.loss.size(), 2u);
  const auto error = [&](const Tree& t) {
    double e = 0;
    for (std::size_t k = 0; k < t.params.size(); ++k) {
      const double d = t.params.at(k).value - goal.params.at(k).value;
      e += d * d;
    }
    return std::sqrt(e);
  };
  std::printf("loss %g -> %g, parameter error %g -> %g\n", r.loss.front(), r.loss.back(),
              error(start), error(r.tree));
  EXPECT_LT(r.loss.back(), 0.2 * r.loss.front());
  EXPECT_LT(error(r.tree), 0.5 * error(start));
}

}  // namespace
}  // namespace fuzzycsg::diffcsg
