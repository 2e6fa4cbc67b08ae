#!/usr/bin/env bash
# Times whole fits: the two reference cases of the authors' public release (Liu et al. 2024;
# liu2024/PROVENANCE.md of the data collection, scripts/data-dir.sh), trained with the fuzzycsg program, then the PyTorch
# model of the paper (torch_model.py train) timed on the same configurations, and prints one
# table: steps, fuzzycsg training seconds and steps/s, wall time of the whole command, final
# loss, MSE on 2M points before and after pruning, primitives kept, PyTorch seconds per step and
# its projected time for the same steps, the ratio, and PASS/FAIL against the project's limits
# (2D logo <= 30 s, 3D table <= 600 s of training).
#
#   bench/run_fit_bench.sh                                 # both cases, full length, 2 threads
#   CASES=logo bench/run_fit_bench.sh                      # the 2D logo only
#   LOGO_ITERS=10000 TABLE_ITERS=5000 bench/run_fit_bench.sh   # short runs (projected)
#
# Environment: CASES (comma list of logo, table; default both), LOGO_ITERS (default 100000),
# TABLE_ITERS (default 200000), THREADS (default 2), TORCH_STEPS (steps timed per repetition for
# the PyTorch baseline, default 200), TORCH_REPS (default 3), BIN (a fuzzycsg program to use
# instead of building build/release/apps/fuzzycsg/fuzzycsg with the "release" preset), BUILD_DIR
# (default build/release), JOBS (build parallelism, default 2), PYTHON (default /usr/bin/python3),
# OUT (output directory, default a temporary one), KEEP (1: keep the temporary OUT; an OUT given
# is always kept), TORCH (0: skip the PyTorch baseline).
# Exit status: 0 when every case passes, 1 otherwise (or on an error before the table).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BUILD_DIR:-$root/build/release}
CASES=${CASES:-logo,table}
LOGO_FULL=100000
TABLE_FULL=200000
LOGO_ITERS=${LOGO_ITERS:-$LOGO_FULL}
TABLE_ITERS=${TABLE_ITERS:-$TABLE_FULL}
THREADS=${THREADS:-2}
TORCH_STEPS=${TORCH_STEPS:-200}
TORCH_REPS=${TORCH_REPS:-3}
JOBS=${JOBS:-2}
PYTHON=${PYTHON:-/usr/bin/python3}
if [[ -n "${OUT:-}" ]]; then
  out=$OUT
  remove_out=0
else
  out=$(mktemp -d)
  remove_out=$([[ "${KEEP:-0}" == 1 ]] && echo 0 || echo 1)
fi
mkdir -p "$out"
out=$(cd "$out" && pwd)

die() {
  echo "error: $*" >&2
  exit 1
}

for v in LOGO_ITERS TABLE_ITERS THREADS TORCH_STEPS TORCH_REPS; do
  [[ "${!v}" =~ ^[1-9][0-9]*$ ]] || die "$v must be a positive integer (got '${!v}')"
done

# --- cases and data --------------------------------------------------------------------------
# The data is not vendored: it is the data collection's liu2024/ (scripts/data-dir.sh).
source "$root/scripts/data-dir.sh"
data=$(fuzzycsg_data_dir liu2024) || exit 2
IFS=, read -r -a cases <<<"$CASES"
[[ ${#cases[@]} -gt 0 ]] || die "CASES is empty"
for c in "${cases[@]}"; do
  case $c in
    logo) file=2D_github_logo.jpg ;;
    table) file=3D_table_51016.obj ;;
    *) die "unknown case '$c' in CASES (known: logo, table)" ;;
  esac
  [[ -f "$data/$file" ]] ||
    die "missing $data/$file: the reference data of the authors' release (liu2024/ of the data collection; set FUZZYCSG_DATA to its folder)"
done
data=$(cd "$data" && pwd)
# The baseline needs PyTorch: say so before minutes of fitting, not after.
if [[ "${TORCH:-1}" != 0 ]] && ! "$PYTHON" -c "import torch" 2>/dev/null; then
  die "$PYTHON cannot import torch, which the PyTorch baseline needs: apt-get install python3-torch, or TORCH=0 to skip the baseline"
fi

# --- build -----------------------------------------------------------------------------------
if [[ -z "${BIN:-}" ]]; then
  if [[ ! -f "$build/CMakeCache.txt" ]]; then
    if [[ "$build" == "$root/build/release" ]]; then
      (cd "$root" && cmake --preset release >/dev/null)
    else
      cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
    fi
  fi
  echo "building fuzzycsg (Release) ..." >&2
  if ! cmake --build "$build" --target fuzzycsg -j"$JOBS" >"$out/build.log" 2>&1; then
    tail -n 40 "$out/build.log" >&2
    die "the fuzzycsg program does not build (log: $out/build.log)"
  fi
  BIN=$build/apps/fuzzycsg/fuzzycsg
