#include "batch_slurm.hpp"

#include <fmt/format.h>
#include <pwd.h>
#include <unistd.h>

#include <algorithm>
#include <ctime>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "batch_run.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/files.hpp"
#include "support.hpp"

namespace fuzzycsg::app {

namespace fs = std::filesystem;

namespace {

// Slurm's default MaxArraySize, for a cluster whose configuration cannot be read.
constexpr int kDefaultMaxArraySize = 1001;

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (const char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

fs::path slurm_dir(const fs::path& out) { return out / ".slurm"; }

std::string sbatch_script(const fs::path& manifest, const fs::path& out) {
  // The manifest and OUTDIR were checked by the verb before anything was created.
  refuse_control_characters(fs::read_symlink("/proc/self/exe").string(), "the program");
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  const fs::path logs = slurm_dir(out) / "logs";
  return fmt::format(
      R"SH(#!/bin/bash
# One task of a fuzzycsg batch: manifest entry OFFSET + SLURM_ARRAY_TASK_ID (OFFSET is the
# script's argument, 0 when absent). `fuzzycsg batch MANIFEST -o OUTDIR --slurm` submits it; by
# hand, for entries 0 to 99, 16 at a time:
#   sbatch --array=0-99%16 --partition=P --time=1:00:00 --cpus-per-task=4 batch.sbatch 0
# The program, the manifest, its inputs and OUTDIR must be at the same paths on every node.
# A task's verb runs with --threads SLURM_CPUS_PER_TASK (unless its options name --threads).
#SBATCH --job-name=fuzzycsg-batch
#SBATCH --output={logs}/%A_%a.out
#SBATCH --error={logs}/%A_%a.err
set -eu
offset=${{1:-0}}
exec {program} batch {manifest} -o {out} --index "$((offset + SLURM_ARRAY_TASK_ID))"
)SH",
      fmt::arg("logs", logs.string()), fmt::arg("program", shell_quote(self)),
      fmt::arg("manifest", shell_quote(manifest.string())),
      fmt::arg("out", shell_quote(out.string())));
}

std::vector<std::string> split_words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// One of Slurm's commands, run to completion; Error when it is not on PATH.
Captured slurm_command(const std::string& program, const std::vector<std::string>& args,
                       const fs::path& out) {
  Captured c = run_captured(program, args, slurm_dir(out) / "scratch");
  if (c.status == 127 && c.err.empty()) {
    throw CommandError(fmt::format(
        "{}: not found on PATH (--slurm runs Slurm's sbatch, squeue and scontrol)", program));
  }
  return c;
}

// Manifest entries of earlier submissions still in Slurm's queue (pending or running).
std::set<int> queued_entries(const fs::path& out) {
  const fs::path record = slurm_dir(out) / "submissions.jsonl";
  std::map<std::string, int> offsets;  // Slurm job id -> offset
  std::error_code ec;
  if (!fs::exists(record, ec)) return {};
  std::istringstream in(io::read_file(record));
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    const auto j = nlohmann::json::parse(line, nullptr, false);
    if (!j.is_object() || !j.contains("job") || !j["job"].is_string() || !j.contains("offset") ||
        !j["offset"].is_number_integer()) {
      throw InputError(fmt::format("{}: a line that is not a submission record", record.string()));
    }
    offsets[j["job"].get<std::string>()] = j["offset"].get<int>();
  }
  const passwd* user = getpwuid(getuid());
  const Captured q = slurm_command(
      "squeue",
      {"-h", "-r", "-u", user != nullptr ? user->pw_name : std::to_string(getuid()), "-o", "%F %K"},
      out);
  if (q.status != 0) {
    throw CommandError(
        fmt::format("squeue failed (exit status {}): {}", q.status, last_lines(q.err, 1)));
  }
  std::set<int> queued;
  std::istringstream lines(q.out);
  for (std::string job, task; lines >> job >> task;) {
    const auto it = offsets.find(job);
    if (it == offsets.end()) continue;
    try {
      queued.insert(it->second + std::stoi(task));
    } catch (const std::exception&) {
      // Not an array task (%K is N/A): not one of ours.
    }
  }
  return queued;
}

int max_array_size(const fs::path& out) {
  const Captured c = slurm_command("scontrol", {"show", "config"}, out);
  std::istringstream in(c.out);
  for (std::string line; std::getline(in, line);) {
    if (!line.starts_with("MaxArraySize")) continue;
    const auto eq = line.find('=');
    if (eq != std::string::npos) {
      try {
        return std::max(1, std::stoi(line.substr(eq + 1)));
      } catch (const std::exception&) {
        break;
      }
    }
  }
  return kDefaultMaxArraySize;
}

// sbatch of one array; the Slurm job id.
std::string submit_array(const fs::path& out, const fs::path& script, const std::vector<int>& tasks,
                         int offset, const SlurmSubmission& s) {
  std::string spec = array_spec(tasks);
  if (s.array_limit > 0) spec += fmt::format("%{}", s.array_limit);
  std::vector<std::string> args{"--parsable", "--array=" + spec};
  for (const std::string& w : split_words(s.sbatch_args)) args.push_back(w);
  args.push_back(script.string());
  args.push_back(std::to_string(offset));
  const Captured c = slurm_command("sbatch", args, out);
  std::string id = c.out.substr(0, c.out.find_first_of(";\n"));
  if (c.status != 0 || id.empty()) {
    throw CommandError(fmt::format("sbatch failed (exit status {}): {}", c.status,
                                   last_lines(c.err.empty() ? c.out : c.err, 1)));
  }
  nlohmann::ordered_json record{{"job", id},
                                {"offset", offset},
                                {"array", spec},
                                {"tasks", tasks.size()},
                                {"submitted", static_cast<long long>(std::time(nullptr))}};
  const fs::path file = slurm_dir(out) / "submissions.jsonl";
  std::string text;
  std::error_code ec;
  if (fs::exists(file, ec)) text = io::read_file(file);
  io::write_text_file_atomic(file, text + record.dump() + "\n");
  return id;
}

}  // namespace

