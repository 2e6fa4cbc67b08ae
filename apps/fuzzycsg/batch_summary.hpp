#pragma once
// `fuzzycsg batch OUTDIR --summary`: every job of the batch (as OUTDIR/.batch/jobs.json records
// the manifest) with its status (done, failed, pending), time, IoU, Chamfer distance, primitives
// and error, written to OUTDIR/summary.csv and OUTDIR/summary.json with totals and the slowest
// and worst jobs, and a contact sheet of targets and results, OUTDIR/summary.png.

#include <filesystem>
#include <optional>
#include <string>

namespace fuzzycsg::app {

// The names the summary writes in OUTDIR (no job may take them).
inline constexpr const char* kSummaryFiles[] = {"summary.csv", "summary.json", "summary.png"};

// Writes the summary and prints its totals; the program's exit status (0).
int summarise_batch(const std::filesystem::path& out, bool quiet);

}  // namespace fuzzycsg::app
