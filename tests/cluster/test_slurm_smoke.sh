#!/usr/bin/env bash
# shellcheck source-path=SCRIPTDIR
# A real one-node Slurm (tests/cluster/slurm.sh; docs/cluster.md): an array job runs every task, at most
# %N at a time, and `sbatch --wait` reports a failing task; afterwards no daemon, job step or job
# of ours is left running. Twice in a row, in fresh folders. Label "slurm" (ctest -L slurm);
# exit 77 (skipped) without the packages.
set -uo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
. "$HERE/slurm.sh"
slurm_available_or_skip
# Short path under /tmp, not the build folder: munge's and slurmd's Unix sockets live in it
# (and mode 755: munged wants every folder above its socket open to all)
T=$(mktemp -d "${TMPDIR:-/tmp}/fovsim-slurm.XXXXXX") && chmod 755 "$T" && T=$(cd "$T" && pwd -P) || exit 1
. "$HERE/../cli/harness.sh"

orphans=()
cleanup() {
  local p
  slurm_down
  for p in "${orphans[@]}"; do                       # should round 2 not have run
    SLURM_TEST_DIR=$T/orphan _slurm_ours "$p" && kill -KILL "$p"
  done
  if [ "$failed" -eq 0 ]; then rm -rf "$T"; else echo "kept $T (configuration, logs, outputs)" >&2; fi
}
trap cleanup EXIT

now() { echo "${EPOCHREALTIME/,/.}"; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }

# The array task: its index and the CPUs it sees, its start and end times; task FAIL_TASK fails
cat >"$T/task.sh" <<'EOF'
#!/bin/bash
start=$EPOCHREALTIME
sleep 1
echo "task $SLURM_ARRAY_TASK_ID nproc $(nproc) start ${start/,/.} end ${EPOCHREALTIME/,/.}" \
  >"$SMOKE_OUT/task_$SLURM_ARRAY_TASK_ID.txt"
[ "$SLURM_ARRAY_TASK_ID" != "${FAIL_TASK:-none}" ] || exit 3
EOF
chmod +x "$T/task.sh"

