// diffcsg_protocol: DiffCSG's benchmark protocol (Yuan et al. 2024, §4.1 and its released
// code) on OpenSCAD models, with the two comparisons of §4.3 on the same cases.
//
// For each model (an OpenSCAD .csg, read as a tree: openscad_csg.hpp), each sigma and each
// trial, every free parameter that is not 0 is perturbed by a factor (1 + N(0, sigma)) (seeded
// by the model's name, sigma and the trial), and the perturbed program is refined towards the
// images of the original one. Success: the normal image's mean squared error at a fixed view
// (azimuth 30, elevation 25) falls below --stop (5e-4) within --iters steps. Methods:
//   diffcsg  Adam on the differentiable renderer's gradients, normal images, the tanh loss,
//            one random view redrawn every 5 steps (as the released code), learning rates
//            --lr-relative times each parameter's scale (refine.hpp: parameter_scales);
//   cmaes    CMA-ES on the mean L2 loss of three fixed views (view 0 the check view), --iters
//            evaluations, first steps 0.1 of each parameter's scale;
//   fuzzy    the SDF-style approach through the project's own fuzzy evaluator: the program's
//            leaves become sigmoid occupancies (transition over 2% of the model's extent), the
//            occupancy's MSE against the original program's crisp occupancy on 8,192 points a
//            step (half uniform in the padded bounding box, half within 2% of the primitives'
//            surfaces) is minimised by Adam at the same relative rates; success is checked on
//            the crisp program's normal image every 10 steps.
// One JSON line per trial on stdout (bench/diffcsg_protocol_summary.py makes the table).
//
//   diffcsg_protocol --models a.csg,b.csg [--sigmas 0.05,0.1,0.2,0.3] [--trials 2]
//                    [--methods diffcsg,cmaes,fuzzy] [--size 256] [--iters 1000]
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diffcsg/openscad_csg.hpp"
#include "fuzzycsg/diffcsg/refine.hpp"
#include "fuzzycsg/eval/evaluator.hpp"

using namespace fuzzycsg;
using namespace fuzzycsg::diffcsg;

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

struct Case {
  std::string name;
  OpenscadModel model;
  std::shared_ptr<PreparedScene> truth;
  Vec3 centre{};
  double distance = 1, extent = 1;
};

Tree perturbed(const Tree& tree, double sigma, std::uint64_t seed) {
  Tree out = tree;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0, sigma);
  for (std::size_t k = 0; k < out.params.size(); ++k) {
    Parameter& p = out.params.at(k);
    if (p.fixed || p.value == 0) continue;
    double v = p.value * (1 + n(rng));
    if (v < p.range.lo || (p.range.lo_open && v <= p.range.lo)) v = p.range.lo + 1e-6;
    p.value = std::min(v, p.range.hi);
  }
  return out;
}

double check_mse(const Case& c, const Tree& tree, const Camera& check, const Image& target) {
  return image_mse(render_image(prepare_scene(scene_from_tree(tree, c.name, c.model.tessellation)),
                                check, Shading::kNormals),
                   target);
}

