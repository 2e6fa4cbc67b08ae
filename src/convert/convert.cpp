#include "fuzzycsg/convert/convert.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include "convert/candidates.hpp"
#include "convert/csg_input.hpp"
#include "convert/picture.hpp"
#include "convert/program.hpp"
#include "convert/refine.hpp"
#include "convert/search.hpp"
#include "convert/self_intersect.hpp"
#include "convert/tidy.hpp"
#include "fuzzycsg/convert/detect.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/limits.hpp"
#include "fuzzycsg/target/mesh_file.hpp"
#include "fuzzycsg/target/target.hpp"

namespace fuzzycsg::convert {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

TriangleMesh mapped(TriangleMesh mesh, const Similarity& m) {
  for (auto& v : mesh.vertices) v = m.apply(v);
  return mesh;
}

int count_leaves(const Tree& tree) {
  int n = 0;
  for (const Node& node : tree.nodes) n += node.kind == NodeKind::kPrimitive ? 1 : 0;
  return n;
}

class Stages {
 public:
  Stages(ConvertResult& result, const ConvertHooks& hooks) : result_(result), hooks_(hooks) {}
  void begin(std::string name) {
    name_ = std::move(name);
    start_ = Clock::now();
    report({});
  }
  void end() { result_.stages.push_back({name_, since(start_)}); }
  void report(std::optional<double> iou, int primitives = 0) const {
    if (!hooks_.progress) return;
    ConvertProgress p;
    p.stage = name_;
    p.iou = iou;
    p.primitives = primitives;
    hooks_.progress(p);
  }