std::string array_spec(const std::vector<int>& tasks) {
  std::string spec;
  for (std::size_t i = 0; i < tasks.size();) {
    std::size_t j = i;
    while (j + 1 < tasks.size() && tasks[j + 1] == tasks[j] + 1) ++j;
    if (!spec.empty()) spec += ',';
    spec += j == i ? std::to_string(tasks[i]) : fmt::format("{}-{}", tasks[i], tasks[j]);
    i = j + 1;
  }
  return spec;
}

int submit_slurm(const std::vector<BatchJob>& jobs, const fs::path& manifest, const fs::path& out,
                 const SlurmSubmission& s) {
  for (const std::string& w : split_words(s.sbatch_args)) {
    if (w.starts_with("--array") || w == "-a" || w.starts_with("--output") ||
        w.starts_with("--error") || w == "-o" || w == "-e") {
      throw InputError(
          fmt::format("--sbatch-args: {}: the batch sets the array and the logs itself", w));
    }
  }
  const std::set<int> queued = queued_entries(out);
  std::vector<int> pending;
  int done = 0;
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const int k = static_cast<int>(i);
    if (fs::exists(done_dir(out, jobs[i]))) {
      ++done;
    } else if (!queued.contains(k)) {
      pending.push_back(k);
    }
  }
  const auto say = [&](const std::string& line) {
    if (!s.quiet) fmt::print("{}\n", line);
  };
  if (pending.empty()) {
    say(fmt::format("batch: nothing to submit: {} of {} jobs done, {} queued or running", done,
                    jobs.size(), queued.size()));
    return 0;
  }
  for (const int k : pending) {
    const BatchJob& job = jobs[static_cast<std::size_t>(k)];
    const fs::path failed = failed_dir(out, job);
    if (fs::exists(failed / "job.json")) {
      const auto j = nlohmann::json::parse(io::read_file(failed / "job.json"), nullptr, false);
      const std::string status =
          j.is_object() && j.contains("exit_status") && j["exit_status"].is_number_integer()
              ? exit_status_text(j["exit_status"].get<int>())
              : "failed";
      fmt::print(stderr, "batch: again: {} (manifest line {}) failed earlier ({}): {}\n", job.id,
                 job.line, status, tail_of(failed / "stderr.txt", 1));
    }
  }
  fs::create_directories(slurm_dir(out) / "logs");
  const fs::path script = slurm_dir(out) / "batch.sbatch";
  io::write_text_file_atomic(script, sbatch_script(fs::absolute(manifest).lexically_normal(),
                                                   fs::absolute(out).lexically_normal()));
  // Entries past the cluster's MaxArraySize go to further arrays, each task id below it.
  const int max_size = max_array_size(out);
  std::map<int, std::vector<int>> arrays;  // offset -> task ids
  for (const int k : pending) arrays[k / max_size * max_size].push_back(k % max_size);
  for (const auto& [offset, tasks] : arrays) {
    const std::string id = submit_array(out, script, tasks, offset, s);
    say(fmt::format("batch: submitted {} task{} as Slurm job {} (--array={}{}{})", tasks.size(),
                    tasks.size() == 1 ? "" : "s", id, array_spec(tasks),
                    s.array_limit > 0 ? fmt::format("%{}", s.array_limit) : "",
                    offset > 0 ? fmt::format(", entries from {}", offset) : ""));
  }
  say(fmt::format(
      "batch: {} of {} jobs done, {} queued or running earlier, {} submitted; logs in {}; "
      "`fuzzycsg batch {} --summary` reports",
      done, jobs.size(), queued.size(), pending.size(), (slurm_dir(out) / "logs").string(),
      out.string()));
  return 0;
}

}  // namespace fuzzycsg::app
