// fuzzycsg trace BITMAP -o OUTDIR [search options] [--runs N]
// fuzzycsg morph A B -o OUTDIR [search options] [--frames N] [--rotation R] [--delay MS]
//
// The bitmap tracer of Gibson et al. 1997: the global search for a CSG tree of circles and
// rectangles that reproduces a bitmap (trace: OUTDIR/tree.json, result.png, primitives.svg,
// report.json; with --runs N > 1 also OUTDIR/distinct/NN/ for each distinct result), and the
// morph between two bitmaps through a pair of trees of the same structure (morph:
// OUTDIR/first.json, second.json, report.json, frames/frame_000.png ..., morph.gif; a program
// built without giflib refuses morph).
// docs/trace.md describes the outputs and the report's fields.

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/convert.hpp"
#include "fuzzycsg/trace/evaluate.hpp"
#include "fuzzycsg/trace/morph_frames.hpp"
#include "fuzzycsg/trace/pictures.hpp"
#include "fuzzycsg/trace/refine.hpp"
#include "fuzzycsg/trace/report.hpp"
#include "fuzzycsg/trace/search.hpp"

namespace fuzzycsg::app {

namespace {

namespace fs = std::filesystem;
using trace::Bitmap;
using trace::CsgTree;
using trace::SearchOptions;

struct SearchArgs {
  SearchOptions options;
  std::string probabilities;  // "REP,ADD,CUT,MOD" as given ("": the defaults)
  bool quiet = false;
};

struct TraceArgs {
  std::string bitmap, out_dir;
  SearchArgs search;
  int runs = 1;
  double min_difference = 0.01;
  bool refine = false;
  trace::RefineOptions refine_options;
};

struct MorphArgs {
  std::string first, second, out_dir;
  SearchArgs search;
  int frames = 30;
  std::string rotation = "shortest";
  int delay_ms = 80;
};

void add_search_options(CLI::App* cmd, SearchArgs& a) {
  SearchOptions& o = a.options;
  cmd->add_option("--seed", o.seed, "Random seed")->capture_default_str()->check(unsigned_number());
  cmd->add_option("--population", o.population, "|S|: trees searched in parallel")
      ->capture_default_str();
  cmd->add_option("--max-trees", o.max_trees, "N: iterations (trees perturbed) at most")
      ->capture_default_str();
  cmd->add_option("--patience", o.patience,
                  "B: stop after this many iterations without improvement")
      ->capture_default_str();
  cmd->add_option("--refocus", o.refocus,
                  "n: every n iterations the worse half of S is replaced by the better")
      ->capture_default_str();
  cmd->add_option("--initial-size", o.initial_size, "a: mean primitives of the initial trees")
      ->capture_default_str();
  cmd->add_option("--initial-sd", o.initial_sd, "s: their standard deviation")
      ->capture_default_str();
  cmd->add_option("--added-size", o.added_size, "a': mean primitives added by REP and ADD")
      ->capture_default_str();
  cmd->add_option("--added-sd", o.added_sd, "s': their standard deviation")->capture_default_str();
  cmd->add_option("--probabilities", a.probabilities,
                  "REP,ADD,CUT,MOD: the perturbations' probabilities (normalised)")
      ->default_str(fmt::format("{},{},{},{}", o.probabilities[0], o.probabilities[1],
                                o.probabilities[2], o.probabilities[3]));
  cmd->add_option("--iterations", o.local.max_iterations,
                  "M: sweeps of the local optimizer at most")
      ->capture_default_str();
  cmd->add_option("--k", o.local.k, "k: score = EXCESS + UNCOVERED + k * primitives")
      ->capture_default_str();
  add_threads_option(cmd, o.threads);
  cmd->add_option("--batch", o.batch,
                  "Iterations optimized in parallel (the result depends on it, not on --threads)")
      ->capture_default_str();
  cmd->add_option("--time-limit", o.time_limit, "Stop after this many seconds (0: none)")
      ->capture_default_str();
  cmd->add_option("--statistics-window", o.statistics_window,
                  "Iterations per row of the report's history")
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", a.quiet, "No summary");
}

// The options as given: --probabilities parsed, everything validated (InputError naming the
// flag).
SearchOptions search_options(const SearchArgs& a) {
  SearchOptions o = a.options;
  if (!a.probabilities.empty()) {
    std::vector<double> values;
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = a.probabilities.find(',', start);
      const std::string item = a.probabilities.substr(
          start, comma == std::string::npos ? std::string::npos : comma - start);
      std::size_t used = 0;
      double v = 0;
      try {
        v = std::stod(item, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != item.size() || !std::isfinite(v)) {
        throw InputError(fmt::format(
            "--probabilities: \"{}\" is not a number (expected four numbers REP,ADD,CUT,MOD)",
            item));
      }
      values.push_back(v);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    if (values.size() != 4) {
      throw InputError(fmt::format("--probabilities: expected four numbers REP,ADD,CUT,MOD, got {}",
                                   values.size()));
    }
    for (std::size_t i = 0; i < 4; ++i) {
      if (values[i] < 0) {
        throw InputError(fmt::format("--probabilities: {} = {} is negative",
                                     trace::kPerturbationNames[i], values[i]));
      }
      o.probabilities[i] = values[i];
    }
    if (values[0] + values[1] + values[2] + values[3] <= 0) {
      throw InputError("--probabilities: all four are zero");
    }
  }
  trace::validate(o);
  return o;
}

// The distinct results of an earlier run with more of them (OUTDIR/distinct/NN beyond `keep`):
// their files, and the folders when nothing else is left in them.
void remove_stale_distinct(const fs::path& out, std::size_t keep) {
  const fs::path root = out / "distinct";
  std::error_code ec;
  if (!fs::is_directory(root, ec)) return;
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(root, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() < 2 || name.size() > 9 ||
        name.find_first_not_of("0123456789") != std::string::npos) {
      continue;
    }
    if (std::stoul(name) > keep) stale.push_back(entry.path());
  }
  for (const fs::path& dir : stale) {
    fs::remove(dir / "tree.json", ec);
    fs::remove(dir / "result.png", ec);
    fs::remove(dir, ec);  // only when empty
  }
  fs::remove(root, ec);  // only when empty
}

// A traced tree's files: tree.json, result.png (and primitives.svg when `svg`), in memory.
struct TreeFiles {
  std::string tree_json, result_png, primitives_svg;
};
TreeFiles tree_files(const CsgTree& tree, const Bitmap& target, bool svg) {
  const trace::TreeEvaluator e(tree, target.width(), target.height());
  const int scale = trace::display_scale(target.width(), target.height());
  const int svg_scale = trace::display_scale(target.width(), target.height(), 512);
  TreeFiles f;
  f.tree_json = io::write_tree_string(trace::to_tree(tree, target.width(), target.height()));
  f.result_png = trace::result_png(e.result(), target, scale);
  if (svg) f.primitives_svg = trace::primitives_svg(tree, e.result(), target, svg_scale);
  return f;
}

std::string summary(const trace::Score& s) {
  return fmt::format("score {:.6g} (excess {}, uncovered {}, {} primitive{})", s.total(), s.excess,
                     s.uncovered, s.primitives, s.primitives == 1 ? "" : "s");
}

int run_trace(const TraceArgs& a) {
  if (a.runs < 1) throw InputError(fmt::format("--runs: must be >= 1, got {}", a.runs));
  if (!(a.min_difference >= 0 && a.min_difference <= 1)) {
    throw InputError(fmt::format("--min-difference: must lie in [0, 1], got {}", a.min_difference));
  }
  const SearchOptions options = search_options(a.search);
  trace::RefineOptions ro = a.refine_options;
  ro.k = options.local.k;
  ro.seed = options.seed;
  ro.threads = options.threads;
  if (a.refine) {
    try {
      trace::validate(ro);
    } catch (const OptionError& e) {  // the verb's flags for them are --refine-*
      throw OptionError("refine_" + e.field(), e.problem());
    }
  }
  const Bitmap target = trace::read_bitmap(a.bitmap);
  trace::check_traceable(target, a.bitmap);
  const fs::path out(a.out_dir);
  prepare_output_dir(out);

  trace::TraceOutcome outcome;
  outcome.runs = a.runs;
  outcome.min_difference = a.min_difference;
  trace::TraceReportContext context{command_line(), a.bitmap, {}};
  std::vector<std::pair<std::string, TreeFiles>> distinct_files;
  if (a.runs == 1) {
    outcome.search = trace::search(target, options);
  } else {
    outcome.variety = trace::search_variety(target, options, a.runs, a.min_difference);
    const trace::Variety& v = outcome.variety;
    if (v.runs.empty() || v.distinct.empty()) {
      throw std::runtime_error("search_variety returned no runs");
    }
    for (std::size_t d = 0; d < v.distinct.size(); ++d) {
      const auto run = static_cast<std::size_t>(v.distinct[d]);
      const std::string dir = fmt::format("distinct/{:02}", d + 1);
      context.distinct_directories.push_back(dir);
      distinct_files.emplace_back(dir, tree_files(v.runs[run].best, target, false));
    }
    outcome.search = v.runs[static_cast<std::size_t>(v.distinct.front())];
  }
  // --refine: the best tree refined by gradient descent on its fuzzy relaxation; it replaces
  // the search's tree only when its crisp score is lower (the search's is kept as
  // search_tree.json).
  trace::SearchResult best = outcome.search;
  std::string search_tree;
  const trace::RefineResult* refined = nullptr;
  if (a.refine) {
    outcome.refinement = trace::TraceOutcome::Refinement{ro, trace::refine(best.best, target, ro)};
    refined = &outcome.refinement->result;
    search_tree = io::write_tree_string(trace::to_tree(best.best, target.width(), target.height()));
    best.best = refined->tree;
    best.score = refined->after;
  }
  const std::string report = trace::trace_report_json(target, options, outcome, context);
  const TreeFiles files = tree_files(best.best, target, true);

  // Everything is computed; each file is written atomically, the report last.
  io::write_text_file_atomic(out / "tree.json", files.tree_json);
  if (a.refine) io::write_text_file_atomic(out / "search_tree.json", search_tree);
  io::write_text_file_atomic(out / "result.png", files.result_png);
  io::write_text_file_atomic(out / "primitives.svg", files.primitives_svg);
  remove_stale_distinct(out, distinct_files.size());
  for (const auto& [dir, f] : distinct_files) {
    std::error_code ec;
    fs::create_directories(out / dir, ec);
    if (ec) {
      throw InputError(
          fmt::format("{}: cannot create directory ({})", (out / dir).string(), ec.message()));
    }
    io::write_text_file_atomic(out / dir / "tree.json", f.tree_json);
    io::write_text_file_atomic(out / dir / "result.png", f.result_png);
  }
  io::write_text_file_atomic(out / "report.json", report);

  if (!a.search.quiet) {
    const trace::SearchStatistics& s = best.statistics;
    fmt::print("trace: {} ({}x{}, {} pixels set)\n", a.bitmap, target.width(), target.height(),
               target.count());
    fmt::print("trace: {} after {} trees evaluated in {:.2f}s ({} thread{}, stopped by {})\n",
               summary(best.score), s.trees_evaluated, s.seconds, s.threads,
               s.threads == 1 ? "" : "s", s.stopped_by ? s.stopped_by : "?");
    if (a.runs > 1) {
      fmt::print("trace: {} runs, {} distinct results\n", a.runs, distinct_files.size());
    }
    if (refined) {
      fmt::print("trace: refined in {} steps ({:.2f}s): {} -> {}{}\n", refined->iterations,
                 refined->seconds, refined->before.total(), refined->after.total(),
                 refined->improved ? "" : " (not improved, the search's tree kept)");
    }
    fmt::print("trace: wrote {}/{{tree.json, result.png, primitives.svg, report.json{}{}}}\n",
               out.string(), a.refine ? ", search_tree.json" : "", a.runs > 1 ? ", distinct/" : "");
  }
  return 0;
}

int run_morph(const MorphArgs& a) {
  if (a.frames < 1 || a.frames > 10000) {
    throw InputError(fmt::format("--frames: must lie in [1, 10000], got {}", a.frames));
  }
  if (a.delay_ms < 0 || a.delay_ms > 600000) {
    throw InputError(fmt::format("--delay: must lie in [0, 600000] ms, got {}", a.delay_ms));
  }
  const std::optional<trace::Rotation> rotation = trace::rotation_from_name(a.rotation);
  if (!rotation) {
    throw InputError(fmt::format("--rotation: shortest, cw or ccw, got {}", a.rotation));
  }
  const SearchOptions options = search_options(a.search);
  const Bitmap first = trace::read_bitmap(a.first);
  const Bitmap second = trace::read_bitmap(a.second);
  if (first.width() != second.width() || first.height() != second.height()) {
    throw InputError(fmt::format(
        "{}: {}x{} pixels, but {} is {}x{} (morph needs bitmaps of the "
        "same size)",
        a.second, second.width(), second.height(), a.first, first.width(), first.height()));
  }
  trace::check_traceable(first, a.first);
  trace::check_traceable(second, a.second);
  // Checked before the search and before anything is written.
  if (!FUZZYCSG_HAVE_GIFLIB) {
    throw InputError(
        "morph: this fuzzycsg was built without giflib (FUZZYCSG_WITH_GIF=OFF), so it cannot "
        "write morph.gif");
  }
  const fs::path out(a.out_dir);
  prepare_output_dir(out);

  const trace::MorphResult m = trace::search_morph(first, second, options);
  const int width = first.width(), height = first.height();
  const trace::MorphInterpolator morph(m.first, m.second, *rotation);
  const int scale = trace::display_scale(width, height);
  const int digits = std::max(3, static_cast<int>(std::to_string(a.frames - 1).size()));
  const auto frame_t = [&](int i) {
    return a.frames <= 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(a.frames - 1);
  };

  const fs::path frame_dir = out / "frames";
  std::error_code ec;
  fs::create_directories(frame_dir, ec);
  if (ec) {
    throw InputError(
        fmt::format("{}: cannot create directory ({})", frame_dir.string(), ec.message()));
  }
  // Frames of an earlier, longer morph would be mistaken for this one's.
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(frame_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("frame_") && entry.path().extension() == ".png") {
      stale.push_back(entry.path());
    }
  }
  for (const fs::path& p : stale) fs::remove(p, ec);

