// fuzzycsg batch MANIFEST -o OUTDIR [--jobs N]      every job of the manifest, N at a time
// fuzzycsg batch MANIFEST -o OUTDIR --slurm          the jobs not done as one Slurm job array
// fuzzycsg batch MANIFEST -o OUTDIR --index I       job I alone (what a job array's task runs)
// fuzzycsg batch OUTDIR --summary                    summary.csv, summary.json, summary.png
//
// The manifest is batch_manifest.hpp's; a job runs as batch_run.hpp says (done or absent, failed
// attempts kept apart and tried again); Slurm submission is batch_slurm.hpp's and the summary
// batch_summary.hpp's.

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "batch_manifest.hpp"
#include "batch_run.hpp"
#include "batch_slurm.hpp"
#include "batch_summary.hpp"
#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "support.hpp"

namespace fuzzycsg::app {

namespace {

namespace fs = std::filesystem;

struct BatchArgs {
  std::string manifest, out;
  int jobs = 1;
  int index = -1;
  int threads = 0;
  bool slurm = false;
  SlurmSubmission submission;
  bool summary = false;
  bool quiet = false;
};

int env_int(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr ? std::max(0, std::atoi(v)) : 0;
}

// A job's threads when its options do not say: --threads, else the CPUs Slurm gave the task,
// else this machine's cores shared among the jobs running at once.
int threads_per_job(const BatchArgs& a) {
  if (a.threads > 0) return a.threads;
  if (const int c = env_int("SLURM_CPUS_PER_TASK"); c > 0) return c;
  if (const int c = env_int("SLURM_CPUS_ON_NODE"); c > 0 && a.index >= 0) return c;
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::max(1, cores / std::max(1, a.jobs));
}

// Every job not yet done, `jobs` at a time, with a progress line on a terminal.
int run_local(const std::vector<BatchJob>& all, const fs::path& out, const BatchArgs& a) {
  remove_stale(out);
  std::vector<const BatchJob*> pending;
  for (const BatchJob& j : all) {
    if (!fs::exists(done_dir(out, j))) pending.push_back(&j);
  }
  const int threads = threads_per_job(a);
  const bool tty = isatty(2) != 0 && !a.quiet;
  std::mutex mutex;
  std::atomic<std::size_t> next{0};
  int done = 0, failed = 0, running = 0, busy = 0;
  int elsewhere = 0;  // done by another batch on the same OUTDIR since this one began
  std::vector<const BatchJob*> failures;
  const auto start = std::chrono::steady_clock::now();
  const auto report = [&](const std::string& line) {  // under the mutex
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const int finished = done + failed + busy + elsewhere;
    const double eta = finished > 0 ? s / finished * (pending.size() - finished) : 0.0;
    if (tty) {
      fmt::print(stderr, "\rbatch: {}/{} done, {} running, {} failed, {:.0f} s, ETA {:.0f} s   ",
                 done, pending.size(), running, failed, s, eta);
      if (!line.empty()) fmt::print(stderr, "\n");
    }
    if (!line.empty() && !a.quiet) fmt::print(stderr, "{}\n", line);
  };
  const auto worker = [&] {
    for (std::size_t k; (k = next++) < pending.size();) {
      const BatchJob& job = *pending[k];
      {
        const std::lock_guard lock(mutex);
        ++running;
        report("");
      }
      const Finished f = run_job(job, out, threads);
      const std::lock_guard lock(mutex);
      --running;
      if (f.outcome == Outcome::kBusy) {
        ++busy;
        report(fmt::format("batch: {} {}", job.id, f.status));
      } else if (f.outcome == Outcome::kFailed) {
        ++failed;
        failures.push_back(&job);
        report(fmt::format("batch: {} failed ({}, {:.1f} s)", job.id, f.status, f.seconds));
      } else {
        ++(f.outcome == Outcome::kSkipped ? elsewhere : done);
        report(tty ? "" : fmt::format("batch: {} {} ({:.1f} s)", job.id, f.status, f.seconds));
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < std::min<int>(a.jobs, static_cast<int>(pending.size())); ++t) {
    pool.emplace_back(worker);
  }
  for (std::thread& t : pool) t.join();
  if (tty) fmt::print(stderr, "\n");
  for (const BatchJob* j : failures) {
    fmt::print(stderr, "batch: failed: {} (manifest line {}): {}\n", j->id, j->line,
               tail_of(failed_dir(out, *j) / "stderr.txt", 3));
  }
  if (!a.quiet) {
    fmt::print("batch: {} jobs: {} done now, {} done earlier, {}{} failed; {}\n", all.size(), done,
               all.size() - pending.size() + static_cast<std::size_t>(elsewhere),
               busy > 0 ? fmt::format("{} left to another batch running them, ", busy) : "", failed,
               out.string());
  }
  return failed > 0 ? 1 : 0;
}

void check_args(const BatchArgs& a, std::size_t jobs, const std::string& manifest) {
  if (a.jobs < 1 || a.jobs > kMaxThreads) {
    throw InputError(fmt::format("--jobs: must be in [1, {}]", kMaxThreads));
  }
  if (a.threads < 0 || a.threads > kMaxThreads) {
    throw InputError(fmt::format("--threads: must be in [0, {}]", kMaxThreads));
  }
  if (a.index >= static_cast<int>(jobs)) {
    throw InputError(
        fmt::format("--index: {} jobs in {}, so at most {}", jobs, manifest, jobs - 1));
  }
}

int run_batch(const BatchArgs& a) {
  if (a.summary) {
    if (!a.out.empty()) throw InputError("--summary: name the output directory alone, no -o");
    return summarise_batch(a.manifest, a.quiet);
  }
  if (a.out.empty()) throw InputError("-o,--output: required (the output directory)");
  if (!fs::is_regular_file(a.manifest)) {
    throw InputError(fmt::format("{}: no such manifest", a.manifest));
  }
  const std::vector<BatchJob> jobs = read_batch_manifest(a.manifest);
  check_args(a, jobs.size(), a.manifest);
  const fs::path out(a.out);
  // Both are written into the Slurm script and the job records.
  refuse_control_characters(a.out, "the output folder");
  refuse_control_characters(a.manifest, "the manifest");
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec || !fs::is_directory(out)) throw InputError(fmt::format("{}: cannot create", a.out));
  record_jobs(out, a.manifest, jobs);
  if (a.slurm) return submit_slurm(jobs, a.manifest, out, a.submission);
  if (a.index >= 0) {
    forward_termination_signals();  // scancel: the job ends as failed, its record kept
    remove_stale(out);
    const BatchJob& job = jobs[static_cast<std::size_t>(a.index)];
    const Finished f = run_job(job, out, threads_per_job(a));
    if (!a.quiet) fmt::print("batch: {}: {} ({:.1f} s)\n", job.id, f.status, f.seconds);
    if (f.outcome == Outcome::kFailed) {
      fmt::print(stderr, "batch: failed: {} (manifest line {}): {}\n", job.id, job.line,
                 tail_of(failed_dir(out, job) / "stderr.txt", 3));
      return 1;
    }
    return 0;
  }
  return run_local(jobs, out, a);
}

}  // namespace

Verb register_batch(CLI::App& app) {
  auto a = std::make_shared<BatchArgs>();
  CLI::App* cmd = app.add_subcommand(
      "batch",
      "Run the jobs of a manifest (JSON lines: id, verb, input, options) here, N at a time, or "
      "as a Slurm job array; or summarise an output directory");
  cmd->add_option("manifest", a->manifest,
                  "Manifest: one JSON object a line (with --summary: the output directory)")
      ->required();
  cmd->add_option("-o,--output", a->out, "Output directory: one folder per job");
  cmd->add_option("--jobs", a->jobs, "Jobs at a time on this machine")->capture_default_str();
  cmd->add_option("--threads", a->threads,
                  "Threads of each job whose options do not say (0: the CPUs of a Slurm task, "
                  "else this machine's cores / --jobs)")
      ->capture_default_str();
  CLI::Option* index =
      cmd->add_option("--index", a->index, "Run job I (from 0) alone: a job array's task")
          ->check(CLI::NonNegativeNumber);
  CLI::Option* slurm = cmd->add_flag(
      "--slurm", a->slurm, "Submit the jobs not done (nor queued) as one Slurm job array (sbatch)");
  cmd->add_option("--array-limit", a->submission.array_limit,
                  "With --slurm: tasks running at once (the array's %K; 0: no limit)")
      ->check(CLI::NonNegativeNumber)
      ->needs(slurm);
  cmd->add_option("--sbatch-args", a->submission.sbatch_args,
                  "With --slurm: more sbatch options, e.g. \"--partition=cpu --time=2:00:00 "
                  "--cpus-per-task=4\"")
      ->needs(slurm);
  CLI::Option* summary = cmd->add_flag(
      "--summary", a->summary,
      "Summarise OUTDIR (given in place of the manifest): summary.csv, summary.json, summary.png");
  slurm->excludes(index)->excludes(summary);
  index->excludes(summary);
  cmd->add_flag("-q,--quiet", a->quiet, "No progress or summary lines");
  return {cmd, [a] {
            a->submission.quiet = a->quiet;
            return run_batch(*a);
          }};
}

}  // namespace fuzzycsg::app
