// fuzzycsg convert MESH|MODEL.csg|PICTURE -o OUTDIR [--max-primitives K] [--time-limit S] [--seed
// N]
//                  [--threads N] [--resolution R] [--restarts N] [--refine-steps N]
//                  [--padding P] [--metric-points N] [-q]
//
// A part's mesh, an OpenSCAD model (.csg) or a picture as an editable CSG program of primitives
// (fuzzycsg/convert/convert.hpp). Writes OUTDIR/tree.json (crisp, in the input's coordinates),
// model.scad (OpenSCAD primitives only), report.json, render.png (target and result side by
// side) and, with the diagram module, diagram.svg.

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
#include "fuzzycsg/io/output_dir.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/render/render.hpp"
#include "fuzzycsg/scad/scad.hpp"
#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/convert.hpp"
#include "fuzzycsg/trace/evaluate.hpp"
#include "fuzzycsg/trace/morph_frames.hpp"
#include "fuzzycsg/trace/pictures.hpp"
#if FUZZYCSG_HAVE_DIAGRAM
#include "fuzzycsg/diagram/diagram.hpp"
#endif

namespace fuzzycsg::app {

namespace {

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

// Target and result side by side: 3D, the mesh and a smooth mesh of the tree from the same
// cameras; 2D, the traced tree over the picture (trace's result picture).
std::string comparison_png(const ConvertJob& a, const convert::ConvertResult& r) {
  if (r.tree.dim == 2) {
    const trace::Bitmap picture = trace::read_bitmap(a.target);
    const int w = picture.width(), h = picture.height();
    const trace::TreeEvaluator result(trace::from_tree(r.tree, w, h), w, h);
    return trace::result_png(result.result(), picture, trace::display_scale(w, h));
  }
  ComparisonOptions co;
  co.threads = a.options.threads;
  co.result_label = fmt::format("convert: {} primitives", r.primitives);
  return render_comparison_png(r.target_mesh,
                               convert::solid_mesh(r.tree, co.resolution, co.threads), co);
}

}  // namespace

int run_convert_job(const ConvertJob& a) {
  if (std::filesystem::is_directory(a.target)) {
    throw InputError(a.target + ": is a folder, not a mesh file");
  }
  if (!std::filesystem::is_regular_file(a.target)) {
    throw InputError(a.target + ": no such file");
  }
  // The folder is checked before the work and replaced as a set after it.
  std::vector<std::string> names{"tree.json", "model.scad", "report.json", "render.png",
                                 "diagram.svg"};
  for (const auto& file : a.also_write) names.push_back(file.first);
  io::OutputDir out(a.out_dir, names);
  out.check();
  const StagePrinter printer(a.quiet);
  convert::ConvertHooks hooks;
  hooks.progress = [&printer](const convert::ConvertProgress& p) { printer(p); };
  const convert::ConvertResult r = convert::convert(a.target, a.options, hooks);
  printer.done();

  out.add("tree.json", io::write_tree_string(r.tree));
  scad::ExportOptions eo;
  eo.threads = a.options.threads;
  eo.source = std::filesystem::path(a.target).filename().string();
  eo.writer = "fuzzycsg convert";
  eo.leaf_comments = false;  // each line's primitive says what it is; tree.json has the paths
  const char* against = r.tree.dim == 2                     ? "picture"
                        : has_extension(a.target, {".csg"}) ? "model"
                                                            : "mesh";
  eo.note = fmt::format("IoU {:.4f} against the {}{}; settings and measures in report.json.",
                        r.metrics.iou, against,
                        r.chamfer ? fmt::format(", Chamfer distance {:.3g}", *r.chamfer) : "");
  out.add("model.scad", scad::export_scad(r.tree, r.tree.params.values(), eo));
  out.add("report.json", convert::report_json(r, a.options));
  out.add("render.png", comparison_png(a, r));
#if FUZZYCSG_HAVE_DIAGRAM
  out.add("diagram.svg", render_dot(diagram_dot(r.tree), DiagramFormat::kSvg));
#endif
  for (const auto& [name, bytes] : a.also_write) out.add(name, bytes);
  out.commit();
  for (const std::string& warning : r.warnings) {
    fmt::print(stderr, "convert: {}: warning: {}\n", a.target, warning);
  }
  if (!r.reached || r.time_limit_reached) {
    fmt::print(
        stderr, "convert: {}: {}{}; the best tree found is written\n", a.target,
        r.reached ? "" : fmt::format("IoU {:.4f} is below {}", r.metrics.iou, a.options.warn_iou),
        r.time_limit_reached ? fmt::format("{}the time limit ({} s) cut the search short",
                                           r.reached ? "" : "; ", a.options.time_limit)
                             : "");
  }
  if (!a.quiet) {
    fmt::print("convert: {} -> {}: {} primitives, IoU {:.4f}{}, {:.1f} s\n", a.target, a.out_dir,
               r.primitives, r.metrics.iou,
               r.chamfer ? fmt::format(", Chamfer {:.4g}", *r.chamfer) : "", r.seconds);
    fmt::print("convert: wrote {}/{{tree.json, model.scad, report.json, render.png{}}}\n",
               a.out_dir, FUZZYCSG_HAVE_DIAGRAM ? ", diagram.svg" : "");
  }
  return 0;
}

Verb register_convert(CLI::App& app) {
  auto a = std::make_shared<ConvertJob>();
  CLI::App* cmd = app.add_subcommand(
      "convert", "A part's mesh as an editable CSG program of CAD primitives (tree, OpenSCAD)");
  cmd->add_option("target", a->target,
                  "Closed triangle mesh (OBJ, STL, PLY, OFF), OpenSCAD model (.csg) or picture "
                  "(PNG, JPEG, PBM, PGM)")
      ->required();
  cmd->add_option("-o,--output", a->out_dir, "Output directory")->required();
  auto& o = a->options;
  cmd->add_option("--max-primitives", o.max_primitives,
                  "At most this many primitives a part (0: as many as pay for themselves)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1 << 20));
  cmd->add_option("--time-limit", o.time_limit, "Seconds (the stages end early to keep within it)")
      ->capture_default_str();
  cmd->add_option("--warn-iou", o.warn_iou,
                  "Say so on stderr and in report.json when the IoU ends below this")
      ->capture_default_str();
  cmd->add_option("--seed", o.seed, "Random seed")->capture_default_str()->check(unsigned_number());
  cmd->add_option("--resolution", o.resolution, "Search grid cells along the longest side")
      ->capture_default_str();
  cmd->add_option("--restarts", o.restarts, "Random restarts of the search")->capture_default_str();
  cmd->add_option("--refine-steps", o.refine_steps, "Steps of fuzzy refinement (0: none)")
      ->capture_default_str();
  cmd->add_option("--padding", o.padding, "Margin of the normalised box")->capture_default_str();
  cmd->add_option("--metric-points", o.metrics.points, "Uniform points for IoU")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 28));
  cmd->add_flag("!--no-tidy", o.tidy, "Keep the fitted numbers: no snapping to axes, no rounding");
  cmd->add_flag("-q,--quiet", a->quiet, "No progress or summary");
  add_threads_option(cmd, o.threads);
  return {cmd, [a] {
            a->options.metrics.threads = a->options.threads;
            a->options.metrics.seed = a->options.seed;
            return run_convert_job(*a);
          }};
}

}  // namespace fuzzycsg::app
