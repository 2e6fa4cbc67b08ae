#include "fuzzycsg/diffcsg/refine.hpp"
#include "fuzzycsg/core/snap.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <set>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/limits.hpp"
#include "fuzzycsg/core/placement.hpp"
#include "fuzzycsg/optim/adam.hpp"
#include "fuzzycsg/optim/cmaes.hpp"

namespace fuzzycsg::diffcsg {

namespace {

using Clock = std::chrono::steady_clock;

Vec3 rotate(const std::array<double, 9>& r, const Vec3& l) {
  return {r[0] * l[0] + r[1] * l[1] + r[2] * l[2], r[3] * l[0] + r[4] * l[1] + r[5] * l[2],
          r[6] * l[0] + r[7] * l[1] + r[8] * l[2]};
}

}  // namespace

std::vector<double> parameter_gradient(const Tree& tree, const Scene& scene,
                                       const std::vector<std::vector<Vec3>>& grad_vertices) {
  if (scene.bindings.size() != scene.primitives.size()) {
    throw Error("parameter_gradient: the scene was not built from a tree");
  }
  std::vector<double> grad(tree.params.size(), 0.0);
  const auto value = [&](ParamRef r) { return tree.params[r].value; };
  for (std::size_t p = 0; p < scene.primitives.size() && p < grad_vertices.size(); ++p) {
    const PrimitiveBinding& b = scene.bindings[p];
    const std::array<double, 9>& r = b.rotation;
    const double s = b.scale_value;
    std::array<double, 9> g_rot{};  // dL/dR
    Vec3 g_t{0, 0, 0};
    double g_s = 0;
    const std::vector<Vec3>& gv = grad_vertices[p];
    for (std::size_t v = 0; v < b.local.size() && v < gv.size(); ++v) {
      const Vec3& g = gv[v];
      if (g[0] == 0 && g[1] == 0 && g[2] == 0) continue;
      const Vec3& l = b.local[v];
      // v = t + s R l.
      for (std::size_t a = 0; a < 3; ++a) {
        g_t[a] += g[a];
        for (std::size_t c = 0; c < 3; ++c) g_rot[a * 3 + c] += s * g[a] * l[c];
      }
      const Vec3 rl = rotate(r, l);
      g_s += dot(g, rl);
      // dL/dl = s R^T g.
      const Vec3 gl{s * (r[0] * g[0] + r[3] * g[1] + r[6] * g[2]),
                    s * (r[1] * g[0] + r[4] * g[1] + r[7] * g[2]),
                    s * (r[2] * g[0] + r[5] * g[1] + r[8] * g[2])};
      for (std::uint32_t k = b.offsets[v]; k < b.offsets[v + 1]; ++k) {
        grad[b.terms[k].param.index] += dot(gl, b.terms[k].coefficient);
      }
    }
    for (std::size_t k = 0; k < b.translate.size() && k < 3; ++k) {
      grad[b.translate[k].index] += g_t[k];
    }
    if (b.rotate.size() == 3) {
      const std::array<double, 3> ga = placement::rotation_3d_vjp(
          value(b.rotate[0]), value(b.rotate[1]), value(b.rotate[2]), g_rot);
      for (std::size_t k = 0; k < 3; ++k) grad[b.rotate[k].index] += ga[k];
    }
    if (b.scale) grad[b.scale->index] += g_s;
  }
  return grad;
}

std::vector<std::vector<Vec3>> vertex_tangent(const Tree& tree, const Scene& scene,
                                              std::size_t param) {
  if (scene.bindings.size() != scene.primitives.size()) {
    throw Error("vertex_tangent: the scene was not built from a tree");
  }
  if (param >= tree.params.size()) throw Error("vertex_tangent: no such parameter");
  const auto value = [&](ParamRef r) { return tree.params[r].value; };
  std::vector<std::vector<Vec3>> out(scene.primitives.size());
  for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
    const PrimitiveBinding& b = scene.bindings[p];
    out[p].assign(b.local.size(), Vec3{0, 0, 0});
    // dR/dθ where θ is one of the angles: the Jacobian column, from the VJP of unit matrices.
    std::array<double, 9> d_rot{};
    bool rotates = false;
    for (std::size_t k = 0; k < b.rotate.size() && k < 3; ++k) {
      if (b.rotate[k].index != param) continue;
      rotates = true;
      for (std::size_t e = 0; e < 9; ++e) {
        std::array<double, 9> unit{};
        unit[e] = 1;
        d_rot[e] += placement::rotation_3d_vjp(value(b.rotate[0]), value(b.rotate[1]),
                                               value(b.rotate[2]), unit)[k];
      }
    }
    Vec3 d_t{0, 0, 0};
    for (std::size_t k = 0; k < b.translate.size() && k < 3; ++k) {
      if (b.translate[k].index == param) d_t[k] += 1;
    }
    const bool scales = b.scale && b.scale->index == param;
    for (std::size_t v = 0; v < b.local.size(); ++v) {
      const Vec3& l = b.local[v];
      Vec3 dl{0, 0, 0};
      for (std::uint32_t k = b.offsets[v]; k < b.offsets[v + 1]; ++k) {
        if (b.terms[k].param.index != param) continue;
        for (std::size_t c = 0; c < 3; ++c) dl[c] += b.terms[k].coefficient[c];
      }
      Vec3 d = d_t;
      const Vec3 rdl = rotate(b.rotation, dl);
      for (std::size_t c = 0; c < 3; ++c) d[c] += b.scale_value * rdl[c];
      if (scales) {
        const Vec3 rl = rotate(b.rotation, l);
        for (std::size_t c = 0; c < 3; ++c) d[c] += rl[c];
      }
      if (rotates) {
        const Vec3 drl = rotate(d_rot, l);
        for (std::size_t c = 0; c < 3; ++c) d[c] += b.scale_value * drl[c];
      }
      out[p][v] = d;
    }
  }
  return out;
}

