#!/usr/bin/env bash
# No shell between fovsim and the programs it starts (docs/testing.md "Security tests"): every command that starts
# another program (merge -> gnuplot, bench --accuracy -> gnuplot, compare --fvvdp -> python3) is run
# with hostile paths (a space, quotes, $(...), backquotes, ;...;, a newline, a leading dash) and with
# hostile values read back from files (a task's metrics.csv, a scene file's name that lands in a
# plot's title); and the scripts sweep writes for the user's shell (--jobs-file, --slurm). Each command either works (a path with a space must) or refuses in one line, and
# no marker file appears anywhere: every hostile string runs `touch PWNED_<where>` if anything
# hands it to a shell or to gnuplot's system(). Tiny sizes: about 10 s.
#
# compare --fvvdp runs a stand-in pyfvvdp (tests/cli/fake_fvvdp: the API run_fvvdp.py calls, with a
# JOD computed from the frames) under /usr/bin/python3 (numpy, scripts/setup.sh); a fake `fvvdp`
# command is on PATH too, which is what fovsim looked for before 2026-12-02.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SRC=${FOVSIM_SOURCE:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/security
START=$PWD
rm -rf "$T"; mkdir -p "$T/run"
. "$(dirname "$0")/harness.sh"
cd "$T/run" || exit 1 # a relative `touch` lands here

# no_marks NAME: no PWNED_* file anywhere under $T (nor in the folder the test started in)
no_marks() {
  local found; found=$(find "$T" -name 'PWNED*' 2>/dev/null; find "$START" -maxdepth 1 -name 'PWNED*' 2>/dev/null)
  if [ -z "$found" ]; then ok "$1: nothing ran"; else fail "$1: a marker appeared: $found"; fi
  find "$T" -name 'PWNED*' -exec rm -f {} + 2>/dev/null
}
# works_or_one_line NAME RC ERRFILE [FILE-THAT-MUST-EXIST]: exit 0 (and the file, when given) or a
# non-zero exit with exactly one line on stderr
works_or_one_line() {
  local name=$1 rc=$2 err=$3 file=${4:-}
  if [ "$rc" -eq 0 ] && { [ -z "$file" ] || [ -s "$file" ]; }; then ok "$name: works"
  elif [ "$rc" -ne 0 ] && [ "$(wc -l <"$err")" -eq 1 ]; then ok "$name: refused in one line ($(cat "$err"))"
  else fail "$name: exit $rc, $(wc -l <"$err") stderr lines:"; cat -v "$err" >&2; fi
}

# One folder name per class (each a single path component; the newline one where the filesystem
# takes it, which every Linux filesystem does).
NAMES=(
  "sp ace"
  "q';touch PWNED_sq;'"
  "g';system('touch PWNED_gp');'"
  'd"q;touch PWNED_dq;"'
  '$(touch PWNED_dollar)'
  '`touch PWNED_bq`'
  ';touch PWNED_semi;'
  $'n\ntouch PWNED_nl\n'
  '-dash'
)
# All of them at once, nested: quotes that would toggle each other's meaning in a shell line
ALL=$(printf '%s/' "${NAMES[@]}"); ALL=${ALL%/}
HAVE_GNUPLOT=0; command -v gnuplot >/dev/null && HAVE_GNUPLOT=1
[ $HAVE_GNUPLOT = 1 ] || echo "note: gnuplot is not installed (scripts/setup.sh installs gnuplot-nox): merge and bench --accuracy run without their plots" >&2

# ---- merge SWEEP_DIR -> gnuplot: a tiny finished sweep, copied under every hostile name
cat >"$T/m.json" <<'EOF'
{"scenes": ["fence"], "gaze": ["centre"], "modes": ["traditional", "hashed"],
 "width": 32, "height": 18, "frames": 2, "reference": {"supersample": 2}, "cache": "cache"}
EOF
"$BIN" sweep "$T/m.json" --local 1 --out "$T/base" --quiet >"$T/sweep.txt" 2>&1
check "a tiny sweep finishes" test $? -eq 0
merge_in() { # merge_in LABEL DIR: copies the sweep to DIR and merges it there
  mkdir -p "${2%/*}" && cp -r "$T/base" "$2" || { fail "merge $1: cannot copy the sweep there"; return; }
  "$BIN" merge "$2" >"$T/out.txt" 2>"$T/err.txt"; local rc=$?
  if [ $HAVE_GNUPLOT = 1 ]; then works_or_one_line "merge $1" $rc "$T/err.txt" "$2/accuracy.png"
  else works_or_one_line "merge $1" $rc "$T/err.txt" "$2/accuracy.csv"; fi
  no_marks "merge $1"
}
for i in "${!NAMES[@]}"; do
  n=${NAMES[$i]}
  [ "$n" = "-dash" ] && continue # below: as a relative path
  merge_in "$(printf '%q' "$n")" "$T/m$i/$n"
