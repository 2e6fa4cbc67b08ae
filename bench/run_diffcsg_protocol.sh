#!/usr/bin/env bash
# DiffCSG's benchmark protocol (bench/diffcsg_protocol.cpp) on OpenSCAD examples: the five of
# the data collection's scad/ (scripts/data-dir.sh) and the pure-CSG examples of Debian's openscad package (flattened to .csg
# by openscad itself), then the table of docs/results.md (bench/diffcsg_protocol_summary.py).
#   OUT=/tmp/protocol bench/run_diffcsg_protocol.sh [extra diffcsg_protocol options]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/data-dir.sh
scad=$(fuzzycsg_data_dir scad) || exit 2
out=${OUT:-/tmp/diffcsg_protocol}
mkdir -p "$out/models"
bin=build/release/bench/diffcsg_protocol
models=()
for m in Basics/CSG Basics/logo Old/example001 Old/example003 Old/example004; do
  models+=("$scad/$m.openscad.csg")
done
examples=/usr/share/openscad/examples
for m in Old/example002 Old/example005 Old/example014; do
  name=$(basename "$m")
  (cd "$examples/$(dirname "$m")" && openscad -o "$out/models/$name.csg" "$name.scad" 2>/dev/null)
  models+=("$out/models/$name.csg")
done
list=$(IFS=,; echo "${models[*]}")
"$bin" --models "$list" "$@" | tee "$out/results.jsonl"
/usr/bin/python3 bench/diffcsg_protocol_summary.py "$out/results.jsonl"
