#!/usr/bin/env bash
# The batch verb on this machine: a manifest of small fits run two at a time, each job done or
# absent, a rerun that skips what is done, a batch killed with kill -9 and run again that
# completes the set with every job run to completion once, failed jobs kept apart and retried,
# and bad manifests refused with one line naming the manifest's line before anything runs.
# Usage: batch_cli_test.sh PATH/TO/fuzzycsg SOURCE_DIR
set -u
bin=$1
src=$2
source "$(dirname "$0")/lib.sh"

mkdir -p "$tmp/parts"
cat >"$tmp/parts/disc.json" <<'JSON'
{"format": "fuzzycsg-tree", "version": 1, "dim": 2,
 "root": {"type": "circle", "radius": 0.5, "translate": [0.1, 0.0]}}
JSON
# manifest N ITERS: N fits of the disc (relative input paths: against the manifest's folder).
manifest() {
  for ((i = 0; i < $1; i++)); do
    printf '{"id": "disc-s%d", "verb": "fit", "input": "parts/disc.json", "options": ["--prims", "4", "--iters", "%d", "--seed", "%d", "--threads", "1", "-q", "--metric-points", "20000"]}\n' \
      "$i" "$2" "$i"
  done
}
manifest 8 200 >"$tmp/m.jsonl"

# All eight, two at a time; each folder is the fit's output with job.json beside it.
if "$bin" batch "$tmp/m.jsonl" -o "$tmp/runs" --jobs 2 >"$tmp/b1.out" 2>"$tmp/b1.err" &&
    python3 - "$tmp/runs" <<'PY'
import glob, json, os, sys
out = sys.argv[1]
ids = sorted(d for d in os.listdir(out) if not d.startswith("."))
assert ids == [f"disc-s{i}" for i in range(8)], ids
for i in ids:
    job = json.load(open(os.path.join(out, i, "job.json")))
    assert job["status"] == "done" and job["exit_status"] == 0 and job["id"] == i, job
    assert os.path.isabs(job["input"]) and job["input"].endswith("parts/disc.json"), job
    assert os.path.getsize(os.path.join(out, i, "tree.json")) > 0
    assert json.load(open(os.path.join(out, i, "report.json")))["seed"] == int(i[6:])
assert not os.path.exists(os.path.join(out, ".failed"))
assert all(os.listdir(d) == [] for d in glob.glob(os.path.join(out, ".tmp", "*")))
PY
then ok; else bad "batch --jobs 2: $(tail -3 "$tmp/b1.err")"; fi

# A rerun skips what is done: nothing is rewritten.
stamp=$(stat -c %Y.%N "$tmp/runs/disc-s3/job.json")
if "$bin" batch "$tmp/m.jsonl" -o "$tmp/runs" --jobs 2 >"$tmp/b2.out" 2>&1 &&
    grep -q "0 done now, 8 done earlier, 0 failed" "$tmp/b2.out" &&
    [[ $(stat -c %Y.%N "$tmp/runs/disc-s3/job.json") == "$stamp" ]]; then ok
else bad "rerun: $(cat "$tmp/b2.out")"; fi

# --index I runs job I alone (a job array's task): done once, then skipped.
if "$bin" batch "$tmp/m.jsonl" -o "$tmp/one" --index 5 -q && [[ -f "$tmp/one/disc-s5/job.json" ]] &&
    [[ $(ls "$tmp/one") == "disc-s5" ]] &&
    "$bin" batch "$tmp/m.jsonl" -o "$tmp/one" --index 5 | grep -q "disc-s5: done earlier"; then ok
else bad "--index"; fi

# kill -9 of the batch while jobs run: no job folder is half written, and a rerun completes the
# set; every job ran to completion exactly once (its report's start time is unique).
manifest 8 4000 >"$tmp/long.jsonl"
"$bin" batch "$tmp/long.jsonl" -o "$tmp/killed" --jobs 2 -q >/dev/null 2>&1 &
batch=$!
for _ in $(seq 600); do
  [[ -n $(ls "$tmp/killed" 2>/dev/null | grep -v '^\.') ]] && break
  sleep 0.1
done
kill -9 "$batch"
wait "$batch" 2>/dev/null
sleep 0.3
first=$(ls "$tmp/killed" | grep -cv '^\.')
if [[ $first -ge 1 && $first -lt 8 ]] && ! pgrep -f "killed/.tmp" >/dev/null; then ok
else bad "kill -9: $first jobs done (expected some, not all), or orphaned jobs still running"; fi
if "$bin" batch "$tmp/long.jsonl" -o "$tmp/killed" --jobs 2 -q &&
    python3 - "$tmp/killed" "$first" <<'PY'
