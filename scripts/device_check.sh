#!/usr/bin/env bash
# device_check.sh: fovsim on a GPU in one command (docs/benchmarks.md "On a GPU: the device check").
# Builds (unless --build names a build), runs the test suite on the EGL device fovsim picks (the
# first hardware device), the bench matrix (rings default and aggressive, each beside full
# resolution, x TAA off/on x traditional and hashed, at 1280x720 and 1920x1080), the cost-model
# calibration (bench --calibrate), and writes the raw results and a Markdown report:
#   docs/benchmarks/gpu-<renderer>.md and .json   (or --doc-dir DIR)
#   OUT/: each bench's JSON, the test log, the calibrated model (default out/device_check)
# It refuses a software renderer (llvmpipe, softpipe) unless --allow-software: the report is about
# a GPU. --quick shrinks everything (sizes /4, 3 frames) to check the script itself.
# Exit status: 0 when everything ran (goals missed are reported, not failed), 1 when a step failed,
# 2 on bad usage or no GPU.
set -u -o pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD="" OUT="$ROOT/out/device_check" DOC="$ROOT/docs/benchmarks"
QUICK=0 SOFTWARE=0 TESTS=1
usage() { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; echo "usage: scripts/device_check.sh [--build DIR] [--out DIR] [--doc-dir DIR] [--quick] [--allow-software] [--no-tests]"; }
while [ $# -gt 0 ]; do
  case "$1" in
    --build) BUILD=${2:?--build needs a directory}; shift ;;
    --out) OUT=${2:?--out needs a directory}; shift ;;
    --doc-dir) DOC=${2:?--doc-dir needs a directory}; shift ;;
    --quick) QUICK=1 ;;
    --allow-software) SOFTWARE=1 ;;
    --no-tests) TESTS=0 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "device_check.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
mkdir -p "$OUT" "$DOC" || exit 1
LOG="$OUT/device_check.log"
: >"$LOG"
step() { echo "device_check: $*" | tee -a "$LOG" >&2; }
T0=$(date +%s)

# 1. Build (Release), unless a build was given.
if [ -z "$BUILD" ]; then
  BUILD="$ROOT/build-device"
  step "building into $BUILD"
  if ! { cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release && cmake --build "$BUILD" -j"$(nproc)"; } >>"$LOG" 2>&1; then
    step "build failed (see $LOG; the packages scripts/setup.sh installs are needed)"; exit 1
  fi
fi
BIN="$BUILD/fovsim"
[ -x "$BIN" ] || { step "no fovsim in $BUILD"; exit 2; }

# 2. Which renderer: a GPU, or say why not.
PROBE="$OUT/probe.json"
if ! "$BIN" bench --frames 1 --warmup 0 --width 64 --height 36 --format json --quiet >"$PROBE" 2>>"$LOG"; then
  step "fovsim could not draw (see $LOG)"; exit 1
fi
RENDERER=$(/usr/bin/env python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["renderer"])' "$PROBE") || exit 1
step "renderer: $RENDERER"
case "$RENDERER" in
  *llvmpipe*|*softpipe*|*software*|*swrast*)
    if [ "$SOFTWARE" -eq 0 ]; then step "no GPU: the renderer is $RENDERER (--allow-software to check the script itself)"; exit 2; fi ;;
esac

# 3. The test suite on this device.
TESTS_LINE="not run (--no-tests)"
if [ "$TESTS" -eq 1 ]; then
  step "test suite (ctest -LE slurm)"
  ctest --test-dir "$BUILD" -LE slurm -j"$(nproc)" --output-on-failure >"$OUT/ctest.log" 2>&1
  # Judged by what ctest prints, not its exit status alone.
  TESTS_LINE=$(grep -E '^[0-9]+% tests passed' "$OUT/ctest.log" | tail -1)
  [ -n "$TESTS_LINE" ] || TESTS_LINE="ctest printed no summary (see ctest.log)"
  step "tests: $TESTS_LINE"
fi

# 4. The bench matrix: each run measures full resolution and the foveated layout, per mode.
if [ "$QUICK" -eq 1 ]; then SIZES="320x180 480x270"; FRAMES=3; WARM=1; else SIZES="1280x720 1920x1080"; FRAMES=30; WARM=5; fi
FAILED=0
for size in $SIZES; do
  w=${size%x*} h=${size#*x}
  for rings in auto aggressive; do
    for taa in off on; do
      f="$OUT/bench-$size-$rings-taa$taa.json"
      step "bench $size rings $rings TAA $taa"
      if ! "$BIN" bench --builtin forest --width "$w" --height "$h" --rings "$rings" --taa "$taa" \
           --modes traditional,hashed --frames "$FRAMES" --warmup "$WARM" --format json --quiet >"$f" 2>>"$LOG"; then
        step "bench failed: $size $rings TAA $taa"; rm -f "$f"; FAILED=1
      fi
    done
  done
done

# 5. The cost model of this device.
MODEL="$OUT/cost-model.json"
CAL_SIZE=()
[ "$QUICK" -eq 1 ] && CAL_SIZE=(--width 160 --height 90 --frames 2)
step "bench --calibrate"
if ! "$BIN" bench --calibrate --cost-model "$MODEL" "${CAL_SIZE[@]}" --quiet >"$OUT/calibrate.txt" 2>>"$LOG"; then
  step "calibration failed (see $OUT/calibrate.txt and $LOG)"; rm -f "$MODEL"; FAILED=1
fi

# 6. The report.
step "report"
REPORT_ARGS=(--out "$OUT" --doc-dir "$DOC" --tests "$TESTS_LINE" --seconds $(( $(date +%s) - T0 )))
[ "$QUICK" -eq 1 ] && REPORT_ARGS+=(--quick)
if ! /usr/bin/env python3 "$ROOT/scripts/device_report.py" "${REPORT_ARGS[@]}" >>"$LOG" 2>&1; then
  step "report failed (see $LOG)"; exit 1
fi
step "done in $(( $(date +%s) - T0 )) s"
exit "$FAILED"
