// The engines with their options: fit, convert, prune, trace, refine, mesh and export. Each
// options struct of the library is a Python class whose attributes are its fields, as the
// struct spells them (fuzzycsg/__init__.py sets them from keyword arguments); settings chosen
// from a list are strings, as the tree file and report.json spell them. Results come back as
// dictionaries of trees, NumPy arrays and numbers (fuzzycsg/__init__.py makes them objects).

#include <pybind11/stl.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common.hpp"
#include "fuzzycsg/convert/convert.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/snap.hpp"
#include "fuzzycsg/core/transform.hpp"
#include "fuzzycsg/diffcsg/refine.hpp"
#include "fuzzycsg/diffcsg/refine_target.hpp"
#include "fuzzycsg/diffcsg/shade.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "fuzzycsg/fit/option_names.hpp"
#include "fuzzycsg/fit/prune.hpp"
#include "fuzzycsg/mesh/mesh.hpp"
#include "fuzzycsg/render/render.hpp"
#include "fuzzycsg/scad/scad.hpp"
#include "fuzzycsg/target/target.hpp"
#include "fuzzycsg/trace/trace.hpp"

namespace fuzzycsg::python {

namespace {

// A setting chosen from a list, as a string attribute.
template <class C, class Opt, class E, std::size_t N>
void named_field(C& c, const char* name, E Opt::*member, const OptionNames<E, N>& names) {
  c.def_property(
      name, [member, &names](const Opt& o) { return std::string(option_name(names, o.*member)); },
      [member, &names, name](Opt& o, const std::string& v) {
        const auto e = option_value(names, v);
        if (!e) {
          std::string list;
          for (const auto& n : names) list += (list.empty() ? "" : ", ") + std::string(n.name);
          throw OptionError(name, "unknown value '" + v + "' (" + list + ")");
        }
        o.*member = *e;
      });
}

inline const OptionNames<diffcsg::Method, 2> kMethodNames{{
    {"adam", diffcsg::Method::kAdam},
    {"cmaes", diffcsg::Method::kCmaes},
}};
inline const OptionNames<diffcsg::Loss, 3> kLossNames{{
    {"l1", diffcsg::Loss::kL1},
    {"l2", diffcsg::Loss::kL2},
    {"tanh", diffcsg::Loss::kTanh},
}};
inline const OptionNames<diffcsg::Shading, 2> kShadingNames{{
    {"normals", diffcsg::Shading::kNormals},
    {"colours", diffcsg::Shading::kColours},
}};
inline const OptionNames<scad::Clip, 3> kClipNames{{
    {"auto", scad::Clip::kAuto},
    {"always", scad::Clip::kAlways},
    {"never", scad::Clip::kNever},
}};

py::dict metrics_dict(const Metrics& m) {
  py::dict d;
  d["mse"] = m.mse;
  d["iou"] = m.iou;
  d["chamfer"] = m.chamfer ? py::cast(*m.chamfer) : py::none();
  d["hausdorff"] = m.hausdorff ? py::cast(*m.hausdorff) : py::none();
  d["points"] = m.points;
  return d;
}

// A fit's or prune's target: a file (mesh, picture, tree file) or a tree.
std::unique_ptr<Target> target_of(const py::object& target, const TargetOptions& options) {
  if (py::isinstance<Tree>(target)) return tree_target(target.cast<Tree>(), "<tree>", options);
  if (py::isinstance<py::str>(target) || py::hasattr(target, "__fspath__")) {
    const std::string path = py::str(py::module_::import("os").attr("fspath")(target));
    return load_target(path, options);
  }
  throw py::type_error("target: a path or a fuzzycsg.Tree expected");
}

std::string path_of(const py::object& p, const char* what) {
  if (py::isinstance<py::str>(p) || py::hasattr(p, "__fspath__")) {
    return py::str(py::module_::import("os").attr("fspath")(p));
  }
  throw py::type_error(std::string(what) + ": a path expected");
}

// FitOptions and the structs it holds; TargetOptions.
void bind_fit_options(py::module_& m) {
  py::class_<SamplingOptions> sampling(m, "SamplingOptions");
  sampling.def(py::init<>())
      .def_readwrite("surface", &SamplingOptions::surface)
      .def_readwrite("near", &SamplingOptions::near)
      .def_readwrite("near_distance", &SamplingOptions::near_distance);
  named_field(sampling, "scheme", &SamplingOptions::scheme, kSamplingSchemeNames);

  py::class_<MetricsOptions>(m, "MetricsOptions")
      .def(py::init<>())
      .def_readwrite("points", &MetricsOptions::points)
      .def_readwrite("seed", &MetricsOptions::seed)
      .def_readwrite("threads", &MetricsOptions::threads)
      .def_readwrite("chamfer", &MetricsOptions::chamfer)
      .def_readwrite("chamfer_resolution", &MetricsOptions::chamfer_resolution)
      .def_readwrite("chamfer_samples", &MetricsOptions::chamfer_samples);

  py::class_<TargetOptions>(m, "TargetOptions")
      .def(py::init<>())
      .def_readwrite("padding", &TargetOptions::padding)
      .def_readwrite("image_resolution", &TargetOptions::image_resolution)
      .def_readwrite("threads", &TargetOptions::threads);

  py::class_<FitOptions> fit(m, "FitOptions");
  fit.def(py::init<>())
      .def_readwrite("prims", &FitOptions::prims)
      .def_property(
          "families",
          [](const FitOptions& o) {
            std::vector<std::string> v;
            for (PrimitiveType t : o.families) v.emplace_back(primitive_info(t).name);
            return v;
          },
          [](FitOptions& o, const std::vector<std::string>& names) {
            o.families.clear();
            for (const std::string& n : names) {
              auto t = primitive_from_name(n, 3);
              if (!t) t = primitive_from_name(n, 2);
              if (!t) throw OptionError("families", "unknown primitive " + n);
              o.families.push_back(*t);
            }
          })
      .def_readwrite("init_range", &FitOptions::init_range)
      .def_readwrite("init_slope", &FitOptions::init_slope)
      .def_readwrite("temperature", &FitOptions::temperature)
      .def_readwrite("temperature_start", &FitOptions::temperature_start)
      .def_readwrite("temperature_ramp", &FitOptions::temperature_ramp)
      .def_readwrite("omega", &FitOptions::omega)
      .def_readwrite("seed", &FitOptions::seed)
      .def_readwrite("iters", &FitOptions::iters)
      .def_readwrite("batch", &FitOptions::batch)
      .def_readwrite("pool", &FitOptions::pool)
      .def_readwrite("resample_every", &FitOptions::resample_every)
      .def_readwrite("lr", &FitOptions::lr)
      .def_readwrite("beta1", &FitOptions::beta1)
      .def_readwrite("beta2", &FitOptions::beta2)
      .def_readwrite("adam_eps", &FitOptions::adam_eps)
      .def_readwrite("lr_end", &FitOptions::lr_end)
      .def_readwrite("reseed_every", &FitOptions::reseed_every)
      .def_readwrite("reseed_until", &FitOptions::reseed_until)
      .def_readwrite("type_search_every", &FitOptions::type_search_every)
      .def_readwrite("type_search_from", &FitOptions::type_search_from)
      .def_readwrite("type_search_until", &FitOptions::type_search_until)
      .def_readwrite("type_search_points", &FitOptions::type_search_points)
      .def_readwrite("type_search_switches", &FitOptions::type_search_switches)
      .def_readwrite("sampling", &FitOptions::sampling)
      .def_readwrite("threads", &FitOptions::threads)
      .def_readwrite("time_limit", &FitOptions::time_limit)
      .def_readwrite("prune_threshold", &FitOptions::prune_threshold)
      .def_readwrite("prune_points", &FitOptions::prune_points)
      .def_readwrite("prune_max_primitives", &FitOptions::prune_max_primitives)
      .def_readwrite("metrics", &FitOptions::metrics)
      .def_readwrite("measure", &FitOptions::measure);
  named_field(fit, "ops", &FitOptions::ops, kOperatorModeNames);
  named_field(fit, "op_init", &FitOptions::op_init, kOperatorInitNames);
  named_field(fit, "op_types", &FitOptions::op_types, kOperatorTypesNames);
  named_field(fit, "init", &FitOptions::init, kInitModeNames);
  named_field(fit, "lr_schedule", &FitOptions::lr_schedule, kLrScheduleNames);
  named_field(fit, "sharpness_param", &FitOptions::sharpness_param, kSharpnessParamNames);
}

void bind_convert_and_trace_options(py::module_& m) {
  py::class_<convert::ConvertOptions>(m, "ConvertOptions")
      .def(py::init<>())
      .def_readwrite("max_primitives", &convert::ConvertOptions::max_primitives)
      .def_readwrite("time_limit", &convert::ConvertOptions::time_limit)
      .def_readwrite("warn_iou", &convert::ConvertOptions::warn_iou)
      .def_readwrite("seed", &convert::ConvertOptions::seed)
      .def_readwrite("threads", &convert::ConvertOptions::threads)
      .def_readwrite("resolution", &convert::ConvertOptions::resolution)
      .def_readwrite("restarts", &convert::ConvertOptions::restarts)
      .def_readwrite("refine_steps", &convert::ConvertOptions::refine_steps)
      .def_readwrite("padding", &convert::ConvertOptions::padding)
      .def_readwrite("tidy", &convert::ConvertOptions::tidy)
      .def_readwrite("metrics", &convert::ConvertOptions::metrics);

  py::class_<PruneOptions>(m, "PruneOptions")
      .def(py::init<>())
      .def_readwrite("threshold", &PruneOptions::threshold)
      .def_readwrite("threads", &PruneOptions::threads)
      .def_readwrite("max_primitives", &PruneOptions::max_primitives);

  py::class_<trace::LocalOptions>(m, "TraceLocalOptions")
      .def(py::init<>())
      .def_readwrite("max_iterations", &trace::LocalOptions::max_iterations)
      .def_readwrite("k", &trace::LocalOptions::k)
      .def_readwrite("margin", &trace::LocalOptions::margin)
      .def_readwrite("shift_step", &trace::LocalOptions::shift_step)
      .def_readwrite("size_step", &trace::LocalOptions::size_step)
      .def_readwrite("angle_step", &trace::LocalOptions::angle_step)
      .def_readwrite("min_size", &trace::LocalOptions::min_size)
      .def_readwrite("max_steps", &trace::LocalOptions::max_steps)
      .def_readwrite("prune", &trace::LocalOptions::prune);
  py::class_<trace::SearchOptions>(m, "TraceOptions")
      .def(py::init<>())
      .def_readwrite("population", &trace::SearchOptions::population)
      .def_readwrite("max_trees", &trace::SearchOptions::max_trees)
      .def_readwrite("patience", &trace::SearchOptions::patience)
      .def_readwrite("refocus", &trace::SearchOptions::refocus)
      .def_readwrite("initial_size", &trace::SearchOptions::initial_size)
      .def_readwrite("initial_sd", &trace::SearchOptions::initial_sd)
      .def_readwrite("added_size", &trace::SearchOptions::added_size)
      .def_readwrite("added_sd", &trace::SearchOptions::added_sd)
      .def_readwrite("probabilities", &trace::SearchOptions::probabilities)
      .def_readwrite("local", &trace::SearchOptions::local)
      .def_readwrite("seed", &trace::SearchOptions::seed)
      .def_readwrite("threads", &trace::SearchOptions::threads)
      .def_readwrite("batch", &trace::SearchOptions::batch)
      .def_readwrite("time_limit", &trace::SearchOptions::time_limit);
  py::class_<trace::RefineOptions>(m, "TraceRefineOptions")
      .def(py::init<>())
      .def_readwrite("iterations", &trace::RefineOptions::iterations)
      .def_readwrite("batch", &trace::RefineOptions::batch)
      .def_readwrite("lr", &trace::RefineOptions::lr)
      .def_readwrite("lr_end", &trace::RefineOptions::lr_end)
      .def_readwrite("angle_lr", &trace::RefineOptions::angle_lr)
      .def_readwrite("sharpness_start", &trace::RefineOptions::sharpness_start)
      .def_readwrite("sharpness_end", &trace::RefineOptions::sharpness_end)
      .def_readwrite("min_size", &trace::RefineOptions::min_size)
      .def_readwrite("check_every", &trace::RefineOptions::check_every)
      .def_readwrite("time_limit", &trace::RefineOptions::time_limit);
}

// diffcsg's refinement and the views of its target.
void bind_refine_options(py::module_& m) {
  py::class_<diffcsg::RefineOptions> refine(m, "RefineOptions");
  refine.def(py::init<>())
      .def_readwrite("cmaes_sigma", &diffcsg::RefineOptions::cmaes_sigma)
      .def_readwrite("iterations", &diffcsg::RefineOptions::iterations)
      .def_readwrite("lr", &diffcsg::RefineOptions::lr)
      .def_readwrite("lr_relative", &diffcsg::RefineOptions::lr_relative)
      .def_readwrite("beta1", &diffcsg::RefineOptions::beta1)
      .def_readwrite("beta2", &diffcsg::RefineOptions::beta2)
      .def_readwrite("eps", &diffcsg::RefineOptions::eps)
      .def_readwrite("intersection_aa", &diffcsg::RefineOptions::intersection_aa)
      .def_readwrite("stop_mse", &diffcsg::RefineOptions::stop_mse)
      .def_readwrite("check_every", &diffcsg::RefineOptions::check_every)
      .def_readwrite("random_view_every", &diffcsg::RefineOptions::random_view_every)
      .def_readwrite("seed", &diffcsg::RefineOptions::seed)
      .def_readwrite("threads", &diffcsg::RefineOptions::threads);
  named_field(refine, "method", &diffcsg::RefineOptions::method, kMethodNames);
  named_field(refine, "loss", &diffcsg::RefineOptions::loss, kLossNames);

  py::class_<diffcsg::TargetViewOptions> views(m, "TargetViewOptions");
  views.def(py::init<>())
      .def_readwrite("views", &diffcsg::TargetViewOptions::views)
      .def_readwrite("size", &diffcsg::TargetViewOptions::size)
      .def_readwrite("size_given", &diffcsg::TargetViewOptions::size_given)
      .def_readwrite("elevation", &diffcsg::TargetViewOptions::elevation)
      .def_readwrite("distance", &diffcsg::TargetViewOptions::distance)
      .def_readwrite("fov", &diffcsg::TargetViewOptions::fov)
      .def_readwrite("threads", &diffcsg::TargetViewOptions::threads);
  named_field(views, "shading", &diffcsg::TargetViewOptions::shading, kShadingNames);
}

// What turns a tree into files: meshes, pictures, OpenSCAD programs.
void bind_output_options(py::module_& m) {
  py::class_<MeshOptions>(m, "MeshOptions")
      .def(py::init<>())
      .def_readwrite("resolution", &MeshOptions::resolution)
      .def_readwrite("brick", &MeshOptions::brick)
      .def_readwrite("prune", &MeshOptions::prune)
      .def_readwrite("simplify", &MeshOptions::simplify)
      .def_readwrite("level", &MeshOptions::level)
      .def_readwrite("threads", &MeshOptions::threads);

  py::class_<Camera>(m, "Camera")
      .def(py::init<>())
      .def_readwrite("eye", &Camera::eye)
      .def_readwrite("target", &Camera::target)
      .def_readwrite("up", &Camera::up)
      .def_readwrite("fov_deg", &Camera::fov_deg);
  py::class_<RenderOptions>(m, "RenderOptions")
      .def(py::init<>())
      .def_readwrite("width", &RenderOptions::width)
      .def_readwrite("height", &RenderOptions::height)
      .def_readwrite("camera", &RenderOptions::camera)
      .def_readwrite("views", &RenderOptions::views)
      .def_readwrite("up", &RenderOptions::up)
      .def_readwrite("resolution", &RenderOptions::resolution)
      .def_readwrite("crease_deg", &RenderOptions::crease_deg)
      .def_readwrite("threads", &RenderOptions::threads);

  py::class_<scad::ExportOptions> exp(m, "ExportOptions");
  exp.def(py::init<>())
      .def_readwrite("fn", &scad::ExportOptions::fn)
      .def_readwrite("resolution", &scad::ExportOptions::resolution)
      .def_readwrite("source", &scad::ExportOptions::source)
      .def_readwrite("writer", &scad::ExportOptions::writer)
      .def_readwrite("note", &scad::ExportOptions::note)
      .def_readwrite("threads", &scad::ExportOptions::threads)
      .def_readwrite("leaf_comments", &scad::ExportOptions::leaf_comments);
  named_field(exp, "clip", &scad::ExportOptions::clip, kClipNames);
}

py::dict run_fit(const py::object& target, const FitOptions& o, const TargetOptions& to) {
  const auto t = target_of(target, to);
  validate(o, t->dim());
  FitResult r;
  {
    interruptible([&] { r = fit(*t, o); });
  }
  // In the target's own coordinates, as `fuzzycsg fit` writes them.
  const Similarity back = t->normalisation().inverse();
  py::dict d;
  d["trained"] = transformed(r.trained, back);
  d["snapped"] = transformed(r.snapped, back);
  d["pruned"] = transformed(r.pruned, back);
  d["stop"] = std::string(stop_reason_name(r.stop));
  d["steps"] = r.state.step;
  std::vector<double> curve;
  for (const LossPoint& p : r.state.curve)
    curve.insert(curve.end(), {double(p.step), p.loss, p.seconds});
  const auto rows = static_cast<py::ssize_t>(r.state.curve.size());
  d["loss_curve"] = to_numpy(std::move(curve), {rows, py::ssize_t{3}});
  d["metrics_trained"] =
      r.metrics_trained ? py::object(metrics_dict(*r.metrics_trained)) : py::none();
  d["metrics_pruned"] = r.metrics_pruned ? py::object(metrics_dict(*r.metrics_pruned)) : py::none();
  d["primitives_before"] = r.prune.primitives_before;
  d["primitives_after"] = r.prune.primitives_after;
  d["train_seconds"] = r.train_seconds;
  return d;
}

py::dict convert_dict(const convert::ConvertResult& r, const convert::ConvertOptions& o,
                      const std::string& source);

py::dict run_convert(const py::object& path, const convert::ConvertOptions& o) {
  const std::string p = path_of(path, "target");
  convert::ConvertResult r;
  {
    interruptible([&] { r = convert::convert(p, o); });
  }
  return convert_dict(r, o, std::filesystem::path(p).filename().string());
}

// What Python's convert returns: the tree, its program, the measures and report.json.
py::dict convert_dict(const convert::ConvertResult& r, const convert::ConvertOptions& o,
                      const std::string& source) {
  scad::ExportOptions eo;
  eo.threads = o.threads;
  eo.source = source;
  eo.writer = "fuzzycsg convert";
  eo.leaf_comments = false;
  py::dict d;
  d["tree"] = r.tree;
  d["primitives"] = r.primitives;
  d["metrics"] = metrics_dict(r.metrics);
  d["chamfer"] = r.chamfer ? py::cast(*r.chamfer) : py::none();
  d["hausdorff"] = r.hausdorff ? py::cast(*r.hausdorff) : py::none();
  d["reached"] = r.reached;
  d["seconds"] = r.seconds;
  d["scad"] = scad::export_scad(r.tree, r.tree.params.values(), eo);
  d["report"] = convert::report_json(r, o);
  return d;
}

// A mesh given as arrays (V x 3 vertices, F x 3 triangle indices) converted as a file of the
// same mesh is.
py::dict run_convert_mesh(const py::handle& vertices, const py::handle& faces,
                          const convert::ConvertOptions& o, const std::string& name) {
  const CArray<double> v = as_array<double>(vertices, "vertices");
  check_shape(v, "vertices", {-1, 3});
  check_finite(v, "vertices");
  const CArray<long long> f = as_array<long long>(faces, "faces");
  check_shape(f, "faces", {-1, 3});
  TriangleMesh mesh;
  mesh.vertices.resize(static_cast<std::size_t>(v.shape(0)));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) mesh.vertices[i][k] = v.data()[3 * i + k];
  }
  mesh.triangles.resize(static_cast<std::size_t>(f.shape(0)));
  const long long n = static_cast<long long>(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      const long long index = f.data()[3 * i + k];
      if (index < 0 || index >= n) {
        throw py::value_error("faces: entry " + std::to_string(3 * i + k) + " is " +
                              std::to_string(index) + ", outside the " + std::to_string(n) +
                              " vertices");
      }
      mesh.triangles[i][k] = static_cast<int>(index);
    }
  }
  convert::ConvertResult r;
  {
    interruptible([&] { r = convert::convert(mesh, o, {}, name); });
  }
  return convert_dict(r, o, name);
}