  // One frame at a time (a large picture's frames would not all fit): rasterised, written as
  // frames/frame_NNN.png and handed to the GIF encoder.
  const std::vector<std::array<std::uint8_t, 3>> palette{
      {trace::kOutsideRgb[0], trace::kOutsideRgb[1], trace::kOutsideRgb[2]},
      {trace::kInsideRgb[0], trace::kInsideRgb[1], trace::kInsideRgb[2]}};
  std::vector<trace::MorphFrame> frame_list;
  const std::string gif =
      trace::encode_gif(a.frames, width * scale, height * scale, palette, a.delay_ms, [&](int i) {
        const Bitmap f = morph.frame(frame_t(i), width, height);
        const std::string name = fmt::format("frame_{:0{}}.png", i, digits);
        io::write_text_file_atomic(frame_dir / name, trace::bitmap_png(f, scale));
        frame_list.push_back({"frames/" + name, frame_t(i), f.count()});
        return trace::indexed_image(f, scale, 0, 1);
      });

  const trace::MorphAnimation animation{a.frames, *rotation, a.delay_ms};
  const std::string report =
      trace::morph_report_json(first, second, options, animation, m, frame_list,
                               trace::MorphReportContext{command_line(), a.first, a.second});

  io::write_tree_file(trace::to_tree(m.first, width, height), out / "first.json");
  io::write_tree_file(trace::to_tree(m.second, width, height), out / "second.json");
  io::write_text_file_atomic(out / "morph.gif", gif);
  io::write_text_file_atomic(out / "report.json", report);

