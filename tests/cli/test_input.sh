#!/usr/bin/env bash
# Hostile and malformed input (issue 17, the input side): every case exits with its documented
# status, prints exactly one line on stderr naming the file and what was expected, leaves no output
# behind, and never echoes control characters from the input.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SHARED=${FOVSIM_SHARED:?set by CMake}
SRC=${FOVSIM_SOURCE:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/input
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

# expect_exit NAME CODE CMD...: exit status CODE, exactly one line on stderr, no control bytes in it
expect_exit() {
  local name=$1 code=$2; shift 2
  "$@" >"$T/out.txt" 2>"$T/err.txt"; local rc=$?
  local lines; lines=$(wc -l <"$T/err.txt")
  if [ "$rc" -eq "$code" ] && [ "$lines" -eq 1 ] && ! LC_ALL=C grep -q '[[:cntrl:]]' "$T/err.txt"; then ok "$name"
  else fail "$name (exit $rc, wanted $code; $lines stderr lines:)"; cat -v "$T/err.txt" >&2; fi
}

# tiny settings, so that a case the old code accepted still ends quickly
SMALL=(--frames 1 --width 32 --height 32)
# ---- --modes: an empty list or item is a usage error with a message (defect 6)
for cmd in compare bench; do
  extra=(--samples 2 --supersample 1 --no-cache); [ $cmd = bench ] && extra=(--warmup 0)
  for v in '' ',' 'traditional,' ',hashed' 'traditional,,hashed'; do
    expect_exit "$cmd --modes '$v' -> 2 with a message" 2 "$BIN" $cmd fence --modes "$v" "${SMALL[@]}" "${extra[@]}" --out "$T/modes"
    check "$cmd --modes '$v' says what it expects" grep -q "modes: expected alpha modes separated by commas" "$T/err.txt"
  done
done
check "--modes errors create nothing" test ! -e "$T/modes"

summary
