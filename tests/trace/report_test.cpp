// report.json of the trace and morph verbs built from small results made by hand: the header,
// the settings echoed, scores, statistics, runs, refinement and frames.
#include "fuzzycsg/trace/report.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzzycsg/trace/pictures.hpp"

namespace fuzzycsg::trace {
namespace {

using json = nlohmann::ordered_json;

Bitmap small_bitmap() {
  Bitmap b(8, 6);
  b.set_span(2, 1, 6);  // 5 pixels
  b.set(3, 4);
  return b;
}

// (circle | rectangle).
CsgTree two_primitives() {
  CsgTree t;
  Primitive c;
  c.x = 3;
  c.y = 3;
  c.r = 2;
  Primitive r;
  r.shape = Shape::kRectangle;
  r.x = 5;
  r.y = 2;
  r.w = 3;
  r.h = 1;
  const int a = t.add_leaf(c);
  const int b = t.add_leaf(r);
  t.add_op(Op::kUnion, a, b);
  return t;
}

Score make_score(std::int64_t excess, std::int64_t uncovered, int primitives, double k) {
  Score s;
  s.excess = excess;
  s.uncovered = uncovered;
  s.primitives = primitives;
  s.k = k;
  return s;
}

SearchResult make_search(std::int64_t excess) {
  SearchResult r;
  r.best = two_primitives();
  r.score = make_score(excess, 2, 2, 10.0);
  SearchStatistics& s = r.statistics;
  s.trees_evaluated = 42;
  s.tree_evaluations = 420;
  s.primitives_scanned = 4200;
  s.iterations = 30;
  s.stopped_by = "patience";
  s.best_found_at = 17;
  s.tried = {4, 8, 2, 0};
  s.improved = {1, 2, 0, 0};
  OperatorWindow w;
  w.first_iteration = 0;
  w.last_iteration = 30;
  w.tried = s.tried;
  w.improved = s.improved;
  s.history.push_back(w);
  s.best_score = {{12, 80.0}, {17, 24.0}};
  s.threads = 3;
  return r;
}

SearchOptions options() {
  SearchOptions o;
  o.seed = 7;
  o.population = 12;
  o.max_trees = 40;
  o.local.k = 10.0;
  return o;
}

TEST(TraceReport, OneRunHasHeaderSettingsScoreAndStatistics) {
  TraceOutcome outcome;
  outcome.search = make_search(3);
  const json j = json::parse(
      trace_report_json(small_bitmap(), options(), outcome, {"fuzzycsg trace p.png", "p.png", {}}));
  std::vector<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.push_back(key);
  const std::vector<std::string> expected{"format",    "version",    "verb",       "command_line",
                                          "bitmap",    "settings",   "score",      "excess",
                                          "uncovered", "mismatch",   "primitives", "k",
                                          "depth",     "expression", "statistics"};
  EXPECT_EQ(keys, expected);
  EXPECT_EQ(j["format"], "fuzzycsg-trace-report");
  EXPECT_EQ(j["version"], 1);
  EXPECT_EQ(j["verb"], "trace");
  EXPECT_EQ(j["command_line"], "fuzzycsg trace p.png");
  EXPECT_EQ(j["bitmap"]["path"], "p.png");
  EXPECT_EQ(j["bitmap"]["width"], 8);
  EXPECT_EQ(j["bitmap"]["height"], 6);
  EXPECT_EQ(j["bitmap"]["pixels_set"], 6);

  const json& s = j["settings"];
  EXPECT_EQ(s["seed"], 7);
  EXPECT_EQ(s["population"], 12);
  EXPECT_EQ(s["max_trees"], 40);
  EXPECT_DOUBLE_EQ(s["probabilities"]["MOD"].get<double>(), 0.1);
  EXPECT_DOUBLE_EQ(s["k"].get<double>(), 10.0);
  EXPECT_EQ(s["runs"], 1);
  EXPECT_FALSE(s.contains("min_difference"));
  EXPECT_FALSE(s.contains("refine"));
  EXPECT_FALSE(j.contains("runs"));
  EXPECT_FALSE(j.contains("refine"));

  EXPECT_DOUBLE_EQ(j["score"].get<double>(), 3 + 2 + 10.0 * 2);
  EXPECT_EQ(j["mismatch"], 5);
  EXPECT_EQ(j["primitives"], 2);
  EXPECT_EQ(j["depth"], 1);
  EXPECT_EQ(j["expression"], expression(two_primitives()));

  const json& st = j["statistics"];
  EXPECT_EQ(st["trees_evaluated"], 42);
  EXPECT_EQ(st["primitives_scanned"], 4200);
  EXPECT_EQ(st["stopped_by"], "patience");
  EXPECT_EQ(st["best_found_at"], 17);
  EXPECT_EQ(st["threads"], 3);
  EXPECT_EQ(st["operators"]["ADD"]["tried"], 8);
  EXPECT_DOUBLE_EQ(st["operators"]["ADD"]["rate"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(st["operators"]["MOD"]["rate"].get<double>(), 0.0);  // none tried
  ASSERT_EQ(st["history"].size(), 1u);
  EXPECT_EQ(st["history"][0]["last_iteration"], 30);
  EXPECT_EQ(st["best_score"], json::parse("[[12, 80.0], [17, 24.0]]"));
}

TEST(TraceReport, SeveralRunsListEveryRunAndTheDistinctOnes) {
  TraceOutcome outcome;
  outcome.runs = 3;
  outcome.min_difference = 0.05;
  outcome.variety.runs = {make_search(9), make_search(4), make_search(1)};
  outcome.variety.distinct = {2, 0};
  outcome.search = outcome.variety.runs[2];
  const json j = json::parse(
      trace_report_json(small_bitmap(), options(), outcome, {"cmd", "p.png", {"d/01", "d/02"}}));
  EXPECT_EQ(j["settings"]["runs"], 3);
  EXPECT_DOUBLE_EQ(j["settings"]["min_difference"].get<double>(), 0.05);
  ASSERT_EQ(j["runs"].size(), 3u);
  EXPECT_EQ(j["runs"][1]["run"], 1);
  EXPECT_EQ(j["runs"][1]["seed"], 8);
  EXPECT_EQ(j["runs"][1]["excess"], 4);
  EXPECT_EQ(j["runs"][1]["statistics"]["iterations"], 30);
  ASSERT_EQ(j["distinct"].size(), 2u);
  EXPECT_EQ(j["distinct"][0]["directory"], "d/01");
  EXPECT_EQ(j["distinct"][0]["run"], 2);
  EXPECT_EQ(j["distinct"][0]["seed"], 9);
  EXPECT_DOUBLE_EQ(j["distinct"][1]["score"].get<double>(), 9 + 2 + 20.0);
  EXPECT_EQ(j["best_run"], 2);
  EXPECT_EQ(j["excess"], 1);

  outcome.variety.distinct = {2};  // two folders for one result
  EXPECT_THROW(
      trace_report_json(small_bitmap(), options(), outcome, {"cmd", "p.png", {"d/01", "d/02"}}),
      std::invalid_argument);
}

TEST(TraceReport, RefinementReplacesTheScoreAndKeepsTheSearchsAsBefore) {
  TraceOutcome outcome;
  outcome.search = make_search(6);
  TraceOutcome::Refinement refinement;
  refinement.options.iterations = 77;
  refinement.options.lr = 0.25;
  refinement.result.tree = two_primitives();
  refinement.result.before = outcome.search.score;
  refinement.result.after = make_score(1, 1, 2, 10.0);
  refinement.result.improved = true;
  refinement.result.iterations = 77;
  refinement.result.best_iteration = 60;
  refinement.result.loss = {0.5, 0.125};
  outcome.refinement = refinement;
  const json j =
      json::parse(trace_report_json(small_bitmap(), options(), outcome, {"cmd", "p.png", {}}));
  EXPECT_EQ(j["settings"]["refine"]["iterations"], 77);
  EXPECT_DOUBLE_EQ(j["settings"]["refine"]["lr"].get<double>(), 0.25);
  EXPECT_EQ(j["refine"]["improved"], true);
  EXPECT_EQ(j["refine"]["best_iteration"], 60);
  EXPECT_DOUBLE_EQ(j["refine"]["before"]["score"].get<double>(), 6 + 2 + 20.0);
  EXPECT_DOUBLE_EQ(j["refine"]["after"]["score"].get<double>(), 1 + 1 + 20.0);
  EXPECT_DOUBLE_EQ(j["refine"]["final_loss"].get<double>(), 0.125);
  EXPECT_DOUBLE_EQ(j["score"].get<double>(), 22.0);   // the refined tree's
  EXPECT_EQ(j["statistics"]["trees_evaluated"], 42);  // the search's
}

TEST(TraceReport, MorphCountsShapeChangesAndListsTheFrames) {
  MorphResult m;
  m.first = two_primitives();
  m.second = two_primitives();
  m.second.primitive(m.second.leaves().front()).shape = Shape::kRectangle;
  m.first_score = make_score(2, 0, 2, 10.0);
  m.second_score = make_score(4, 2, 2, 10.0);
  m.score = 24.0;
  m.statistics = make_search(0).statistics;
  EXPECT_EQ(shape_changes(m), 1);

  const MorphAnimation animation{2, Rotation::kCounterClockwise, 40};
  const std::vector<MorphFrame> frames{{"frames/frame_000.png", 0.0, 6},
                                       {"frames/frame_001.png", 1.0, 9}};
  const json j = json::parse(morph_report_json(small_bitmap(), small_bitmap(), options(), animation,
                                               m, frames, {"cmd", "a.png", "b.png"}));
  EXPECT_EQ(j["format"], "fuzzycsg-trace-report");
  EXPECT_EQ(j["verb"], "morph");
  EXPECT_EQ(j["first_bitmap"]["path"], "a.png");
  EXPECT_EQ(j["second_bitmap"]["path"], "b.png");
  EXPECT_EQ(j["settings"]["frames"], 2);
  EXPECT_EQ(j["settings"]["rotation"], "ccw");
  EXPECT_EQ(j["settings"]["delay_ms"], 40);
  EXPECT_DOUBLE_EQ(j["score"].get<double>(), 24.0);
  EXPECT_DOUBLE_EQ(j["second"]["score"].get<double>(), 26.0);
  EXPECT_EQ(j["primitives"], 2);
  EXPECT_EQ(j["shape_changes"], 1);
  EXPECT_EQ(j["statistics"]["stopped_by"], "patience");
  ASSERT_EQ(j["frames"].size(), 2u);
  EXPECT_EQ(j["frames"][1]["file"], "frames/frame_001.png");
  EXPECT_DOUBLE_EQ(j["frames"][1]["t"].get<double>(), 1.0);
  EXPECT_EQ(j["frames"][1]["pixels_set"], 9);
}

TEST(TraceReport, RotationNamesRoundTrip) {
  for (const Rotation r :
       {Rotation::kShortest, Rotation::kClockwise, Rotation::kCounterClockwise}) {
    EXPECT_EQ(rotation_from_name(rotation_name(r)), r);
  }
  EXPECT_EQ(rotation_name(Rotation::kClockwise), "cw");
  EXPECT_FALSE(rotation_from_name("left").has_value());
}

}  // namespace
}  // namespace fuzzycsg::trace
