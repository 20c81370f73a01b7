#!/usr/bin/env bash
# fovsim sweep and merge (docs/cluster.md): one task list run serially, --local 2 and through GNU parallel
# gives the same metrics (byte-identical rows apart from the timing column); a task killed with
# SIGKILL is redone on the next run; merge reports a missing task; frame chunks cover every frame
# once and, with the whole history as warm-up, equal an unbroken run; bad manifests get one line
# naming the JSON path. The Slurm run of the same sweep is tests/cluster/test_slurm_sweep.sh.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SRC=${FOVSIM_SOURCE:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/sweep
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
cd "$T" || exit 1

# metrics without the timing column (frame_ms, the last), for comparing runs
untimed() { rev "$1" | cut -d, -f2- | rev; }
same_metrics() { cmp -s <(untimed "$1/metrics.csv") <(untimed "$2/metrics.csv"); }

# 2 scenes x 2 traces x 2 modes, tiny
cat >m.json <<'EOF'
{
  "scenes": ["fence", "tree"],
  "gaze": ["builtin:demo_tour", "centre"],
  "modes": ["traditional", "hashed"],
  "width": 64, "height": 36, "frames": 3,
  "reference": {"supersample": 2},
  "cache": "cache"
}
EOF
"$BIN" sweep m.json --list --out serial >"$T/out.txt" 2>&1
check "--list exits 0" test $? -eq 0
check "--list: 4 tasks, all to do" grep -q '^0 done, 0 incomplete, 4 to do' "$T/out.txt"
check "--list: each task's compare command" test "$(grep -c "'fovsim' 'compare'" "$T/out.txt")" -eq 4
"$BIN" sweep m.json --local 1 --out serial --quiet >/dev/null 2>&1
check "--local 1 exits 0" test $? -eq 0
"$BIN" merge serial >"$T/out.txt" 2>&1
check "merge exits 0" test $? -eq 0
check "merge: 4 tasks x 3 frames x 2 modes x 2 rows (a ring and the display)" test "$(tail -n +2 serial/metrics.csv | wc -l)" -eq 48
check "merge: the sweep's columns first" bash -c "head -1 serial/metrics.csv | grep -q '^task,scene,gaze,rings,taa,frame,time,mode,ring,'"
check "merge: summary.json lists 4 complete tasks" python3 -c "
import json,sys; s=json.load(open('serial/summary.json'))
sys.exit(not (s['complete'] == 4 and len(s['results']) == 4 and s['missing_or_incomplete'] == [] and s['results'][0]['summary']['modes']))"
check "merge: one accuracy point per configuration and mode" test "$(tail -n +2 serial/accuracy.csv | wc -l)" -eq 8
command -v gnuplot >/dev/null && check "merge: the accuracy-vs-time plot" test -s serial/accuracy.png
check "sweep tasks write no previews unless their options ask (--previews 0)" bash -c "test -d serial/tasks && ! ls -d serial/tasks/*/preview 2>/dev/null | grep -q ."
check "merge: report.html with each task's table and the accuracy plot with its front" bash -c \
  "grep -q 'id=\"accuracy\"' serial/report.html && grep -q 'Pareto front' serial/report.html && [ \$(grep -c '<h2>Task ' serial/report.html) -eq 4 ]"

"$BIN" sweep m.json --local 2 --out local2 --quiet >/dev/null 2>&1
check "--local 2 exits 0" test $? -eq 0
"$BIN" merge local2 >/dev/null 2>&1
check "--local 2 gives the serial run's metrics" same_metrics serial local2
"$BIN" sweep m.json --local 2 --out local2 >"$T/out.txt" 2>&1
check "a second run skips the completed tasks" grep -q '^0 tasks run, 4 already complete, 0 failed' "$T/out.txt"

