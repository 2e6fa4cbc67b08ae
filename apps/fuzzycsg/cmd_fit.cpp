// fuzzycsg fit TARGET -o OUTDIR [options]
//
// Inverse CSG (Liu et al. 2024): fits a full binary tree of fuzzy booleans to a mesh, a picture or
// a tree file, snaps and prunes it, measures it, and writes OUTDIR/tree.json (trained),
// tree_pruned.json, report.json, loss.png (and for 2D targets target.png, fit.png and
// contours.svg, for 3D slices.png and mesh.obj: the pruned tree's 0.5 level set; pictures of the
// pruned tree: render.png in 3D, plot.png and outlines.svg in 2D), with
// OUTDIR/checkpoint.json every --checkpoint-every steps for --resume.

#include <fmt/format.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/transform.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "fuzzycsg/fit/option_names.hpp"
#include "fuzzycsg/fit/plot.hpp"
#include "fuzzycsg/fit/report.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "fuzzycsg/mesh/mesh.hpp"
#include "fuzzycsg/render/render.hpp"

namespace fuzzycsg::app {

namespace {

namespace fs = std::filesystem;

std::string duration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  const long t = std::lround(s);
  if (t >= 3600) return fmt::format("{}h{:02}m", t / 3600, (t / 60) % 60);
  if (t >= 60) return fmt::format("{}m{:02}s", t / 60, t % 60);
  return fmt::format("{}s", t);
}

// Progress on stderr: a bar redrawn in place on a terminal, a plain line every few seconds
// otherwise (logs, CI).
class ProgressPrinter {
 public:
  ProgressPrinter(bool quiet, double time_limit)
      : quiet_(quiet), tty_(::isatty(2) == 1), time_limit_(time_limit) {}

  double interval() const { return tty_ ? 0.25 : 5.0; }

  void operator()(const Progress& p) {
    if (quiet_) return;
    double left =
        p.steps_per_second > 0 ? static_cast<double>(p.iters - p.step) / p.steps_per_second : NAN;
    if (time_limit_ > 0)
      left = std::min(std::isnan(left) ? time_limit_ : left, time_limit_ - p.seconds);
    const double frac =
        p.iters > 0 ? static_cast<double>(p.step) / static_cast<double>(p.iters) : 1;
    if (tty_) {
      constexpr int kWidth = 24;
      const int filled = static_cast<int>(frac * kWidth);
      fmt::print(stderr, "\r  [{}{}] {}/{}  loss {:.5f}  {:.0f} steps/s  {} left  t={:.3g}   ",
                 std::string(static_cast<std::size_t>(filled), '#'),
                 std::string(static_cast<std::size_t>(kWidth - filled), '.'), p.step, p.iters,
                 p.loss, p.steps_per_second, duration(p.final ? 0 : left), p.temperature);
      if (p.final) fmt::print(stderr, "\n");
    } else {
      fmt::print(stderr, "fit: step {}/{} loss {:.6f} {:.0f} steps/s {} left t={:.4g}\n", p.step,
                 p.iters, p.loss, p.steps_per_second, duration(p.final ? 0 : left), p.temperature);
    }
    std::fflush(stderr);
  }

