#pragma once
// One job of `fuzzycsg batch`: the program itself run on one line of the manifest, its output in
// a temporary folder, OUTDIR/.tmp/HOST/ID.PID.K, renamed to OUTDIR/ID when the verb succeeded,
// so a job is done or absent. job.json in that folder records the command, the exit status, the
// time and the host; stdout.txt and stderr.txt are the verb's output. A job that failed leaves
// OUTDIR/.failed/ID (the same files) and is tried again by the next run.

#include <filesystem>
#include <string>
#include <vector>

#include "batch_manifest.hpp"

namespace fuzzycsg::app {

// kBusy: another batch on the same OUTDIR is running the job.
enum class Outcome { kDone, kSkipped, kBusy, kFailed };

struct Finished {
  Outcome outcome = Outcome::kDone;
  double seconds = 0;
  std::string status;  // "done", "done earlier", "exit 3", "signal 9"
};

// The job's folder when done, and where a failed attempt is kept.
std::filesystem::path done_dir(const std::filesystem::path& out, const BatchJob& job);
std::filesystem::path failed_dir(const std::filesystem::path& out, const BatchJob& job);

// Runs the job unless its folder exists. `threads`, when > 0 and the job's options name no
// --threads, is passed as the verb's --threads.
Finished run_job(const BatchJob& job, const std::filesystem::path& out, int threads);

// Signals that end a batch (SIGTERM from `scancel` or a scheduler's preemption, SIGINT, SIGHUP)
// are passed on to the job running in this process, which then ends as failed ("signal 15");
// with no job running, the process exits at once (128 + the signal). For a process that runs
// one job at a time (--index).
void forward_termination_signals();

// Removes this host's temporary folders of runs that are no longer alive.
void remove_stale(const std::filesystem::path& out);

// The last `lines` lines of a text, without its final newlines; of a text file ("" when it cannot
// be read).
std::string last_lines(std::string text, int lines);
std::string tail_of(const std::filesystem::path& file, int lines);

// A job's exit status as job.json records it, in words: "exit 3", or "signal 15" past 128.
std::string exit_status_text(int code);

// A program run to completion with its output captured.
struct Captured {
  int status = 0;  // the exit status, or 128 + the signal that ended it; 127: could not start
  std::string out, err;
};
// `program` found on PATH unless it has a '/'; `scratch` is a folder for the output files.
Captured run_captured(const std::string& program, const std::vector<std::string>& args,
                      const std::filesystem::path& scratch);

// The jobs of the manifest as recorded in OUTDIR/.batch/jobs.json (what --summary reads), and
// the recording itself (written atomically; the same content from every run of a manifest).
void record_jobs(const std::filesystem::path& out, const std::filesystem::path& manifest,
                 const std::vector<BatchJob>& jobs);

}  // namespace fuzzycsg::app
