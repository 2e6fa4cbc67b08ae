#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz preset: clang, ASan, UBSan) and runs the tree reader
# fuzzer for SECONDS (default 60) on a copy of fuzz/corpus/tree, so the checked-in corpus is not
# modified. A finding is saved as fuzz/crash-* (or leak-*, timeout-*, oom-*) and the script
# exits non-zero.
#   scripts/fuzz.sh [SECONDS]
set -euo pipefail

seconds=${1:-60}
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [[ "$seconds" -lt 1 ]]; then
  echo "usage: scripts/fuzz.sh [SECONDS]" >&2
  exit 2
fi
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

cmake --preset fuzz >/dev/null
cmake --build build/fuzz --target tree_reader_fuzz -j "${FUZZYCSG_JOBS:-2}"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp -r fuzz/corpus/tree "$work/corpus"

status=0
build/fuzz/fuzz/tree_reader_fuzz "$work/corpus" \
  -dict=fuzz/tree.dict \
  -max_total_time="$seconds" \
  -max_len=8192 \
  -timeout=10 \
  -rss_limit_mb=2048 \
  -artifact_prefix="$root/fuzz/" \
  -print_final_stats=1 || status=$?

if [[ $status -ne 0 ]]; then
  echo "fuzz: tree_reader_fuzz found a problem (exit status $status); see fuzz/ for the input" >&2
  exit 1
fi
echo "fuzz: no findings in ${seconds}s"
