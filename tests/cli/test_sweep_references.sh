#!/usr/bin/env bash
# fovsim sweep draws each reference frame once (docs/cluster.md "References first"): a sweep of 4
# tasks over one scene plans one reference job, runs it first (--local 2: beside the first task,
# which waits for the cache entries the job draws, reference.c's lock per entry), and between them
# the 3 frames are drawn 3 times, not 4 x 3; two compares started together on one fresh cache draw
# each frame once too. Also the scripts: the jobs file's reference line first, Slurm arrays split
# at --max-array-size with their offsets, job names, --requeue and --open-mode=append.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/sweep_references
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
cd "$T" || exit 1

cat >m.json <<'JSON'
{
  "scenes": ["fence"],
  "gaze": ["builtin:demo_tour", "centre"],
  "taa": ["on", "off"],
  "modes": ["traditional", "hashed"],
  "width": 96, "height": 54, "frames": 3,
  "reference": {"supersample": 3},
  "cache": "cache"
}
JSON
# frames a task drew itself: 3 minus those it read from the cache (its summary.json)
task_draws() {
  python3 -c "
import json, glob
print(sum(3 - json.load(open(f))['reference']['frames_from_cache'] for f in glob.glob('$1/tasks/*/summary.json')))"
}
ref_draws() { sed -n 's/^reference job [0-9]* .*: \([0-9]*\) frames\{0,1\} drawn.*/\1/p' "$1"/logs/ref-*.log | paste -sd+ | bc; }

"$BIN" sweep m.json --local 2 --out local >"$T/out.txt" 2>&1
check "--local 2 exits 0" test $? -eq 0
check "  one reference job, its log" test "$(ls local/logs/ref-*.log | wc -l)" -eq 1
check "  4 tasks" grep -q '^4 tasks run, 0 already complete, 0 failed' "$T/out.txt"
draws=$(( $(ref_draws local) + $(task_draws local) ))
check "  each of the 3 reference frames drawn once in all (drawn $draws times)" test "$draws" -eq 3
check "  3 entries in the cache" test "$(ls cache/ref-*.exr | wc -l)" -eq 3
"$BIN" merge local >/dev/null 2>&1
check "  merge exits 0" test $? -eq 0

# Two compares together on a fresh cache: the entry's lock makes one wait for the other's frame
args=(compare fence --modes hashed --width 96 --height 54 --frames 3 --supersample 3 --cache cache2 --previews 0)
"$BIN" "${args[@]}" --out c1 >c1.txt 2>&1 & p1=$!
"$BIN" "${args[@]}" --out c2 >c2.txt 2>&1 & p2=$!
wait $p1; r1=$?; wait $p2; r2=$?
check "two concurrent compares exit 0" test "$r1:$r2" = 0:0
cached=$(sed -n 's/.*, \([0-9]\) of 3 frames from the cache,.*/\1/p' c1.txt c2.txt | paste -sd+ | bc)
check "  between them 3 of their 6 frames came from the cache (got ${cached:-none})" test "${cached:-0}" -eq 3

# The jobs file: the reference job's line first
"$BIN" sweep m.json --jobs-file jobs.txt --out jobs >/dev/null 2>&1
check "--jobs-file: the reference job, then the 4 tasks" \
  bash -c "test \$(wc -l <jobs.txt) -eq 5 && head -1 jobs.txt | grep -q -- '--reference-task 0 >' && sed -n 2p jobs.txt | grep -q -- '--task 0 >'"
expect_exit "--reference-task past the end -> 2" 2 "$BIN" sweep "$(ls jobs/manifest-*.json)" --reference-task 1
check "  names the count" grep -q -- '--reference-task 1: the sweep has 1 reference jobs' "$T/err.txt"

# Slurm scripts split at --max-array-size (submitting them is tests/cluster/test_slurm_sweep.sh)
"$BIN" sweep m.json --slurm --out sl --max-array-size 3 --job-name study-7 >"$T/out.txt" 2>&1
check "--slurm --max-array-size 3: two task arrays and a reference array" \
  bash -c "test -f sl/sweep-0.sbatch && test -f sl/sweep-1.sbatch && test ! -e sl/sweep-2.sbatch && test -f sl/references.sbatch"
check "  sizes 3 and 1" bash -c "grep -q '^#SBATCH --array=0-2$' sl/sweep-0.sbatch && grep -q '^#SBATCH --array=0-0$' sl/sweep-1.sbatch"
check "  the second one offset by 3" grep -q -- '--task "$((SLURM_ARRAY_TASK_ID + 3))"$' sl/sweep-1.sbatch
check "  --job-name, NAME-ref for the reference jobs" \
  bash -c "grep -q '^#SBATCH --job-name=study-7$' sl/sweep-1.sbatch && grep -q '^#SBATCH --job-name=study-7-ref$' sl/references.sbatch"
check "  --requeue and --open-mode=append" \
  bash -c "grep -q '^#SBATCH --requeue$' sl/sweep-0.sbatch && grep -q '^#SBATCH --open-mode=append$' sl/sweep-0.sbatch"
check "  the reference jobs' own logs" grep -q '^#SBATCH --output=.*/logs/ref-%A_%a.out$' sl/references.sbatch
"$BIN" sweep m.json --slurm --out sl2 >/dev/null 2>&1
check "without a cluster: one array (MaxArraySize 1001), named after the manifest" \
  bash -c "grep -q '^#SBATCH --array=0-3$' sl2/sweep.sbatch && grep -q '^#SBATCH --job-name=fovsim-m$' sl2/sweep.sbatch"
"$BIN" sweep m.json --slurm --out sl >/dev/null 2>&1
check "written again unsplit: the split scripts are removed" \
  bash -c "test -f sl/sweep.sbatch && test ! -e sl/sweep-0.sbatch && test ! -e sl/sweep-1.sbatch"
expect_exit "--job-name without --slurm -> 2" 2 "$BIN" sweep m.json --job-name x
expect_exit "--job-name with a blank -> 2" 2 "$BIN" sweep m.json --slurm --out sl3 --job-name "my study"
check "  one line naming it" grep -q -- "--job-name 'my study': expected letters" "$T/err.txt"
expect_exit "--max-array-size 0 -> 2" 2 "$BIN" sweep m.json --slurm --max-array-size 0

summary
