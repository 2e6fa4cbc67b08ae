#include <nlohmann/json.hpp>

#include "convert/program.hpp"
#include "fuzzycsg/convert/convert.hpp"

namespace fuzzycsg::convert {

std::string report_json(const ConvertResult& r, const ConvertOptions& o) {
  using nlohmann::ordered_json;
  ordered_json j;
  j["verb"] = "convert";
  j["target"] = r.target;
  j["settings"] = {{"seed", o.seed},
                   {"threads", o.threads},
                   {"max_primitives", o.max_primitives},
                   {"time_limit", o.time_limit},
                   {"warn_iou", o.warn_iou},
                   {"resolution", o.resolution},
                   {"restarts", o.restarts},
                   {"refine_steps", o.refine_steps},
                   {"padding", o.padding},
                   {"tidy", o.tidy},
                   {"metric_points", o.metrics.points}};
  ordered_json metrics;
  metrics["iou"] = r.metrics.iou;
  metrics["mse"] = r.metrics.mse;
  metrics["chamfer"] = r.chamfer ? ordered_json(*r.chamfer) : ordered_json(nullptr);
  metrics["hausdorff"] = r.hausdorff ? ordered_json(*r.hausdorff) : ordered_json(nullptr);
  metrics["points"] = r.metrics.points;
  j["metrics"] = metrics;
  j["reached"] = r.reached;
  j["time_limit_reached"] = r.time_limit_reached;
  j["warnings"] = r.warnings;
  j["primitives"] = r.primitives;
  ordered_json kinds = ordered_json::object();
  const std::vector<double> params = r.tree.params.values();
  for (int i = 0; i < static_cast<int>(r.tree.nodes.size()); ++i) {
    const Node& n = r.tree.node(i);
    if (n.kind != NodeKind::kPrimitive) continue;
    // 3D: the solid's kind ("prism" for an extrude of straight sides); 2D: the leaf's family.
    const std::optional<Solid> s = solid_of_leaf(r.tree, params, i);
    const std::string name(s ? solid_kind_name(s->kind) : primitive_info(n.shape.type).name);
    kinds[name] = kinds.value(name, 0) + 1;
  }
  j["primitive_kinds"] = kinds;
  j["normalisation"] = {{"translate", r.normalisation.translate}, {"scale", r.normalisation.scale}};
  j["surfaces"] = r.surfaces;
  j["search"] = {{"components", r.components},
                 {"grid_cells", r.grid_cells},
                 {"dropped_cells", r.dropped_cells},
                 {"search_error_cells", r.search_error},
                 {"refine_error_cells",
                  r.refine_error >= 0 ? ordered_json(r.refine_error) : ordered_json(nullptr)},
                 {"refined", r.refined},
                 {"refined_solids", r.refined_solids},
                 {"tidy_error_samples", r.tidy_error},
                 {"axes_snapped", r.axes_snapped},
                 {"values_rounded", r.values_rounded},
                 {"angles_rounded", r.angles_rounded},
                 {"tidy_finer", r.tidy_finer}};
  ordered_json stages = ordered_json::object();
  for (const StageTime& s : r.stages) stages[s.name] = s.seconds;
  j["seconds"] = stages;
  j["seconds"]["total"] = r.seconds;
  ordered_json solids = ordered_json::array();
  for (const Solid& s : tree_solids(r.tree)) solids.push_back(s.describe());
  j["solids"] = solids;
  return j.dump(2) + "\n";
}

}  // namespace fuzzycsg::convert
