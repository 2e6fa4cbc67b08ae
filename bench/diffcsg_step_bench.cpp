// diffcsg_step_bench: one refinement step of DiffCSG (one view, 512 x 512, forward and
// backward to the parameters) against the paper's GPU times for the same triangle counts
// (Yuan et al. 2024, Table 1: 128 triangles 0.061 s, 2,980 triangles 0.345 s), on:
//   small  a cube less a cylinder of 29 sides, with a bar through it: 136 triangles;
//   large  OpenSCAD's CSG.scad example (a cube less a sphere, a cube and a sphere intersected,
//          three cylinders): 2,724 triangles.
// A step: the scene tessellated from the tree's parameters, intersection edges, visibility,
// normal shading and antialiasing, the loss against a target image, and the backward pass
// through antialiasing and shading to the vertices and the parameters. Medians of N steps with
// every hardware thread, then with one (the baseline, same process). Prints the split and the
// ratio to the paper's time (< 1: faster than the paper's GPU).
//
//   diffcsg_step_bench [steps]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>
#include <vector>

#include "bench/bench_lists.hpp"
#include "bench/data_dir.hpp"
#include "diffcsg_scenes.hpp"
#include "fuzzycsg/diffcsg/openscad_csg.hpp"
#include "fuzzycsg/diffcsg/refine.hpp"

using namespace fuzzycsg;
using namespace fuzzycsg::diffcsg;

namespace {

using fuzzycsg::bench::median;

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

struct Split {
  double scene = 0, edges = 0, visibility = 0, shade_aa = 0, backward = 0, total = 0;
};

// One refinement step; `pass` and `grad` are reused from step to step, as refine does.
Split step(const OpenscadModel& m, const Camera& cam, const Image& target, int threads,
           ViewPass& pass, Image& grad) {
  Split s;
  const auto t0 = Clock::now();
  Scene scene = scene_from_tree(m.tree, "bench", m.tessellation);
  s.scene = since(t0);
  const PreparedScene ps = prepare_scene(std::move(scene), true);
  s.edges = ps.seconds_edges;
  render_view(ps, cam, Shading::kNormals, threads, pass);
  s.visibility = pass.seconds_visibility;
  s.shade_aa = pass.seconds_antialias;
  const auto t1 = Clock::now();
  image_loss(pass.image, target, diffcsg::Loss::kTanh, &grad);
  VertexGradient gv;
  render_view_backward(ps, cam, Shading::kNormals, pass, grad, gv);
  const std::vector<double> g = parameter_gradient(m.tree, ps.scene, gv.g);
  s.backward = since(t1);
  s.total = since(t0);
  if (g.empty()) std::abort();
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 7;
  const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  struct Model {
    const char* name;
    OpenscadModel model;
    double paper;  // Table 1's seconds for that many triangles
  };
  std::vector<Model> models;
  models.push_back(
      {"small", parse_openscad_csg_tree(fuzzycsg::bench::kSmallScene, "small"), 0.061});
  models.push_back(
      {"large", read_openscad_csg_tree(fuzzycsg::bench::data_file("scad/Basics/CSG.openscad.csg")),
       0.345});
  std::printf("one step, one view, 512x512, normal images; median of %d steps\n", runs);
  std::printf("%-6s %9s %6s %8s %8s %8s %8s %8s %8s %8s %7s\n", "model", "triangles", "thr",
              "scene", "edges", "visib.", "shadeAA", "backward", "total", "paper", "ratio");
  for (const Model& m : models) {
    const Scene scene = scene_from_tree(m.model.tree, m.name, m.model.tessellation);
    const auto [lo, hi] = scene.bounds();
    const Vec3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
    const Camera cam =
        orbit_views(centre, framing_distance(scene, centre, 30, 1.2), 1, 25, 512, 512, 30)[0];
    // The target: the same program with every parameter 2% larger.
    Tree goal = m.model.tree;
    for (std::size_t k = 0; k < goal.params.size(); ++k) goal.params.at(k).value *= 1.02;
    const Image target = render_image(
        prepare_scene(scene_from_tree(goal, "goal", m.model.tessellation)), cam, Shading::kNormals);
    for (const int threads : {hw, 1}) {
      std::vector<Split> splits;
      ViewPass pass;
      Image grad;
      step(m.model, cam, target, threads, pass, grad);  // warm up
      for (int r = 0; r < runs; ++r)
        splits.push_back(step(m.model, cam, target, threads, pass, grad));
      const auto med = [&](double Split::*field) {
        std::vector<double> v;
        for (const Split& s : splits) v.push_back(s.*field);
        return median(v) * 1000;
      };
      const double total = med(&Split::total);
      std::printf("%-6s %9zu %6d %7.1fms %7.1fms %7.1fms %7.1fms %7.1fms %7.1fms %7.0fms %7.2f\n",
                  m.name, scene.triangle_count(), threads, med(&Split::scene), med(&Split::edges),
                  med(&Split::visibility), med(&Split::shade_aa), med(&Split::backward), total,
                  m.paper * 1000, total / (m.paper * 1000));
    }
  }
  return 0;
}
