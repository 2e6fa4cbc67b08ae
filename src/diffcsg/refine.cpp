#include "fuzzycsg/diffcsg/refine.hpp"

#include <fmt/core.h>

#include <chrono>
#include <cmath>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/placement.hpp"
#include "fuzzycsg/fit/prune.hpp"

namespace fuzzycsg::diffcsg {

std::vector<double> parameter_gradient(const Tree& tree, const Scene& scene,
                                       const std::vector<std::vector<Vec3>>& grad_vertices,
                                       const TessellationOptions& options) {
  std::vector<double> grad(tree.params.size(), 0.0);
  const auto value = [&](ParamRef r) { return tree.params[r].value; };
  const auto add = [&](ParamRef r, double g) { grad[r.index] += g; };
  const TriMesh box = unit_box(), sphere = unit_sphere(options.sphere_subdivisions),
                cylinder = unit_cylinder(options.cylinder_segments);
  for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
    const Node& n = tree.node(scene.tree_node[p]);
    const TriMesh* unit = n.shape.type == PrimitiveType::kBox      ? &box
                          : n.shape.type == PrimitiveType::kSphere ? &sphere
                                                                   : &cylinder;
    Vec3 size{1, 1, 1};
    if (n.shape.type == PrimitiveType::kBox) {
      size = {value(n.intrinsic[0]), value(n.intrinsic[1]), value(n.intrinsic[2])};
    } else if (n.shape.type == PrimitiveType::kSphere) {
      size = {value(n.intrinsic[0]), value(n.intrinsic[0]), value(n.intrinsic[0])};
    } else {
      size = {value(n.intrinsic[0]), value(n.intrinsic[0]), value(n.intrinsic[1])};
    }
    std::array<double, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};
    const bool rotated = n.placement.rotate.size() == 3;
    if (rotated) {
      r = placement::rotation_3d(value(n.placement.rotate[0]), value(n.placement.rotate[1]),
                                 value(n.placement.rotate[2]));
    }
    const double s = n.placement.scale ? value(*n.placement.scale) : 1.0;
    std::array<double, 9> g_rot{};  // dL/dR
    Vec3 g_t{0, 0, 0}, g_size{0, 0, 0};
    double g_s = 0;
    const std::vector<Vec3>& gv = grad_vertices[p];
    for (std::size_t v = 0; v < unit->vertices.size() && v < gv.size(); ++v) {
      const Vec3& u = unit->vertices[v];
      const Vec3& g = gv[v];
      const Vec3 l{s * size[0] * u[0], s * size[1] * u[1], s * size[2] * u[2]};
      for (int a = 0; a < 3; ++a) {
        g_t[static_cast<std::size_t>(a)] += g[static_cast<std::size_t>(a)];
        for (int b = 0; b < 3; ++b) {
          g_rot[static_cast<std::size_t>(a * 3 + b)] +=
              g[static_cast<std::size_t>(a)] * l[static_cast<std::size_t>(b)];
        }
      }
      // v = t + R l: dv/dl_b = R[:, b]; l_b = s size_b u_b.
      for (int b = 0; b < 3; ++b) {
        double gr = 0;  // g . R[:, b]
        for (int a = 0; a < 3; ++a) {
          gr += g[static_cast<std::size_t>(a)] * r[static_cast<std::size_t>(a * 3 + b)];
        }
        g_size[static_cast<std::size_t>(b)] += gr * s * u[static_cast<std::size_t>(b)];
        g_s += gr * size[static_cast<std::size_t>(b)] * u[static_cast<std::size_t>(b)];
      }
    }
    for (std::size_t k = 0; k < n.placement.translate.size() && k < 3; ++k) {
      add(n.placement.translate[k], g_t[k]);
    }
    if (rotated) {
      const std::array<double, 3> ga =
          placement::rotation_3d_vjp(value(n.placement.rotate[0]), value(n.placement.rotate[1]),
                                     value(n.placement.rotate[2]), g_rot);
      for (std::size_t k = 0; k < 3; ++k) add(n.placement.rotate[k], ga[k]);
    }
    if (n.placement.scale) add(*n.placement.scale, g_s);
    if (n.shape.type == PrimitiveType::kBox) {
      for (std::size_t k = 0; k < 3; ++k) add(n.intrinsic[k], g_size[k]);
    } else if (n.shape.type == PrimitiveType::kSphere) {
      add(n.intrinsic[0], g_size[0] + g_size[1] + g_size[2]);
    } else {
      add(n.intrinsic[0], g_size[0] + g_size[1]);
      add(n.intrinsic[1], g_size[2]);
    }
  }
  return grad;
}

std::array<float, 3> primitive_colour(int p) {
  static constexpr std::array<std::array<float, 3>, 10> kPalette{{{31, 119, 180},
                                                                  {255, 127, 14},
                                                                  {44, 160, 44},
                                                                  {214, 39, 40},
                                                                  {148, 103, 189},
                                                                  {140, 86, 75},
                                                                  {227, 119, 194},
                                                                  {127, 127, 127},
                                                                  {188, 189, 34},
                                                                  {23, 190, 207}}};
  const auto& c = kPalette[static_cast<std::size_t>(p) % kPalette.size()];
  return {c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f};
}

