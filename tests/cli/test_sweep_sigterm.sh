#!/usr/bin/env bash
# SIGTERM and SIGINT to `fovsim sweep --local 2` reach its running tasks (docs/cluster.md "Resume",
# run_local since issue 28): the sweep passes the signal on, waits for both task processes, says
# both were stopped and exits 130; afterwards no task process is left (checked by PID).
# tests/cli/test_bounds.sh part 11 checks SIGTERM too; this adds SIGINT and "both stopped".
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/sweep_sigterm
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
cd "$T" || exit 1

# two tasks (two traces) long enough to be running when the signal comes
cat >m.json <<'EOF2'
{ "scenes": ["fence"], "gaze": ["builtin:demo_tour", "centre"], "modes": ["hashed"],
  "width": 48, "height": 27, "frames": 1500, "reference": {"supersample": 1}, "cache": "cache" }
EOF2

# stop SIGNAL: starts the sweep, waits until both tasks run, sends SIGNAL to the sweep alone
stop() {
  "$BIN" sweep m.json --local 2 --out s --quiet >"$T/run.txt" 2>&1 &
  local pid=$! kids=""
  for _ in $(seq 1 500); do
    kids=$(pgrep -P $pid | tr '\n' ' ')
    [ "$(wc -w <<<"$kids")" -eq 2 ] && break
    sleep 0.02
  done
  check "$1: both tasks started (pids $kids)" test "$(wc -w <<<"$kids")" -eq 2
  sleep 0.3
  kill -"$1" $pid
  wait $pid; local rc=$?
  check "$1: the sweep exits 130" test $rc -eq 130
  check "$1:   saying both tasks were stopped" grep -q "interrupted (SIG$1): 0 of 2 tasks finished, 2 stopped" "$T/run.txt"
  local left=""
  for k in $kids; do kill -0 "$k" 2>/dev/null && left="$left $k"; done
  check "$1: no task process left running (was:$kids)" test -z "$left"
  for k in $left; do kill -KILL "$k"; done
}
stop TERM
stop INT

summary
