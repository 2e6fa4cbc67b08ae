# Sourced by the scripts that read the larger data collection (benchmarks, studies, docs'
# pictures). It is not part of the repository: its folder is $FUZZYCSG_DATA, or ../shared/data
# beside the repository root when that is unset (then printed relative to the working folder,
# so that commands recorded in reports read the same on every machine). The test suite never
# reads it.
#   source scripts/data-dir.sh; glyphs=$(fuzzycsg_data_dir glyphs) || exit 2
fuzzycsg_data_dir() {
  local dir
  if [[ -n "${FUZZYCSG_DATA:-}" ]]; then
    dir=$FUZZYCSG_DATA
  else
    dir=$(realpath -m --relative-to="$PWD" "$(dirname "${BASH_SOURCE[0]}")/../../shared/data")
  fi
  local want="$dir${1:+/$1}"
  if [[ ! -e "$want" ]]; then
    echo "$want: missing; this script reads the data collection at $dir (set FUZZYCSG_DATA to its folder)" >&2
    return 2
  fi
  echo "$want"
}