fi
[[ -x "$BIN" ]] || die "BIN=$BIN is not an executable"

# --- machine -----------------------------------------------------------------------------------
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')
echo "machine: $cpu, $(nproc) hardware threads, load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "fuzzycsg: $BIN; outputs: $out"

now_ns() { date +%s%N; }

# --- fuzzycsg: the release cases -----------------------------------------------------------------
for c in "${cases[@]}"; do
  case $c in
    logo)
      args=(fit "$data/2D_github_logo.jpg" -o "$out/logo" --prims 128 --iters "$LOGO_ITERS"
        --batch 1024 --resample-every 10 --lr 1e-3 --temperature 1000 --temperature-ramp 0
        --omega 10 --seed 0 --threads "$THREADS" --image-resolution 256 --sampler release)
      ;;
    table)
      args=(fit "$data/3D_table_51016.obj" -o "$out/table" --prims 1024 --iters "$TABLE_ITERS"
        --batch 1024 --pool 102400 --resample-every 1000 --lr 5e-4 --temperature 100
        --temperature-ramp 0 --omega 10 --seed 0 --threads "$THREADS" --padding 0.2)
      ;;
  esac
  echo "fuzzycsg $c: $BIN ${args[*]}" >&2
  rm -rf "${out:?}/$c"
  t0=$(now_ns)
  rc=0
  "$BIN" "${args[@]}" >"$out/$c.log" 2>&1 || rc=$?
  ms=$((($(now_ns) - t0) / 1000000))
  printf '{"case": "%s", "rc": %d, "wall_seconds": %d.%03d}\n' "$c" "$rc" $((ms / 1000)) \
    $((ms % 1000)) >"$out/$c.wall.json"
  if [[ $rc != 0 ]]; then
    echo "fuzzycsg $c FAILED (exit status $rc); the end of its output:" >&2
    tail -n 20 "$out/$c.log" >&2
  fi
done

# --- PyTorch: the same configurations ------------------------------------------------------------
if [[ "${TORCH:-1}" != 0 ]]; then
  for c in "${cases[@]}"; do
    case $c in
      logo) targs=(--dim 2 --P 128 --temperature 1000 --lr 1e-3 --resample-every 10) ;;
      # The release draws a new batch of 1024 from its pool of 102,400 points every step.
      table) targs=(--dim 3 --P 1024 --temperature 100 --lr 5e-4 --resample-every 1) ;;
    esac
    targs=(train "${targs[@]}" --batch 1024 --omega 10 --steps "$TORCH_STEPS" --reps "$TORCH_REPS"
      --threads "$THREADS" --seed 0)
    echo "torch $c: torch_model.py ${targs[*]}" >&2
    # The malloc tunables of run_eval_bench.sh: freed temporaries stay mapped.
    if ! GLIBC_TUNABLES=${GLIBC_TUNABLES:-glibc.malloc.mmap_threshold=4294967296:glibc.malloc.trim_threshold=17179869184} \
      "$PYTHON" "$root/bench/torch_model.py" "${targs[@]}" >"$out/torch_$c.json"; then
      echo "torch $c FAILED" >&2
      rm -f "$out/torch_$c.json"
    fi
  done
fi
echo "load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"

# --- table -------------------------------------------------------------------------------------
status=0
CASES=$CASES LOGO_ITERS=$LOGO_ITERS TABLE_ITERS=$TABLE_ITERS LOGO_FULL=$LOGO_FULL \
  TABLE_FULL=$TABLE_FULL THREADS=$THREADS "$PYTHON" - "$out" <<'EOF' || status=$?
import json, os, sys
out = sys.argv[1]
env = os.environ
CASE = {  # name, full length, time limit of training (s), loss of the authors' release
    "logo": ("2D logo", int(env["LOGO_FULL"]), 30.0, "about 0.04"),
    "table": ("3D table", int(env["TABLE_FULL"]), 600.0, "about 0.07"),
}
asked = {"logo": int(env["LOGO_ITERS"]), "table": int(env["TABLE_ITERS"])}


def load(name):
    try:
        with open(os.path.join(out, name)) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def get(d, *path):
    for key in path:
        if not isinstance(d, dict) or d.get(key) is None:
            return None
        d = d[key]
    return d