if command -v parallel >/dev/null; then
  "$BIN" sweep m.json --jobs-file jobs.txt --out jobs >/dev/null 2>&1
  check "--jobs-file: one line per reference job (2 scenes), then per task" test "$(wc -l <jobs.txt)" -eq 6
  timeout 300 parallel --will-cite --jobs 2 --joblog jobs/joblog <jobs.txt
  check "the jobs file through GNU parallel exits 0" test $? -eq 0
  "$BIN" merge jobs >/dev/null 2>&1
  check "GNU parallel gives the serial run's metrics" same_metrics serial jobs
else
  echo "note: GNU parallel is not installed (apt-get install parallel); the jobs-file run did not run" >&2
fi

# ---- SIGKILL a task mid-way, run the sweep again: it completes, the metrics equal the serial run's
"$BIN" sweep m.json --list --out killed >/dev/null 2>&1
FOVSIM_SWEEP=$(ls killed/manifest-*.json)
"$BIN" sweep "$FOVSIM_SWEEP" --task 2 >/dev/null 2>&1 &
pid=$!
for _ in $(seq 1 300); do
  [ -n "$(ls killed/tasks/tree.demo_tour.*/compare.0000.exr 2>/dev/null)" ] && break
  kill -0 $pid 2>/dev/null || break; sleep 0.02
done
kill -KILL $pid 2>/dev/null; wait $pid 2>/dev/null
"$BIN" sweep m.json --list --out killed >"$T/out.txt" 2>&1
grep -q 'incomplete' "$T/out.txt" || echo "note: the killed task had finished before the kill" >&2
"$BIN" sweep m.json --local 2 --out killed --quiet >/dev/null 2>&1
check "after a SIGKILL the sweep runs to the end" test $? -eq 0
"$BIN" merge killed >/dev/null 2>&1
check "after a SIGKILL the metrics equal the serial run's" same_metrics serial killed

# ---- merge with a task folder removed: named, exit 11
cp -r serial partial
rm -rf partial/tasks/fence.centre.*
expect_exit "merge with a task missing -> 11" 11 "$BIN" merge partial
check "merge names the missing task" grep -q '^task 1 (fence.centre.rings-default.taa-default.[0-9a-f]*): missing' "$T/out.txt"
check "merge still writes what it has" test "$(tail -n +2 partial/metrics.csv | wc -l)" -eq 36

# ---- chunks: the held grazing study cuts at 2 s and 4 s (frames 8 and 16 at 4 fps)
cat >c.json <<EOF
{ "scenes": ["$SRC/scenes/studies/fence_grazing_2m_held.json"], "modes": ["hashed"],
  "width": 48, "height": 27, "fps": 4, "frames": 20, "reference": {"supersample": 1}, "cache": "cache" }
EOF
"$BIN" sweep c.json --local 2 --out whole --quiet >/dev/null 2>&1 && "$BIN" merge whole >/dev/null 2>&1
check "an unbroken sequence as one task" test $? -eq 0
# chunks of 7 frames: boundaries 7 -> 8 (the cut), 14 -> 16 (the cut, within 7/4), then 21 is past the end
"$BIN" sweep c.json --list --out cuts --chunk-frames 7 >"$T/out.txt" 2>&1
check "chunk boundaries move to the cuts" bash -c "grep -q 'f00000-00007' '$T/out.txt' && grep -q 'f00008-00015' '$T/out.txt' && grep -q 'f00016-00019' '$T/out.txt'"
"$BIN" sweep c.json --local 2 --out cuts --chunk-frames 7 --quiet >/dev/null 2>&1 && "$BIN" merge cuts >/dev/null 2>&1
check "chunks at the cuts: 3 tasks merged" test $? -eq 0
check "chunks at the cuts equal the unbroken run (no warm-up needed)" \
  cmp -s <(untimed whole/metrics.csv | cut -d, -f6-) <(untimed cuts/metrics.csv | cut -d, -f6-)
# chunks of 5 frames with a warm-up longer than the sequence: the same frames as the unbroken run
"$BIN" sweep c.json --local 2 --out full_warm --chunk-frames 5 --warmup 1000 --quiet >/dev/null 2>&1 && "$BIN" merge full_warm >/dev/null 2>&1
check "chunks with the whole history as warm-up equal the unbroken run" \
  cmp -s <(untimed whole/metrics.csv | cut -d, -f6-) <(untimed full_warm/metrics.csv | cut -d, -f6-)