  if (!a.search.quiet) {
    const int leaves = m.first.empty() ? 0 : m.first.primitive_count();
    fmt::print("morph: {} -> {} ({}x{})\n", a.first, a.second, width, height);
    fmt::print("morph: first {}\n", summary(m.first_score));
    fmt::print("morph: second {}\n", summary(m.second_score));
    fmt::print("morph: {} leaves, {} change shape; {} trees evaluated in {:.2f}s (stopped by {})\n",
               leaves, trace::shape_changes(m), m.statistics.trees_evaluated, m.statistics.seconds,
               m.statistics.stopped_by ? m.statistics.stopped_by : "?");
    fmt::print(
        "morph: wrote {}/{{first.json, second.json, report.json, morph.gif, frames/ ({} "
        "frames)}}\n",
        out.string(), a.frames);
  }
  return 0;
}

}  // namespace

Verb register_trace(CLI::App& app) {
  auto a = std::make_shared<TraceArgs>();
  CLI::App* cmd = app.add_subcommand(
      "trace", "Trace a bitmap as a CSG tree of circles and rectangles (Gibson et al. 1997)");
  cmd->add_option("bitmap", a->bitmap, "Picture (.png .jpg .pbm .pgm ...; dark is inside)")
      ->required();
  cmd->add_option("-o,--output", a->out_dir, "Output directory")->required();
  add_search_options(cmd, a->search);
  cmd->add_option("--runs", a->runs,
                  "Independent runs (seeds seed, seed + 1, ...); > 1 keeps the distinct results")
      ->capture_default_str();
  cmd->add_option("--min-difference", a->min_difference,
                  "--runs: share of the pixels by which results must differ to be distinct")
      ->capture_default_str();
  cmd->add_flag("--refine", a->refine,
                "Refine the best tree by gradient descent on its fuzzy relaxation (kept only "
                "when its score is lower)");
  cmd->add_option("--refine-iterations", a->refine_options.iterations, "--refine: Adam steps")
      ->capture_default_str();
  cmd->add_option("--refine-lr", a->refine_options.lr, "--refine: initial learning rate (pixels)")
      ->capture_default_str();
  cmd->add_option("--refine-batch", a->refine_options.batch,
                  "--refine: pixels sampled per step (0: every pixel)")
      ->capture_default_str();
  cmd->add_option("--refine-time-limit", a->refine_options.time_limit,
                  "--refine: stop refining after this many seconds (0: none)")
      ->capture_default_str();
  return {cmd, [a, cmd] {
            for (const char* flag :
                 {"--refine-iterations", "--refine-lr", "--refine-batch", "--refine-time-limit"}) {
              if (cmd->count(flag) > 0 && !a->refine) {
                throw InputError(fmt::format("{}: only with --refine", flag));
              }
            }
            return run_trace(*a);
          }};
}

Verb register_morph(CLI::App& app) {
  auto a = std::make_shared<MorphArgs>();
  a->search.options.initial_size = 5.0;  // the paper's a for morphing
  CLI::App* cmd = app.add_subcommand(
      "morph", "Morph between two bitmaps through two CSG trees of the same structure");
  cmd->add_option("first", a->first, "First picture")->required();
  cmd->add_option("second", a->second, "Second picture (the same size)")->required();
  cmd->add_option("-o,--output", a->out_dir, "Output directory")->required();
  add_search_options(cmd, a->search);
  cmd->add_option("--frames", a->frames, "Frames from t = 0 to t = 1 inclusive")
      ->capture_default_str();
  cmd->add_option("--rotation", a->rotation,
                  "Rectangles turn the shortest way (modulo 180 degrees), cw or ccw")
      ->capture_default_str()
      ->check(CLI::IsMember({"shortest", "cw", "ccw"}));
  cmd->add_option("--delay", a->delay_ms, "Milliseconds per frame of morph.gif")
      ->capture_default_str();
  return {cmd, [a] { return run_morph(*a); }};
}

}  // namespace fuzzycsg::app
