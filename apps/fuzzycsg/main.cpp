// fuzzycsg: turn shapes into compact CSG trees and model with fuzzy booleans.
//
// Exit status: 0 success, 2 bad input (one line on stderr naming the file, the place and the
// field), 1 internal error.

#include <fmt/core.h>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "support.hpp"

int main(int argc, char** argv) {
  // --threads may ask for more threads than this machine has cores (up to kMaxThreads): oneTBB
  // then grants them, instead of warning on the terminal that the request is ignored.
  const tbb::global_control parallelism(
      tbb::global_control::max_allowed_parallelism,
      static_cast<std::size_t>(std::max(fuzzycsg::kMaxThreads, tbb::info::default_concurrency())));
  for (int i = 0; i < argc; ++i) {
    fuzzycsg::app::command_line() += (i ? " " : "") + std::string(argv[i]);
  }
  CLI::App app{"fuzzycsg: CSG trees with fuzzy booleans", "fuzzycsg"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "fuzzycsg 0.1.0");
  std::vector<fuzzycsg::app::Verb> verbs{
      fuzzycsg::app::register_eval(app),  fuzzycsg::app::register_info(app),
      fuzzycsg::app::register_demo(app),  fuzzycsg::app::register_fit(app),
      fuzzycsg::app::register_prune(app), fuzzycsg::app::register_mesh(app),
      fuzzycsg::app::register_render(app)};
  verbs.push_back(fuzzycsg::app::register_diagram(app));
  verbs.push_back(fuzzycsg::app::register_export(app));
  verbs.push_back(fuzzycsg::app::register_raster(app));
  verbs.push_back(fuzzycsg::app::register_refine(app));
  verbs.push_back(fuzzycsg::app::register_trace(app));
  verbs.push_back(fuzzycsg::app::register_morph(app));
  verbs.push_back(fuzzycsg::app::register_convert(app));
  verbs.push_back(fuzzycsg::app::register_batch(app));

  // A first word that names no verb is refused by name (CLI11 would only ask for a verb).
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const auto& verb : verbs) {
      known = known || verb.command->check_name(argv[1]);
      names += (names.empty() ? "" : ", ") + verb.command->get_name();
    }
    if (!known) {
      fmt::print(stderr, "fuzzycsg: error: {}: unknown verb (verbs: {})\n", argv[1], names);
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "fuzzycsg: error: {}\n", e.what());
    return 2;
  }

  try {
    for (const auto& verb : verbs) {
      if (verb.command->parsed()) return verb.run();
    }
  } catch (const fuzzycsg::OptionError& e) {
    // The library names its option fields; the user knows them as flags.
    fmt::print(stderr, "fuzzycsg: error: {}: {}\n", fuzzycsg::app::flag_for(e.field()),
               e.problem());
    return 2;
  } catch (const fuzzycsg::InputError& e) {
    fmt::print(stderr, "fuzzycsg: error: {}\n", e.what());
    return 2;
  } catch (const fuzzycsg::app::CommandError& e) {
    fmt::print(stderr, "fuzzycsg: error: {}\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "fuzzycsg: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "fuzzycsg: internal error: {}\n", e.what());
    return 1;
  }
  return 1;
}