done
merge_in "all names nested" "$T/mall/$ALL"
check "merge: a folder with a space works" test -s "$T/m0/sp ace/accuracy.csv"
mkdir -p "$T/mdash" && cp -r "$T/base" "$T/mdash/-dash"
(cd "$T/mdash" && "$BIN" merge -dash >"$T/out.txt" 2>"$T/err.txt"); works_or_one_line "merge -dash" $? "$T/err.txt"
(cd "$T/mdash" && "$BIN" merge ./-dash >"$T/out.txt" 2>"$T/err.txt"); works_or_one_line "merge ./-dash" $? "$T/err.txt" "$T/mdash/-dash/accuracy.csv"
no_marks "merge -dash"

# ---- merge: values read back from a task's metrics.csv are what fovsim writes, or refused (file:line)
# tamper DIR AWK-PROGRAM: rewrites every task's metrics.csv of the sweep copy DIR
tamper() { for f in "$1"/tasks/*/metrics.csv; do awk -F, -v OFS=, "$2" "$f" >"$f.new" && mv "$f.new" "$f"; done; }
# the column of NAME in a metrics.csv
col() { head -1 "$(ls "$T"/base/tasks/*/metrics.csv | head -1)" | tr , '\n' | grep -nx "$1" | cut -d: -f1; }
CM=$(col mode); CMS=$(col frame_ms); CR=$(col ring)
bad_value() { # bad_value LABEL AWK-PROGRAM: merge refuses, one line naming metrics.csv:LINE, exit 6
  rm -rf "$T/v"; cp -r "$T/base" "$T/v"; tamper "$T/v" "$2"
  "$BIN" merge "$T/v" >"$T/out.txt" 2>"$T/err.txt"; local rc=$?
  check "merge refuses $1 (exit 6, one line naming metrics.csv:line)" bash -c \
    "[ $rc -eq 6 ] && [ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -Eq 'metrics\.csv:[0-9]+: ' '$T/err.txt'"
  check "... and writes no plot" test ! -e "$T/v/accuracy.png"
  no_marks "merge with $1"
}
bad_value "a mode that is gnuplot code" "NR > 1 && \$$CM == \"traditional\" { \$$CM = \"h';system('touch PWNED_mode');'\" } 1"
bad_value "a mode that is shell code" "NR > 1 && \$$CM == \"hashed\" { \$$CM = \"\\\$(touch PWNED_mode2)\" } 1"
bad_value "a mode fovsim does not have" "NR == 3 { \$$CM = \"nearest\" } 1"
bad_value "a frame time that is not a number" "NR == 2 { \$$CMS = \"12ms\" } 1"
bad_value "a ring that is not an integer" "NR == 2 { \$$CR = \"-1;\" } 1"

# ---- bench --accuracy -> gnuplot: a hostile output folder, and a scene file whose name lands in
# the plot's title
ACC=(--accuracy --modes traditional --width 32 --height 18 --frames 2 --warmup 1 --supersample 2 --samples 8 --cache "$T/cache" --quiet)
if [ $HAVE_GNUPLOT = 1 ]; then
  mkdir -p "$T/b"
  "$BIN" bench fence "${ACC[@]}" --out "$T/b/$ALL" >"$T/out.txt" 2>"$T/err.txt"
  works_or_one_line "bench --accuracy --out (all names nested)" $? "$T/err.txt" "$T/b/$ALL/accuracy.png"
  no_marks "bench --accuracy --out (all names nested)"
  "$BIN" bench fence "${ACC[@]}" --out "$T/b/sp ace" >"$T/out.txt" 2>"$T/err.txt"
  check "bench --accuracy --out with a space works" bash -c "[ $? -eq 0 ] && [ -s '$T/b/sp ace/accuracy.png' ]"
  S="$T/b/s';system('touch PWNED_title');'\`touch PWNED_tbq\`.json"
  cp "$SRC/scenes/builtin/fence.json" "$S"
  "$BIN" bench "$S" "${ACC[@]}" --out "$T/b/title" >"$T/out.txt" 2>"$T/err.txt"
  works_or_one_line "bench --accuracy on a scene named like gnuplot code" $? "$T/err.txt" "$T/b/title/accuracy.png"
  check "... the title holds the name as text" grep -q "system(''touch PWNED_title'')" "$T/b/title/accuracy.gp"
  no_marks "bench --accuracy, scene named like gnuplot code"
else
  "$BIN" bench fence "${ACC[@]}" --out "$T/b/sp ace" >"$T/out.txt" 2>"$T/err.txt"
  check "bench --accuracy without gnuplot: refused in one line" bash -c "[ $? -ne 0 ] && [ \$(wc -l <'$T/err.txt') -eq 1 ]"
fi