 private:
  ConvertResult& result_;
  const ConvertHooks& hooks_;
  std::string name_;
  Clock::time_point start_;
};

struct LoadedInput {
  std::unique_ptr<Target> target;
  TriangleMesh mesh;  // the target's surface in its own coordinates
  std::vector<std::string> warnings;
};

// A mesh checked closed and manifold, and its target. A surface that bounds no solid would give
// an inside test that depends on the ray's direction; it is refused with its defect named
// rather than converted as noise.
LoadedInput mesh_input(TriangleMesh mesh, const std::string& name, const ConvertOptions& options) {
  LoadedInput in;
  in.mesh = joined_mesh(std::move(mesh), name);
  if (const std::optional<std::string> defect = mesh_defect(in.mesh)) {
    throw InputError(name + ": " + *defect);
  }
  if (const std::optional<std::size_t> crossing = crossing_triangle_pairs(in.mesh);
      crossing && *crossing > 0) {
    in.warnings.push_back(fmt::format(
        "the mesh intersects itself ({} pairs of triangles cross): where its pieces overlap it "
        "counts as outside, so the part is converted as the exclusive or of its pieces; merge "
        "them (a union) first",
        *crossing));
  }
  TargetOptions target_options;
  target_options.padding = options.padding;
  target_options.threads = options.threads;
  in.target = mesh_target(in.mesh, name, target_options);
  return in;
}

// A mesh file (checked closed and manifold) as itself; an OpenSCAD `.csg` model as its tree,
// the true solid, and a mesh of that tree to detect surfaces on.
LoadedInput load_input(const std::string& path, const ConvertOptions& options) {
  static constexpr const char* kTakes =
      ": convert takes a 3D mesh (OBJ, STL, PLY, OFF), an OpenSCAD .csg or a picture";
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  TargetOptions target_options;
  target_options.padding = options.padding;
  target_options.threads = options.threads;
  LoadedInput in;
  if (ext == ".csg") {
    CsgInput csg = read_csg_input(path, options.padding, 2 * options.resolution, options.threads);
    in.target = tree_target(std::move(csg.solid), std::filesystem::path(path).filename().string(),
                            target_options);
    in.mesh = std::move(csg.mesh);
    return in;
  }
  if (ext != ".obj" && ext != ".stl" && ext != ".ply" && ext != ".off") {
    throw InputError(path + kTakes);
  }
  return mesh_input(read_mesh_file(path), path, options);
}

// The searched tree's solids refined by fuzzy gradient descent (unified operators, sigmoid
// steps annealed), each taking its refined placement and size where that puts cells right: the
// refinement's gains are kept and its losses (an end drawn onto a face, say) are not. Records
// what it did in `result`.
Tree refine_stage(const std::vector<Chain>& chains, const Tree& searched, const Target& target,
                  const LabelGrid& grid, const ConvertOptions& options, Clock::time_point deadline,
                  ConvertResult& result) {
  RefineOptions refine;
  BuildOptions soft;
  soft.sharpness = refine.sharpness_start;
  soft.unified = true;
  refine.steps = options.refine_steps;
  refine.seed = options.seed;
  refine.threads = options.threads;
  refine.deadline = deadline;
  const RefineResult refined = refine_fuzzy(chains_tree(chains, soft), target, refine);
  result.time_limit_reached = result.time_limit_reached || refined.stopped;
  const std::vector<Solid> refined_solids = tree_solids(crisp_tree(refined.tree));
  std::vector<Solid> solids = tree_solids(searched);
  const GridScorer scorer = sample_scorer(target, grid, std::size_t{1} << 20, options.seed);
  const Domain box = searched.domain_or_default();
  long long error = scorer.error(searched, options.threads);
  for (std::size_t i = 0; i < solids.size() && i < refined_solids.size(); ++i) {
    const Solid kept = solids[i];
    solids[i] = refined_solids[i];
    const long long e = scorer.error(tree_with_solids(searched, solids, box), options.threads);
    if (e < error) {
      error = e;
      ++result.refined_solids;
    } else {
      solids[i] = kept;
    }
  }
  Tree best = searched;
  if (result.refined_solids > 0) {
    best = tree_with_solids(searched, solids, box);
    result.refined = true;
  }
  result.refine_error = tree_error(best, grid, options.threads);
  return best;
}

// The surfaces described one a line, in the mesh's units (`to_mesh`: from the normalised box).
std::vector<std::string> described(const std::vector<Surface>& surfaces,
                                   const Similarity& to_mesh) {
  std::vector<std::string> out;
  for (Surface s : surfaces) {
    const double k = to_mesh.scale;
    const std::array<double, 3> p = to_mesh.apply({s.point[0], s.point[1], s.point[2]});
    s.point = {p[0], p[1], p[2]};
    s.radius *= k;
    s.minor_radius *= k;
    s.area *= k * k;
    s.rms *= k;
    s.axial_min *= k;
    s.axial_max *= k;
    out.push_back(describe_surface(s));
  }
  return out;
}

// The final tree (in the normalised box) measured against the target. IoU and MSE are the crisp
// tree's; the level set for the Chamfer and Hausdorff distances is meshed from its smooth form
// (a sigmoid about a grid cell wide), so that they measure the solids, not the grid's steps on
// their slanted and curved faces. The distances are also given in the mesh's units.
void measure_stage(const Tree& best, const Target& target, const ConvertOptions& options,
                   ConvertResult& result) {
  MetricsOptions crisp_metrics = options.metrics;
  crisp_metrics.chamfer = false;
  result.metrics = measure(best, best.params.values(), target, crisp_metrics);
  if (options.metrics.chamfer) {
    const Tree smooth = smooth_tree(best, options.metrics.chamfer_resolution);
    const Metrics distances = measure(smooth, smooth.params.values(), target, options.metrics);
    result.metrics.chamfer = distances.chamfer;
    result.metrics.hausdorff = distances.hausdorff;
  }
  if (result.metrics.chamfer) result.chamfer = *result.metrics.chamfer / result.normalisation.scale;
  if (result.metrics.hausdorff) {
    result.hausdorff = *result.metrics.hausdorff / result.normalisation.scale;
  }
}

// The tidy stage's outcome: the tree in the mesh's units and in the normalised box.
struct Tidied {
  TidyResult tidy;
  Tree mesh_units, normalised;
  bool finer = false;  // tidied again with a quarter of the tolerances, or not at all
};

Tidied tidy_tree(const Tree& tree, const Similarity& normalisation, const Target& target,
                 const LabelGrid& grid, const TidyOptions& options) {
  Tidied t;
  t.tidy = tidy_solids(tree, normalisation, target, grid, options);
  const Domain box = tree.domain_or_default();
  const Similarity to_mesh = normalisation.inverse();
  t.mesh_units =
      tree_with_solids(tree, t.tidy.solids, Domain{to_mesh.apply(box.min), to_mesh.apply(box.max)});
  std::vector<Solid> in_box;
  for (const Solid& s : t.tidy.solids) in_box.push_back(s.mapped(normalisation));
  t.normalised = tree_with_solids(tree, in_box, box);
  return t;
}

// Tidied, unless the roundings take a tree that reaches ConvertOptions::warn_iou below it: then
// tidied again with a quarter of the tolerances, and not at all when that is still below.
Tidied tidy_within_bar(const Tree& tree, const Similarity& normalisation, const Target& target,
                       const LabelGrid& grid, TidyOptions tidy, const ConvertOptions& options) {
  Tidied t = tidy_tree(tree, normalisation, target, grid, tidy);
  if (!tidy.enabled) return t;
  MetricsOptions iou_only = options.metrics;
  iou_only.chamfer = false;
  const auto iou = [&](const Tree& x) {
    return measure(x, x.params.values(), target, iou_only).iou;
  };
  if (iou(t.normalised) >= options.warn_iou || iou(tree) < options.warn_iou) return t;
  tidy.step_tolerance /= 4;
  tidy.total_tolerance /= 4;
  t = tidy_tree(tree, normalisation, target, grid, tidy);
  if (iou(t.normalised) < options.warn_iou) {
    tidy.enabled = false;
    t = tidy_tree(tree, normalisation, target, grid, tidy);
  }
  t.finer = true;
  return t;
}

}  // namespace