py::tuple run_prune(const Tree& tree, const py::object& points, const PruneOptions& o,
                    std::uint64_t seed, std::size_t count) {
  std::vector<float> pts;
  if (points.is_none()) {
    Rng rng(seed);
    pts = uniform_points(tree.dim, count, rng);
  } else {
    const CArray<float> a = points_array(points, tree.dim);
    pts.assign(a.data(), a.data() + a.size());
  }
  PruneReport report;
  Tree pruned;
  {
    interruptible([&] { pruned = prune(snap_operators(tree), pts, o, &report); });
  }
  py::dict d;
  d["primitives_before"] = report.primitives_before;
  d["primitives_after"] = report.primitives_after;
  d["operators_before"] = report.operators_before;
  d["operators_after"] = report.operators_after;
  return py::make_tuple(pruned, d);
}

py::dict score_dict(const trace::Score& s) {
  py::dict d;
  d["excess"] = s.excess;
  d["uncovered"] = s.uncovered;
  d["primitives"] = s.primitives;
  d["total"] = s.total();
  return d;
}

py::dict run_trace(const py::object& picture, const trace::SearchOptions& so, bool refine,
                   trace::RefineOptions ro) {
  const std::string p = path_of(picture, "picture");
  trace::validate(so);
  ro.k = so.local.k;
  ro.seed = so.seed;
  ro.threads = so.threads;
  if (refine) trace::validate(ro);
  const trace::Bitmap target = trace::read_bitmap(p);
  trace::check_traceable(target, p);
  trace::SearchResult s;
  std::optional<trace::RefineResult> rr;
  {
    interruptible([&] {
      s = trace::search(target, so);
      if (refine) rr = trace::refine(s.best, target, ro);
    });
  }
  const trace::CsgTree& best = rr ? rr->tree : s.best;
  py::dict d;
  d["tree"] = trace::to_tree(best, target.width(), target.height());
  d["search_tree"] = trace::to_tree(s.best, target.width(), target.height());
  d["score"] = score_dict(rr ? rr->after : s.score);
  d["search_score"] = score_dict(s.score);
  d["trees_evaluated"] = s.statistics.trees_evaluated;
  d["stopped_by"] = std::string(s.statistics.stopped_by);
  d["seconds"] = s.statistics.seconds + (rr ? rr->seconds : 0.0);
  d["width"] = target.width();
  d["height"] = target.height();
  return d;
}

