#!/usr/bin/env bash
# VRS foveation, part 3 (docs/benchmarks.md "VRS: coarse-shading invocations"): the counting frame's
# coarse-shading invocations equal a brute-force CPU count of the distinct (triangle, coarse pixel)
# pairs with a covered pixel, on 80 random triangles of 0.5 to 12 pixels on a 64 x 62 display (62
# rows: the coarse pixels align from the top, not from the window's bottom row), at each rate shape;
# covered fragments equal the CPU's covered pixels; the VRS stage's fs_invocations is the count.
# Counts only, never times.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SRC=$(cd "$(dirname "$0")/../.." && pwd)
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/vrs_counts
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
PY=/usr/bin/python3
CPU="$PY $SRC/tests/cli/vrs_counts.py"
eq() { [ "$1" = "$2" ] || { echo "  got $1, expected $2" >&2; return 1; }; }

$CPU make "$T/tris.gltf" "$T/tris.json" 64 62 80 7
cat >"$T/scene.json" <<JSON
{"display": {"width": 64, "height": 62, "hfov": 90}, "assets": [{"name": "t", "gltf": "tris.gltf"}],
 "instances": [{"asset": "t"}], "camera": [{"time": 0, "position": [0, 0, 1], "target": [0, 0, 0]}]}
JSON
# gpu FILE: the VRS configuration's forward pass: covered, shaded fragments and fs_invocations
gpu() {
  $PY -c "
import json, sys
c = [c for c in json.load(open(sys.argv[1]))['configs'] if c['name'].endswith('(VRS)')][0]
s = c['stages'][0]
print(s['covered_fragments_all_frames'], s['shaded_fragments_all_frames'], s['fs_invocations_all_frames'])" "$1"
}
for r in 1x1 2x2 4x4 2x4 4x2 1x2; do
  w=${r%x*}; h=${r#*x}
  "$BIN" bench "$T/scene.json" --frames 1 --warmup 0 --taa off --foveation vrs --vrs "*:$r" --format json \
    >"$T/b_$r.json" 2>"$T/err.txt" || cat "$T/err.txt" >&2
  read -r cov shd <<<"$($CPU count "$T/tris.json" 64 62 "$w" "$h")"
  read -r gcov gshd gfs <<<"$(gpu "$T/b_$r.json")"
  check "$r: covered fragments = the CPU's covered pixels ($cov)" eq "$gcov" "$cov"
  check "$r: coarse-shading invocations = the CPU's (triangle, coarse pixel) pairs ($shd)" eq "$gshd" "$shd"
  check "$r: the VRS stage's fs_invocations is that count" eq "$gfs" "$shd"
done
read -r cov shd <<<"$($CPU count "$T/tris.json" 64 62 4 4)"
check "the CPU count can tell the rates apart (4x4: $shd of $cov)" test "$shd" -lt "$cov"
check "bench JSON consistent" $PY "$SRC/tests/cli/check_bench_json.py" "$T/b_2x2.json" known
summary
