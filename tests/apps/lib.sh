# Helpers of the command-line tests, sourced by cli_test.sh and trace_cli_test.sh: a
# temporary directory removed on exit, pass/fail counters, and expect_error.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

# expect_error PATTERN CMD...: exit status 2, exactly one line on stderr matching PATTERN.
expect_error() {
  local pattern=$1
  shift
  "$@" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  local lines
  lines=$(wc -l <"$tmp/err")
  if [[ $rc -ne 2 ]]; then
    bad "$* -> exit $rc, expected 2 ($(head -c 300 "$tmp/err"))"
  elif [[ $lines -ne 1 ]]; then
    bad "$* -> $lines lines on stderr, expected 1: $(cat "$tmp/err")"
  elif ! grep -qE -- "$pattern" "$tmp/err"; then
    bad "$* -> stderr '$(cat "$tmp/err")' does not match '$pattern'"
  else
    ok
  fi
}