Image colour_image(const Frame& frame) {
  Image img{frame.width, frame.height, 3, std::vector<float>(frame.primitive.size() * 3, 0.0f)};
  for (std::size_t p = 0; p < frame.primitive.size(); ++p) {
    if (frame.primitive[p] < 0) continue;
    const auto c = primitive_colour(frame.primitive[p]);
    for (std::size_t k = 0; k < 3; ++k) img.at(p)[k] = c[k];
  }
  return img;
}

std::string_view method_name(Method m) {
  switch (m) {
    case Method::kAdam:
      return "adam";
    case Method::kCmaes:
      return "cmaes";
  }
  return "adam";
}

std::optional<Method> method_from_name(std::string_view name) {
  for (const Method m : {Method::kAdam, Method::kCmaes}) {
    if (name == method_name(m)) return m;
  }
  return std::nullopt;
}

std::string_view loss_name(Loss l) {
  switch (l) {
    case Loss::kL1:
      return "l1";
    case Loss::kL2:
      return "l2";
    case Loss::kTanh:
      return "tanh";
  }
  return "l2";
}

std::optional<Loss> loss_from_name(std::string_view name) {
  if (name == "l1") return Loss::kL1;
  if (name == "l2") return Loss::kL2;
  if (name == "tanh") return Loss::kTanh;
  return std::nullopt;
}

double image_loss(const Image& image, const Image& target, Loss loss, Image* grad) {
  if (image.width != target.width || image.height != target.height ||
      image.channels != target.channels) {
    throw Error("image_loss: the images differ in size");
  }
  if (grad) {
    grad->width = image.width;
    grad->height = image.height;
    grad->channels = image.channels;
    grad->data.assign(image.data.size(), 0.0f);
  }
  const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
  const std::size_t ch = static_cast<std::size_t>(image.channels);
  if (pixels == 0) return 0;
  double sum = 0;
  if (loss == Loss::kTanh) {
    for (std::size_t p = 0; p < pixels; ++p) {
      double e = 0;
      for (std::size_t c = 0; c < ch; ++c) {
        const double d = image.data[p * ch + c] - target.data[p * ch + c];
        e += d * d;
      }
      const double th = std::tanh(10 * e);
      sum += th;
      if (grad) {
        const double k = (1 - th * th) * 10 / static_cast<double>(pixels);
        for (std::size_t c = 0; c < ch; ++c) {
          const double d = image.data[p * ch + c] - target.data[p * ch + c];
          grad->data[p * ch + c] = static_cast<float>(k * 2 * d);
        }
      }
    }
    return sum / static_cast<double>(pixels);
  }
  const double n = static_cast<double>(pixels * ch);
  for (std::size_t k = 0; k < pixels * ch; ++k) {
    const double d = image.data[k] - target.data[k];
    if (loss == Loss::kL1) {
      sum += std::abs(d);
      if (grad) grad->data[k] = static_cast<float>((d > 0 ? 1 : (d < 0 ? -1 : 0)) / n);
    } else {
      sum += d * d;
      if (grad) grad->data[k] = static_cast<float>(2 * d / n);
    }
  }
  return sum / n;
}

