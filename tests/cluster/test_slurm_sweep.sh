#!/usr/bin/env bash
# fovsim sweep on a real (one-node) Slurm (docs/cluster.md) whose MaxArraySize is 5: a 12-task sweep
# (2 scenes x 2 traces x 3 TAA settings, 2 modes each) is split into three task arrays (5 + 5 + 2)
# after one reference array (a job per scene), submitted with `fovsim sweep --slurm --submit
# --wait`, merged, and compared with a serial run of the same manifest (byte-identical metrics
# apart from the timing column). Then one task is resubmitted and cancelled with scancel before it
# runs: the next submission submits exactly that one index; a third submits nothing.
# Exits 77 (skipped) without the packages.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/slurm_sweep
HERE=$(cd "$(dirname "$0")" && pwd)
. "$HERE/slurm.sh"
slurm_available_or_skip
rm -rf "$T"; mkdir -p "$T"
. "$HERE/../cli/harness.sh"
cd "$T" || exit 1

cat >m.json <<'JSON'
{
  "scenes": ["fence", "tree"],
  "gaze": ["builtin:demo_tour", "centre"],
  "taa": ["default", "on", "off"],
  "modes": ["traditional", "hashed"],
  "width": 64, "height": 36, "frames": 3,
  "reference": {"supersample": 2},
  "cache": "cache",
  "slurm": {"cpus_per_task": 1, "time": "00:10:00"}
}
JSON
# The Slurm run with a cache of its own, so that its reference jobs draw
sed 's/"cache": "cache"/"cache": "cache-slurm"/' m.json >ms.json
untimed() { rev "$1" | cut -d, -f2- | rev; }
jobs_in() { grep -c '^submitted batch job' "$1"; }

"$BIN" sweep m.json --local 2 --out serial --quiet >/dev/null 2>&1 && "$BIN" merge serial >/dev/null 2>&1
check "the serial run" test $? -eq 0

trap slurm_down EXIT
SLURM_TEST_CONF_EXTRA="MaxArraySize=5" slurm_up "$T/cluster"
timeout 300 "$BIN" sweep ms.json --slurm --submit --wait --out onslurm >"$T/out.txt" 2>&1
rc=$?
check "sweep --slurm --submit --wait exits 0 (exit $rc)" test $rc -eq 0
[ $rc -eq 0 ] || { cat "$T/out.txt" >&2; cat onslurm/logs/*.err >&2 2>/dev/null; }
check "MaxArraySize read from the cluster" grep -q 'at most 5 indices: MaxArraySize from scontrol show config' "$T/out.txt"
check "three task arrays and one reference array submitted" \
  test "$(grep -c '^submitted batch job .*/sweep-[0-2].sbatch, ' "$T/out.txt"):$(grep -c '^submitted batch job .*/references.sbatch, 2 reference jobs' "$T/out.txt")" = 3:1
check "  the last array with the 2 tasks left over" grep -q 'sweep-2.sbatch, 2 tasks (--array=0-1)' "$T/out.txt"
check "  each of the three with its index offset" \
  bash -c 'grep -q "SLURM_ARRAY_TASK_ID\"\$" onslurm/sweep-0.sbatch && grep -q "SLURM_ARRAY_TASK_ID + 5))\"\$" onslurm/sweep-1.sbatch && grep -q "SLURM_ARRAY_TASK_ID + 10))\"\$" onslurm/sweep-2.sbatch'
check "one output file per task, one per reference job" \
  test "$(ls onslurm/logs/slurm-*_*.out | wc -l):$(ls onslurm/logs/ref-*_*.out | wc -l)" = 12:2
check "the job names derive from the manifest" grep -q '^#SBATCH --job-name=fovsim-ms$' onslurm/sweep-1.sbatch
check "each reference job drew its scene's 3 frames" test "$(cat onslurm/logs/ref-*_*.out | grep -c ': 3 frames drawn, 0 from the cache')" -eq 2
check "  and every task read all 3 from the cache" \
  test "$(cat onslurm/tasks/*/summary.json | grep -c '"frames_from_cache": 3}')" -eq 12
"$BIN" merge onslurm >/dev/null 2>&1
check "merge of the Slurm run exits 0" test $? -eq 0
check "the Slurm arrays give the serial run's metrics" cmp -s <(untimed serial/metrics.csv) <(untimed onslurm/metrics.csv)

# Task 7 (the second array's index 2) cancelled for real: its folder removed, the node drained so
# that the submitted jobs stay pending, task 7's array task cancelled with scancel, the node back
t7=$("$BIN" sweep ms.json --list --out onslurm | awk '$1 == 7 { print $3 }')
rm -rf "onslurm/tasks/$t7"
scontrol update NodeName="$SLURM_TEST_NODE" State=DRAIN Reason=fovsim-test
timeout 60 "$BIN" sweep ms.json --slurm --submit --out onslurm >"$T/out_c.txt" 2>&1
ref=$(sed -n 's|^submitted batch job \([0-9]*\): .*/references.sbatch, .*|\1|p' "$T/out_c.txt")
job=$(sed -n 's|^submitted batch job \([0-9]*\): .*/sweep-1.sbatch, 1 task (--array=2)$|\1|p' "$T/out_c.txt")
check "task 7 submitted alone, pending on a drained node" test -n "$ref" -a -n "$job"
scancel "${job}_2"
scontrol update NodeName="$SLURM_TEST_NODE" State=RESUME
slurm_wait "$ref" 120; slurm_wait "$job" 120
check "  cancelled: task 7 is still to do" \
  bash -c "'$BIN' sweep ms.json --list --out onslurm | grep -q '^   7  todo '"
timeout 300 "$BIN" sweep ms.json --slurm --submit --wait --out onslurm >"$T/out2.txt" 2>&1
check "the resubmission after the cancellation exits 0" test $? -eq 0
check "  says it skips 11 complete tasks" grep -q '^11 of 12 tasks complete, skipped; submitting 1$' "$T/out2.txt"
check "  submits exactly one task index: 2 of sweep-1" grep -q 'sweep-1.sbatch, 1 task (--array=2)$' "$T/out2.txt"
check "  and the one reference job of its scene" test "$(jobs_in "$T/out2.txt")" -eq 2
check "  which ran once" test "$(ls onslurm/logs/slurm-*_*.out | wc -l)" -eq 13
"$BIN" merge onslurm >/dev/null 2>&1
check "  merge then equals the serial run again" cmp -s <(untimed serial/metrics.csv) <(untimed onslurm/metrics.csv)
timeout 300 "$BIN" sweep ms.json --slurm --submit --wait --out onslurm >"$T/out3.txt" 2>&1
check "a third submission exits 0 and submits nothing" \
  test "$?:$(jobs_in "$T/out3.txt")" = 0:0
check "  saying that every task is complete" grep -q '^12 of 12 tasks complete, skipped; submitting 0$' "$T/out3.txt"
slurm_down
trap - EXIT
check "no Slurm daemon of the test is left" test -z "$(slurm_leftovers)"

summary