py::dict run_refine(const py::object& model, const py::object& target,
                    const diffcsg::RefineOptions& o, const diffcsg::TargetViewOptions& vo,
                    int sphere_subdivisions, int cylinder_segments) {
  diffcsg::TessellationOptions tess;
  tess.sphere_subdivisions = sphere_subdivisions;
  tess.cylinder_segments = cylinder_segments;
  diffcsg::OpenscadModel m;
  std::string name = "<tree>";
  if (py::isinstance<Tree>(model)) {
    m = {model.cast<Tree>(), tess};
  } else {
    name = path_of(model, "model");
    m = diffcsg::read_refine_model(name, tess);
  }
  const diffcsg::Scene scene = diffcsg::scene_from_tree(m.tree, name, m.tessellation);
  diffcsg::TargetViewOptions views = vo;
  views.random_views = o.random_view_every;
  views.intersection_aa = o.intersection_aa;
  diffcsg::RefineResult r;
  std::string kind;
  const std::string target_path = path_of(target, "target");
  {
    interruptible([&] {
      const diffcsg::LoadedTarget t =
          diffcsg::load_refine_target(target_path, views, m.tessellation, scene);
      kind = t.kind;
      r = diffcsg::refine(m.tree, t.target, o, m.tessellation);
    });
  }
  py::dict d;
  d["tree"] = r.tree;
  d["loss"] = py::array(py::cast(r.loss));
  d["check_mse"] = r.check_mse;
  d["steps"] = r.steps;
  d["converged"] = r.converged;
  d["vanished"] = r.vanished;
  d["target_kind"] = kind;
  d["seconds"] = r.seconds;
  return d;
}

