#!/usr/bin/env bash
# A sweep task's identity is its whole configuration (docs/cluster.md "When a task is done"):
# after a complete run, editing the manifest's modes, size, reference, options or warm-up makes
# the tasks it changes "stale": --list says so naming the setting, merge refuses them (exit 2, one
# line naming the task and the setting), and the next run draws them again. Also: the sweep
# checks every scene and trace before it writes anything (a broken scene file fails --slurm with
# no sweep folder), and the jobs file gives each task LP_NUM_THREADS from cpus_per_task.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/sweep_identity
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
cd "$T" || exit 1

# manifest MODES WIDTH HEIGHT SUPERSAMPLE OPTIONS: the study, 4 frames in two chunks (--chunk-frames 2)
manifest() {
  cat >m.json <<EOF2
{ "scenes": ["fence"], "modes": [$1], "width": $2, "height": $3, "frames": 4,
  "reference": {"supersample": $4}, "options": [$5], "cache": "cache", "chunk_frames": 2, "warmup": 8 }
EOF2
}
# edited NAME SETTING STALE: after an edit, STALE tasks (of 2) are stale and named with SETTING;
# merge refuses them naming the task and SETTING; the next run draws exactly them again; merge is whole
edited() {
  "$BIN" sweep m.json --list --out s ${4:-} >"$T/list.txt" 2>&1
  check "$1: --list says $3 stale, naming '$2'" bash -c "grep -q ', $3 stale' '$T/list.txt' && grep -q \"another configuration: $2\" '$T/list.txt'"
  check "$1: none reported done" bash -c "grep -q '^$((2 - $3)) done' '$T/list.txt'"
  expect_exit "$1: merge refuses -> 2" 2 "$BIN" merge s
  check "$1:   naming the task and the setting" grep -q "s: task [01] (fence.*) holds another configuration than the manifest ($2" "$T/err.txt"
  "$BIN" sweep m.json --local 1 --out s ${4:-} >"$T/run.txt" 2>&1
  check "$1: the next run draws the $3 stale task(s) again" grep -q "^$3 tasks\? run ($3 of them stale" "$T/run.txt"
  "$BIN" merge s >/dev/null 2>&1
  check "$1: then merge takes them (exit 0)" test $? -eq 0
}

manifest '"traditional"' 64 36 1 ''
"$BIN" sweep m.json --local 1 --out s --quiet >/dev/null 2>&1
check "the sweep runs" test $? -eq 0
"$BIN" sweep m.json --local 1 --out s >"$T/run.txt" 2>&1
check "unchanged, the tasks are complete" grep -q '^0 tasks run, 2 already complete' "$T/run.txt"

manifest '"hashed"' 64 36 1 ''
edited "modes" "modes: 'hashed' now, 'traditional' there" 2
manifest '"hashed"' 48 27 1 ''
edited "size" "size: '48x27' now, '64x36' there" 2
manifest '"hashed"' 48 27 2 ''
edited "reference" "reference: 'kind 0, supersample 2" 2
manifest '"hashed"' 48 27 2 '"--hash-scale", "0.5"'
edited "options" "hash: 'scale 0.5" 2
# the warm-up changes only the chunk that starts after frame 0 (the first has no earlier frames)
edited "warm-up" "chunk: 'from frame 2, warm-up 3' now, 'from frame 2, warm-up 8' there" 1 "--warmup 3"

# ---- merge refuses a task folder holding another configuration (a folder copied in by hand)
cp -r s other && manifest '"traditional"' 48 27 2 '"--hash-scale", "0.5"'
"$BIN" sweep m.json --local 1 --out other --quiet --warmup 3 >/dev/null 2>&1
t0=$(ls -d s/tasks/*f00000* | head -1)
rm -rf other/tasks/*f00000*; cp -r "$t0" other/tasks/
rm -f other/metrics.csv other/summary.json other/accuracy.* other/report.html
expect_exit "merge of a folder holding another configuration -> 2" 2 "$BIN" merge other
check "  names the task and the setting" grep -q "task 0 (fence.*f00000-00001.*) holds another configuration than the manifest (modes: 'traditional' now, 'hashed' there)" "$T/err.txt"
check "  and writes nothing (no merged file, no temporary file)" test -z "$(ls -A other | grep -E '^metrics|^summary|^accuracy|^report|tmp')"

# ---- a broken scene file or trace is found when the sweep is built, before anything is written
printf '{"assets": [' >broken.json
printf '{ "scenes": ["broken.json"], "modes": ["hashed"] }' >bad_scene.json
expect_exit "a broken scene file -> 3 at --slurm" 3 "$BIN" sweep bad_scene.json --slurm --out bad_scene
check "  names the task and the file" grep -q 'bad_scene.json: task 0 .*broken.json' "$T/err.txt"
check "  and writes no sweep folder" test ! -e bad_scene
printf 'not,a,gaze,trace\n1,2\n' >broken.csv
printf '{ "scenes": ["fence"], "gaze": ["broken.csv"], "modes": ["hashed"] }' >bad_gaze.json
expect_exit "a broken gaze trace -> 5 at --jobs-file" 5 "$BIN" sweep bad_gaze.json --jobs-file bad_gaze.txt --out bad_gaze
check "  names the file" grep -q 'broken.csv' "$T/err.txt"
check "  and writes neither the jobs file nor the sweep folder" test ! -e bad_gaze.txt -a ! -e bad_gaze

# ---- the jobs file: LP_NUM_THREADS from cpus_per_task, unless set; a line runs through sh
manifest '"hashed"' 48 27 1 ''
"$BIN" sweep m.json --jobs-file jobs.txt --out jobs --cpus-per-task 3 >/dev/null 2>&1
check "jobs file: each line (2 tasks, a reference job per chunk) sets LP_NUM_THREADS from --cpus-per-task" \
  test "$(grep -c '^LP_NUM_THREADS=${LP_NUM_THREADS:-3} ' jobs.txt)" -eq 4 -a "$(wc -l <jobs.txt)" -eq 4 \
    -a "$(grep -c -e '--task ' jobs.txt)" -eq 2
grep -e '--task 0 ' jobs.txt | sh
check "  a line runs through sh and completes its task" grep -q '^complete: yes' jobs/tasks/*f00000*/fovsim-run.txt

summary
