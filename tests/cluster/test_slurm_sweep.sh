#!/usr/bin/env bash
# fovsim sweep on a real (one-node) Slurm (docs/cluster.md): the 2 scenes x 2 traces x 2 modes sweep of
# tests/cli/test_sweep.sh submitted as an array with `fovsim sweep --slurm --submit --wait`, merged,
# and compared with a serial run of the same manifest (byte-identical metrics apart from the timing
# column); then a second submission skips every task. Exits 77 (skipped) without the packages.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/slurm_sweep
HERE=$(cd "$(dirname "$0")" && pwd)
. "$HERE/slurm.sh"
slurm_available_or_skip
rm -rf "$T"; mkdir -p "$T"
. "$HERE/../cli/harness.sh"
cd "$T" || exit 1

cat >m.json <<'EOF'
{
  "scenes": ["fence", "tree"],
  "gaze": ["builtin:demo_tour", "centre"],
  "modes": ["traditional", "hashed"],
  "width": 64, "height": 36, "frames": 3,
  "reference": {"supersample": 2},
  "cache": "cache",
  "slurm": {"cpus_per_task": 1, "time": "00:10:00"}
}
EOF
untimed() { rev "$1" | cut -d, -f2- | rev; }

"$BIN" sweep m.json --local 1 --out serial --quiet >/dev/null 2>&1 && "$BIN" merge serial >/dev/null 2>&1
check "the serial run" test $? -eq 0

trap slurm_down EXIT
slurm_up "$T/cluster"
timeout 300 "$BIN" sweep m.json --slurm --submit --wait --out onslurm >"$T/out.txt" 2>&1
rc=$?
check "sweep --slurm --submit --wait exits 0 (exit $rc)" test $rc -eq 0
[ $rc -eq 0 ] || { cat "$T/out.txt" >&2; cat onslurm/logs/*.err >&2 2>/dev/null; }
check "sbatch said the job was submitted" grep -q 'Submitted batch job' "$T/out.txt"
check "one output and one error file per array task" test "$(ls onslurm/logs/slurm-*_*.out | wc -l)" -eq 4
"$BIN" merge onslurm >/dev/null 2>&1
check "merge of the Slurm run exits 0" test $? -eq 0
check "the Slurm array gives the serial run's metrics" cmp -s <(untimed serial/metrics.csv) <(untimed onslurm/metrics.csv)
timeout 300 "$BIN" sweep m.json --slurm --submit --wait --out onslurm >/dev/null 2>&1
check "a second submission exits 0" test $? -eq 0
check "  and skips every completed task" test "$(cat onslurm/logs/slurm-*_*.out | grep -c 'complete, skipped')" -eq 4
slurm_down
trap - EXIT
check "no Slurm daemon of the test is left" test -z "$(slurm_leftovers)"

summary
