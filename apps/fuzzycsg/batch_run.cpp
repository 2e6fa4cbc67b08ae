#include "batch_run.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "fuzzycsg/io/files.hpp"

namespace fuzzycsg::app {

namespace fs = std::filesystem;

namespace {

// The job this process runs when it runs one at a time (for forward_termination_signals).
std::atomic<pid_t> g_child{0};

std::string host_name() {
  char name[256] = {};
  gethostname(name, sizeof name - 1);
  return name[0] != 0 ? std::string(name) : std::string("localhost");
}

// Starts `path` (or the program found on PATH) with stdout and stderr to files; waits for it.
// The exit status, or 128 + the signal that ended it; 127 when it could not be started.
int spawn_and_wait(const std::string& program, const std::vector<std::string>& args,
                   const fs::path& out, const fs::path& err, bool dies_with_parent) {
  std::vector<std::string> argv_store{program};
  argv_store.insert(argv_store.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_store) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    if (dies_with_parent) {
      // The job dies with the batch: no orphan keeps running or writing after a kill -9.
      prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (getppid() != parent) _exit(127);
    }
    const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (o < 0 || e < 0 || dup2(o, 1) < 0 || dup2(e, 2) < 0) _exit(127);
    execvp(program.c_str(), argv.data());
    _exit(127);
  }
  if (dies_with_parent) g_child = pid;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error("waitpid failed");
  }
  if (dies_with_parent) g_child = 0;
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
  j["host"] = host_name();
  if (const char* id = std::getenv("SLURM_ARRAY_JOB_ID")) {
    j["slurm_job"] = fmt::format(
        "{}_{}", id,
        std::getenv("SLURM_ARRAY_TASK_ID") != nullptr ? std::getenv("SLURM_ARRAY_TASK_ID") : "");
  }
  return j.dump(2) + "\n";
}

bool names_threads(const std::vector<std::string>& options) {
  return std::any_of(options.begin(), options.end(), [](const std::string& o) {
    return o == "--threads" || o.starts_with("--threads=");
  });
}

fs::path tmp_root(const fs::path& out) { return out / ".tmp" / host_name(); }

}  // namespace

fs::path done_dir(const fs::path& out, const BatchJob& job) { return out / job.id; }
fs::path failed_dir(const fs::path& out, const BatchJob& job) { return out / ".failed" / job.id; }

