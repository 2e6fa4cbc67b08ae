#pragma once
// The report.json of a refinement (refine.hpp): the settings, the loss at every step, the check
// view's error, the time per step split into visibility, edges, antialiasing and backward, and
// every parameter before and after. What only the program knows (its command line, the paths
// as given, how it read the target) comes in as plain values.

#include <string>
#include <string_view>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/diffcsg/refine.hpp"
#include "fuzzycsg/diffcsg/scene.hpp"

namespace fuzzycsg::diffcsg {

// The report's "format" and "version".
inline constexpr std::string_view kRefineReportFormat = "fuzzycsg-refine-report";
inline constexpr int kRefineReportVersion = 1;

// The program's facts about a refinement.
struct RefineReportContext {
  std::string command_line;
  std::string model_path, target_path;  // as given
  std::string target_kind;              // how the target was read: "views", "mesh" or "model"
  bool shared_only = false;             // only the tree's shared parameters were free
};

// report.json (JSON text, keys sorted, two-space indents, a final newline). `model` is the tree
// refined (its parameters are the "before" values), `model_scene` its scene (the triangles
// counted), `target` what it was matched to (cameras[0], the check view, gives the image size
// and field of view). Throws std::invalid_argument when the target has no camera or the result's
// tree has not the model's parameters.
std::string refine_report_json(const Tree& model, const Scene& model_scene,
                               const RefineTarget& target, const RefineOptions& options,
                               const RefineResult& result, const RefineReportContext& context);

}  // namespace fuzzycsg::diffcsg
