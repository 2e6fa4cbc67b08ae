#!/usr/bin/env bash
# Throughput of `fuzzycsg batch` on this machine: the same manifest of conversions run with one
# job at a time using every core (--jobs 1 --threads N) and with N jobs of one thread each
# (--jobs N --threads 1), REPS times each, alternating; prints each run's wall time, the medians
# and their ratio, and the per-shape seconds and IoU of the last run of each mode (from
# `batch --summary`). The shapes are the convert study's meshes that convert in under 30 s
# (docs/results.md), read from the data collection.
# Usage: bench/batch_throughput.sh [FUZZYCSG [REPS [OUTDIR]]]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/data-dir.sh
bin=$(realpath "${1:-build/release/apps/fuzzycsg/fuzzycsg}")
reps=${2:-3}
out=${3:-/tmp/fuzzycsg-batch-throughput}
scad=$(fuzzycsg_data_dir scad) || exit 2
cad=$(fuzzycsg_data_dir meshes/cad) || exit 2
cores=$(nproc)
rm -rf "$out"
mkdir -p "$out"
manifest=$out/manifest.jsonl
for m in "$scad/Basics/CSG.ref.off" "$scad/Basics/logo.ref.off" "$scad/Old/example001.ref.off" \
    "$scad/Old/example003.ref.off" "$scad/Old/example004.ref.off" "$cad/cgal_hole.off" \
    "$cad/cgal_u.off" "$cad/cgal_pipe.off" "$cad/cgal_cross.off" "$cad/cgal_corner.off" \
    "$cad/cgal_P.off"; do
  name=$(basename "$m")
  name=${name%%.*}
  printf '{"id": "%s", "verb": "convert", "input": "%s", "options": ["-q"]}\n' "${name#cgal_}" \
    "$(realpath "$m")"
done >"$manifest"

declare -A times
for ((r = 0; r < reps; r++)); do
  for mode in "1 $cores" "$cores 1"; do
    read -r jobs threads <<<"$mode"
    dir=$out/jobs${jobs}_threads${threads}
    rm -rf "$dir"
    start=$(date +%s.%N)
    "$bin" batch "$manifest" -o "$dir" --jobs "$jobs" --threads "$threads" -q
    t=$(python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.1f}')" \
      "$start" "$(date +%s.%N)")
    times[$jobs]+="$t "
    echo "run $r: --jobs $jobs --threads $threads: $t s"
  done
done
python3 - "$cores" "${times[1]}" "${times[$cores]}" <<'PY'
import statistics, sys
cores, one, many = sys.argv[1], [float(x) for x in sys.argv[2].split()], [float(x) for x in sys.argv[3].split()]
m1, mn = statistics.median(one), statistics.median(many)
print(f"median wall time: --jobs 1 --threads {cores}: {m1:.1f} s; --jobs {cores} --threads 1: "
      f"{mn:.1f} s; ratio {m1 / mn:.2f}")
PY
for dir in "$out"/jobs*; do
  "$bin" batch "$dir" --summary -q
  echo "== $(basename "$dir")"
  python3 - "$dir/summary.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for r in rows:
    print(f"{r['id']:12s} {r['status']:6s} {float(r['seconds']):6.1f} s  IoU {r['iou']}  primitives {r['primitives']}")
secs = [float(r["seconds"]) for r in rows]
print(f"jobs {len(rows)}, per-job seconds: median {statistics.median(secs):.1f}, sum {sum(secs):.1f}")
PY
done