# a short warm-up: every frame still measured exactly once
"$BIN" sweep c.json --local 2 --out short_warm --chunk-frames 5 --warmup 1 --quiet >/dev/null 2>&1 && "$BIN" merge short_warm >/dev/null 2>&1
check "chunks with a short warm-up: every frame once" \
  test "$(tail -n +2 short_warm/metrics.csv | cut -d, -f6 | sort -n | uniq -c | awk '{print $1}' | sort -u | tr '\n' ' ')" = "2 "

# ---- bad manifests: one line naming the JSON path, exit 2
printf '{"scenes": ["fence"], "modez": ["hashed"]}' >bad1.json
expect_exit "an unknown key -> 2" 2 "$BIN" sweep bad1.json
check "  names it and what is allowed" grep -q 'bad1.json: modez: unknown key (expected one of: scenes, gaze' "$T/err.txt"
printf '{"gaze": ["centre"]}' >bad2.json
expect_exit "no scenes -> 2" 2 "$BIN" sweep bad2.json
printf '{"scenes": ["fence"], "modes": ["hashed", "hashd"]}' >bad3.json
expect_exit "a bad mode -> 2" 2 "$BIN" sweep bad3.json
check "  names modes[1]" grep -q "bad3.json: modes: \[1\]: 'hashd': expected an alpha mode" "$T/err.txt"
printf '{"scenes": ["fence"],\n "taa": ["maybe"]}' >bad4.json
expect_exit "a bad TAA setting -> 2" 2 "$BIN" sweep bad4.json
printf '{"scenes": ["fence"],\n "gaze": ["nowhere.csv"]}' >bad5.json
expect_exit "a missing gaze file -> 2" 2 "$BIN" sweep bad5.json
check "  names the file" grep -q 'bad5.json: gaze: \[0\]: .*nowhere.csv: expected a readable gaze trace' "$T/err.txt"
printf '{"scenes": ["fence"],\n "width": 64,,}' >bad6.json
expect_exit "invalid JSON -> 2 with line and column" 2 "$BIN" sweep bad6.json
check "  file:line:column" grep -q 'bad6.json:2:' "$T/err.txt"
printf '{"scenes": ["fence"], "rings": ["10:1:0,*:3:0"]}' >bad7.json
expect_exit "a bad ring layout -> 2, checked before anything runs" 2 "$BIN" sweep bad7.json --local 1 --out bad7
check "  names the task" grep -q 'bad7.json: task 0 .*--rings' "$T/err.txt"
check "  no task ran" test -z "$(ls bad7/tasks 2>/dev/null)"
expect_exit "--task past the end -> 2" 2 "$BIN" sweep m.json --task 9 --out serial
expect_exit "merge of a folder that is no sweep -> 6" 6 "$BIN" merge "$T/nowhere"
expect_exit "--wait without --submit -> 2" 2 "$BIN" sweep m.json --slurm --wait

# ---- the Slurm script (submitting it is the slurm-labelled test)
"$BIN" sweep m.json --slurm --out serial --cpus-per-task 3 --mem 2G --max-running 2 >/dev/null 2>&1
check "--slurm writes an array script" grep -q '^#SBATCH --array=0-3%2$' serial/sweep.sbatch
check "  with the resources" bash -c "grep -q '^#SBATCH --cpus-per-task=3$' serial/sweep.sbatch && grep -q '^#SBATCH --mem=2G$' serial/sweep.sbatch"
check "  and per-task log paths" grep -q '^#SBATCH --output=.*/logs/slurm-%A_%a.out$' serial/sweep.sbatch
check "  that runs the task of its index" grep -q 'sweep .*manifest-[0-9a-f]*.json'"'"' --task "$SLURM_ARRAY_TASK_ID"$' serial/sweep.sbatch

summary
