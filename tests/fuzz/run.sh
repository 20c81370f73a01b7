#!/usr/bin/env bash
# Runs every fuzz target of build-fuzz/ (scripts/setup.sh --fuzz builds them; this builds nothing)
# for SECONDS each (default 60), two at a time, each on a copy of its seed corpus and saved
# regressions in a temporary folder: new corpus entries never land in the repository.
#   tests/fuzz/run.sh [SECONDS] [TARGET...]     TARGET: scene_json gltf gaze rings ring_lod vrs hmd check_merge cost_model (default: all)
# Prints one line per target (executions, coverage, time). On a crash, sanitizer report, leak,
# timeout (-timeout=10 s per input) or out-of-memory (-rss_limit_mb=2048) it copies the input that
# did it to tests/fuzz/regressions/<target>/<sha1> (replayed from then on by the ctest
# fuzz_replay_<target>), prints the report and how to reproduce, and exits 1. Exit 2: bad usage or
# a missing binary. Every wait is bounded: a fuzzer still running 90 s after its time is killed
# (and counts as a failure).
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)

secs=${1:-60}
[ $# -gt 0 ] && shift
if ! [[ "$secs" =~ ^[0-9]+$ ]] || [ "$secs" -lt 1 ]; then
  echo "usage: tests/fuzz/run.sh [SECONDS] [TARGET...]" >&2
  exit 2
fi
all=(scene_json gltf gaze rings ring_lod vrs hmd check_merge cost_model)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
declare -A max_len=([scene_json]=8192 [gltf]=8192 [gaze]=4096 [rings]=512 [ring_lod]=512 [vrs]=512 [hmd]=512 [check_merge]=4096 [cost_model]=8192)
for t in "${targets[@]}"; do
  if [ -z "${max_len[$t]:-}" ]; then
    echo "run.sh: unknown target '$t' (targets: ${all[*]})" >&2
    exit 2
  fi
  if [ ! -x "build-fuzz/fuzz_$t" ]; then
    echo "run.sh: build-fuzz/fuzz_$t is missing: run scripts/setup.sh --fuzz first" >&2
    exit 2
  fi
done

work=$(mktemp -d "${TMPDIR:-/tmp}/fovsim-fuzz-run.XXXXXX")
cleanup() {
  local f
  for f in "$work"/*/pid; do [ -f "$f" ] && kill "$(cat "$f")" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# One target: its own corpus copy, artifacts and scratch folder (the targets' temporary files live
# there, so even a crashed run leaves nothing behind once this script removes $work).
run_one() {
  local t=$1 d="$work/$1"
  mkdir -p "$d/corpus" "$d/artifacts" "$d/scratch"
  cp tests/fuzz/corpus/"$t"/* "$d/corpus/"
  find tests/fuzz/regressions/"$t" -maxdepth 1 -type f ! -name '.*' -exec cp {} "$d/corpus/" \;
  local start rc=0
  start=$(date +%s)
  FOVSIM_FUZZ_TMP="$d/scratch" UBSAN_OPTIONS=print_stacktrace=1 \
    timeout -k 10 $((secs + 90)) "build-fuzz/fuzz_$t" "$d/corpus" \
      -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len="${max_len[$t]}" \
      -close_fd_mask=2 -print_final_stats=1 -artifact_prefix="$d/artifacts/" \
      </dev/null >"$d/log" 2>&1 &
  echo $! >"$d/pid" # timeout's: the cleanup stops it (it passes the signal on to the fuzzer)
  wait $! || rc=$?
  rm -f "$d/pid"
  echo "$rc $(( $(date +%s) - start ))" >"$d/status"
}

# Two at a time (2 cores): start one whenever fewer than two run.
for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge 2 ]; do wait -n || true; done
  run_one "$t" &
done
wait || true

failed=0
for t in "${targets[@]}"; do
  d="$work/$t"
  read -r rc took <"$d/status" || { rc=99; took=0; }
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$d/log" | tail -1)
  rss=$(sed -n 's/^stat::peak_rss_mb: *//p' "$d/log" | tail -1)
  last=$(grep -E '^#[0-9]+.*cov: ' "$d/log" | tail -1 || true)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  corp=$(sed -n 's/.* corp: \([0-9]*\)\/.*/\1/p' <<<"$last")
  [ -n "$execs" ] || execs=$(sed -n 's/^#\([0-9]*\).*/\1/p' <<<"$last")
  mapfile -t found < <(find "$d/artifacts" -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' \
                                                     -o -name 'oom-*' \) | sort)
  verdict=ok
  if [ "$rc" -ne 0 ] || [ ${#found[@]} -gt 0 ]; then
    verdict="FAILED (exit $rc)"
    [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ] && verdict="FAILED (still running $((secs + 90)) s after start: killed)"
    failed=1
  fi
  printf 'fuzz_%-10s %9s execs in %3s s (%s/s), cov %s edges, ft %s features, corpus %s, peak rss %s MB: %s\n' \
    "$t" "${execs:-?}" "$took" "$(( ${execs:-0} / (took > 0 ? took : 1) ))" "${cov:-?}" "${ft:-?}" \
    "${corp:-?}" "${rss:-?}" "$verdict"
  if [ "$verdict" != ok ]; then
    echo "---- fuzz_$t: end of its log ----"
    # The report: from the sanitizer's or libFuzzer's first error line, else the last lines.
    if grep -qnE '^==[0-9]+==ERROR|runtime error:|^==[0-9]+== ERROR: libFuzzer|fuzz invariant broken|ERROR: libFuzzer' "$d/log"; then
      first=$(grep -nE '^==[0-9]+==ERROR|runtime error:|ERROR: libFuzzer|fuzz invariant broken' "$d/log" | head -1 | cut -d: -f1)
      tail -n +"$first" "$d/log" | grep -v '^#[0-9]' | head -80
    else
      tail -40 "$d/log"
    fi
    echo "----"
    for a in "${found[@]}"; do
      sum=$(sha1sum "$a" | cut -d' ' -f1)
      mkdir -p "tests/fuzz/regressions/$t"
      cp "$a" "tests/fuzz/regressions/$t/$sum"
      echo "fuzz_$t: $(basename "$a" | cut -d- -f1) input kept as tests/fuzz/regressions/$t/$sum"
      # For a CI log, whose working tree is gone: the input itself, to recreate the file.
      echo "  recreate: echo '$(base64 -w0 "$a")' | base64 -d > tests/fuzz/regressions/$t/$sum"
      echo "  reproduce: build-fuzz/fuzz_$t tests/fuzz/regressions/$t/$sum"
      echo "  replay without clang: cmake --build build && ctest --test-dir build -R fuzz_replay_$t --output-on-failure"
    done
    [ ${#found[@]} -gt 0 ] || echo "fuzz_$t: no input was saved (see the log above)"
  fi
done
if [ "$failed" -ne 0 ]; then
  echo "fuzz: FAILED. Fix the bug, keep the input under tests/fuzz/regressions/ (git add it), see tests/fuzz/README.md." >&2
  exit 1
fi
echo "fuzz: ${#targets[@]} targets, ${secs} s each: no crash, leak, timeout or out-of-memory"
