#!/usr/bin/env bash
# The eye tracker as sweep axes (docs/cluster.md, docs/latency.md): gaze_latency, gaze_rate,
# gaze_noise and gaze_loss are lists like taa, gaze_seed one value; each task's compare gets the
# options, its name the values; merge adds the tracker columns; bad values get one line naming
# the JSON path.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/sweep_tracker
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
cd "$T" || exit 1

cat >m.json <<'EOF'
{
  "scenes": ["fence"],
  "gaze": ["builtin:demo_tour"],
  "modes": ["traditional", "hashed"],
  "width": 64, "height": 36, "frames": 3,
  "reference": {"supersample": 2},
  "cache": "cache",
  "gaze_latency": [0, 50],
  "gaze_loss": "full",
  "gaze_seed": 3
}
EOF
"$BIN" sweep m.json --list --out s >"$T/out.txt" 2>&1
check "--list: 2 tasks, one per latency" grep -q '^2 tasks (1 scene x 1 trace x 1 ring layout x 1 TAA setting x 2 tracker settings)' "$T/out.txt"
check "--list: each task's compare has its latency, the loss policy and the seed" bash -c \
  "grep -q \"'--gaze-latency' '0' '--gaze-loss' 'full' '--gaze-seed' '3'\" '$T/out.txt' &&
   grep -q \"'--gaze-latency' '50' '--gaze-loss' 'full' '--gaze-seed' '3'\" '$T/out.txt'"
check "--list: task names carry the values" grep -q 'fence.demo_tour.rings-default.taa-default.lat-50.loss-full.' "$T/out.txt"
"$BIN" sweep m.json --local 1 --out s --quiet >/dev/null 2>&1
check "--local 1 exits 0" test $? -eq 0
"$BIN" merge s >/dev/null 2>&1
check "merge exits 0" test $? -eq 0
check "merge: the tracker columns after the sweep's" bash -c \
  "head -1 s/metrics.csv | grep -q '^task,scene,gaze,rings,taa,gaze_latency,gaze_rate,gaze_noise,gaze_loss,frame,'"
check "merge: rows of both latencies" bash -c \
  "grep -q ',builtin:demo_tour,default,default,0,default,default,full,' s/metrics.csv && grep -q ',builtin:demo_tour,default,default,50,default,default,full,' s/metrics.csv"
check "merge: one accuracy point per latency and mode" test "$(tail -n +2 s/accuracy.csv | wc -l)" -eq 4
check "merge: summary.json names each task's latency" python3 -c "
import json,sys; s=json.load(open('s/summary.json'))
sys.exit(sorted(r['gaze_latency'] for r in s['results']) != ['0', '50'])"
check "the task's run record names its tracker" bash -c \
  "grep -q '^gaze tracker: latency 50 ms, rate trace, noise 0 deg seed 3, loss full' s/tasks/*lat-50*/fovsim-run.txt"

# ---- bad values: one line naming the JSON path, exit 2
printf '{"scenes": ["fence"], "gaze_latency": [0, -5]}' >bad1.json
expect_exit "a negative latency -> 2" 2 "$BIN" sweep bad1.json --list
check "  names gaze_latency[1]" grep -q 'bad1.json: gaze_latency\[1\]: expected a number in \[0, 10000\]' "$T/err.txt"
printf '{"scenes": ["fence"], "gaze_loss": ["hold", "blink"]}' >bad2.json
expect_exit "an unknown loss policy -> 2" 2 "$BIN" sweep bad2.json --list
check "  names gaze_loss[1]" grep -q 'bad2.json: gaze_loss\[1\]: expected "hold", "centre" or "full"' "$T/err.txt"
printf '{"scenes": ["fence"], "gaze_seed": 1.5}' >bad3.json
expect_exit "a fractional seed -> 2" 2 "$BIN" sweep bad3.json --list
printf '{"scenes": ["fence"], "options": ["--gaze-latency", "0,20"]}' >bad4.json
expect_exit "a latency list in options -> 2" 2 "$BIN" sweep bad4.json --list --out bad4
check "  points at the gaze_latency axis, nothing written" bash -c "grep -q 'the \"gaze_latency\" axis' '$T/err.txt' && test ! -e bad4"

summary