# tasks_ran DIR N: task_0..N-1.txt each name their task and a CPU count
tasks_ran() {
  local i
  for ((i = 0; i < $2; i++)); do
    grep -qE "^task $i nproc [1-9][0-9]* start " "$1/task_$i.txt" 2>/dev/null ||
      { echo "  task $i wrote no result" >&2; return 1; }
  done
}
# at_most DIR K: no more than K tasks ran at the same time (their [start, end] intervals)
at_most() {
  cat "$1"/task_*.txt | awk -v k="$2" '{ s[NR] = $6; e[NR] = $8 }
    END { for (i = 1; i <= NR; i++) { n = 0
            for (j = 1; j <= NR; j++) if (s[j] <= s[i] && s[i] < e[j]) n++
            if (n > k) { print "  " n " tasks ran at once" > "/dev/stderr"; exit 1 } } }'
}
# slurm_outputs DIR JOB N: sbatch wrote DIR/JOB_0.out .. JOB_(N-1).out
slurm_outputs() {
  local i
  for ((i = 0; i < $3; i++)); do [ -f "$1/$2_$i.out" ] || { echo "  no $2_$i.out" >&2; return 1; }; done
}
# gave_up RC WHAT: after a timeout (124) there is no point going on: the cluster is stuck. (Worst
# case then: 30 s slurm_up + 120 s + 30 s slurm_down, inside ctest's 300 s.)
gave_up() {
  [ "$1" -eq 124 ] || return 0
  fail "$2 timed out"
  exit 1
}
# all_alive PID...: every one of these processes runs
all_alive() {
  local p
  [ $# -gt 0 ] || return 1
  for p in "$@"; do _slurm_alive "$p" || { echo "  pid $p is gone" >&2; return 1; }; done
}
# none_alive PID...: none of these processes runs
none_alive() {
  local p
  for p in "$@"; do _slurm_alive "$p" && { echo "  pid $p still running" >&2; return 1; }; done
  return 0
}
# nothing_left PID...: none of these processes, nor any other of the cluster, is running
nothing_left() {
  local left
  none_alive "$@" || return 1
  left=$(slurm_leftovers)
  [ -z "$left" ] || { echo "  still running: $left" >&2; return 1; }
}

# Round 1: sbatch --wait, as the sweep's Slurm test submits. sbatch --wait polls after 2 s, 8 s
# later, then every 32 s: each array below ends within the first 10 s.
echo "== round 1: sbatch --wait"
t0=$(now)
slurm_up "$T/cluster1" || { fail "round 1: slurm_up"; exit 1; }
echo "slurm: node $SLURM_TEST_NODE idle after $(since "$t0") s ($(sed -n 's/^AuthType=//p' "$SLURM_CONF"))"
daemons=("${_slurm_pids[@]}")
_slurm_reap_orphans
check "round 1: the sweep for killed tests' clusters leaves a live one alone" all_alive "${daemons[@]}"

# 4 tasks, at most 2 at a time
out=$T/out1; mkdir -p "$out"
t0=$(now)
job=$(SMOKE_OUT=$out timeout 120 sbatch --parsable --array=0-3%2 --wait \
        --output="$out/%A_%a.out" "$T/task.sh"); rc=$?
echo "slurm: 4-task array (job ${job:-?}) done after $(since "$t0") s, exit $rc"
gave_up "$rc" "round 1: sbatch --wait"
check "round 1: sbatch --wait exits 0" [ "$rc" -eq 0 ]
check "round 1: all 4 array tasks ran" tasks_ran "$out" 4
check "round 1: %2 keeps at most 2 tasks running" at_most "$out" 2
check "round 1: one output file per task (%A_%a)" slurm_outputs "$out" "$job" 4
cat "$out"/task_*.txt

# sbatch --wait exits with the highest exit status of the array's tasks
out=$T/fail1; mkdir -p "$out"
t0=$(now)
SMOKE_OUT=$out FAIL_TASK=1 timeout 120 sbatch --quiet --array=0-2 --wait \
  --output="$out/%A_%a.out" "$T/task.sh"; rc=$?
echo "slurm: 3-task array, task 1 failing, done after $(since "$t0") s, exit $rc"
gave_up "$rc" "round 1: sbatch --wait"
check "round 1: a failing array task makes sbatch --wait exit 3 (its status)" [ "$rc" -eq 3 ]
check "round 1: the other tasks of that array ran" tasks_ran "$out" 3

t0=$(now)
slurm_down
echo "slurm: stopped after $(since "$t0") s"
check "round 1: no daemon, step or job of ours left after slurm_down" nothing_left "${daemons[@]}"

# A test killed with SIGKILL (ctest's timeout, kill -9) runs no trap: here a subshell that starts
# a cluster and kills itself. Its daemons stay; the next slurm_up (round 2's) must remove them.
{ ( slurm_up "$T/orphan" >/dev/null; echo "${_slurm_pids[*]}" >"$T/orphan.pids"; kill -KILL "$BASHPID" ); } 2>/dev/null
read -ra orphans <"$T/orphan.pids"
check "a killed test's cluster stays behind (the case for round 2)" all_alive "${orphans[@]}"

# Round 2, right after, in a fresh folder: the same arrays, waited for with slurm_wait
echo "== round 2: slurm_wait"
t0=$(now)
slurm_up "$T/cluster2" || { fail "round 2: slurm_up"; exit 1; }
echo "slurm: node $SLURM_TEST_NODE idle after $(since "$t0") s"
daemons=("${_slurm_pids[@]}")
check "round 2: slurm_up removed the killed test's cluster" none_alive "${orphans[@]}"
out=$T/out2 fails=$T/fail2; mkdir -p "$out" "$fails"
t0=$(now)
job=$(SMOKE_OUT=$out timeout 20 sbatch --parsable --array=0-3%2 --output="$out/%A_%a.out" "$T/task.sh")
failing=$(SMOKE_OUT=$fails FAIL_TASK=1 timeout 20 sbatch --parsable --array=0-2 \
            --output="$fails/%A_%a.out" "$T/task.sh")
if [ -z "$job" ] || [ -z "$failing" ]; then fail "round 2: sbatch submitted nothing"; exit 1; fi
slurm_wait "$job" 60; rc=$?
echo "slurm: 4-task array (job $job) done after $(since "$t0") s, exit $rc"
gave_up "$rc" "round 2: slurm_wait"
check "round 2: slurm_wait returns 0" [ "$rc" -eq 0 ]
check "round 2: all 4 array tasks ran" tasks_ran "$out" 4
check "round 2: %2 keeps at most 2 tasks running" at_most "$out" 2
slurm_wait "$failing" 60; rc=$?
echo "slurm: 3-task array, task 1 failing, (job $failing) done after $(since "$t0") s, exit $rc"
gave_up "$rc" "round 2: slurm_wait"
check "round 2: slurm_wait returns 3 for the failing array" [ "$rc" -eq 3 ]
check "round 2: the other tasks of that array ran" tasks_ran "$fails" 3

t0=$(now)
slurm_down
echo "slurm: stopped after $(since "$t0") s"
check "round 2: no daemon, step or job of ours left after slurm_down" nothing_left "${daemons[@]}"
summary