Image colour_image(const Frame& frame) {
  Image img{frame.width, frame.height, 3, std::vector<float>(frame.primitive.size() * 3, 0.0f)};
  for (std::size_t p = 0; p < frame.primitive.size(); ++p) {
    if (frame.primitive[p] < 0) continue;
    const auto c = primitive_colour(frame.primitive[p]);
    for (int k = 0; k < 3; ++k) img.at(p)[k] = c[static_cast<std::size_t>(k)];
  }
  return img;
}

RefineResult refine_to_images(const Tree& input, const std::vector<Camera>& cameras,
                              const std::vector<Image>& targets, const RefineOptions& o,
                              const TessellationOptions& tessellation) {
  if (cameras.empty() || cameras.size() != targets.size()) {
    throw InputError("refine: one target image per camera expected");
  }
  for (std::size_t v = 0; v < cameras.size(); ++v) {
    if (targets[v].width != cameras[v].width || targets[v].height != cameras[v].height ||
        targets[v].channels != 3) {
      throw InputError(fmt::format("refine: target image {} is {}x{}, the camera's {}x{}", v,
                                   targets[v].width, targets[v].height, cameras[v].width,
                                   cameras[v].height));
    }
  }
  if (o.iterations < 0 || !(o.lr > 0)) throw InputError("refine: iterations >= 0 and lr > 0");
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  RefineResult result;
  bool unified = false;
  for (const Node& n : input.nodes) {
    unified = unified || (n.kind == NodeKind::kOperator && n.op == OpKind::kUnified);
  }
  result.tree = unified ? snap_operators(input) : input;
  Tree& tree = result.tree;
  std::vector<double> params = tree.params.values(), m(params.size(), 0.0), v2(params.size(), 0.0);
  for (int step = 0; step <= o.iterations; ++step) {
    tree.params.set_values(params);
    const Scene scene = scene_from_tree(tree, "refine", tessellation);
    const Topology topology = opposite_vertices(scene);
    auto t0 = Clock::now();
    const std::vector<IntersectionEdge> edges =
        o.intersection_aa ? intersection_edges(scene) : std::vector<IntersectionEdge>{};
    result.seconds_edges += since(t0);
    std::vector<double> grad(params.size(), 0.0);
    double loss = 0;
    int visible = 0;
    for (std::size_t v = 0; v < cameras.size(); ++v) {
      t0 = Clock::now();
      const Frame f = render_visibility(scene, cameras[v], o.threads);
      result.seconds_visibility += since(t0);
      visible += f.visible_pixels();
      const Image colour = colour_image(f);
      std::vector<AaPair> pairs;
      t0 = Clock::now();
      const Image out = antialias(scene, topology, cameras[v], f, colour, &pairs,
                                  o.intersection_aa ? &edges : nullptr);
      result.seconds_antialias += since(t0);
      t0 = Clock::now();
      Image g_out = out;
      const double norm = 1.0 / (static_cast<double>(out.data.size()) * cameras.size());
      for (std::size_t k = 0; k < out.data.size(); ++k) {
        const double d = out.data[k] - targets[v].data[k];
        loss += d * d * norm;
        g_out.data[k] = static_cast<float>(2 * d * norm);
      }
      Image g_colour;
      std::vector<std::vector<Vec3>> gv;
      antialias_backward(scene, cameras[v], colour, pairs, g_out, g_colour, gv,
                         o.intersection_aa ? &edges : nullptr);
      const std::vector<double> gp = parameter_gradient(tree, scene, gv, tessellation);
      for (std::size_t k = 0; k < grad.size(); ++k) grad[k] += gp[k];
      result.seconds_backward += since(t0);
    }
    result.loss.push_back(loss);
    if (visible == 0) {
      result.vanished = true;
      break;
    }
    if (loss < o.stop_loss) {
      result.converged = true;
      break;
    }
    if (step == o.iterations) break;
    ++result.steps;
    const double c1 = 1 - std::pow(o.beta1, result.steps), c2 = 1 - std::pow(o.beta2, result.steps);
    for (std::size_t k = 0; k < params.size(); ++k) {
      const Parameter& p = tree.params.at(k);
      if (p.fixed) continue;
      m[k] = o.beta1 * m[k] + (1 - o.beta1) * grad[k];
      v2[k] = o.beta2 * v2[k] + (1 - o.beta2) * grad[k] * grad[k];
      params[k] -= o.lr * (m[k] / c1) / (std::sqrt(v2[k] / c2) + o.eps);
      // Sizes and radii stay positive (their ranges say so).
      if (params[k] < p.range.lo || (p.range.lo_open && params[k] <= p.range.lo)) {
        params[k] = p.range.lo + 1e-6;
      }
      if (params[k] > p.range.hi) params[k] = p.range.hi;
    }
  }
  tree.params.set_values(params);
  return result;
}

}  // namespace fuzzycsg::diffcsg