def timing(report, key):  # under "timings", or at the top level
    v = get(report, "timings", key)
    return v if v is not None else get(report, key)


def f(v, spec="%.4g", suffix=""):
    return "n/a" if v is None else (spec % v) + suffix


cases = [c for c in env["CASES"].split(",") if c]
rows, verdicts = [], []
cols = {}
for c in cases:
    title, full, limit, ref = CASE[c]
    rep = load(os.path.join(c, "report.json"))
    wall = load(c + ".wall.json") or {}
    tr = load("torch_" + c + ".json")
    steps = get(rep, "steps")
    train_s = timing(rep, "train_seconds")
    sps = timing(rep, "steps_per_second")
    if sps is None and steps and train_s:
        sps = steps / train_s
    reduced = asked[c] < full
    projected = full / sps if sps else None
    tsps = get(tr, "seconds_per_step")
    torch_proj = tsps * steps if tsps is not None and steps else None
    ratio = torch_proj / train_s if torch_proj and train_s else None
    stop = get(rep, "stop")
    # The verdict: training time of the full-length case (projected from steps/s for a reduced
    # run) within the limit, the run finished its steps, and the command succeeded.
    judged = projected if reduced else train_s
    if rep is None or wall.get("rc", 1) != 0:
        verdict = "FAIL (no report)" if rep is None else f"FAIL (exit status {wall.get('rc')})"
    elif stop not in (None, "iterations"):
        verdict = f"FAIL (stopped: {stop})"
    elif judged is None:
        verdict = "FAIL (no timing)"
    else:
        verdict = ("PASS" if judged <= limit else "FAIL") + (" (projected)" if reduced else "")
    verdicts.append(f"{title}: training {f(judged, '%.1f', ' s')}"
                    f"{' projected to full length' if reduced else ''} vs limit {limit:.0f} s "
                    f"-> {verdict}")
    pr_prims = get(rep, "counts", "pruned", "primitives")
    tr_prims = get(rep, "counts", "trained", "primitives")
    cols[c] = {
        "case": title,
        "steps": (f"{steps} of {full} (REDUCED)" if reduced else str(steps)) if steps else "n/a",
        "stop": stop or "n/a",
        "fuzzycsg train s": f(train_s, "%.2f"),
        "fuzzycsg steps/s": f(sps, "%.1f"),
        "full-length train s": f(projected, "%.1f") + (" (projected)" if reduced else ""),
        "whole command wall s": f(wall.get("wall_seconds"), "%.1f"),
        "final loss (release)": f"{f(get(rep, 'final_loss'), '%.4f')} ({ref})",
        "MSE trained (2M pts)": f(get(rep, "metrics", "trained", "mse"), "%.4g"),
        "MSE pruned (2M pts)": f(get(rep, "metrics", "pruned", "mse"), "%.4g"),
        "primitives pruned": (f"{pr_prims} of {tr_prims}" if pr_prims is not None else "n/a"),
        "torch s/step": f(tsps, "%.4g") + (f" (median of {tr['reps']}x{tr['steps']})"
                                            if tr else ""),
        "torch projected s": f(torch_proj, "%.1f"),
        "torch projected full s": f(tsps * full if tsps is not None else None, "%.1f"),
        "ratio torch/fuzzycsg": f(ratio, "%.1f", "x"),
        "limit (training)": f"{limit:.0f} s",
        "result": verdict,
    }

keys = list(next(iter(cols.values())).keys())
w0 = max(len(k) for k in keys)
widths = {c: max(len(cols[c][k]) for k in keys) for c in cases}
for k in keys:
    print(f"{k:<{w0}}  " + "  ".join(f"{cols[c][k]:>{widths[c]}}" for c in cases))
print()
print(f"threads: {env['THREADS']}. fuzzycsg train s / steps/s: report.json timings (training "
      "only); whole command: also reading the target, pruning and the metrics on 2M points.")
print("torch s/step: torch_model.py train (Adam on the MSE of 1024-point batches, same P, "
      "temperature, omega, lr, threads); projected = s/step x the steps fuzzycsg ran; "
      "ratio = torch projected / fuzzycsg train s.")
print("final loss: report.json final_loss; the authors' release reaches about 0.04 (2D logo) "
      "and about 0.07 (3D table).")
for v in verdicts:
    print(v)
sys.exit(0 if all(v.endswith("PASS") or v.endswith("PASS (projected)") for v in verdicts) else 1)
EOF
if [[ $remove_out == 1 ]]; then rm -rf "$out"; fi
exit "$status"