 private:
  bool quiet_, tty_;
  double time_limit_;
};

std::vector<PrimitiveType> parse_families(const std::string& spec, int dim) {
  std::vector<std::string> names;
  if (spec == "mix") {
    names = dim == 3 ? std::vector<std::string>{"quadric", "sphere", "box", "cylinder"}
                     : std::vector<std::string>{"quadric", "circle", "rectangle", "ellipse"};
  } else {
    std::size_t start = 0;
    while (start <= spec.size()) {
      const std::size_t comma = spec.find(',', start);
      names.push_back(spec.substr(start, comma == std::string::npos ? comma : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  std::vector<PrimitiveType> out;
  for (const std::string& name : names) {
    const std::optional<PrimitiveType> t = primitive_from_name(name, dim);
    if (!t) {
      throw InputError(fmt::format("--family: unknown {}D primitive \"{}\"", dim, name));
    }
    out.push_back(*t);
  }
  return out;
}

// An option that takes one of `choices` by name and sets `target` to its value; help and errors
// list the names ("--init: Check surfaces value in {...}" would otherwise show the numbers).
template <class E, std::size_t N>
CLI::Option* add_choice(CLI::App* cmd, const std::string& flag, E& target,
                        const OptionNames<E, N>& choices, const std::string& help) {
  std::vector<std::string> names;
  for (const OptionName<E>& c : choices) names.emplace_back(c.name);
  return cmd
      ->add_option_function<std::string>(
          flag,
          [&target, choices](const std::string& v) {
            if (const std::optional<E> value = option_value(choices, v)) target = *value;
          },
          help)
      ->check(CLI::IsMember(names))
      ->default_str(std::string(option_name(choices, target)));
}

}  // namespace

namespace {

// The settings field a model flag sets ("--near-distance" -> "/sampling/near_distance"), or ""
// for flags whose value the checkpoint does not keep.
std::string settings_field(const std::string& flag) {
  if (flag == "--padding" || flag == "--image-resolution" || flag == "--family") return "";
  if (flag == "--surface" || flag == "--near" || flag == "--near-distance" || flag == "--sampler") {
    return flag == "--sampler" ? "/sampling/scheme" : "/sampling/" + flag.substr(2);
  }
  std::string key = flag.substr(2);
  for (char& c : key) {
    if (c == '-') c = '_';
  }
  return "/" + key;
}

// With --resume, a model flag may repeat the checkpoint's value; a different one is refused.
void check_resume_flags(const FitJob& job, const Checkpoint& ck) {
  const nlohmann::json given = nlohmann::json::parse(fit_options_json(job.options));
  const nlohmann::json fixed = nlohmann::json::parse(fit_options_json(ck.options));
  for (const std::string& flag : job.given_model_flags) {
    bool same = false;
    if (flag == "--family") {
      same = parse_families(job.family, ck.dim) == ck.options.families;
    } else if (const std::string field = settings_field(flag); !field.empty()) {
      const nlohmann::json::json_pointer at(field);
      same = given.contains(at) && fixed.contains(at) && given[at] == fixed[at];
    }
    if (!same) {
      throw InputError(
          fmt::format("{}: cannot change with --resume (the checkpoint fixes it)", flag));
    }
  }
}

}  // namespace

int run_fit_job(const FitJob& job) {
  const fs::path out(job.out_dir);
  FitOptions options = job.options;
  std::unique_ptr<TrainState> resume;
  std::string target_path = job.target;
  if (job.resume) {
    Checkpoint ck = read_checkpoint(out / "checkpoint.json");
    if (fs::weakly_canonical(ck.target) != fs::weakly_canonical(job.target)) {
      throw InputError(fmt::format("{}: checkpoint is for target {}, not {}",
                                   (out / "checkpoint.json").string(), ck.target, job.target));
    }
    check_resume_flags(job, ck);
    const FitOptions given = options;
    options = ck.options;
    if (job.iters_given) options.iters = given.iters;
    if (job.time_limit_given) options.time_limit = given.time_limit;
    options.threads = given.threads;
    options.measure = given.measure;
    resume = std::make_unique<TrainState>(std::move(ck.state));
  }

  prepare_output_dir(out);
  TargetOptions to;
  to.padding = job.padding;
  to.image_resolution = job.image_resolution;
  to.threads = options.threads;
  const std::unique_ptr<Target> target = load_target(target_path, to);
  const int dim = target->dim();
  if (!job.family.empty()) options.families = parse_families(job.family, dim);
  validate(options, dim);
  if (!job.quiet) {
    fmt::print("fit: {}\n", target->describe());
    fmt::print("fit: {} {} primitives, {} operators, {} steps of {} points{}\n", options.prims,
               options.families.empty() ? std::string("quadric")
                                        : std::string(primitive_info(options.families[0]).name) +
                                              (options.families.size() > 1 ? " (mixed)" : ""),
               operator_mode_name(options.ops), options.iters, options.batch,
               resume ? fmt::format(", resuming at step {}", resume->step) : "");
    std::fflush(stdout);
  }

  ProgressPrinter printer(job.quiet, options.time_limit);
  FitHooks hooks;
  hooks.progress = [&printer](const Progress& p) { printer(p); };
  hooks.progress_seconds = printer.interval();
  hooks.checkpoint_every = job.checkpoint_every;
  const fs::path checkpoint_path = out / "checkpoint.json";
  hooks.checkpoint = [&](const Tree&, const TrainState& st) {
    Checkpoint ck;
    ck.target = target_path;
    ck.dim = dim;
    ck.options = options;
    ck.state = st;
    io::write_text_file_atomic(checkpoint_path, checkpoint_to_string(ck));
  };

  const FitResult r = fit(*target, options, hooks, resume.get());
  if (r.stop == StopReason::kNonFinite) {
    // Nothing else is written: the trees and the report would describe a model that failed.
    const bool kept = resume || r.nonfinite_step > 1;
    throw InputError(fmt::format(
        "{}: the loss became NaN or infinite at step {} (is --lr or --init-range too large?); "
        "stopped, {}",
        target_path, r.nonfinite_step,
        kept ? fmt::format("{} keeps the parameters after step {}, the last with a finite loss",
                           checkpoint_path.string(), r.last_good_step)
             : std::string("no step had a finite loss, nothing written")));
  }

  // Everything is computed before anything is written; each file is written atomically.
  ReportContext ctx;
  ctx.target_path = target_path;
  ctx.target = target.get();
  ctx.command_line = job.command_line;
  ctx.threads = options.threads;
  const std::string report = fit_report_json(r, options, ctx);
  // The trees files, and the mesh, in the target's own coordinates (a mesh's); the pictures
  // and plots are drawn in the normalised box, as the training saw it.
  const Similarity to_target = target->normalisation().inverse();
  const Tree pruned_tree = transformed(r.pruned, to_target);
  const std::string trained = io::write_tree_string(transformed(r.trained, to_target));
  const std::string pruned = io::write_tree_string(pruned_tree);
  const std::string plot = loss_curve_png(
      r.state.curve, fmt::format("{} {} x{} - {}", fs::path(target_path).filename().string(),
                                 operator_mode_name(options.ops), options.prims, "training loss"));
  io::write_text_file_atomic(out / "tree.json", trained);
  io::write_text_file_atomic(out / "tree_pruned.json", pruned);
  io::write_text_file_atomic(out / "loss.png", plot);
  if (dim == 2) {
    constexpr int kRes = 256;
    std::vector<float> grid(static_cast<std::size_t>(kRes) * kRes * 2);
    for (int row = 0; row < kRes; ++row) {
      for (int col = 0; col < kRes; ++col) {
        const std::size_t i = static_cast<std::size_t>(row) * kRes + static_cast<std::size_t>(col);
        grid[2 * i] = static_cast<float>(-1.0 + (col + 0.5) * 2.0 / kRes);
        grid[2 * i + 1] = static_cast<float>(1.0 - (row + 0.5) * 2.0 / kRes);
      }
    }
    std::vector<float> occ(static_cast<std::size_t>(kRes) * kRes);
    target->occupancy(grid, occ);
    io::write_text_file_atomic(out / "target.png", occupancy_png(occ, kRes, kRes));
    io::write_text_file_atomic(
        out / "fit.png",
        occupancy_png(occupancy_grid_2d(r.pruned, kRes, options.threads), kRes, kRes));
  }
  if (dim == 3) {
    io::write_text_file_atomic(out / "slices.png",
                               slices_png(*target, r.pruned, 256, options.threads));
  }
  // The pruned tree's 0.5 level set (nothing when it is empty).
  MeshOptions mo;
  mo.threads = options.threads;
  std::string surface;
  if (dim == 3) {
    const TriangleMesh mesh = extract_mesh(pruned_tree, pruned_tree.params.values(), mo);
    if (!mesh.triangles.empty()) {
      write_mesh(mesh, out / "mesh.obj");
      surface = ", mesh.obj";
    }
  } else {
    const Contours contours = extract_contours(pruned_tree, pruned_tree.params.values(), mo);
    if (!contours.loops.empty()) {
      write_contours(contours, pruned_tree, out / "contours.svg");
      surface = ", contours.svg";
    }
  }
  // Pictures of the pruned tree: shaded views (3D), the occupancy plot and the primitives'
  // outlines over the result (2D). One that cannot be drawn (an empty result) is reported in
  // one line and does not fail the fit.
  std::string pictures;
  const auto picture = [&](const char* name, const auto& draw) {
    std::string bytes;
    try {
      bytes = draw();
    } catch (const Error& e) {  // InputError (an empty result) or a renderer's failure
      fmt::print(stderr, "fit: {} not written: {}\n", name, e.what());
      return;
    }
    io::write_text_file_atomic(out / name, bytes);
    pictures += std::string(", ") + name;
  };
  if (dim == 3) {
    picture("render.png", [&] {
      RenderOptions ro;
      ro.width = 400;
      ro.height = 300;
      ro.views = 3;
      ro.threads = options.threads;
      return render_png(r.pruned, r.pruned.params.values(), ro);
    });
  } else {
    picture("plot.png", [&] {
      PlotOptions po;
      po.threads = options.threads;
      return plot_2d(r.pruned, r.pruned.params.values(), po);
    });
    picture("outlines.svg", [&] {
      OutlineOptions oo;
      oo.threads = options.threads;
      return outlines_svg(r.pruned, r.pruned.params.values(), oo);
    });
  }
  io::write_text_file_atomic(out / "report.json", report);

  if (!job.quiet) {
    const TreeCounts before = count(r.trained), after = count(r.pruned);
    fmt::print("fit: {} steps in {} ({}), final loss {:.5f}\n", r.state.step,
               duration(r.train_seconds), stop_reason_name(r.stop),
               r.state.curve.empty() ? 0.0 : r.state.curve.back().loss);
    if (r.operators_total > 0) {
      fmt::print("fit: {} of {} operators changed type during training, {} structure bits\n",
                 r.operators_changed, r.operators_total, r.operators_restructured);
    }
    if (options.init == InitMode::kBalls) {
      fmt::print("fit: {} primitives started as balls inside the target\n", r.initialised_leaves);
    }
    if (options.reseed_every > 0) {
      fmt::print("fit: {} dead primitives re-seeded\n", r.reseeded);
    }
    if (options.type_search_every > 0) {
      fmt::print("fit: {} operator types switched by {} type searches\n", r.type_switches,
                 r.type_searches);
    }
    fmt::print("fit: pruned {}+{} -> {}+{} nodes (primitives+operators)\n", before.primitives,
               before.operators, after.primitives, after.operators);
    const auto line = [](const char* what, const std::optional<Metrics>& m) {
      if (!m) return;
      fmt::print("fit: {:<8} MSE {:.5f}  IoU {:.4f}{}{}\n", what, m->mse, m->iou,
                 m->chamfer ? fmt::format("  Chamfer {:.5f}", *m->chamfer) : "",
                 m->hausdorff ? fmt::format("  Hausdorff {:.5f}", *m->hausdorff) : "");
    };
    line("trained", r.metrics_trained);
    line("pruned", r.metrics_pruned);
    fmt::print("fit: wrote {}/{{tree.json, tree_pruned.json, report.json, loss.png{}{}{}}}\n",
               out.string(), dim == 2 ? ", target.png, fit.png" : ", slices.png", surface,
               pictures);
  }
  return 0;
}

Verb register_fit(CLI::App& app) {
  auto job = std::make_shared<FitJob>();
  auto o = std::make_shared<FitOptions>();
  CLI::App* cmd = app.add_subcommand(
      "fit", "Fit a CSG tree of fuzzy booleans to a mesh, a picture or a tree (inverse CSG)");
  cmd->add_option("target", job->target,
                  "Mesh (.obj .stl .ply .off), picture (.png .jpg .pbm .pgm) or tree (.json)")
      ->required();
  cmd->add_option("-o,--output", job->out_dir, "Output directory")->required();

  // Options that define the model: fixed by a checkpoint, so not accepted with --resume.
  std::vector<CLI::Option*> model;
  model.push_back(
      cmd->add_option("--prims", o->prims, "Primitives (a power of two)")->capture_default_str());
  model.push_back(cmd->add_option("--family", job->family,
                                  "Primitive family: quadric (default), sphere, box, cylinder, "
                                  "plane, circle, rectangle, ..., a comma list, or mix"));
  model.push_back(add_choice(cmd, "--ops", o->ops, kOperatorModeNames,
                             "Operators: unified B_c, or fixed random booleans with product or "
                             "Goedel logic"));
  model.push_back(add_choice(cmd, "--op-init", o->op_init, kOperatorInitNames,
                             "Unified operators' start: uniform (logits U[-r, r], as the paper: a "
                             "difference half of the time) or balanced (union, intersection, "
                             "difference a third each, as the fixed baselines)"));
  model.push_back(add_choice(
      cmd, "--op-types", o->op_types, kOperatorTypesNames,
      "Types a unified operator can take: all four of B_c, or union and intersection only "
      "(with quadric, conic or plane leaves these reach, with some leaves negated, what the "
      "four reach)"));
  model.push_back(cmd->add_option("--batch", o->batch, "Points per step")->capture_default_str());
  model.push_back(cmd->add_option("--pool", o->pool,
                                  "Points drawn at each resampling (0: the batch); steps cycle "
                                  "through them")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--lr", o->lr, "Adam learning rate")->capture_default_str());
  model.push_back(cmd->add_option("--beta1", o->beta1, "Adam beta1")->capture_default_str());
  model.push_back(cmd->add_option("--beta2", o->beta2, "Adam beta2")->capture_default_str());
  model.push_back(cmd->add_option("--resample-every", o->resample_every,
                                  "Steps between resamplings of the training points")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--temperature", o->temperature,
                                  "Softmax temperature t of the unified operators (final value)")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--temperature-start", o->temperature_start,
                                  "Temperature at step 0 when ramped")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--temperature-ramp", o->temperature_ramp,
                                  "Fraction of the steps over which t rises geometrically to "
                                  "--temperature (0: constant, as the authors' release)")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--omega", o->omega, "Frequency omega of sin(omega c)")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--init-range", o->init_range, "Initial parameters ~ U[-r, r]")
                      ->capture_default_str());
  model.push_back(add_choice(cmd, "--init", o->init, kInitModeNames,
                             "Start: random (U[-r, r], as the paper), balls (a union of balls "
                             "covering the target) or surface (random quadrics through target "
                             "surface points)"));
  model.push_back(cmd->add_option("--init-slope", o->init_slope,
                                  "--init balls|surface: slope of the occupancy across each "
                                  "leaf's surface (0: 20 for balls, 1 for surface)")
                      ->capture_default_str());
  model.push_back(add_choice(cmd, "--lr-schedule", o->lr_schedule, kLrScheduleNames,
                             "Learning rate: constant, or cosine from --lr down to "
                             "--lr * --lr-end"));
  model.push_back(cmd->add_option("--lr-end", o->lr_end,
                                  "Cosine schedule: final learning rate as a fraction of --lr")
                      ->capture_default_str());
  model.push_back(add_choice(cmd, "--sharpness-param", o->sharpness_param, kSharpnessParamNames,
                             "What Adam steps for each leaf's sharpness s: s (linear, as the "
                             "paper and its release) or log s (log: the occupancy sharpens "
                             "much faster)"));
  model.push_back(cmd->add_option("--reseed-every", o->reseed_every,
                                  "Steps between re-seedings of dead primitives (0: none)")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--reseed-until", o->reseed_until,
                                  "Re-seed during this fraction of the steps")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--type-search-every", o->type_search_every,
                                  "Steps between searches over the unified operators' types "
                                  "(0: none)")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--type-search-from", o->type_search_from,
                                  "Search operator types from this fraction of the steps")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--type-search-until", o->type_search_until,
                                  "Search operator types during this fraction of the steps")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--type-search-switches", o->type_search_switches,
                                  "Most operator types a round of a search switches together")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--type-search-points", o->type_search_points,
                                  "Points of each of a type search's two samples")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--seed", o->seed, "Random seed")
                      ->capture_default_str()
                      ->check(unsigned_number()));
  model.push_back(cmd->add_option("--surface", o->sampling.surface,
                                  "Fraction of training points on the surface")
                      ->capture_default_str());
  model.push_back(
      cmd->add_option("--near", o->sampling.near, "Fraction of training points near the surface")
          ->capture_default_str());
  model.push_back(cmd->add_option("--near-distance", o->sampling.near_distance,
                                  "Near points lie within this distance along the normal")
                      ->capture_default_str());
  model.push_back(add_choice(
      cmd, "--sampler", o->sampling.scheme, kSamplingSchemeNames,
      "Training points: appendix-a (Liu et al. App. A: --surface on the boundary, --near near "
      "it, the rest uniform) or release (pictures: the authors' release, a quarter uniform, the "
      "rest with density exp(1/(|d|/5 + 0.2)) at d pixels from the boundary)"));
  model.push_back(cmd->add_option("--prune-threshold", o->prune_threshold,
                                  "Mean squared occupancy change below which a node is redundant")
                      ->capture_default_str());
  model.push_back(cmd->add_option("--prune-max-primitives", o->prune_max_primitives,
                                  "Then keep at most this many primitives, removing those that "
                                  "change the output least (0: no limit)")
                      ->capture_default_str());
  model.push_back(
      cmd->add_option("--padding", job->padding, "Meshes: margin left around the normalised shape")
          ->capture_default_str());
  model.push_back(cmd->add_option("--image-resolution", job->image_resolution,
                                  "Pictures: resampled to this square size (0: native)")
                      ->capture_default_str());

  CLI::Option* iters =
      cmd->add_option("--iters", o->iters, "Optimisation steps")->capture_default_str();
  CLI::Option* time_limit = cmd->add_option("--time-limit", o->time_limit,
                                            "Stop training after this many seconds (0: none)")
                                ->capture_default_str();
  add_threads_option(cmd, o->threads);
  cmd->add_option("--checkpoint-every", job->checkpoint_every,
                  "Steps between checkpoints (OUTDIR/checkpoint.json; 0: none)")
      ->capture_default_str();
  cmd->add_option("--metric-points", o->metrics.points,
                  "Uniform points for the MSE and IoU after training")
      ->capture_default_str();
  cmd->add_flag("--no-metrics", job->no_metrics, "Skip measuring after training");
  cmd->add_flag("--resume", job->resume, "Continue from OUTDIR/checkpoint.json");
  cmd->add_flag("-q,--quiet", job->quiet, "No progress or summary");

  return {cmd, [cmd, job, o, model, iters, time_limit] {
            if (o->sampling.scheme == SamplingScheme::kRelease) {
              for (const char* flag : {"--surface", "--near", "--near-distance"}) {
                if (cmd->count(flag) > 0) {
                  throw InputError(fmt::format("{}: not used by --sampler release", flag));
                }
              }
            }
            job->options = *o;
            job->command_line = command_line();
            job->options.measure = !job->no_metrics;
            job->iters_given = iters->count() > 0;
            job->time_limit_given = time_limit->count() > 0;
            job->given_model_flags.clear();
            if (job->resume) {
              for (const CLI::Option* opt : model) {
                if (opt->count() > 0) job->given_model_flags.push_back(opt->get_name());
              }
            }
            return run_fit_job(*job);
          }};
}

}  // namespace fuzzycsg::app
