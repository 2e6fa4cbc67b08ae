#pragma once
// The report.json of a trace and of a morph (docs/trace.md describes its fields): the bitmaps,
// every setting, the scores of the trees found with their expressions, and the search's
// statistics (trees evaluated, why it stopped, each perturbation's rate of improvement, the
// best score over time). What only the program knows (its command line, the paths as given,
// the names of the files it writes) comes in as plain values.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/csg.hpp"
#include "fuzzycsg/trace/morph_frames.hpp"
#include "fuzzycsg/trace/refine.hpp"
#include "fuzzycsg/trace/search.hpp"

namespace fuzzycsg::trace {

// The report's "format" and "version".
inline constexpr std::string_view kReportFormat = "fuzzycsg-trace-report";
inline constexpr int kReportVersion = 1;

// What a trace found: one search, or with runs > 1 several (search_variety). With refinement
// the report's tree and score are the refined ones (RefineResult::tree and after, which are the
// search's own when refinement did not improve on it).
struct TraceOutcome {
  int runs = 1;
  double min_difference = 0.01;  // recorded with runs > 1
  Variety variety;               // runs > 1: every run and the distinct ones
  // The search's best tree, score and statistics; with runs > 1 the best distinct run's
  // (variety.runs[variety.distinct.front()]).
  SearchResult search;
  struct Refinement {
    RefineOptions options;
    RefineResult result;
  };
  std::optional<Refinement> refinement;
};

// The program's facts about a trace.
struct TraceReportContext {
  std::string command_line;
  std::string bitmap_path;  // as given
  // runs > 1: the folder each distinct result is written to (one per Variety::distinct).
  std::vector<std::string> distinct_directories;
};

// report.json of a trace (JSON text, two-space indents, a final newline): format, version,
// verb "trace", the command line, the bitmap, the settings (the search's, then runs,
// min_difference and refine's), with runs > 1 every run and the distinct results, the
// refinement, the tree's score, and the statistics of the search that found it. Throws
// std::invalid_argument when runs > 1 and the distinct results and their folders disagree.
std::string trace_report_json(const Bitmap& bitmap, const SearchOptions& options,
                              const TraceOutcome& outcome, const TraceReportContext& context);

// How a morph was drawn.
struct MorphAnimation {
  int frames = 30;  // from t = 0 to t = 1 inclusive
  Rotation rotation = Rotation::kShortest;
  int delay_ms = 80;  // per frame of the GIF
};

// One frame the program wrote.
struct MorphFrame {
  std::string file;  // as the report names it ("frames/frame_000.png")
  double t = 0;
  std::int64_t pixels_set = 0;
};

// The program's facts about a morph.
struct MorphReportContext {
  std::string command_line;
  std::string first_path, second_path;  // the bitmaps as given
};

// The leaves of a morph's trees that are a circle in one and a rectangle in the other.
int shape_changes(const MorphResult& morph);

// report.json of a morph: format, version, verb "morph", the command line, both bitmaps, the
// settings (the search's, then the animation's), the mean score, each tree's score, the
// number of primitives and of shape changes, the statistics and the frames.
std::string morph_report_json(const Bitmap& first, const Bitmap& second,
                              const SearchOptions& options, const MorphAnimation& animation,
                              const MorphResult& morph, const std::vector<MorphFrame>& frames,
                              const MorphReportContext& context);

}  // namespace fuzzycsg::trace