double image_mse(const Image& image, const Image& target) {
  return image_loss(image, target, Loss::kL2, nullptr);
}

namespace {

// The primitives no fixed view shows.
std::vector<int> unseen_primitives(const Tree& tree, const RefineTarget& target,
                                   const TessellationOptions& tessellation, int threads) {
  const Scene scene = scene_from_tree(tree, "refine", tessellation);
  std::set<int> seen;
  for (const Camera& cam : target.cameras) {
    const Frame f = render_visibility(scene, cam, threads);
    for (const int p : f.primitive) {
      if (p >= 0) seen.insert(p);
    }
  }
  std::vector<int> out;
  for (std::size_t p = 0; p < scene.primitives.size(); ++p) {
    if (!seen.count(static_cast<int>(p))) out.push_back(scene.tree_node[p]);
  }
  return out;
}

// The model refined: unified operators snapped to their largest weight.
Tree crisp_model(const Tree& input) {
  for (const Node& n : input.nodes) {
    if (n.kind == NodeKind::kOperator && n.op == OpKind::kUnified) return snap_operators(input);
  }
  return input;
}

}  // namespace

std::vector<double> parameter_scales(const Tree& tree, const TessellationOptions& tessellation) {
  const auto [lo, hi] = scene_from_tree(tree, "refine", tessellation).bounds();
  const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-9});
  std::vector<double> out;
  for (std::size_t k = 0; k < tree.params.size(); ++k) {
    const Parameter& p = tree.params.at(k);
    out.push_back(std::abs(p.value) > 0                         ? std::abs(p.value)
                  : p.name.find(".rotate") != std::string::npos ? 10.0
                                                                : 0.05 * extent);
  }
  return out;
}

