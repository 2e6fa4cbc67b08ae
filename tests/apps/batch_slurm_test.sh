#!/usr/bin/env bash
# The batch verb against a real Slurm: a single-node cluster on this machine (slurm_cluster.sh)
# with MaxArraySize 5, so that a manifest of 8 fits goes as two arrays (entries 0-4, then 5-7
# with an offset). A resubmission while they are queued submits nothing; one running task is
# cancelled (scancel) and ends as failed with its record kept; the next resubmission runs it
# alone, and the set completes with every job run to completion exactly once. A bad manifest is
# refused before anything is submitted. Exit 77 (skipped) without slurm-wlm and munge or root.
# Usage: batch_slurm_test.sh PATH/TO/fuzzycsg SOURCE_DIR
set -u
bin=$1
src=$2
source "$(dirname "$0")/lib.sh"
source "$(dirname "$0")/slurm_cluster.sh"

if [[ $(id -u) -ne 0 ]]; then
  echo "skipped: a test cluster's daemons run as root"
  exit 77
fi
export SLURM_EXTRA_CONF=MaxArraySize=5
if ! slurm_start "$tmp/slurm" 2>"$tmp/start.err"; then
  cat "$tmp/start.err"
  grep -q "not found" "$tmp/start.err" && exit 77
  exit 1
fi
trap 'slurm_stop; rm -rf "$tmp"' EXIT

# Waits (bounded) until none of this user's jobs is queued or running.
wait_idle() {
  for _ in $(seq 600); do
    [[ -z $(squeue -h -u "$(id -un)" -o %i 2>/dev/null) ]] && return 0
    sleep 0.5
  done
  return 1
}

mkdir -p "$tmp/parts"
cat >"$tmp/parts/disc.json" <<'JSON'
{"format": "fuzzycsg-tree", "version": 1, "dim": 2,
 "root": {"type": "circle", "radius": 0.5, "translate": [0.1, 0.0]}}
JSON
for ((i = 0; i < 8; i++)); do
  printf '{"id": "disc-s%d", "verb": "fit", "input": "parts/disc.json", "options": ["--prims", "4", "--iters", "3000", "--seed", "%d", "-q", "--metric-points", "20000"]}\n' "$i" "$i"
done >"$tmp/m.jsonl"
out=$tmp/runs

# The submission: two arrays (MaxArraySize 5), two tasks of each at a time.
if "$bin" batch "$tmp/m.jsonl" -o "$out" --slurm --array-limit 2 >"$tmp/s1.out" 2>&1 &&
    grep -q "submitted 5 tasks as Slurm job [0-9]* (--array=0-4%2)" "$tmp/s1.out" &&
    grep -q "submitted 3 tasks as Slurm job [0-9]* (--array=0-2%2, entries from 5)" "$tmp/s1.out" &&
    grep -q '^#SBATCH --output=.*/.slurm/logs/%A_%a.out' "$out/.slurm/batch.sbatch"; then ok
else bad "--slurm: $(cat "$tmp/s1.out")"; fi

# Submitted again while queued: nothing (every job is done, queued or running).
if "$bin" batch "$tmp/m.jsonl" -o "$out" --slurm >"$tmp/s2.out" 2>&1 &&
    grep -q "nothing to submit: [0-9] of 8 jobs done" "$tmp/s2.out"; then ok
else bad "a second submission while queued: $(cat "$tmp/s2.out")"; fi