void validate(const ConvertOptions& o) {
  if (o.max_primitives < 0) throw OptionError("max_primitives", "must be >= 0");
  if (!(o.time_limit > 0)) throw OptionError("time_limit", "must be > 0");
  if (o.resolution < 16 || o.resolution > 512)
    throw OptionError("resolution", "must be in 16..512");
  if (o.restarts < 0 || o.restarts > 256) throw OptionError("restarts", "must be in 0..256");
  if (o.refine_steps < 0) throw OptionError("refine_steps", "must be >= 0");
  if (!(o.padding >= 0 && o.padding < 0.5)) throw OptionError("padding", "must be in [0, 0.5)");
  check_threads(o.threads);
  if (!(o.warn_iou >= 0 && o.warn_iou <= 1)) throw OptionError("warn_iou", "must be in [0, 1]");
}

namespace {

// The stages after loading (convert.hpp), on a loaded input; `name` names it in errors.
void convert_loaded(LoadedInput input, const std::string& name, const ConvertOptions& options,
                    Clock::time_point start, ConvertResult& result, Stages& stages) {
  const std::unique_ptr<Target>& target = input.target;
  result.target = target->describe();
  result.normalisation = target->normalisation();
  result.target_mesh = std::move(input.mesh);
  result.warnings = std::move(input.warnings);
  const TriangleMesh mesh = mapped(result.target_mesh, result.normalisation);
  stages.end();

  stages.begin("detect");
  DetectOptions detect_options;
  detect_options.seed = options.seed;
  const std::vector<Surface> surfaces = detect_surfaces(mesh, detect_options);
  result.surfaces = described(surfaces, result.normalisation.inverse());
  stages.end();

  stages.begin("search");
  const Eigen::Matrix3d frame = dominant_frame(surfaces);
  const LabelGrid grid =
      make_label_grid(*target, frame, frame_bounds(mesh, frame), options.resolution, 3);
  result.grid_cells = static_cast<long long>(grid.size());
  const Candidates candidates = propose_candidates(surfaces, mesh, frame);
  std::size_t dropped = 0;
  const std::size_t inside = grid.count(1);
  const std::vector<LabelGrid> parts =
      split_components(grid, std::max<std::size_t>(8, inside / 500), 3, dropped);
  result.dropped_cells = static_cast<long long>(dropped);
  result.components = static_cast<int>(parts.size());
  if (parts.empty()) throw InputError(name + ": the mesh encloses no cell of the search grid");
  SearchOptions search;
  search.seed = options.seed;
  search.restarts = options.restarts;
  if (options.max_primitives > 0) search.max_steps = options.max_primitives;
  // Saturating: --time-limit inf (or 1e300) is a deadline never reached, not an overflow.
  const auto at = [&](double fraction) {
    return deadline_after(start, fraction * options.time_limit);
  };
  search.deadline = at(0.6);
  std::vector<Chain> chains;
  for (const LabelGrid& part : parts) chains.push_back(search_chain(part, candidates, search));
  if (std::all_of(chains.begin(), chains.end(), [](const Chain& c) { return c.steps.empty(); })) {
    throw InputError(name + ": no solid proposed from the detected surfaces covers the part");
  }
  result.time_limit_reached = Clock::now() > *search.deadline;  // before extending the cutters
  extend_cutters(chains, grid, 0.1, options.threads);
  const Tree searched = chains_tree(chains);
  result.search_error = tree_error(searched, grid, options.threads);
  stages.end();

  Tree best = searched;
  if (options.refine_steps > 0) {
    stages.begin("refine");
    best = refine_stage(chains, searched, *target, grid, options, at(0.8), result);
    stages.end();
  }

  stages.begin("tidy");
  TidyOptions tidy;
  tidy.threads = options.threads;
  tidy.enabled = options.tidy;
  tidy.seed = options.seed;
  tidy.deadline = at(0.95);
  const Tidied tidied = tidy_within_bar(best, result.normalisation, *target, grid, tidy, options);
  result.tidy_error = tidied.tidy.error_after;
  result.time_limit_reached = result.time_limit_reached || tidied.tidy.stopped;
  result.axes_snapped = tidied.tidy.axes_snapped;
  result.values_rounded = tidied.tidy.values_rounded;
  result.angles_rounded = tidied.tidy.angles_rounded;
  result.tidy_finer = tidied.finer;
  result.tree = tidied.mesh_units;
  best = tidied.normalised;
  stages.end();

  stages.begin("measure");
  measure_stage(best, *target, options, result);
  stages.end();

  result.reached = result.metrics.iou >= options.warn_iou;
  result.primitives = count_leaves(result.tree);
  result.seconds = since(start);
  // Loading, detection and measuring are not cut short: a run that took longer than the limit
  // says so.
  result.time_limit_reached = result.time_limit_reached || result.seconds > options.time_limit;
}

}  // namespace

ConvertResult convert(const std::string& path, const ConvertOptions& options,
                      const ConvertHooks& hooks) {
  validate(options);
  if (is_picture(path)) return convert_picture(path, options, hooks);
  const Clock::time_point start = Clock::now();
  ConvertResult result;
  Stages stages(result, hooks);
  stages.begin("load");
  LoadedInput input = load_input(path, options);
  convert_loaded(std::move(input), path, options, start, result, stages);
  return result;
}

ConvertResult convert(const TriangleMesh& mesh, const ConvertOptions& options,
                      const ConvertHooks& hooks, const std::string& name) {
  validate(options);
  const Clock::time_point start = Clock::now();
  ConvertResult result;
  Stages stages(result, hooks);
  stages.begin("load");
  LoadedInput input = mesh_input(mesh, name, options);
  convert_loaded(std::move(input), name, options, start, result, stages);
  return result;
}

}  // namespace fuzzycsg::convert
