#!/usr/bin/env bash
# Builds the benchmarks (Release), measures this machine's peak fp32 FMA and exp throughput,
# times the fuzzycsg evaluator (eval_bench) and the PyTorch model of the paper (torch_model.py)
# on the same configurations, and prints one table: P, N, threads, fuzzycsg and torch leaf-point
# evaluations per second, their ratio and the fraction of the compute limit fuzzycsg reaches.
#
#   bench/run_eval_bench.sh                      # P=64,256,1024 N=1024,65536 threads=1,2
#   P=1024 N=65536 THREADS=2 bench/run_eval_bench.sh
#
# Environment: P, N, THREADS (comma lists), REPS (minimum timed runs, default 5), BUILD_DIR
# (default build/release, configured with the "release" preset if it does not exist), JOBS
# (build parallelism, default 2), CHECK (0: skip the cross-check against PyTorch autograd that
# runs first when eval_bench builds), PYTHON (default /usr/bin/python3), TORCH_CHUNK (points per
# slice of the PyTorch model, default: torch_model.py's), KEEP (directory to keep the raw JSON
# lines in).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BUILD_DIR:-$root/build/release}
P=${P:-64,256,1024}
N=${N:-1024,65536}
THREADS=${THREADS:-1,2}
REPS=${REPS:-5}
JOBS=${JOBS:-2}
PYTHON=${PYTHON:-/usr/bin/python3}
raw=${KEEP:-$(mktemp -d)}
mkdir -p "$raw"

# --- build ---------------------------------------------------------------------------------
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  if [[ "$build" == "$root/build/release" ]]; then
    (cd "$root" && cmake --preset release -DFUZZYCSG_BUILD_BENCH=ON >/dev/null)
  else
    cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DFUZZYCSG_BUILD_BENCH=ON \
      >/dev/null
  fi
fi
cmake --build "$build" --target peak_bench -j"$JOBS" >/dev/null
have_eval=1
if ! cmake --build "$build" --target eval_bench -j"$JOBS" >"$raw/eval_build.log" 2>&1; then
  cat "$raw/eval_build.log" >&2
  echo "error: eval_bench does not build" >&2
  exit 1
fi

# --- machine --------------------------------------------------------------------------------
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')
cores=$(nproc)
echo "machine: $cpu, $cores hardware threads, load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"

# --- measurements ----------------------------------------------------------------------------
echo "peak (peak_bench) ..." >&2
"$build/bench/peak_bench" --json --threads "$THREADS" >"$raw/peak.jsonl"
: >"$raw/eval.jsonl"
if [[ $have_eval == 1 && "${CHECK:-1}" == 1 ]]; then
  # A fast wrong kernel is no result: cross-check one tree against PyTorch autograd first.
  echo "cross-check against PyTorch autograd (check_against_torch.py) ..." >&2
  if "$PYTHON" "$root/bench/check_against_torch.py" --eval-bench "$build/bench/eval_bench" \
    >"$raw/check.log" 2>&1; then
    echo "cross-check: $(grep '^RESULT' "$raw/check.log")"
  else
    echo "cross-check FAILED (details below); the fuzzycsg numbers measure a wrong result"
    cat "$raw/check.log"
  fi
fi
if [[ $have_eval == 1 ]]; then
  echo "fuzzycsg (eval_bench) ..." >&2
  "$build/bench/eval_bench" --json --no-peak --P "$P" --N "$N" --threads "$THREADS" \
    --reps "$REPS" >"$raw/eval.jsonl"
fi
echo "torch (torch_model.py) ..." >&2
torch_args=(bench --P "$P" --N "$N" --threads "$THREADS" --reps "$REPS")
if [[ -n "${TORCH_CHUNK:-}" ]]; then torch_args+=(--chunk "$TORCH_CHUNK"); fi
# glibc returns large freed blocks to the kernel by default, so every big PyTorch temporary
# page-faults afresh; these tunables keep freed memory in the process (what a tuned PyTorch
# CPU deployment does, e.g. with jemalloc or tcmalloc).
GLIBC_TUNABLES=${GLIBC_TUNABLES:-glibc.malloc.mmap_threshold=4294967296:glibc.malloc.trim_threshold=17179869184} \
  "$PYTHON" "$root/bench/torch_model.py" "${torch_args[@]}" >"$raw/torch.jsonl"
echo "load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"

# --- table ------------------------------------------------------------------------------------
"$PYTHON" - "$raw" <<'EOF'
import json, os, sys
raw = sys.argv[1]

def lines(name):
    path = os.path.join(raw, name)
    with open(path) as f:
        return [json.loads(l) for l in f if l.startswith("{")]

peaks = {d["threads"]: d for d in lines("peak.jsonl")}
evals = lines("eval.jsonl")
cost = {d["P"]: d for d in evals if d["impl"] == "cost"}
ours = {(d["P"], d["N"], d["threads"]): d for d in evals if d["impl"] == "fuzzycsg"}
torch = {(d["P"], d["N"], d["threads"]): d for d in lines("torch.jsonl")}

target = next(iter(peaks.values()))["target"] if peaks else "?"
print(f"Highway target: {target}")
for t, p in sorted(peaks.items()):
    print(f"peak, {t} thread(s): {p['flops_per_s'] / 1e9:.1f} GFLOP/s (FMA = 2 flops), "
          f"{p['exps_per_s'] / 1e9:.2f} G exp/s (best of {p['runs']} runs)")
for P, c in sorted(cost.items()):
    print(f"work per leaf-point, P={P}: {c['fma']:.2f} FMA + {c['other']:.2f} other = "
          f"{c['flops']:.2f} flops, {c['exps']:.0f} exp")
print()
hdr = ("P", "N", "threads", "fuzzycsg lp/s", "torch lp/s", "ratio", "frac of peak")
print("%6s %7s %7s %15s %13s %8s %13s" % hdr)
goal = ours.get((1024, 65536, 2), {}).get("leaf_points_per_s")
for key in sorted(set(ours) | set(torch)):
    P, N, T = key
    o, tr = ours.get(key), torch.get(key)
    ov = o["leaf_points_per_s"] if o else None
    tv = tr["leaf_points_per_s"] if tr else None
    frac = None
    if ov and T in peaks and P in cost:
        c, pk = cost[P], peaks[T]
        limit = 1.0 / (c["flops"] / pk["flops_per_s"] + c["exps"] / pk["exps_per_s"])
        frac = ov / limit
    fmt = lambda v, spec: (spec % v) if v is not None else "n/a"
    print("%6d %7d %7d %15s %13s %8s %13s" % (
        P, N, T, fmt(ov, "%.4g"), fmt(tv, "%.4g"),
        fmt(ov / tv if ov and tv else None, "%.1fx"), fmt(frac, "%.3f")))
print()
print("lp/s: leaf-point evaluations (forward+backward, MSE loss) per second = P*N / median time;")
print("ratio: fuzzycsg / torch; frac of peak: fuzzycsg rate / (1 / (flops/FLOP_peak + exps/exp_peak)).")
if goal is not None:
    print(f"goal >= 0.7e9 lp/s at P=1024, N=65536, 2 threads: {goal:.3g} -> "
          f"{'met' if goal >= 0.7e9 else 'NOT met'}")
EOF
if [[ -z "${KEEP:-}" ]]; then rm -rf "$raw"; fi