import glob, json, os, sys
out, first = sys.argv[1], int(sys.argv[2])
ids = sorted(d for d in os.listdir(out) if not d.startswith("."))
assert len(ids) == 8, ids
for i in ids:
    assert json.load(open(os.path.join(out, i, "job.json")))["status"] == "done"
    assert json.load(open(os.path.join(out, i, "report.json")))["stop"] == "iterations"
assert all(os.listdir(d) == [] for d in glob.glob(os.path.join(out, ".tmp", "*")))
PY
then ok; else bad "rerun after kill -9"; fi

# Two batches on one OUTDIR at once: each job runs once (the other batch skips it while it runs),
# neither aborts, and every job ends done with its records whole.
manifest 6 600 >"$tmp/two.jsonl"
"$bin" batch "$tmp/two.jsonl" -o "$tmp/two" --jobs 2 >"$tmp/two1.out" 2>"$tmp/two1.err" &
first_batch=$!
"$bin" batch "$tmp/two.jsonl" -o "$tmp/two" --jobs 2 >"$tmp/two2.out" 2>"$tmp/two2.err"
rc2=$?
wait "$first_batch"
rc1=$?
if [[ $rc1 -eq 0 && $rc2 -eq 0 ]] && python3 - "$tmp/two" "$tmp/two1.out" "$tmp/two2.out" <<'PY'
import json, os, re, sys
out = sys.argv[1]
ids = sorted(d for d in os.listdir(out) if not d.startswith("."))
assert ids == [f"disc-s{i}" for i in range(6)], ids
for i in ids:
    assert json.load(open(os.path.join(out, i, "job.json")))["status"] == "done"