namespace {

// An exclusive lock on one job of OUTDIR (flock on OUTDIR/.batch/locks/ID), held while this
// process runs it: a second batch on the same folder skips the job instead of running it again
// or racing on its folders. Released when the process ends, however it ends.
class JobLock {
 public:
  JobLock(const fs::path& out, const BatchJob& job) {
    const fs::path dir = out / ".batch" / "locks";
    std::error_code ec;
    fs::create_directories(dir, ec);
    fd_ = ::open((dir / job.id).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    held_ = fd_ >= 0 && ::flock(fd_, LOCK_EX | LOCK_NB) == 0;
  }
  ~JobLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  JobLock(const JobLock&) = delete;
  JobLock& operator=(const JobLock&) = delete;
  bool held() const { return held_; }

 private:
  int fd_ = -1;
  bool held_ = false;
};

Finished run_locked(const BatchJob& job, const fs::path& out, int threads) {
  static std::atomic<int> counter{0};
  const fs::path final_dir = done_dir(out, job);
  if (fs::exists(final_dir)) return {Outcome::kSkipped, 0, "done earlier"};
  const fs::path root = tmp_root(out);
  fs::create_directories(root);
  const std::string name = fmt::format("{}.{}.{}", job.id, getpid(), counter++);
  const fs::path tmp = root / name;
  const fs::path log_out = root / (name + ".stdout"), log_err = root / (name + ".stderr");
  std::vector<std::string> args = batch_job_arguments(job, tmp);
  if (threads > 0 && !names_threads(job.options)) {
    args.insert(args.end(), {"--threads", std::to_string(threads)});
  }
  const auto start = std::chrono::steady_clock::now();
  const int code =
      spawn_and_wait(fs::read_symlink("/proc/self/exe").string(), args, log_out, log_err, true);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto keep_logs = [&](const fs::path& dir) {
    fs::rename(log_out, dir / "stdout.txt");
    fs::rename(log_err, dir / "stderr.txt");
  };
  if (code == 0 && fs::is_directory(tmp)) {
    keep_logs(tmp);
    io::write_text_file_atomic(tmp / "job.json", job_json(job, "done", 0, seconds));
    std::error_code ec;
    fs::rename(tmp, final_dir, ec);
    if (ec) {  // another run finished it first
      fs::remove_all(tmp);
      return {Outcome::kSkipped, seconds, "done by another run"};
    }
    fs::remove_all(failed_dir(out, job));
    return {Outcome::kDone, seconds, "done"};
  }
  const fs::path failed = failed_dir(out, job);
  fs::remove_all(failed);
  fs::create_directories(failed);
  keep_logs(failed);
  io::write_text_file_atomic(failed / "job.json", job_json(job, "failed", code, seconds));
  fs::remove_all(tmp);
  return {Outcome::kFailed, seconds, exit_status_text(code)};
}

}  // namespace

Finished run_job(const BatchJob& job, const fs::path& out, int threads) {
  // A failure to record the job (a full disk, a folder in the way) fails the job, in words; it
  // never escapes the worker thread that runs it.
  try {
    const JobLock lock(out, job);
    if (!lock.held()) return {Outcome::kBusy, 0, "running in another batch"};
    return run_locked(job, out, threads);
  } catch (const std::exception& e) {
    return {Outcome::kFailed, 0, std::string("not recorded: ") + e.what()};
  }
}

void forward_termination_signals() {
  struct sigaction sa {};
  sa.sa_handler = [](int signal) {
    // With a job running, the job ends and is recorded as failed; without, the batch ends here
    // (before the job starts, or after it ended and before its folder was renamed: it is then
    // absent, and runs again).
    const pid_t child = g_child.load();
    if (child > 0) {
      kill(child, signal);
    } else {
      _exit(128 + signal);
    }
  };
  sigemptyset(&sa.sa_mask);
  for (const int s : {SIGTERM, SIGINT, SIGHUP}) sigaction(s, &sa, nullptr);
}

void remove_stale(const fs::path& out) {
  const fs::path root = tmp_root(out);
  std::error_code ec;
  if (!fs::is_directory(root, ec)) return;
  for (const auto& e : fs::directory_iterator(root)) {
    // ID.PID.K[.stdout|.stderr]: the PID is the second field from the end of the stem.
    std::string stem = e.path().filename().string();
    for (const std::string ext : {".stdout", ".stderr"}) {
      if (stem.ends_with(ext)) stem.resize(stem.size() - ext.size());
    }
    const auto k = stem.rfind('.');
    const auto p = k == std::string::npos || k == 0 ? std::string::npos : stem.rfind('.', k - 1);
    if (p == std::string::npos) continue;
    const pid_t pid = static_cast<pid_t>(std::atol(stem.substr(p + 1, k - p - 1).c_str()));
    if (pid > 0 && (kill(pid, 0) == 0 || errno != ESRCH)) continue;
    fs::remove_all(e.path(), ec);
  }
}

std::string exit_status_text(int code) {
  return code > 128 ? fmt::format("signal {}", code - 128) : fmt::format("exit {}", code);
}

std::string tail_of(const fs::path& file, int lines) {
  try {
    return last_lines(io::read_file(file), lines);
  } catch (const std::exception&) {
    return "";
  }
}

std::string last_lines(std::string text, int lines) {
  while (!text.empty() && text.back() == '\n') text.pop_back();
  // The start of the last `lines` lines: after the lines-th newline from the end, if any.
  std::size_t start = text.size();
  for (int k = 0; k < lines; ++k) {
    const std::size_t nl = start == 0 ? std::string::npos : text.rfind('\n', start - 1);
    if (nl == std::string::npos) return text;
    start = nl;
  }
  return text.substr(start + 1);
}

Captured run_captured(const std::string& program, const std::vector<std::string>& args,
                      const fs::path& scratch) {
  static std::atomic<int> counter{0};
  fs::create_directories(scratch);
  const std::string stem =
      fmt::format("{}.{}.{}", program.substr(program.rfind('/') + 1), getpid(), counter++);
  const fs::path o = scratch / (stem + ".stdout"), e = scratch / (stem + ".stderr");
  Captured c;
  c.status = spawn_and_wait(program, args, o, e, false);
  c.out = io::read_file(o);
  c.err = io::read_file(e);
  std::error_code ec;
  fs::remove(o, ec);
  fs::remove(e, ec);
  return c;
}

void record_jobs(const fs::path& out, const fs::path& manifest, const std::vector<BatchJob>& jobs) {
  nlohmann::ordered_json j;
  j["manifest"] = fs::absolute(manifest).lexically_normal().string();
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const BatchJob& job : jobs) {
    list.push_back({{"id", job.id},
                    {"verb", job.verb},
                    {"input", job.input.string()},
                    {"options", job.options},
                    {"manifest_line", job.line}});
  }
  j["jobs"] = list;
  const std::string text = j.dump(2) + "\n";
  const fs::path file = out / ".batch" / "jobs.json";
  fs::create_directories(file.parent_path());
  std::error_code ec;
  if (fs::exists(file, ec) && io::read_file(file) == text) return;
  io::write_text_file_atomic(file, text);
}

}  // namespace fuzzycsg::app
