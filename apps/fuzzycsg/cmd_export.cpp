// fuzzycsg export TREE -o OUT.scad [--fn N] [--resolution N] [--tolerance F] [--clip MODE]
//                  [--report FILE.json]
//
// The tree's crisp counterpart as an OpenSCAD program: primitives where OpenSCAD has them,
// quadric leaves classified (sphere, ellipsoid, cylinder, cone, plane, paraboloid, ...) and
// written as that primitive, the others meshed. Prints how many quadric leaves were classified,
// per kind.

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/scad/scad.hpp"

namespace fuzzycsg::app {

namespace {

struct ExportArgs {
  std::string tree, out, report, clip = "auto";
  scad::ExportOptions options;
};

std::string lowercase_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

int run_export(ExportArgs a) {
  // Cheap checks first: nothing is read or computed for an output that cannot be written.
  if (lowercase_extension(a.out) != ".scad") {
    throw InputError(fmt::format("{}: unknown format '{}' (export writes .scad)", a.out,
                                 lowercase_extension(a.out)));
  }
  if (!a.report.empty()) {
    if (lowercase_extension(a.report) != ".json") {
      throw InputError(fmt::format("--report {}: the report is JSON (.json)", a.report));
    }
    const auto dir = std::filesystem::path(a.report).parent_path();
    if (!dir.empty() && !std::filesystem::is_directory(dir)) {
      throw InputError(fmt::format("cannot write {}: no directory {}", a.report, dir.string()));
    }
  }
  a.options.clip = a.clip == "always"  ? scad::Clip::kAlways
                   : a.clip == "never" ? scad::Clip::kNever
                                       : scad::Clip::kAuto;
  const Tree tree = io::read_tree_file(a.tree);
  a.options.source = a.tree;
  scad::ExportReport r;
  scad::write_scad(tree, tree.params.values(), a.out, a.options, &r);

  fmt::print("export: {} ({}D, {} lea{}, {} operator{}) -> {}{}\n", a.tree, tree.dim, r.leaves,
             r.leaves == 1 ? "f" : "ves", r.operators, r.operators == 1 ? "" : "s", a.out,
             r.clipped ? " (intersected with the domain)" : "");
  if (r.quadric_leaves > 0) {
    std::string kinds;
    for (const auto& [k, n] : r.quadric_kinds) {
      kinds += fmt::format("{}{} {}", kinds.empty() ? "" : ", ", k, n);
    }
    fmt::print("export: quadric leaves classified: {} of {}{}; written as: {}\n",
               r.quadrics_classified, r.quadric_leaves,
               r.quadrics_outside > 0
                   ? fmt::format(" ({} as the outside of their primitive)", r.quadrics_outside)
                   : "",
               kinds);
  }
  if (r.meshed_leaves > 0) {
    fmt::print("export: {} {} meshed at resolution {}\n", r.meshed_leaves,
               r.meshed_leaves == 1 ? "leaf" : "leaves", a.options.resolution);
  }
  if (!a.report.empty()) {
    nlohmann::ordered_json j;
    j["tree"] = a.tree;
    j["output"] = a.out;
    j["fn"] = a.options.fn;
    j["resolution"] = a.options.resolution;
    j["tolerance"] = a.options.classify.tolerance;
    j["min_agreement"] = a.options.classify.min_agreement;
    const auto counts = nlohmann::ordered_json::parse(scad::report_json(r));
    for (const auto& [key, value] : counts.items()) j[key] = value;
    io::write_text_file_atomic(a.report, j.dump(2) + "\n");
  }
  return 0;
}

}  // namespace

Verb register_export(CLI::App& app) {
  auto a = std::make_shared<ExportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "export", "The tree's crisp counterpart as an OpenSCAD program (.scad), quadrics classified");
  cmd->add_option("tree", a->tree, "Tree file")->required();
  cmd->add_option("-o,--output", a->out, "Output .scad file")->required();
  cmd->add_option("--fn", a->options.fn, "$fn: facets of OpenSCAD's curved primitives")
      ->capture_default_str()
      ->check(CLI::Range(3, 10000));
  cmd->add_option("--resolution", a->options.resolution,
                  "Leaves written as meshes: cells along the domain's longest side")
      ->capture_default_str()
      ->check(CLI::Range(2, 4096));
  cmd->add_option("--tolerance", a->options.classify.tolerance,
                  "Quadric classification: relative tolerance of zero eigenvalues and terms")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.5));
  cmd->add_option("--min-agreement", a->options.classify.min_agreement,
                  "Quadric classification: fraction of domain samples whose sign must agree")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--samples", a->options.classify.samples,
                  "Quadric classification: validation samples per leaf")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000000));
  cmd->add_option("--clip", a->clip,
                  "Intersect the model with the domain: auto (when it has unbounded parts), "
                  "always, never")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "always", "never"}));
  cmd->add_option("--report", a->report, "Also write the counts and every leaf's class as JSON");
  add_threads_option(cmd, a->options.threads);
  return {cmd, [a] { return run_export(*a); }};
}

}  // namespace fuzzycsg::app
