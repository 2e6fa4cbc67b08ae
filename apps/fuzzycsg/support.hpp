#pragma once
// What every verb of the program shares: the command line as given, output directories, and
// the options spelled the same by every verb.

#include <CLI/CLI.hpp>

#include <filesystem>
#include <initializer_list>
#include <string>
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/limits.hpp"

namespace fuzzycsg::app {

// The program's command line, joined with spaces (recorded in reports).
std::string& command_line();

// Creates an output directory (after the inputs are known to be good) and checks that files
// can be written there; InputError naming it otherwise (also when a file is in the way).
void prepare_output_dir(const std::filesystem::path& dir);

// The flag that sets a library option field (OptionError::field): "--" and the field's last
// part with dashes ("type_search_every" -> "--type-search-every"), except where the program
// names it otherwise ("metrics.points" -> "--metric-points", "families" -> "--family").
std::string flag_for(const std::string& field);

// Whether the path's extension, lower-cased, is one of `exts` (each with its dot: ".csg").
bool has_extension(const std::string& path, std::initializer_list<const char*> exts);

// A program the verb runs (sbatch, squeue) is missing or failed: one line on stderr,
// `fuzzycsg: error: ...`, exit status 1 (not bad input, and not an internal error).
class CommandError : public Error {
 public:
  using Error::Error;
};

// Throws InputError when a path holds a control character (a newline, above all), which would
// end a line of a script or a record it is written into; the path is shown with them escaped.
void refuse_control_characters(const std::string& path, const std::string& what);

// A whole number >= 0 (a seed, a count): "-1" refused, where an unsigned option would otherwise
// take it as 2^64 - 1.
const CLI::Validator& unsigned_number();

// --threads N (0: all cores), checked against kMaxThreads.
CLI::Option* add_threads_option(CLI::App* cmd, int& threads, const std::string& help = "");

}  // namespace fuzzycsg::app
