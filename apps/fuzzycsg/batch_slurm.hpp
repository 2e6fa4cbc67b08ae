#pragma once
// `fuzzycsg batch MANIFEST -o OUTDIR --slurm`: the jobs not yet done, and not queued or running
// in an earlier submission, as one Slurm job array whose task T runs `fuzzycsg batch MANIFEST
// -o OUTDIR --index OFFSET+T`. The sbatch script is OUTDIR/.slurm/batch.sbatch, usable by hand
// (sbatch --array=... batch.sbatch OFFSET); the tasks' own logs go to OUTDIR/.slurm/logs; each
// submission is recorded in OUTDIR/.slurm/submissions.jsonl, which is how a later run knows
// which tasks are still in Slurm's queue. A manifest longer than the cluster's MaxArraySize is
// submitted as several arrays with offsets.

#include <filesystem>
#include <string>
#include <vector>

#include "batch_manifest.hpp"

namespace fuzzycsg::app {

struct SlurmSubmission {
  int array_limit = 0;      // the array's %K: tasks at a time (0: as many as Slurm allows)
  std::string sbatch_args;  // more sbatch options, separated by spaces (partition, time, CPUs)
  bool quiet = false;
};

// Submits; returns the program's exit status (0, or 1 when sbatch failed).
int submit_slurm(const std::vector<BatchJob>& jobs, const std::filesystem::path& manifest,
                 const std::filesystem::path& out, const SlurmSubmission& s);

// The array spec of task ids, ranges joined: {0, 1, 2, 5, 7, 8} -> "0-2,5,7-8".
std::string array_spec(const std::vector<int>& tasks);

}  // namespace fuzzycsg::app