assert not os.path.exists(os.path.join(out, ".failed"))
now = [int(re.search(r"(\d+) done now", open(f).read()).group(1)) for f in sys.argv[2:]]
assert sum(now) == 6, now
PY
then ok; else bad "two batches on one OUTDIR (exit $rc1, $rc2): $(cat "$tmp/two1.err" "$tmp/two2.err")"; fi
# A newline in OUTDIR would be a command in the Slurm script: refused, nothing created.
expect_error "control character" "$bin" batch "$tmp/m.jsonl" -o "$tmp/new
line" --slurm
[[ -e "$tmp/new
line" ]] && bad "a refused OUTDIR was created" || ok

# A job that fails is kept apart with its stderr, named at the end, and tried again.
printf '{"format": "fuzzycsg-tree", "version": 1, "dim": 2, "root": {"type": "circle", "radius": 0.5}}\n' \
  >"$tmp/parts/late.json"
printf '%s\n' '{"id": "ok", "verb": "fit", "input": "parts/disc.json", "options": ["--prims", "4", "--iters", "50", "-q"]}' \
  '{"id": "bad", "verb": "fit", "input": "parts/late.json", "options": ["--prims", "4", "--iters", "50", "-q", "--init", "balls", "--surface", "0.9", "--near", "0.9"]}' \
  >"$tmp/f.jsonl"
"$bin" batch "$tmp/f.jsonl" -o "$tmp/f" --jobs 2 >"$tmp/f.out" 2>"$tmp/f.err"
rc=$?
if [[ $rc -eq 1 && -f "$tmp/f/ok/job.json" && ! -e "$tmp/f/bad" && -s "$tmp/f/.failed/bad/stderr.txt" ]] &&
    grep -q "failed: bad (manifest line 2)" "$tmp/f.err"; then ok
else bad "a failing job (rc $rc): $(cat "$tmp/f.err")"; fi

# The summary: a row per job of the manifest (done, failed, pending) with its measures, totals,
# and a contact sheet.
if "$bin" batch "$tmp/f" --summary >"$tmp/sum.out" && "$bin" batch "$tmp/one" --summary -q &&
    grep -q "2 jobs: 1 done, 1 failed, 0 pending" "$tmp/sum.out" &&
    python3 - "$tmp" <<'PY'
import csv, json, os, struct, sys
tmp = sys.argv[1]
rows = {r["id"]: r for r in csv.DictReader(open(os.path.join(tmp, "f", "summary.csv")))}
assert rows["ok"]["status"] == "done" and 0 <= float(rows["ok"]["iou"]) <= 1, rows
assert int(rows["ok"]["primitives"]) >= 1 and float(rows["ok"]["seconds"]) > 0, rows
assert rows["bad"]["status"] == "failed" and "exit 2" in rows["bad"]["error"], rows
s = json.load(open(os.path.join(tmp, "f", "summary.json")))
assert s["totals"]["done"] == 1 and s["totals"]["failed"] == 1 and s["worst"] == ["ok"], s
one = json.load(open(os.path.join(tmp, "one", "summary.json")))
assert one["totals"] == {**one["totals"], "jobs": 8, "done": 1, "pending": 7}, one["totals"]
assert [j["status"] for j in one["jobs"]].count("pending") == 7
png = open(os.path.join(tmp, "one", "summary.png"), "rb").read()
assert png[:8] == b"\x89PNG\r\n\x1a\n"
w, h = struct.unpack(">II", png[16:24])
assert w > 4 * 320 and h > 2 * 150, (w, h)  # four columns, two rows of cells for 8 jobs
PY
then ok; else bad "--summary: $(cat "$tmp/sum.out")"; fi
expect_error 'nothing: not a batch.s output directory' "$bin" batch "$tmp/nothing" --summary
expect_error '--summary: name the output directory alone' "$bin" batch "$tmp/f" --summary -o "$tmp/x"
# A damaged record of the jobs: one line naming it, exit 2.
cp -r "$tmp/one" "$tmp/damaged"
echo '{"jobs": [3]}' >"$tmp/damaged/.batch/jobs.json"
expect_error 'damaged/.batch/jobs.json: jobs: not the batch.s record' "$bin" batch "$tmp/damaged" --summary

# A CSV manifest: a header naming the columns, options separated by blanks, quoted fields.
printf '%s\n' 'id,input,verb,options' \
  'c1,parts/disc.json,fit,"--prims 4 --iters 50 --seed 7 -q"' \
  '"c2",parts/disc.json,fit,--prims 2 --iters 50 -q' >"$tmp/m.csv"
if "$bin" batch "$tmp/m.csv" -o "$tmp/csv" --jobs 2 -q &&
    python3 - "$tmp/csv" <<'PY'
import json, os, sys
out = sys.argv[1]
assert json.load(open(os.path.join(out, "c1", "report.json")))["seed"] == 7
assert json.load(open(os.path.join(out, "c2", "job.json")))["options"][:2] == ["--prims", "2"]
PY
then ok; else bad "a CSV manifest"; fi
printf 'id,verb,input,colour\n' >"$tmp/bad.csv"
expect_error 'bad.csv:1: colour: unknown column' "$bin" batch "$tmp/bad.csv" -o "$tmp/never"
printf 'id,verb,input\na,fit\n' >"$tmp/bad.csv"
expect_error 'bad.csv:2: 2 fields, the header has 3' "$bin" batch "$tmp/bad.csv" -o "$tmp/never"

# --slurm without Slurm's commands: one line saying so, exit status 1.
PATH=/nonexistent "$bin" batch "$tmp/m.jsonl" -o "$tmp/noslurm" --slurm >"$tmp/ns.out" 2>"$tmp/ns.err"
rc=$?
if [[ $rc -eq 1 && $(wc -l <"$tmp/ns.err") -eq 1 ]] && grep -qE "^fuzzycsg: error: (sbatch|squeue|scontrol): not found on PATH" "$tmp/ns.err"; then ok
else bad "--slurm without Slurm: rc $rc, $(cat "$tmp/ns.err")"; fi

# Bad manifests: one line naming the manifest's line, exit 2, nothing run or written.
check_refused() {
  local pattern=$1 text=$2
  printf '%s\n' "$text" >"$tmp/bad.jsonl"
  expect_error "$pattern" "$bin" batch "$tmp/bad.jsonl" -o "$tmp/never"
  [[ -e "$tmp/never" ]] && bad "a refused manifest created its output ($pattern)"
}
good='{"id": "a", "verb": "fit", "input": "parts/disc.json"}'
check_refused 'bad.jsonl:2: id: .a. is used by an earlier line' "$good"$'\n'"$good"
check_refused 'bad.jsonl:1: verb: unknown verb .mesh.' '{"id": "a", "verb": "mesh", "input": "parts/disc.json"}'
check_refused 'bad.jsonl:1: input: .*parts/nothing.stl: no such file' '{"id": "a", "verb": "convert", "input": "parts/nothing.stl"}'
check_refused 'bad.jsonl:1: options: .*--primz' '{"id": "a", "verb": "fit", "input": "parts/disc.json", "options": ["--primz", "4"]}'
check_refused 'bad.jsonl:1: options: .*--prims' '{"id": "a", "verb": "fit", "input": "parts/disc.json", "options": ["--prims", "four"]}'
check_refused 'bad.jsonl:3: not JSON' "$good"$'\n'"# a comment"$'\n''{"id": "b",'
check_refused 'bad.jsonl:1: id: .\.\./x. must be' '{"id": "../x", "verb": "fit", "input": "parts/disc.json"}'
check_refused 'bad.jsonl:1: colour: unknown field' '{"id": "a", "verb": "fit", "input": "parts/disc.json", "colour": 1}'
check_refused 'bad.jsonl: no jobs' '# nothing'
expect_error '--index: 8 jobs in .*m.jsonl, so at most 7' "$bin" batch "$tmp/m.jsonl" -o "$tmp/never2" --index 8

echo "batch: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