// The SDF-style comparison: the program's fuzzy occupancy fitted to the original's on points.
struct FuzzyOutcome {
  Tree tree;
  int steps = 0;
  bool converged = false;
};
FuzzyOutcome refine_fuzzy(const Case& c, const Tree& start, const Camera& check,
                          const Image& check_target, int iters, double lr_relative,
                          std::uint64_t seed, double stop) {
  const auto to_fuzzy = [&](const Tree& crisp) {
    Tree t = crisp;
    const double s = 4 / (0.02 * c.extent);
    for (std::size_t i = 0; i < t.nodes.size(); ++i) {
      Node& n = t.nodes[i];
      if (n.kind != NodeKind::kPrimitive) continue;
      n.step.kind = StepKind::kSigmoid;
      n.step.param =
          t.params.add({"sharpness." + std::to_string(i), s, true, false, Range::positive()});
    }
    return t;
  };
  const Tree model = to_fuzzy(start);
  const Tree truth = to_fuzzy(c.model.tree);
  const Evaluator evaluator(model), crisp_truth(c.model.tree);
  const std::size_t np = start.params.size();  // the fuzzy trees add their sharpness after these
  const auto [lo, hi] = c.truth->scene.bounds();
  std::vector<double> lr = parameter_scales(start, c.model.tessellation);
  for (double& x : lr) x *= lr_relative;
  std::vector<double> params = model.params.values(), m(params.size(), 0), v(params.size(), 0),
                      grad(params.size(), 0);
  (void)truth;
  // Surface samples come from the original's primitives (their triangles, by area).
  std::vector<double> area_cdf;
  std::vector<std::array<Vec3, 3>> triangles;
  for (const PrimitiveMesh& primitive : c.truth->scene.primitives) {
    const TriangleMesh& mesh = primitive.mesh;
    for (const auto& t : mesh.triangles) {
      const Vec3 &a = mesh.vertices[static_cast<std::size_t>(t[0])],
                 &b = mesh.vertices[static_cast<std::size_t>(t[1])],
                 &d = mesh.vertices[static_cast<std::size_t>(t[2])];
      const Vec3 n = cross(sub(b, a), sub(d, a));
      area_cdf.push_back((area_cdf.empty() ? 0 : area_cdf.back()) + std::sqrt(dot(n, n)));
      triangles.push_back({a, b, d});
    }
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, 0.02 * c.extent);
  const std::size_t n_points = 8192;
  std::vector<float> points(n_points * 3), targets(n_points);
  std::vector<double> truth_params = c.model.tree.params.values();
  FuzzyOutcome out;
  Tree result = start;
  for (int step = 0; step <= iters; ++step) {
    if (step % 10 == 0 || step == iters) {
      std::vector<double> values(params.begin(), params.begin() + static_cast<long>(np));
      result.params.set_values(values);
      if (check_mse(c, result, check, check_target) < stop) {
        out.converged = true;
        break;
      }
    }
    if (step == iters) break;
    for (std::size_t i = 0; i < n_points; ++i) {
      Vec3 p;
      if (i % 2 == 0) {
        for (std::size_t k = 0; k < 3; ++k) {
          const double pad = 0.1 * (hi[k] - lo[k]);
          p[k] = lo[k] - pad + u(rng) * (hi[k] - lo[k] + 2 * pad);
        }
      } else {
        const double r = u(rng) * area_cdf.back();
        const std::size_t t = static_cast<std::size_t>(
            std::lower_bound(area_cdf.begin(), area_cdf.end(), r) - area_cdf.begin());
        double a = u(rng), b = u(rng);
        if (a + b > 1) {
          a = 1 - a;
          b = 1 - b;
        }
        const auto& tri = triangles[std::min(t, triangles.size() - 1)];
        for (std::size_t k = 0; k < 3; ++k) {
          p[k] = tri[0][k] + a * (tri[1][k] - tri[0][k]) + b * (tri[2][k] - tri[0][k]) + g(rng);
        }
      }
      for (std::size_t k = 0; k < 3; ++k) points[i * 3 + k] = static_cast<float>(p[k]);
    }
    crisp_truth.forward(truth_params, points, targets);
    fuzzycsg::Loss loss;
    loss.kind = fuzzycsg::Loss::Kind::kMse;
    loss.targets = targets;
    std::fill(grad.begin(), grad.end(), 0.0);
    evaluator.backward(params, points, loss, grad);
    ++out.steps;
    const double c1 = 1 - std::pow(0.9, out.steps), c2 = 1 - std::pow(0.999, out.steps);
    for (std::size_t k = 0; k < np; ++k) {
      const Parameter& p = model.params.at(k);
      if (p.fixed) continue;
      m[k] = 0.9 * m[k] + 0.1 * grad[k];
      v[k] = 0.999 * v[k] + 0.001 * grad[k] * grad[k];
      double x = params[k] - lr[k] * (m[k] / c1) / (std::sqrt(v[k] / c2) + 1e-8);
      if (x < p.range.lo || (p.range.lo_open && x <= p.range.lo)) x = p.range.lo + 1e-6;
      params[k] = std::min(x, p.range.hi);
    }
  }
  std::vector<double> values(params.begin(), params.begin() + static_cast<long>(np));
  result.params.set_values(values);
  out.tree = result;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("DiffCSG's benchmark protocol with CMA-ES and fuzzy-evaluator comparisons");
  std::vector<std::string> models;
  std::vector<double> sigmas{0.05, 0.1, 0.2, 0.3};
  std::vector<std::string> methods{"diffcsg", "cmaes", "fuzzy"};
  int trials = 2, size = 256, iters = 1000, threads = 0;
  double stop = 5e-4, lr_relative = 0.002;
  app.add_option("--models", models, "OpenSCAD .csg files")->delimiter(',')->required();
  app.add_option("--sigmas", sigmas, "Perturbation levels")->delimiter(',');
  app.add_option("--methods", methods, "diffcsg, cmaes, fuzzy")->delimiter(',');
  app.add_option("--trials", trials, "Trials per model and sigma");
  app.add_option("--size", size, "Image size");
  app.add_option("--iters", iters, "Steps (evaluations for CMA-ES)");
  app.add_option("--stop", stop, "Success: the check view's MSE below this");
  app.add_option("--lr-relative", lr_relative, "Adam's rates relative to each parameter");
  app.add_option("--threads", threads, "Threads (0: all)");
  CLI11_PARSE(app, argc, argv);
  try {
    for (const std::string& path : models) {
      Case c;
      c.name = std::filesystem::path(path).stem().string();
      c.model = read_openscad_csg_tree(path);
      c.truth = std::make_shared<PreparedScene>(
          prepare_scene(scene_from_tree(c.model.tree, path, c.model.tessellation)));
      const auto [lo, hi] = c.truth->scene.bounds();
      c.centre = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
      c.extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
      c.distance = framing_distance(c.truth->scene, c.centre, 30, 1.2);
      int free = 0;
      for (const Parameter& p : c.model.tree.params.entries()) free += !p.fixed && p.value != 0;
      const std::vector<Camera> fixed = orbit_views(c.centre, c.distance, 3, 25, size, size, 30);
      RefineTarget target;
      target.shading = Shading::kNormals;
      target.cameras = fixed;
      const auto truth = c.truth;
      target.render = [truth, threads](const Camera& cam) {
        return render_image(*truth, cam, Shading::kNormals, threads);
      };
      for (const Camera& cam : fixed) target.images.push_back(target.render(cam));
      for (const double sigma : sigmas) {
        for (int trial = 0; trial < trials; ++trial) {
          const std::uint64_t seed = std::hash<std::string>{}(c.name) ^
                                     (static_cast<std::uint64_t>(sigma * 1000) << 20) ^
                                     static_cast<std::uint64_t>(trial);
          const Tree start = perturbed(c.model.tree, sigma, seed);
          const double start_mse = check_mse(c, start, fixed[0], target.images[0]);
          for (const std::string& method : methods) {
            const auto t0 = Clock::now();
            Tree result;
            int steps = 0;
            bool converged = false;
            if (method == "fuzzy") {
              const FuzzyOutcome f = refine_fuzzy(c, start, fixed[0], target.images[0], iters,
                                                  lr_relative, seed, stop);
              result = f.tree;
              steps = f.steps;
              converged = f.converged;
            } else {
              RefineOptions o;
              o.iterations = iters;
              o.stop_mse = stop;
              o.threads = threads;
              o.seed = seed;
              if (method == "cmaes") {
                o.method = Method::kCmaes;
                o.loss = diffcsg::Loss::kL2;
              } else {
                o.loss = diffcsg::Loss::kTanh;
                o.lr_relative = lr_relative;
                o.random_view_every = 5;
              }
              const RefineResult r = refine(start, target, o, c.model.tessellation);
              result = r.tree;
              steps = r.steps;
              converged = r.converged;
            }
            const double seconds = seconds_since(t0);
            const double final_mse = check_mse(c, result, fixed[0], target.images[0]);
            nlohmann::json line{
                {"model", c.name},        {"triangles", c.truth->scene.triangle_count()},
                {"parameters", free},     {"sigma", sigma},
                {"trial", trial},         {"method", method},
                {"success", converged},   {"steps", steps},
                {"seconds", seconds},     {"start_mse", start_mse},
                {"final_mse", final_mse}, {"size", size}};
            std::printf("%s\n", line.dump().c_str());
            std::fflush(stdout);
          }
        }
      }
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "diffcsg_protocol: %s\n", e.what());
    return 2;
  }
  return 0;
}
