// report.json of the trace and morph verbs (trace/report.hpp). The keys keep the order in which
// they are set (ordered_json), as docs/trace.md lists them.

#include "fuzzycsg/trace/report.hpp"

#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "fuzzycsg/trace/pictures.hpp"

namespace fuzzycsg::trace {

namespace {

using json = nlohmann::ordered_json;

double rate(std::uint64_t improved, std::uint64_t tried) {
  return tried > 0 ? static_cast<double>(improved) / static_cast<double>(tried) : 0.0;
}

json operators_json(const std::array<std::uint64_t, 4>& tried,
                    const std::array<std::uint64_t, 4>& improved) {
  json j = json::object();
  for (std::size_t i = 0; i < 4; ++i) {
    j[kPerturbationNames[i]] = {
        {"tried", tried[i]}, {"improved", improved[i]}, {"rate", rate(improved[i], tried[i])}};
  }
  return j;
}

json settings_json(const SearchOptions& o) {
  json j;
  j["seed"] = o.seed;
  j["population"] = o.population;
  j["max_trees"] = o.max_trees;
  j["patience"] = o.patience;
  j["refocus"] = o.refocus;
  j["initial_size"] = o.initial_size;
  j["initial_sd"] = o.initial_sd;
  j["added_size"] = o.added_size;
  j["added_sd"] = o.added_sd;
  json p = json::object();
  for (std::size_t i = 0; i < 4; ++i) p[kPerturbationNames[i]] = o.probabilities[i];
  j["probabilities"] = p;
  j["iterations"] = o.local.max_iterations;
  j["k"] = o.local.k;
  j["local"] = {{"margin", o.local.margin},       {"shift_step", o.local.shift_step},
                {"size_step", o.local.size_step}, {"angle_step", o.local.angle_step},
                {"min_size", o.local.min_size},   {"max_steps", o.local.max_steps},
                {"prune", o.local.prune},         {"trust_settled", o.local.trust_settled}};
  j["threads"] = o.threads;
  j["batch"] = o.batch;
  j["time_limit"] = o.time_limit;
  j["statistics_window"] = o.statistics_window;
  return j;
}

json refine_settings_json(const RefineOptions& o) {
  return {{"iterations", o.iterations},
          {"batch", o.batch},
          {"lr", o.lr},
          {"lr_end", o.lr_end},
          {"angle_lr", o.angle_lr},
          {"sharpness_start", o.sharpness_start},
          {"sharpness_end", o.sharpness_end},
          {"min_size", o.min_size},
          {"check_every", o.check_every},
          {"time_limit", o.time_limit}};
}

json statistics_json(const SearchStatistics& s) {
  json j;
  j["trees_evaluated"] = s.trees_evaluated;
  j["tree_evaluations"] = s.tree_evaluations;
  j["primitives_scanned"] = s.primitives_scanned;
  j["iterations"] = s.iterations;
  j["stopped_by"] = s.stopped_by ? s.stopped_by : "";
  j["best_found_at"] = s.best_found_at;
  j["seconds"] = s.seconds;
  j["threads"] = s.threads;
  j["operators"] = operators_json(s.tried, s.improved);
  json history = json::array();
  for (const OperatorWindow& w : s.history) {
    json row;
    row["first_iteration"] = w.first_iteration;
    row["last_iteration"] = w.last_iteration;
    row["operators"] = operators_json(w.tried, w.improved);
    history.push_back(row);
  }
  j["history"] = history;
  json best = json::array();
  for (const auto& [trees, score] : s.best_score) best.push_back({trees, score});
  j["best_score"] = best;
  return j;
}

// A tree's score and shape, added to `j`.
void add_score(json& j, const Score& s, const CsgTree& tree) {
  j["score"] = s.total();
  j["excess"] = s.excess;
  j["uncovered"] = s.uncovered;
  j["mismatch"] = s.mismatch();
  j["primitives"] = s.primitives;
  j["k"] = s.k;
  j["depth"] = tree.empty() ? 0 : tree.depth();
  j["expression"] = expression(tree);
}

json score_json(const Score& s, const CsgTree& tree) {
  json j;
  add_score(j, s, tree);
  return j;
}

json bitmap_json(const std::string& path, const Bitmap& b) {
  return {{"path", path}, {"width", b.width()}, {"height", b.height()}, {"pixels_set", b.count()}};
}

json header(std::string_view verb, const std::string& command_line) {
  json j;
  j["format"] = kReportFormat;
  j["version"] = kReportVersion;
  j["verb"] = verb;
  j["command_line"] = command_line;
  return j;
}

// runs > 1: "runs", "distinct" and "best_run".
void add_variety(json& report, const SearchOptions& options, const Variety& v,
                 const std::vector<std::string>& directories) {
  if (v.runs.empty() || v.distinct.empty() || directories.size() != v.distinct.size()) {
    throw std::invalid_argument(
        "trace_report_json: runs > 1 needs runs, distinct results and a folder for each");
  }
  json runs = json::array();
  for (std::size_t i = 0; i < v.runs.size(); ++i) {
    json r;
    r["run"] = i;
    r["seed"] = options.seed + i;
    add_score(r, v.runs[i].score, v.runs[i].best);
    r["statistics"] = statistics_json(v.runs[i].statistics);
    runs.push_back(r);
  }
  json distinct = json::array();
  for (std::size_t d = 0; d < v.distinct.size(); ++d) {
    const auto run = static_cast<std::size_t>(v.distinct[d]);
    distinct.push_back({{"directory", directories[d]},
                        {"run", run},
                        {"seed", options.seed + run},
                        {"score", v.runs.at(run).score.total()}});
  }
  report["runs"] = runs;
  report["distinct"] = distinct;
  report["best_run"] = v.distinct.front();
}

json refinement_json(const CsgTree& searched, const RefineResult& r) {
  json j;
  j["improved"] = r.improved;
  j["iterations"] = r.iterations;
  j["best_iteration"] = r.best_iteration;
  j["seconds"] = r.seconds;
  j["before"] = score_json(r.before, searched);
  j["after"] = score_json(r.after, r.tree);
  j["final_loss"] = r.loss.empty() ? 0.0 : r.loss.back();
  return j;
}

}  // namespace

std::string trace_report_json(const Bitmap& bitmap, const SearchOptions& options,
                              const TraceOutcome& outcome, const TraceReportContext& context) {
  json report = header("trace", context.command_line);
  report["bitmap"] = bitmap_json(context.bitmap_path, bitmap);
  json settings = settings_json(options);
  settings["runs"] = outcome.runs;
  if (outcome.runs > 1) settings["min_difference"] = outcome.min_difference;
  if (outcome.refinement) settings["refine"] = refine_settings_json(outcome.refinement->options);
  report["settings"] = settings;
  if (outcome.runs > 1) {
    add_variety(report, options, outcome.variety, context.distinct_directories);
  }
  const SearchResult& search = outcome.search;
  if (outcome.refinement) {
    const RefineResult& refined = outcome.refinement->result;
    report["refine"] = refinement_json(search.best, refined);
    add_score(report, refined.after, refined.tree);
  } else {
    add_score(report, search.score, search.best);
  }
  report["statistics"] = statistics_json(search.statistics);
  return report.dump(2) + "\n";
}

int shape_changes(const MorphResult& morph) {
  if (morph.first.empty()) return 0;
  int changed = 0;
  for (const int leaf : morph.first.leaves()) {
    if (morph.first.primitive(leaf).shape != morph.second.primitive(leaf).shape) ++changed;
  }
  return changed;
}

std::string morph_report_json(const Bitmap& first, const Bitmap& second,
                              const SearchOptions& options, const MorphAnimation& animation,
                              const MorphResult& morph, const std::vector<MorphFrame>& frames,
                              const MorphReportContext& context) {
  json report = header("morph", context.command_line);
  report["first_bitmap"] = bitmap_json(context.first_path, first);
  report["second_bitmap"] = bitmap_json(context.second_path, second);
  json settings = settings_json(options);
  settings["frames"] = animation.frames;
  settings["rotation"] = rotation_name(animation.rotation);
  settings["delay_ms"] = animation.delay_ms;
  report["settings"] = settings;
  report["score"] = morph.score;
  report["first"] = score_json(morph.first_score, morph.first);
  report["second"] = score_json(morph.second_score, morph.second);
  report["primitives"] = morph.first.empty() ? std::size_t{0} : morph.first.leaves().size();
  report["shape_changes"] = shape_changes(morph);
  report["statistics"] = statistics_json(morph.statistics);
  json frame_list = json::array();
  for (const MorphFrame& f : frames) {
    frame_list.push_back({{"file", f.file}, {"t", f.t}, {"pixels_set", f.pixels_set}});
  }
  report["frames"] = frame_list;
  return report.dump(2) + "\n";
}

}  // namespace fuzzycsg::trace
