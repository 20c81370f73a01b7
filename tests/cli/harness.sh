# harness.sh: the check helpers of the shell tests (sourced; not a test itself: CMake registers
# only tests/cli/test_*.sh). Set T (the scratch directory) before sourcing; end with `summary`.
passed=0; failed=0
ok()   { passed=$((passed+1)); echo "ok   $1" >&2; }
fail() { failed=$((failed+1)); echo "FAIL $1" >&2; }
check() { local name=$1; shift; if "$@"; then ok "$name"; else fail "$name"; fi; }
# summary: prints the counts; its status is the test's (0 when nothing failed)
summary() { echo "$passed passed, $failed failed"; [ "$failed" -eq 0 ]; }