py::object run_mesh(const Tree& tree, const MeshOptions& o, const py::object& path) {
  const std::vector<double> params = tree.params.values();
  if (tree.dim == 2) {
    Contours c;
    {
      py::gil_scoped_release release;
      c = extract_contours(tree, params, o);
    }
    py::list loops;
    for (auto& loop : c.loops) {
      std::vector<float> flat;
      for (const auto& v : loop) flat.insert(flat.end(), {v[0], v[1]});
      const auto n = static_cast<py::ssize_t>(loop.size());
      loops.append(to_numpy(std::move(flat), {n, py::ssize_t{2}}));
    }
    return loops;
  }
  TriangleMesh mesh;
  const std::string file = path.is_none() ? std::string() : path_of(path, "path");
  {
    interruptible([&] {
      mesh = extract_mesh(tree, params, o);
      if (!file.empty()) write_mesh(mesh, file);
    });
  }
  std::vector<double> v;
  for (const auto& p : mesh.vertices) v.insert(v.end(), {p[0], p[1], p[2]});
  std::vector<int> f;
  for (const auto& t : mesh.triangles) f.insert(f.end(), {t[0], t[1], t[2]});
  const auto nv = static_cast<py::ssize_t>(mesh.vertices.size());
  const auto nf = static_cast<py::ssize_t>(mesh.triangles.size());
  return py::make_tuple(to_numpy(std::move(v), {nv, py::ssize_t{3}}),
                        to_numpy(std::move(f), {nf, py::ssize_t{3}}));
}