# ---- compare --fvvdp -> python3: the stand-in pyfvvdp under Debian's python3 (numpy)
if [ -x /usr/bin/python3 ] && /usr/bin/python3 -c 'import numpy' 2>/dev/null; then
  mkdir -p "$T/fakebin"
  ln -s /usr/bin/python3 "$T/fakebin/python3"
  printf '#!/bin/sh\nexit 0\n' >"$T/fakebin/fvvdp"; chmod +x "$T/fakebin/fvvdp"
  FV=(env PATH="$T/fakebin:$PATH" PYTHONPATH="$SRC/tests/cli/fake_fvvdp" PYTHONDONTWRITEBYTECODE=1)
  CMP=(compare fence --modes traditional,hashed --width 32 --height 18 --frames 2 --supersample 2 --samples 8 --cache "$T/cache" --fvvdp --quiet)
  # jod_read DIR: summary.json's JODs equal results.json's (fovsim ran the script and read them)
  jod_read() {
    /usr/bin/python3 -c "
import json, sys
s = json.load(open(sys.argv[1] + '/summary.json')); r = json.load(open(sys.argv[1] + '/fvvdp/results.json'))['jod']
got = {m['mode']: m.get('fvvdp_jod') for m in s['modes']}
sys.exit(not (set(r) == {'traditional', 'hashed'} and all(abs(got[k] - v) < 1e-5 for k, v in r.items())))" "$1"
  }
  mkdir -p "$T/c"
  for i in 0 1 all; do
    if [ $i = all ]; then D="$T/c/$ALL"; L="all names nested"; else D="$T/c/${NAMES[$i]}"; L=$(printf '%q' "${NAMES[$i]}"); fi
    "${FV[@]}" "$BIN" "${CMP[@]}" --out "$D" >"$T/out.txt" 2>"$T/err.txt"; rc=$?
    check "compare --fvvdp --out ($L) works and reads the JODs" bash -c "[ $rc -eq 0 ] && [ ! -s '$T/err.txt' ]" &&
      check "... summary.json holds results.json's JODs" jod_read "$D"
    no_marks "compare --fvvdp --out ($L)"
  done
  (cd "$T/c" && "${FV[@]}" "$BIN" "${CMP[@]}" --out -dash >"$T/out.txt" 2>"$T/err.txt"); rc=$?
  check "compare --fvvdp --out -dash works and reads the JODs" bash -c "[ $rc -eq 0 ] && [ ! -s '$T/err.txt' ]" &&
    check "... summary.json holds results.json's JODs" jod_read "$T/c/-dash"
  no_marks "compare --fvvdp --out -dash"
  # A run that fails: non-zero exit, one line naming the log; the metrics are still written
  FAKE_FVVDP_FAIL=1 "${FV[@]}" "$BIN" "${CMP[@]}" --out "$T/c/fail" >"$T/out.txt" 2>"$T/err.txt"; rc=$?
  check "compare --fvvdp whose run fails: exit 6, one line naming fvvdp.log" bash -c \
    "[ $rc -eq 6 ] && [ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q 'fvvdp.log' '$T/err.txt' && grep -q 'asked to fail' '$T/c/fail/fvvdp/fvvdp.log'"
  check "... and still writes the metrics" test -s "$T/c/fail/metrics.csv"
  # The check and the run use the same python3: one that cannot import pyfvvdp is reported as not
  # installed (exit 0, one line on stdout), even with an `fvvdp` command on PATH.
  env PATH="$T/fakebin:$PATH" PYTHONPATH= "$BIN" "${CMP[@]}" --out "$T/c/none" >"$T/out.txt" 2>"$T/err.txt"; rc=$?
  check "compare --fvvdp without pyfvvdp (an fvvdp command on PATH): says so, exit 0, no JOD" bash -c \
    "[ $rc -eq 0 ] && [ \$(grep -c 'pyfvvdp is not installed' '$T/out.txt') -eq 1 ] && ! grep -q fvvdp_jod '$T/c/none/summary.json'"
  no_marks "compare --fvvdp"
else
  echo "FAIL /usr/bin/python3 with numpy is missing (scripts/setup.sh installs python3-numpy)" >&2; failed=$((failed+1))
fi

# ---- sweep --jobs-file / --slurm: scripts fovsim writes for the user's shell. Paths are quoted; a
# line break cannot be (each jobs-file line is its own command), so it is refused before anything is
# written.
mkdir -p "$T/j"
"$BIN" sweep "$T/m.json" --jobs-file "$T/j/jobs.txt" --out "$T/j/${NAMES[1]}" >"$T/out.txt" 2>"$T/err.txt"; rc=$?
check "sweep --jobs-file --out (quotes) writes the jobs file" bash -c "[ $rc -eq 0 ] && [ -s '$T/j/jobs.txt' ]"
(cd "$T/j" && bash jobs.txt) >/dev/null 2>&1
check "... which runs the task there" test -s "$T/j/${NAMES[1]}/tasks/$(ls "$T/base/tasks" | head -1)/metrics.csv"
no_marks "sweep --jobs-file (quotes), run by bash"
for act in --jobs-file --slurm; do
  args=("$act"); [ "$act" = --jobs-file ] && args+=("$T/j/jobs2.txt")
  "$BIN" sweep "$T/m.json" "${args[@]}" --out "$T/j/${NAMES[7]}" >"$T/out.txt" 2>"$T/err.txt"; rc=$?
  check "sweep $act --out (a line break): exit 2, one line, nothing written" bash -c \
    "[ $rc -eq 2 ] && [ \$(wc -l <'$T/err.txt') -eq 1 ] && [ ! -e '$T/j/jobs2.txt' ] && [ ! -e '$T/j/${NAMES[7]}' ]"
  no_marks "sweep $act (a line break)"
done

summary
