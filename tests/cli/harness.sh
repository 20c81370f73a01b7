# harness.sh: the check helpers of the shell tests (sourced; not a test itself: CMake registers
# only tests/cli/test_*.sh). Set T (the scratch directory) before sourcing; end with `summary`.
passed=0; failed=0
ok()   { passed=$((passed+1)); echo "ok   $1" >&2; }
fail() { failed=$((failed+1)); echo "FAIL $1" >&2; }
check() { local name=$1; shift; if "$@"; then ok "$name"; else fail "$name"; fi; }
# expect_exit NAME CODE CMD...: exit status CODE, exactly one line on stderr, and no control bytes
# in it (messages escape what they quote from input, issue 17)
expect_exit() {
  local name=$1 code=$2; shift 2
  "$@" >"$T/out.txt" 2>"$T/err.txt"; local rc=$?
  local lines; lines=$(wc -l <"$T/err.txt")
  if [ "$rc" -eq "$code" ] && [ "$lines" -eq 1 ] && ! LC_ALL=C grep -q '[[:cntrl:]]' "$T/err.txt"; then ok "$name"
  else fail "$name (exit $rc, wanted $code; $lines stderr lines:)"; cat -v "$T/err.txt" >&2; fi
}
# summary: prints the counts; its status is the test's (0 when nothing failed)
summary() { echo "$passed passed, $failed failed"; [ "$failed" -eq 0 ]; }
