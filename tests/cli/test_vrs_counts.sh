#!/usr/bin/env bash
# VRS foveation, part 3 (docs/benchmarks.md "VRS: coarse-shading invocations"): the counting frame's
# coarse-shading invocations equal a brute-force CPU count of the distinct (triangle, coarse pixel)
# pairs with a covered pixel, on random triangles of 0.5 to 12 pixels on a 64 x 62 and a 96 x 92
# display (the coarse pixels align from the top, not from the window's bottom row), at each rate shape;
# covered fragments equal the CPU's covered pixels; the VRS stage's fs_invocations (bench's and
# compare's) is the count.
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

# gpu FILE: the VRS configuration's forward pass: covered, shaded fragments and fs_invocations
gpu() {
  $PY -c "
import json, sys
c = [c for c in json.load(open(sys.argv[1]))['configs'] if c['name'].endswith('(VRS)')][0]
s = c['stages'][0]
print(s['covered_fragments_all_frames'], s['shaded_fragments_all_frames'], s['fs_invocations_all_frames'])" "$1"
}
# 64 x 62: one llvmpipe tile (64 x 64) high, coarse pixels aligned from the top row, not the bottom;
# 96 x 92: four tiles, their boundary 28 rows below the top, inside no coarse pixel (92 = 4 * 23).
for d in 64x62:80 96x92:160; do
  W=${d%%x*}; H=${d#*x}; N=${H#*:}; H=${H%:*}
  $CPU make "$T/tris.gltf" "$T/tris.json" "$W" "$H" "$N" 7
  printf '{"display": {"width": %d, "height": %d, "hfov": 90}, "assets": [{"name": "t", "gltf": "tris.gltf"}],
 "instances": [{"asset": "t"}], "camera": [{"time": 0, "position": [0, 0, 1], "target": [0, 0, 0]}]}\n' \
    "$W" "$H" >"$T/scene.json"
  for r in 1x1 2x2 4x4 2x4 4x2 1x2; do
    w=${r%x*}; h=${r#*x}
    "$BIN" bench "$T/scene.json" --frames 1 --warmup 0 --taa off --foveation vrs --vrs "*:$r" --format json \
      >"$T/b_$r.json" 2>"$T/err.txt" || cat "$T/err.txt" >&2
    read -r cov shd split <<<"$($CPU count "$T/tris.json" "$W" "$H" "$w" "$h")"
    read -r gcov gshd gfs <<<"$(gpu "$T/b_$r.json")"
    check "${W}x$H, $r: covered fragments = the CPU's covered pixels ($cov)" eq "$gcov" "$cov"
    check "${W}x$H, $r: coarse-shading invocations = the CPU's (triangle, coarse pixel) pairs ($shd)" eq "$gshd" "$shd"
    check "${W}x$H, $r: the VRS stage's fs_invocations is that count" eq "$gfs" "$shd"
  done
done
read -r cov shd split <<<"$($CPU count "$T/tris.json" 96 92 4 4)"
check "the CPU count can tell the rates apart (4x4: $shd of $cov)" test "$shd" -lt "$cov"

# compare prices VRS the same way: its summary's fs_invocations_median is the coarse count
"$BIN" compare "$T/scene.json" --foveation vrs --vrs '*:2x2' --frames 1 --out "$T/cmp" --quiet >/dev/null 2>"$T/err.txt" ||
  cat "$T/err.txt" >&2
read -r cov shd split <<<"$($CPU count "$T/tris.json" 96 92 2 2)"
check "compare, 2x2: every mode's fs_invocations_median is the CPU's count ($shd)" $PY -c "
import json, sys
m = json.load(open(sys.argv[1]))['modes']
sys.exit(not m or any(x['fs_invocations_median'] != int(sys.argv[2]) for x in m))" "$T/cmp/summary.json" "$shd"

# A height not a multiple of the rate's: coarse pixels straddle the 64-row tiles' boundaries and
# the count is a bound, at most the pairs split by a boundary above the exact count.
$CPU make "$T/tris.gltf" "$T/tris.json" 128 94 300 5
printf '{"display": {"width": 128, "height": 94, "hfov": 90}, "assets": [{"name": "t", "gltf": "tris.gltf"}],
 "instances": [{"asset": "t"}], "camera": [{"time": 0, "position": [0, 0, 1], "target": [0, 0, 0]}]}\n' >"$T/scene.json"
"$BIN" bench "$T/scene.json" --frames 1 --warmup 0 --taa off --foveation vrs --vrs "*:4x4" --format json \
  >"$T/b_odd.json" 2>"$T/err_odd.txt" || cat "$T/err_odd.txt" >&2
read -r cov shd split <<<"$($CPU count "$T/tris.json" 128 94 4 4)"
read -r gcov gshd gfs <<<"$(gpu "$T/b_odd.json")"
check "128x94, 4x4: some coarse pixels straddle a tile boundary (the bound is not the count)" test "$split" -gt 0
check "128x94, 4x4: exact count $shd <= counted $gshd <= $shd + $split" \
  test "$shd" -le "$gshd" -a "$gshd" -le $((shd + split))
check "128x94: bench says the count is a bound" grep -q 'an upper bound' "$T/err_odd.txt"
check "bench JSON consistent" $PY "$SRC/tests/cli/check_bench_json.py" "$T/b_2x2.json" known
summary
