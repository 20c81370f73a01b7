# harness.sh: the check helpers of the shell tests (sourced; not a test itself: CMake registers
# only tests/cli/test_*.sh). Set T (the scratch directory) before sourcing; end with `summary`.
passed=0; failed=0
ok()   { passed=$((passed+1)); echo "ok   $1" >&2; }
fail() { failed=$((failed+1)); echo "FAIL $1" >&2; }
check() { local name=$1; shift; if "$@"; then ok "$name"; else fail "$name"; fi; }
# expect_exit NAME CODE CMD...: exit status CODE, exactly one line on stderr, and no control bytes
# in it (messages escape what they quote from input, README "Limits")
expect_exit() {
  local name=$1 code=$2; shift 2
  "$@" >"$T/out.txt" 2>"$T/err.txt"; local rc=$?
  local lines; lines=$(wc -l <"$T/err.txt")
  if [ "$rc" -eq "$code" ] && [ "$lines" -eq 1 ] && ! LC_ALL=C grep -q '[[:cntrl:]]' "$T/err.txt"; then ok "$name"
  else fail "$name (exit $rc, wanted $code; $lines stderr lines:)"; cat -v "$T/err.txt" >&2; fi
}
# exrinfo_reads FILE [TEXT...]: Debian's exrinfo (OpenEXR 3.1.5) read FILE, judged by what it
# prints: its exit status is an uninitialised variable there (docs/testing.md "Keeping flakiness
# out"), so success is its "File 'FILE': ver 2" header, no "ERROR" line, and each TEXT in the output
exrinfo_reads() {
  local f=$1 out; shift
  out=$(exrinfo -v "$f" 2>&1)
  grep -qF "File '$f': ver 2" <<<"$out" && ! grep -q '^ERROR' <<<"$out" || { echo "  exrinfo -v $f:" >&2; echo "$out" | head -5 >&2; return 1; }
  local t; for t in "$@"; do grep -qF -- "$t" <<<"$out" || { echo "  exrinfo -v $f: no '$t'" >&2; return 1; }; done
}
export -f exrinfo_reads
# summary: prints the counts; its status is the test's (0 when nothing failed)
summary() { echo "$passed passed, $failed failed"; [ "$failed" -eq 0 ]; }
