// fuzzycsg batch MANIFEST -o OUTDIR [--jobs N]      every job of the manifest, N at a time
// fuzzycsg batch MANIFEST -o OUTDIR --index I       job I alone (what a job array's task runs)
//
// Each job is the program itself run on one line of the manifest (batch_manifest.hpp) with its
// output in a temporary folder, OUTDIR/.tmp/ID.PID.K, renamed to OUTDIR/ID when the verb
// succeeded: a job is done or absent. job.json in that folder records the command, the exit
// status and the time; stdout.txt and stderr.txt are the verb's output. A job that failed leaves
// OUTDIR/.failed/ID (the same files) and is tried again by the next run; a job already done is
// skipped. A job's process dies with the batch (a batch killed with kill -9 leaves only
// temporary folders, which the next run removes).

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "batch_manifest.hpp"
#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/files.hpp"

namespace fuzzycsg::app {

namespace {

namespace fs = std::filesystem;

struct BatchArgs {
  std::string manifest, out;
  int jobs = 1;
  int index = -1;
  bool quiet = false;
};

enum class Outcome { kDone, kSkipped, kFailed };

struct Finished {
  Outcome outcome = Outcome::kDone;
  double seconds = 0;
  std::string status;  // "exit 3", "signal 9"
};

// Runs `args` (after the program's name) with stdout and stderr to files; the exit status, or
// 128 + the signal that ended it.
int run_child(const std::vector<std::string>& args, const fs::path& out, const fs::path& err) {
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  std::vector<std::string> argv_store{self};
  argv_store.insert(argv_store.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_store) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    // The job dies with the batch: no orphan keeps running or writing after a kill -9.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);
    const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (o < 0 || e < 0 || dup2(o, 1) < 0 || dup2(e, 2) < 0) _exit(127);
    execv(self.c_str(), argv.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error("waitpid failed");
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string job_json(const BatchJob& job, const std::string& status, int code, double seconds) {
  nlohmann::ordered_json j;
  j["id"] = job.id;
  j["verb"] = job.verb;
  j["input"] = job.input.string();
  j["options"] = job.options;
  j["manifest_line"] = job.line;
  j["status"] = status;
  j["exit_status"] = code;
  j["seconds"] = seconds;
  j["host"] = [] {
    char name[256] = {};
    gethostname(name, sizeof name - 1);
    return std::string(name);
  }();
  return j.dump(2) + "\n";
}

// Moves the job's logs beside its outputs.
void move_logs(const fs::path& from_out, const fs::path& from_err, const fs::path& dir) {
  fs::rename(from_out, dir / "stdout.txt");
  fs::rename(from_err, dir / "stderr.txt");
}

// One job: skipped when OUTDIR/ID exists, otherwise run into a temporary folder and renamed.
Finished run_job(const BatchJob& job, const fs::path& out) {
  static std::atomic<int> counter{0};
  const fs::path final_dir = out / job.id;
  if (fs::exists(final_dir)) return {Outcome::kSkipped, 0, "done earlier"};
  const fs::path tmp_root = out / ".tmp";
  fs::create_directories(tmp_root);
  const std::string name = fmt::format("{}.{}.{}", job.id, getpid(), counter++);
  const fs::path tmp = tmp_root / name;
  const fs::path log_out = tmp_root / (name + ".stdout"), log_err = tmp_root / (name + ".stderr");
  const auto start = std::chrono::steady_clock::now();
  const int code = run_child(batch_job_arguments(job, tmp), log_out, log_err);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (code == 0 && fs::is_directory(tmp)) {
    move_logs(log_out, log_err, tmp);
    io::write_text_file_atomic(tmp / "job.json", job_json(job, "done", 0, seconds));
    std::error_code ec;
    fs::rename(tmp, final_dir, ec);
    if (ec) fs::remove_all(tmp);  // another run finished it first
    fs::remove_all(out / ".failed" / job.id);
    return {Outcome::kDone, seconds, "done"};
  }
  const fs::path failed = out / ".failed" / job.id;
  fs::remove_all(failed);
  fs::create_directories(failed);
  move_logs(log_out, log_err, failed);
  const std::string status =
      code > 128 ? fmt::format("signal {}", code - 128) : fmt::format("exit {}", code);
  io::write_text_file_atomic(failed / "job.json", job_json(job, "failed", code, seconds));
  fs::remove_all(tmp);
  return {Outcome::kFailed, seconds, status};
}

// Temporary folders of runs that are no longer alive (a batch killed, a machine lost).
void remove_stale(const fs::path& out) {
  const fs::path tmp_root = out / ".tmp";
  std::error_code ec;
  if (!fs::is_directory(tmp_root, ec)) return;
  for (const auto& e : fs::directory_iterator(tmp_root)) {
    const std::string n = e.path().filename().string();
    // ID.PID.K[.stdout|.stderr]: the PID is the second field from the end of the stem.
    std::string stem = n;
    for (const char* ext : {".stdout", ".stderr"}) {
      if (stem.ends_with(ext)) stem.resize(stem.size() - std::string(ext).size());
    }
    const auto k = stem.rfind('.');
    const auto p = k == std::string::npos ? std::string::npos : stem.rfind('.', k - 1);
    if (p == std::string::npos) continue;
    const pid_t pid = static_cast<pid_t>(std::atol(stem.substr(p + 1, k - p - 1).c_str()));
    if (pid > 0 && (kill(pid, 0) == 0 || errno != ESRCH)) continue;
    fs::remove_all(e.path(), ec);
  }
}

std::string tail_of(const fs::path& file, int lines) {
  std::string text = io::read_file(file);
  while (!text.empty() && text.back() == '\n') text.pop_back();
  std::size_t pos = text.size();
  for (int k = 0; k < lines && pos != std::string::npos && pos > 0; ++k) {
    pos = text.rfind('\n', pos - 1);
  }
  return pos == std::string::npos ? text : text.substr(pos + 1);
}

// Every job not yet done, `jobs` at a time, with a progress line on a terminal.
int run_local(const std::vector<BatchJob>& all, const fs::path& out, int jobs, bool quiet) {
  remove_stale(out);
  std::vector<const BatchJob*> pending;
  for (const BatchJob& j : all) {
    if (!fs::exists(out / j.id)) pending.push_back(&j);
  }
  const bool tty = isatty(2) != 0 && !quiet;
  std::mutex mutex;
  std::atomic<std::size_t> next{0};
  int done = 0, failed = 0, running = 0;
  std::vector<const BatchJob*> failures;
  const auto start = std::chrono::steady_clock::now();
  const auto report = [&](const std::string& line) {  // under the mutex
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const int finished = done + failed;
    const double eta = finished > 0 ? s / finished * (pending.size() - finished) / 1.0 : 0.0;
    if (tty) {
      fmt::print(stderr, "\rbatch: {}/{} done, {} running, {} failed, {:.0f} s, ETA {:.0f} s   ",
                 done, pending.size(), running, failed, s, eta);
      if (!line.empty()) fmt::print(stderr, "\n");
    }
    if (!line.empty() && !quiet) fmt::print(stderr, "{}\n", line);
  };
  const auto worker = [&] {
    for (std::size_t k; (k = next++) < pending.size();) {
      const BatchJob& job = *pending[k];
      {
        const std::lock_guard lock(mutex);
        ++running;
        report("");
      }
      const Finished f = run_job(job, out);
      const std::lock_guard lock(mutex);
      --running;
      if (f.outcome == Outcome::kFailed) {
        ++failed;
        failures.push_back(&job);
        report(fmt::format("batch: {} failed ({}, {:.1f} s)", job.id, f.status, f.seconds));
      } else {
        ++done;
        report(tty ? "" : fmt::format("batch: {} done ({:.1f} s)", job.id, f.seconds));
      }
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < std::min<int>(jobs, static_cast<int>(pending.size())); ++t) {
    threads.emplace_back(worker);
  }
  for (std::thread& t : threads) t.join();
  if (tty) fmt::print(stderr, "\n");
  for (const BatchJob* j : failures) {
    fmt::print(stderr, "batch: failed: {} (manifest line {}): {}\n", j->id, j->line,
               tail_of(out / ".failed" / j->id / "stderr.txt", 3));
  }
  if (!quiet) {
    fmt::print("batch: {} jobs: {} done now, {} done earlier, {} failed; {}\n", all.size(), done,
               all.size() - pending.size(), failed, out.string());
  }
  return failed > 0 ? 1 : 0;
}

int run_batch(const BatchArgs& a) {
  const std::vector<BatchJob> jobs = read_batch_manifest(a.manifest);
  if (a.jobs < 1 || a.jobs > kMaxThreads) {
    throw InputError(fmt::format("--jobs: must be in [1, {}]", kMaxThreads));
  }
  if (a.index >= static_cast<int>(jobs.size())) {
    throw InputError(fmt::format("--index: {} jobs in {}, so at most {}", jobs.size(), a.manifest,
                                 jobs.size() - 1));
  }
  const fs::path out(a.out);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec || !fs::is_directory(out)) throw InputError(fmt::format("{}: cannot create", a.out));
  if (a.index >= 0) {
    const Finished f = run_job(jobs[static_cast<std::size_t>(a.index)], out);
    if (!a.quiet) {
      fmt::print("batch: {}: {}\n", jobs[static_cast<std::size_t>(a.index)].id, f.status);
    }
    return f.outcome == Outcome::kFailed ? 1 : 0;
  }
  return run_local(jobs, out, a.jobs, a.quiet);
}

}  // namespace

Verb register_batch(CLI::App& app) {
  auto a = std::make_shared<BatchArgs>();
  CLI::App* cmd = app.add_subcommand(
      "batch", "Run the jobs of a manifest (JSON lines: id, verb, input, options), N at a time");
  cmd->add_option("manifest", a->manifest, "Manifest: one JSON object a line")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", a->out, "Output directory: one folder per job")->required();
  cmd->add_option("--jobs", a->jobs, "Jobs at a time")->capture_default_str();
  cmd->add_option("--index", a->index, "Run job I (from 0) alone: a job array's task")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("-q,--quiet", a->quiet, "No progress or summary lines");
  return {cmd, [a] { return run_batch(*a); }};
}

}  // namespace fuzzycsg::app