# Cancel a task that runs (its fit has started: its temporary folder exists).
cancelled=
for _ in $(seq 300); do
  read -r job task < <(squeue -h -r -u "$(id -un)" -t R -o "%F %K" | head -n 1)
  if [[ -n ${task-} ]] && compgen -G "$out/.tmp/*/disc-s*" >/dev/null; then
    # The entry: the task id plus the array's offset (recorded for each submission).
    offset=$(python3 -c "import json,sys
for l in open(sys.argv[1]):
    r = json.loads(l)
    if r['job'] == sys.argv[2]: print(r['offset'])" "$out/.slurm/submissions.jsonl" "$job")
    cancelled=disc-s$((offset + task))
    scancel "${job}_${task}"
    break
  fi
  sleep 0.2
done
if [[ -n $cancelled ]] && wait_idle; then ok; else bad "no running task to cancel, or the arrays never ended"; fi

# The cancelled job is not done; its attempt is kept with the signal; the others are done.
if [[ ! -e $out/$cancelled && -f $out/.failed/$cancelled/job.json ]] &&
    python3 - "$out" "$cancelled" <<'PY'
import json, os, sys
out, cancelled = sys.argv[1], sys.argv[2]
failed = json.load(open(os.path.join(out, ".failed", cancelled, "job.json")))
assert failed["status"] == "failed" and failed["exit_status"] == 128 + 15, failed
done = sorted(d for d in os.listdir(out) if not d.startswith("."))
assert done == sorted(f"disc-s{i}" for i in range(8) if f"disc-s{i}" != cancelled), done
PY
then ok; else bad "after scancel of $cancelled: $(ls -a "$out")"; fi

# Resubmitted: only the cancelled job, named with its failure.
if "$bin" batch "$tmp/m.jsonl" -o "$out" --slurm --array-limit 2 >"$tmp/s3.out" 2>"$tmp/s3.err" &&
    grep -q "submitted 1 task as Slurm job" "$tmp/s3.out" &&
    grep -q "again: $cancelled (manifest line [0-9]*) failed earlier (signal 15)" "$tmp/s3.err" &&
    wait_idle; then ok
else bad "resubmission: $(cat "$tmp/s3.out" "$tmp/s3.err")"; fi

# The set is complete; every job ran to completion once (one "done" line in all the tasks'
# logs), its record names the task that ran it; nothing is left in the temporary folders.
if python3 - "$out" <<'PY'
import glob, json, os, re, sys
out = sys.argv[1]
ids = sorted(d for d in os.listdir(out) if not d.startswith("."))
assert ids == [f"disc-s{i}" for i in range(8)], ids
logs = "".join(open(f).read() for f in glob.glob(os.path.join(out, ".slurm/logs/*.out")))
for i in ids:
    assert len(re.findall(rf"^batch: {i}: done \(", logs, re.M)) == 1, (i, logs)
    job = json.load(open(os.path.join(out, i, "job.json")))
    assert job["status"] == "done" and re.fullmatch(r"\d+_\d+", job["slurm_job"]), job
    assert json.load(open(os.path.join(out, i, "report.json")))["stop"] == "iterations"
assert not os.path.exists(os.path.join(out, ".failed")) or os.listdir(os.path.join(out, ".failed")) == []
assert all(os.listdir(d) == [] for d in glob.glob(os.path.join(out, ".tmp/*")))
PY
then ok; else bad "the completed set"; fi

# Everything done: a further submission submits nothing; the summary lists 8 done jobs.
if "$bin" batch "$tmp/m.jsonl" -o "$out" --slurm | grep -q "nothing to submit: 8 of 8 jobs done" &&
    "$bin" batch "$out" --summary -q && [[ $(grep -c ',done,' "$out/summary.csv") -eq 8 ]]; then ok
else bad "after completion"; fi

# A bad manifest is refused before anything is submitted.
printf '%s\n' '{"id": "a", "verb": "fit", "input": "parts/disc.json"}' \
  '{"id": "a", "verb": "fit", "input": "parts/disc.json"}' >"$tmp/dup.jsonl"
expect_error 'dup.jsonl:2: id: .a. is used by an earlier line' \
  "$bin" batch "$tmp/dup.jsonl" -o "$tmp/never" --slurm
if [[ ! -e $tmp/never && -z $(squeue -h -u "$(id -un)" -o %i) ]]; then ok
else bad "a refused manifest submitted or wrote something"; fi
expect_error '--sbatch-args: --array=0-3: the batch sets the array' \
  "$bin" batch "$tmp/m.jsonl" -o "$out" --slurm --sbatch-args "--array=0-3"

echo "batch on Slurm: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
