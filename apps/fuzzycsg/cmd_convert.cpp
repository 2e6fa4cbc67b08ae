// fuzzycsg convert MESH -o OUTDIR [--max-primitives K] [--time-limit S] [--seed N] [--threads N]
//                  [--resolution R] [--restarts N] [--refine-steps N] [--padding P]
//                  [--metric-points N] [-q]
//
// A part's mesh as an editable CSG program of CAD primitives (fuzzycsg/convert/convert.hpp).
// Writes OUTDIR/tree.json (crisp, in the mesh's coordinates), model.scad (OpenSCAD primitives
// only), report.json, and with the diagram module diagram.svg.

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.hpp"
#include "fuzzycsg/convert/convert.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/scad/scad.hpp"
#if FUZZYCSG_HAVE_DIAGRAM
#include "fuzzycsg/diagram/diagram.hpp"
#endif

namespace fuzzycsg::app {

namespace {

struct ConvertArgs {
  std::string target, out;
  convert::ConvertOptions options;
  bool quiet = false;
};

// The stage on stderr: redrawn in place on a terminal, nothing when piped.
class StagePrinter {
 public:
  explicit StagePrinter(bool quiet) : on_(!quiet && ::isatty(2) == 1) {}
  void operator()(const convert::ConvertProgress& p) const {
    if (!on_) return;
    std::string line = fmt::format("convert: {}", p.stage);
    if (p.steps > 0) line += fmt::format(" {}/{}", p.step, p.steps);
    if (p.iou) line += fmt::format("  IoU {:.4f}", *p.iou);
    if (p.primitives > 0) line += fmt::format("  {} primitives", p.primitives);
    fmt::print(stderr, "\r{:<72}", line);
    std::fflush(stderr);
  }
  void done() const {
    if (on_) fmt::print(stderr, "\r{:<72}\r", "");
  }

 private:
  bool on_;
};

int run_convert(const ConvertArgs& a) {
  if (!std::filesystem::is_regular_file(a.target)) {
    throw InputError(a.target + ": no such file");
  }
  const StagePrinter printer(a.quiet);
  convert::ConvertHooks hooks;
  hooks.progress = [&printer](const convert::ConvertProgress& p) { printer(p); };
  const convert::ConvertResult r = convert::convert(a.target, a.options, hooks);
  printer.done();

  prepare_output_dir(a.out);
  const std::filesystem::path dir(a.out);
  io::write_text_file_atomic(dir / "tree.json", io::write_tree_string(r.tree));
  scad::ExportOptions eo;
  eo.threads = a.options.threads;
  scad::write_scad(r.tree, r.tree.params.values(), dir / "model.scad", eo);
  io::write_text_file_atomic(dir / "report.json", convert::report_json(r, a.options));
#if FUZZYCSG_HAVE_DIAGRAM
  write_diagram(r.tree, dir / "diagram.svg");
#endif
  if (!a.quiet) {
    fmt::print("convert: {} -> {}: {} primitives, IoU {:.4f}{}, {:.1f} s\n", a.target, a.out,
               r.primitives, r.metrics.iou,
               r.chamfer ? fmt::format(", Chamfer {:.4g}", *r.chamfer) : "", r.seconds);
  }
  return 0;
}

}  // namespace

Verb register_convert(CLI::App& app) {
  auto a = std::make_shared<ConvertArgs>();
  CLI::App* cmd = app.add_subcommand(
      "convert", "A part's mesh as an editable CSG program of CAD primitives (tree, OpenSCAD)");
  cmd->add_option("target", a->target, "Closed triangle mesh (OBJ, STL, PLY, OFF)")->required();
  cmd->add_option("-o,--output", a->out, "Output directory")->required();
  auto& o = a->options;
  cmd->add_option("--max-primitives", o.max_primitives,
                  "At most this many primitives a part (0: as many as pay for themselves)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1 << 20));
  cmd->add_option("--time-limit", o.time_limit, "Seconds")->capture_default_str();
  cmd->add_option("--seed", o.seed, "Random seed")->capture_default_str();
  cmd->add_option("--resolution", o.resolution, "Search grid cells along the longest side")
      ->capture_default_str();
  cmd->add_option("--restarts", o.restarts, "Random restarts of the search")->capture_default_str();
  cmd->add_option("--refine-steps", o.refine_steps, "Steps of fuzzy refinement (0: none)")
      ->capture_default_str();
  cmd->add_option("--padding", o.padding, "Margin of the normalised box")->capture_default_str();
  cmd->add_option("--metric-points", o.metrics.points, "Uniform points for IoU")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 28));
  cmd->add_flag("-q,--quiet", a->quiet, "No progress or summary");
  add_threads_option(cmd, o.threads);
  return {cmd, [a] {
            a->options.metrics.threads = a->options.threads;
            a->options.metrics.seed = a->options.seed;
            return run_convert(*a);
          }};
}

}  // namespace fuzzycsg::app
