#pragma once
// The verbs of the fuzzycsg program; one source file each.

#include <CLI/CLI.hpp>
#include <functional>

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

}  // namespace fuzzycsg::app
