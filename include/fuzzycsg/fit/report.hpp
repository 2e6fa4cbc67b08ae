#pragma once
// What a fit leaves on disk: the checkpoint it can resume from, and report.json.

#include <filesystem>
#include <string>
#include <string_view>

#include "fuzzycsg/fit/fit.hpp"

namespace fuzzycsg {

struct Checkpoint {
  std::string target;  // the target path as given
  int dim = 3;         // the target's dimension (resolves family names such as "quadric")
  FitOptions options;
  TrainState state;
};

// JSON text; numbers round-trip exactly, so a resumed run continues bit-identically.
std::string checkpoint_to_string(const Checkpoint& checkpoint);
// Throws InputError "FILE: FIELD: problem" on a missing, unreadable or malformed checkpoint.
Checkpoint read_checkpoint(const std::filesystem::path& path);

std::string_view operator_mode_name(OperatorMode m);  // "unified", "product", "godel"

// The settings of a fit as a JSON object text (the "settings" of report.json and checkpoints).
std::string fit_options_json(const FitOptions& options);

struct ReportContext {
  std::string target_path;
  const Target* target = nullptr;
  std::string command_line;
  int threads = 0;  // threads actually used
};

// report.json: every setting and the seed, the stop reason, the loss curve, metrics, timings,
// operator changes and node counts before and after pruning.
std::string fit_report_json(const FitResult& result, const FitOptions& options,
                            const ReportContext& context);

}  // namespace fuzzycsg
