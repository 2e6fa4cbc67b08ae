#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz preset: clang, ASan, UBSan) and runs each reader's fuzzer
# on a copy of its seed corpus, so the checked-in corpora are not modified:
#   tree_reader_fuzz     tree files (fuzz/corpus/tree)
#   openscad_csg_fuzz    OpenSCAD .csg models, as scenes and as trees (fuzz/corpus/openscad_csg)
#   point_reader_fuzz    point files (fuzz/corpus/points)
#   mesh_loader_fuzz     OFF/OBJ/STL/PLY meshes and mesh targets (fuzz/corpus/mesh)
#   picture_loader_fuzz  PBM/PGM/PNG pictures, bitmaps and image targets (fuzz/corpus/picture)
# SECONDS (default 60) is shared evenly among the fuzzers run, each getting at least 10 s (so a
# run of all five takes at least 50 s of fuzzing). Naming fuzzers runs only those. Every fuzzer
# runs even after another found a problem. Crashes, hangs and leaks inside assimp itself are not
# findings (fuzz/mesh_loader_fuzz.cpp, fuzz/lsan.supp). A finding is saved as fuzz/crash-* (or leak-*,
# timeout-*, oom-*); the script names the fuzzer that found it and exits non-zero. Reproduce
# with build/fuzz/fuzz/NAME fuzz/crash-...
#   scripts/fuzz.sh [SECONDS [NAME...]]
set -euo pipefail

usage() {
  echo "usage: scripts/fuzz.sh [SECONDS [NAME...]]" >&2
  exit 2
}
seconds=${1:-60}
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [[ "$seconds" -lt 1 ]]; then usage; fi
shift || true
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

# name corpus dictionary max_len
table=(
  "tree_reader_fuzz tree tree.dict 8192"
  "openscad_csg_fuzz openscad_csg openscad_csg.dict 4096"
  "point_reader_fuzz points - 4096"
  "mesh_loader_fuzz mesh mesh.dict 4096"
  "picture_loader_fuzz picture picture.dict 4096"
)
selected=()
if [[ $# -eq 0 ]]; then
  selected=("${table[@]}")
else
  for name in "$@"; do
    found=
    for row in "${table[@]}"; do
      if [[ "${row%% *}" == "$name" ]]; then
        selected+=("$row")
        found=1
      fi
    done
    if [[ -z "$found" ]]; then
      echo "fuzz: no fuzzer named $name (known: $(printf '%s ' "${table[@]%% *}"))" >&2
      exit 2
    fi
  done
fi
share=$((seconds / ${#selected[@]}))
if [[ $share -lt 10 ]]; then share=10; fi

cmake --preset fuzz >/dev/null
cmake --build build/fuzz --target "${selected[@]%% *}" -j "${FUZZYCSG_JOBS:-2}"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Leaks inside third-party libraries are not reported (fuzz/lsan.supp).
export LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

failed=()
for row in "${selected[@]}"; do
  read -r name corpus dict max_len <<<"$row"
  cp -r "fuzz/corpus/$corpus" "$work/$name"
  options=(-max_total_time="$share" -max_len="$max_len" -timeout=10 -rss_limit_mb=2048
    -artifact_prefix="$root/fuzz/" -print_final_stats=1)
  if [[ "$dict" != - ]]; then options+=(-dict="fuzz/$dict"); fi
  echo "== fuzz: $name for ${share}s"
  status=0
  # The loaders' fuzzers write each input to a file in a folder under TMPDIR, left behind when
  # they stop at a finding: here, under $work, it goes with it.
  TMPDIR="$work" build/fuzz/fuzz/"$name" "$work/$name" "${options[@]}" || status=$?
  if [[ $status -ne 0 ]]; then
    echo "fuzz: $name found a problem (exit status $status); see fuzz/ for the input" >&2
    failed+=("$name")
  fi
done

if [[ ${#failed[@]} -ne 0 ]]; then
  echo "fuzz: findings by ${failed[*]}" >&2
  exit 1
fi
echo "fuzz: no findings in ${share}s each of ${#selected[@]} fuzzer(s)"
