#!/usr/bin/env bash
# fuzzycsg as another project uses it: this build installed into a temporary prefix, then
# tests/install/downstream (find_package(fuzzycsg 0.1 REQUIRED), fuzzycsg::eval) configured,
# built and run against that prefix with the same generator, compiler and build type; the
# program's output must be exactly the expected line.
# Usage: downstream_test.sh CMAKE BUILD_DIR DOWNSTREAM_SOURCE WORK_DIR GENERATOR MAKE_PROGRAM
#                           CXX_COMPILER BUILD_TYPE
set -euo pipefail
cmake=$1
build=$2
downstream=$3
work=$4
generator=$5
make_program=$6
cxx=$7
build_type=$8

unset DESTDIR  # the prefix alone says where
rm -rf "$work"
mkdir -p "$work"
prefix="$work/prefix"

run() {  # run LOG CMD...: the command's output in LOG, shown when it fails.
  local log=$1
  shift
  if ! "$@" >"$log" 2>&1; then
    echo "FAIL: $*"
    cat "$log"
    exit 1
  fi
}

run "$work/install.log" "$cmake" --install "$build" --prefix "$prefix"
# (The library directory is lib or, for a /usr prefix on Debian, lib/<multiarch>.)
for f in fuzzycsgConfig.cmake fuzzycsgConfigVersion.cmake fuzzycsg-eval-targets.cmake tree.hpp \
    evaluator.hpp libfuzzycsg_core.a libfuzzycsg_eval.a; do
  if [[ -z $(find "$prefix" -name "$f" -type f) ]]; then
    echo "FAIL: cmake --install did not install $f"
    exit 1
  fi
done

run "$work/configure.log" "$cmake" -S "$downstream" -B "$work/build" -G "$generator" \
  -DCMAKE_MAKE_PROGRAM="$make_program" -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_BUILD_TYPE="$build_type" -DCMAKE_PREFIX_PATH="$prefix" \
  -DFUZZYCSG_EXPECTED_PREFIX="$prefix"
run "$work/build.log" "$cmake" --build "$work/build"

status=0
output=$("$work/build/app" 2>&1) || status=$?
expected="fuzzycsg 0.1.0: 10 parameters, inside 1.000, outside 0.000"
if [[ $status -ne 0 || "$output" != "$expected" ]]; then
  echo "FAIL: the downstream program exited $status and printed:"
  echo "$output"
  echo "expected: $expected"
  exit 1
fi
echo "$output"
rm -rf "$work"
