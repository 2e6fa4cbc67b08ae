// report.json of a refinement (diffcsg/report.hpp). Its keys are sorted (nlohmann::json).

#include "fuzzycsg/diffcsg/report.hpp"

#include <algorithm>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "fuzzycsg/diffcsg/shade.hpp"

namespace fuzzycsg::diffcsg {

namespace {

using json = nlohmann::json;

json settings_json(const Scene& model_scene, const RefineTarget& target, const RefineOptions& o,
                   bool shared_only) {
  const Camera& check = target.cameras.front();
  // The seed as the program's --seed takes it, a signed integer of the same bits.
  const auto seed = static_cast<std::int64_t>(o.seed);
  return {{"method", method_name(o.method)},
          {"shading", shading_name(target.shading)},
          {"loss", loss_name(o.loss)},
          {"views", static_cast<int>(target.cameras.size())},
          {"size", {check.width, check.height}},
          {"iters", o.iterations},
          {"lr", o.lr},
          {"lr_relative", o.lr_relative},
          {"stop", o.stop_mse},
          {"random_views", o.random_view_every},
          {"shared_only", shared_only},
          {"seed", seed},
          {"intersection_aa", o.intersection_aa},
          {"fov", check.fov_deg},
          {"triangles", model_scene.triangle_count()}};
}

}  // namespace

std::string refine_report_json(const Tree& model, const Scene& model_scene,
                               const RefineTarget& target, const RefineOptions& options,
                               const RefineResult& result, const RefineReportContext& context) {
  if (target.cameras.empty()) throw std::invalid_argument("refine_report_json: no camera");
  const RefineResult& r = result;
  if (r.tree.params.size() != model.params.size()) {
    throw std::invalid_argument("refine_report_json: the result's parameters are not the model's");
  }
  json report;
  report["format"] = kRefineReportFormat;
  report["version"] = kRefineReportVersion;
  report["command_line"] = context.command_line;
  report["model"] = context.model_path;
  report["target"] = context.target_path;
  report["target_kind"] = context.target_kind;
  report["settings"] = settings_json(model_scene, target, options, context.shared_only);
  report["steps"] = r.steps;
  report["converged"] = r.converged;
  report["vanished"] = r.vanished;
  const std::vector<std::string> paths = node_paths(r.tree);
  report["unseen_primitives"] = json::array();
  for (const int n : r.unseen_primitives) {
    report["unseen_primitives"].push_back(paths.at(static_cast<std::size_t>(n)));
  }
  report["loss"] = r.loss;
  report["check_mse"] = json::array();
  for (const auto& [step, mse] : r.check_mse) report["check_mse"].push_back({step, mse});
  report["seconds"] = r.seconds;
  const int passes = std::max(1, static_cast<int>(r.loss.size()));
  report["seconds_per_step"] = {{"visibility", r.seconds_visibility / passes},
                                {"edges", r.seconds_edges / passes},
                                {"antialias", r.seconds_antialias / passes},
                                {"backward", r.seconds_backward / passes}};
  report["parameters"] = json::array();
  for (std::size_t k = 0; k < r.tree.params.size(); ++k) {
    const Parameter& p = r.tree.params.at(k);
    report["parameters"].push_back({{"name", p.name},
                                    {"before", model.params.at(k).value},
                                    {"after", p.value},
                                    {"fixed", p.fixed}});
  }
  return report.dump(2) + "\n";
}

}  // namespace fuzzycsg::diffcsg
