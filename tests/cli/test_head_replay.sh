#!/usr/bin/env bash
# A VR recording's head motion drives the camera (docs/hmd.md "Head replay"), on the shared EyeNavGS
# recordings: --gaze with one replays its head and eyes (one line says so), --head off keeps the
# scene's camera, a head-only recording drives the camera but is refused as a gaze trace, and the
# run record holds the head. The pose maths is test_head_replay.c's. About 10 s.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SRC=$(cd "$(dirname "$0")/../.." && pwd)
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/head_replay
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
G="$SRC/../shared/gaze/eyenavgs_rutgers"
[ -f "$G/user101_treehill.csv" ] || { echo "no ../shared/gaze/eyenavgs_rutgers: skipping" >&2; exit 77; }
R="--frames 3 --width 96 --height 54"

"$BIN" render forest --gaze "$G/user101_treehill.csv" $R --out "$T/head" >"$T/head.txt" 2>&1
check "render --gaze EyeNavGS exits 0" test $? -eq 0
check "one line says the recording's head replaces the camera, placed at the scene camera's start" bash -c \
  "[ \$(grep -c '^head: .*user101_treehill.csv.s head motion replaces the scene.s camera path' '$T/head.txt') -eq 1 ] && grep -q \"the scene camera's start\" '$T/head.txt'"
check "the run record holds the head" grep -q '^head: .*user101_treehill.csv, content [0-9a-f]*, place ' "$T/head/fovsim-run.txt"
"$BIN" render forest --gaze "$G/user101_treehill.csv" --head off $R --out "$T/off" >"$T/off.txt" 2>&1
check "--head off: the scene's camera (no head line), the recording's gaze still read" bash -c \
  "! grep -q '^head:' '$T/off.txt' && grep -q '^gaze: .*user101_treehill.csv' '$T/off/fovsim-run.txt'"
check "the head moves the camera: frame 2 differs from --head off's" bash -c \
  "! cmp -s '$T/head/frame.0002.exr' '$T/off/frame.0002.exr'"
"$BIN" render forest --head "$G/user102_bicycle.csv" --head-place 0,1.7,4,180 $R --out "$T/bike" >"$T/bike.txt" 2>&1
check "a head-only recording drives the camera with --head (placed as given)" bash -c \
  "grep -q '^head: .*placed at 0,1.7,4, turned 180.0 deg, 1 units/m;' '$T/bike.txt'"
expect_exit "the same recording as a gaze trace: refused, it has no gaze" 5 "$BIN" render forest --gaze "$G/user102_bicycle.csv" $R --out "$T/x"
expect_exit "--head-place without a head recording" 2 "$BIN" render forest --head-place 1,2,3 --out "$T/x"
expect_exit "--head-place: a bad value" 2 "$BIN" render forest --head "$G/user102_bicycle.csv" --head-place 1,2,x --out "$T/x"
expect_exit "--head in plain bench" 2 "$BIN" bench forest --head "$G/user102_bicycle.csv"
expect_exit "--head: a file that is not a recording" 5 "$BIN" render forest --head "$SRC/gaze_paths/fixation_saccade.csv" $R --out "$T/x"
summary
