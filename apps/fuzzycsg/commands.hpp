#pragma once
// The verbs of the fuzzycsg program; one source file each.

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "fuzzycsg/convert/convert.hpp"
#include "fuzzycsg/fit/fit.hpp"
#include "support.hpp"

namespace fuzzycsg::app {

// Each register_* adds a subcommand to `app` and returns it with the action to run when it is
// chosen (after parsing; the action returns the exit status).
struct Verb {
  CLI::App* command = nullptr;
  std::function<int()> run;
};
Verb register_eval(CLI::App& app);
Verb register_info(CLI::App& app);
Verb register_demo(CLI::App& app);
Verb register_fit(CLI::App& app);
Verb register_prune(CLI::App& app);
Verb register_mesh(CLI::App& app);
Verb register_render(CLI::App& app);
Verb register_diagram(CLI::App& app);
Verb register_export(CLI::App& app);
Verb register_raster(CLI::App& app);
Verb register_refine(CLI::App& app);
Verb register_trace(CLI::App& app);
Verb register_morph(CLI::App& app);
Verb register_convert(CLI::App& app);
Verb register_batch(CLI::App& app);

// A fit as the fit verb runs it (the demo runs one too).
struct FitJob {
  std::string target, out_dir;
  FitOptions options;
  std::string family;  // --family as given ("" : quadric)
  double padding = 0.2;
  int image_resolution = 256;
  long checkpoint_every = 1000;
  bool resume = false, quiet = false, no_metrics = false;
  bool iters_given = false, time_limit_given = false;
  std::vector<std::string> given_model_flags;  // with --resume: model flags given (an error)
  std::string command_line;
};
int run_fit_job(const FitJob& job);

// A conversion as the convert verb runs it (the demo runs one too).
struct ConvertJob {
  std::string target, out_dir;
  convert::ConvertOptions options;
  bool quiet = false;
  // More files of the output set (name, bytes): the demo's part beside its conversion.
  std::vector<std::pair<std::string, std::string>> also_write;
};
int run_convert_job(const ConvertJob& job);

}  // namespace fuzzycsg::app