py::tuple run_export(const Tree& tree, const scad::ExportOptions& o) {
  scad::ExportReport report;
  std::string text;
  {
    py::gil_scoped_release release;
    text = scad::export_scad(tree, tree.params.values(), o, &report);
  }
  return py::make_tuple(text, scad::report_json(report));
}

py::bytes run_render(const Tree& tree, const RenderOptions& o) {
  if (tree.dim != 3) throw InputError("render: a 3D tree expected (got a 2D one)");
  std::string png;
  {
    py::gil_scoped_release release;
    png = render_png(tree, tree.params.values(), o);
  }
  return py::bytes(png);
}

}  // namespace

void register_engines(py::module_& m) {
  bind_fit_options(m);
  bind_convert_and_trace_options(m);
  bind_refine_options(m);
  bind_output_options(m);
  m.def("_fit", &run_fit, py::arg("target"), py::arg("options"), py::arg("target_options"));
  m.def("_convert", &run_convert, py::arg("target"), py::arg("options"));
  m.def("_convert_mesh", &run_convert_mesh, py::arg("vertices"), py::arg("faces"),
        py::arg("options"), py::arg("name"));
  m.def("_prune", &run_prune, py::arg("tree"), py::arg("points"), py::arg("options"),
        py::arg("seed"), py::arg("count"));
  m.def("_trace", &run_trace, py::arg("picture"), py::arg("options"), py::arg("refine"),
        py::arg("refine_options"));
  m.def("_refine", &run_refine, py::arg("model"), py::arg("target"), py::arg("options"),
        py::arg("view_options"), py::arg("sphere_subdivisions"), py::arg("cylinder_segments"));
  m.def("_mesh", &run_mesh, py::arg("tree"), py::arg("options"), py::arg("path"));
  m.def("_export", &run_export, py::arg("tree"), py::arg("options"));
  m.def("_render", &run_render, py::arg("tree"), py::arg("options"));
}

}  // namespace fuzzycsg::python
