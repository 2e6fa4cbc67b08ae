#pragma once
// The manifest of `fuzzycsg batch`: one job a line, as JSON lines,
//   {"id": "bracket-s1", "verb": "convert", "input": "parts/bracket.stl", "options": ["--seed",
//   "1"]}
// or, for a manifest named *.csv, CSV with a header naming the columns (id, verb, input and
// optionally options: the flags separated by blanks),
//   id,verb,input,options
//   bracket-s1,convert,parts/bracket.stl,--seed 1
// Relative input paths resolve against the manifest's folder. The whole manifest is checked
// before any job runs: ids (letters, digits, '.', '_', '-'; unique), verbs (convert, fit, trace,
// refine), inputs (existing files) and options (parsed by the verb's own command line) — an
// error is one line naming the manifest's line and field.

#include <filesystem>
#include <string>
#include <vector>

namespace fuzzycsg::app {

struct BatchJob {
  int line = 0;  // in the manifest, from 1
  std::string id, verb;
  std::filesystem::path input;       // resolved
  std::vector<std::string> options;  // the verb's flags, as given
};

// The verbs a manifest may name.
inline constexpr const char* kBatchVerbs[] = {"convert", "fit", "trace", "refine"};

// Reads and checks a manifest; InputError ("MANIFEST:LINE: FIELD: problem") on the first error.
std::vector<BatchJob> read_batch_manifest(const std::filesystem::path& manifest);

// The job's command line after the program's name: VERB INPUT -o OUT OPTIONS...
std::vector<std::string> batch_job_arguments(const BatchJob& job, const std::filesystem::path& out);

}  // namespace fuzzycsg::app
