#!/usr/bin/env bash
# An output folder has one writer at a time (README "Output folders"): while a
# render writes DIR, a second one into DIR, with --replace or --resume, is refused with one line
# naming the first (pid, host) and exit 12; with --wait-lock S it waits, then runs, and DIR ends
# with its frames only, under its own complete record; a wait that runs out is refused the same
# way; a lock file a killed run left (unlocked) does not block; a sweep task whose folder another
# process holds is refused. Every wait is bounded (timeout, bounded polls); no timing is judged:
# the first run is held still with SIGSTOP once it holds the lock.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/lock
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
cd "$T" || exit 1

D="$T/dir"
SMALL=(fence --width 64 --height 36 --quiet)
# wait_for SECONDS CMD...: polls CMD every 0.1 s until it succeeds (status 0) or SECONDS pass (1)
wait_for() { local n=$(($1 * 10)); shift; while [ "$n" -gt 0 ]; do "$@" && return 0; sleep 0.1; n=$((n - 1)); done; return 1; }

# A: a render of many frames (it would take minutes), held still once it holds DIR's lock
timeout 600 "$BIN" render "${SMALL[@]}" --frames 100000 --alpha traditional --out "$D" >"$T/a.out" 2>"$T/a.err" &
A_JOB=$!
check "the first run takes DIR's lock and names itself in it" wait_for 120 grep -qs '^pid [0-9]* on host .*, fovsim render, since ' "$D/fovsim-run.lock"
A=$(awk '{print $2; exit}' "$D/fovsim-run.lock" 2>/dev/null)
check "  and writes its first frame" wait_for 120 test -f "$D/frame.0000.exr"
if [ -n "$A" ]; then kill -STOP "$A"; else kill "$A_JOB"; fi  # no lock: end the first run now (it fails below)

# B: another configuration with --replace, and the same one with --resume: refused, one line each
expect_exit "--replace into a folder another run writes -> 12" 12 timeout 120 "$BIN" render "${SMALL[@]}" --frames 3 --alpha hashed --replace --out "$D"
check "  naming DIR and the other run's pid and host" grep -q "dir: another run is writing this folder (pid $A on host " "$T/err.txt"
expect_exit "--resume of the same configuration -> 12" 12 timeout 120 "$BIN" render "${SMALL[@]}" --frames 100000 --alpha traditional --resume --out "$D"
check "the first run's frames are untouched" test -f "$D/frame.0000.exr"
timeout 120 "$BIN" render "${SMALL[@]}" --frames 3 --alpha hashed --replace --wait-lock 1 --out "$D" >"$T/out.txt" 2>"$T/err.txt"
check "--wait-lock 1 runs out -> 12" test $? -eq 12
check "  saying it waited, naming the other run" grep -q "dir: another run is still writing this folder after 1 s (pid $A on host " "$T/err.txt"

# C: --wait-lock waits (it says so), then runs once the first run has ended (interrupted here)
timeout 300 "$BIN" render "${SMALL[@]}" --frames 3 --alpha hashed --replace --wait-lock 300 --out "$D" >"$T/c.out" 2>"$T/c.err" &
C_JOB=$!
check "--wait-lock waits for the other run, saying so" wait_for 120 grep -qs "dir: another run is writing this folder (pid $A on host .*); waiting up to 300 s" "$T/c.err"
check "  and has not touched the folder" test -f "$D/frame.0000.exr"
[ -n "$A" ] && kill -INT "$A" && kill -CONT "$A"
wait "$A_JOB"; a_rc=$?
check "the first run stops at Ctrl-C (130)" test "$a_rc" -eq 130
wait "$C_JOB"; c_rc=$?
check "then the waiting run runs (exit 0)" test "$c_rc" -eq 0
check "DIR holds the waiting run's 3 frames only" test "$(ls "$D" | grep -c '\.exr$')" -eq 3
check "  each of them its configuration (hashed)" bash -c "for f in '$D'/frame.000[012].exr; do exrheader \"\$f\" | grep -q 'fovsim:alpha_mode.*hashed' || exit 1; done"
check "  under its own record, complete" bash -c "grep -q '^alpha: hashed$' '$D/fovsim-run.txt' && grep -q '^complete: yes$' '$D/fovsim-run.txt'"
check "  and the lock file is gone with the run" test ! -e "$D/fovsim-run.lock"

# A lock file a killed run left behind is not a lock
echo "pid 999999 on host gone, fovsim render, since 2000-01-01 00:00:00 UTC" >"$D/fovsim-run.lock"
timeout 300 "$BIN" render "${SMALL[@]}" --frames 3 --alpha hashed --out "$D" >/dev/null 2>"$T/err.txt"
check "a stale, unlocked lock file does not block a run" test $? -eq 0

# A sweep task's folder: the same lock (held here by flock(1), as another machine's task would)
cat >m.json <<'EOF2'
{ "scenes": ["fence"], "modes": ["traditional"], "width": 64, "height": 36, "frames": 2,
  "reference": {"supersample": 1}, "cache": "cache" }
EOF2
TASK=$(timeout 60 "$BIN" sweep m.json --list --out sw 2>/dev/null | awk '$1 == "0" {print $3; exit}')
check "the sweep lists its task" test -n "$TASK"
mkdir -p "sw/tasks/$TASK"
expect_exit "a sweep task whose folder another process holds -> 12" 12 \
  timeout 120 flock "sw/tasks/$TASK/fovsim-run.lock" timeout 120 "$BIN" sweep m.json --task 0 --out sw --quiet
check "  naming the task's folder" grep -q "tasks/$TASK: another run is writing this folder" "$T/err.txt"
check "  and drawing nothing there" bash -c "! ls 'sw/tasks/$TASK'/*.exr 2>/dev/null"
timeout 300 "$BIN" sweep m.json --task 0 --out sw --quiet >/dev/null 2>"$T/err.txt"
check "the same task runs once the folder is free" bash -c "test $? -eq 0 && grep -q '^complete: yes$' 'sw/tasks/$TASK/fovsim-run.txt'"

summary