namespace {

RefineResult refine_cmaes(const Tree& input, const RefineTarget& target, const RefineOptions& o,
                          const TessellationOptions& options) {
  const auto start = Clock::now();
  RefineResult result;
  result.tree = crisp_model(input);
  Tree& tree = result.tree;
  const TessellationOptions tessellation = fixed_tessellation(tree, "refine", options);
  const std::vector<double> initial = tree.params.values();
  std::vector<std::size_t> free;
  for (std::size_t k = 0; k < tree.params.size(); ++k) {
    if (!tree.params.at(k).fixed) free.push_back(k);
  }
  if (free.empty()) throw InputError("refine: the model has no free parameters");
  const std::vector<double> natural = parameter_scales(tree, tessellation);
  std::vector<double> x0, scale;
  for (const std::size_t k : free) {
    x0.push_back(tree.params.at(k).value);
    scale.push_back(o.cmaes_sigma * natural[k]);
  }
  std::vector<double> params = initial;
  const auto set = [&](std::span<const double> x) {
    for (std::size_t i = 0; i < free.size(); ++i) {
      params[free[i]] = optim::project(x[i], tree.params.at(free[i]).range);
    }
    tree.params.set_values(params);
  };
  int evaluations = 0;
  const auto objective = [&](std::span<const double> x) {
    ++evaluations;
    set(x);
    const PreparedScene ps =
        prepare_scene(scene_from_tree(tree, "refine", tessellation), o.intersection_aa);
    result.seconds_edges += ps.seconds_edges;
    double loss = 0;
    int visible = 0;
    for (std::size_t v = 0; v < target.cameras.size(); ++v) {
      const ViewPass pass = render_view(ps, target.cameras[v], target.shading, o.threads);
      result.seconds_visibility += pass.seconds_visibility;
      result.seconds_antialias += pass.seconds_antialias;
      visible += pass.frame.visible_pixels();
      loss += image_loss(pass.image, target.images[v], o.loss) /
              static_cast<double>(target.cameras.size());
    }
    // A model that leaves every view is as bad as it gets.
    return visible == 0 ? HUGE_VAL : loss;
  };
  optim::CmaesOptions co;
  co.sigma = 1;  // the scales carry cmaes_sigma
  co.seed = o.seed;
  co.max_evaluations = std::max(o.iterations, 1);
  const optim::CmaesResult r =
      optim::cmaes_minimize(objective, x0, scale, co, [&](std::span<const double> x, double best) {
        // The check view's error of the best point so far.
        set(x);
        const double mse = image_mse(
            render_image(
                prepare_scene(scene_from_tree(tree, "refine", tessellation), o.intersection_aa),
                target.cameras[0], target.shading, o.threads),
            target.images[0]);
        result.loss.push_back(best);
        result.check_mse.emplace_back(evaluations, mse);
        if (mse < o.stop_mse) {
          result.converged = true;
          return false;
        }
        return !o.progress || o.progress(static_cast<int>(result.loss.size()), best);
      });
  params = initial;
  for (std::size_t i = 0; i < free.size(); ++i) {
    params[free[i]] = optim::project(r.best[i], tree.params.at(free[i]).range);
  }
  tree.params.set_values(params);
  result.steps = static_cast<int>(r.evaluations);
  if (result.loss.empty()) result.loss.push_back(r.best_value);
  result.vanished = !std::isfinite(r.best_value);
  result.unseen_primitives = unseen_primitives(tree, target, tessellation, o.threads);
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace

RefineResult refine(const Tree& input, const RefineTarget& target, const RefineOptions& o,
                    const TessellationOptions& options) {
  if (target.cameras.empty() || target.cameras.size() != target.images.size()) {
    throw InputError("refine: one target image per camera expected");
  }
  for (std::size_t v = 0; v < target.cameras.size(); ++v) {
    const Image& img = target.images[v];
    if (img.width != target.cameras[v].width || img.height != target.cameras[v].height ||
        img.channels != 3) {
      throw InputError(fmt::format("refine: target image {} is {}x{}, its camera's {}x{}", v,
                                   img.width, img.height, target.cameras[v].width,
                                   target.cameras[v].height));
    }
  }
  if (o.iterations < 0) throw OptionError("iterations", "must not be negative");
  if (!(o.lr > 0) || !std::isfinite(o.lr)) throw OptionError("lr", "must be > 0");
  if (!(o.lr_relative >= 0) || !std::isfinite(o.lr_relative)) {
    throw OptionError("lr_relative", "must not be negative");
  };
  if (o.random_view_every < 0) throw OptionError("random_view_every", "must not be negative");
  if (o.random_view_every > 0 && !target.render) {
    throw OptionError("random_view_every",
                      "random views need a target that can be drawn (a model or a mesh)");
  }
  if (o.check_every < 1) throw OptionError("check_every", "must be at least 1");
  check_threads(o.threads);
  if (o.method == Method::kCmaes) {
    if (o.random_view_every > 0)
      throw OptionError("random_view_every", "CMA-ES uses the fixed views only");
    if (!(o.cmaes_sigma > 0) || !std::isfinite(o.cmaes_sigma)) {
      throw OptionError("cmaes_sigma", "must be > 0");
    };
    return refine_cmaes(input, target, o, options);
  }
  const auto since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  const auto start = Clock::now();
  RefineResult result;
  result.tree = crisp_model(input);
  Tree& tree = result.tree;
  // The meshes keep their connectivity: extrude caps triangulated once, at the start.
  const TessellationOptions tessellation = fixed_tessellation(tree, "refine", options);
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> uniform(0, 1);
  const Camera& check = target.cameras[0];
  const double view_distance =
      std::sqrt(dot(sub(check.eye, check.target), sub(check.eye, check.target)));
  Camera random_camera = check;
  Image random_image;

  std::vector<double> params = tree.params.values(), m(params.size(), 0.0), v2(params.size(), 0.0);
  std::vector<double> previous = params;  // before the last step
  optim::AdamOptions adam_options;
  adam_options.beta1 = o.beta1;
  adam_options.beta2 = o.beta2;
  adam_options.eps = o.eps;
  optim::Adam adam(params.size(), adam_options);
  // A relative learning rate is lr_relative times each parameter's natural scale: the scale is
  // the parameter's rate.
  const double lr = o.lr_relative > 0 ? o.lr_relative : o.lr;
  const std::vector<double> scales =
      o.lr_relative > 0 ? parameter_scales(tree, tessellation) : std::vector<double>{};
  for (std::size_t k = 0; k < params.size(); ++k) {
    const Parameter& p = tree.params.at(k);
    adam.set_free(k, !p.fixed);
    adam.set_range(k, p.range);
    if (!scales.empty()) adam.set_rate(k, scales[k]);
  }
  const auto check_mse = [&](const PreparedScene& ps, const ViewPass* pass0) {
    const double mse =
        pass0 ? image_mse(pass0->image, target.images[0])
              : image_mse(render_image(ps, check, target.shading, o.threads), target.images[0]);
    result.check_mse.emplace_back(result.steps, mse);
    return mse;
  };
  std::vector<ViewPass> passes;  // reused from step to step
  Image grad_image;
  for (int step = 0;; ++step) {
    check_cancelled();
    tree.params.set_values(params);
    PreparedScene ps =
        prepare_scene(scene_from_tree(tree, "refine", tessellation), o.intersection_aa);
    result.seconds_edges += ps.seconds_edges;
    const bool random = o.random_view_every > 0;
    if (random && step % o.random_view_every == 0) {
      random_camera = random_view(check.target, view_distance, uniform(rng), uniform(rng),
                                  check.width, check.height, check.fov_deg);
      random_image = target.render(random_camera);
    }
    const std::size_t views = random ? 1 : target.cameras.size();
    VertexGradient gv;
    gv.resize(ps.scene);
    double loss = 0;
    int visible = 0;
    const ViewPass* pass0 = nullptr;
    passes.resize(views);
    for (std::size_t v = 0; v < views; ++v) {
      const Camera& cam = random ? random_camera : target.cameras[v];
      const Image& goal = random ? random_image : target.images[v];
      ViewPass& pass = passes[v];
      render_view(ps, cam, target.shading, o.threads, pass);
      result.seconds_visibility += pass.seconds_visibility;
      result.seconds_antialias += pass.seconds_antialias;
      visible += pass.frame.visible_pixels();
      const auto t0 = Clock::now();
      loss += image_loss(pass.image, goal, o.loss, &grad_image) / static_cast<double>(views);
      for (float& g : grad_image.data) g /= static_cast<float>(views);
      render_view_backward(ps, cam, target.shading, pass, grad_image, gv);
      result.seconds_backward += since(t0);
      if (!random && v == 0) pass0 = &pass;
    }
    if (visible == 0) {
      if (step == 0) {
        throw InputError("refine: no view sees the model (the cameras see nothing of it)");
      }
      result.vanished = true;
      params = previous;
      break;
    }
    result.loss.push_back(loss);
    const bool last = step == o.iterations;
    // The check view's error is free when view 0 is trained on; otherwise it costs a render,
    // every check_every steps.
    if (!random || step % o.check_every == 0 || last) {
      if (check_mse(ps, pass0) < o.stop_mse) {
        result.converged = true;
        break;
      }
    }
    if (o.progress && !o.progress(step, loss)) break;
    if (last) break;
    auto t0 = Clock::now();
    const std::vector<double> grad = parameter_gradient(tree, ps.scene, gv.g);
    result.seconds_backward += since(t0);
    ++result.steps;
    previous = params;
    adam.step(result.steps, lr, grad, optim::AdamState{params, m, v2});
  }
  tree.params.set_values(params);
  result.unseen_primitives = unseen_primitives(tree, target, tessellation, o.threads);
  result.seconds = since(start);
  return result;
}

}  // namespace fuzzycsg::diffcsg
