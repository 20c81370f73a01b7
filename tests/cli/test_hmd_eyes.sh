#!/usr/bin/env bash
# Two eyes of an hmd display (docs/hmd.md "Two eyes"): render draws each eye with its own
# asymmetric projection at its own eye position and joins them into a multi-view EXR that oiiotool
# reads with both views; a square card straight ahead lands in each eye at the pixel computed here
# from the display's angles (principal point, focal length) and the eye's offset: near, the
# disparity f * ipd / z (crossed: farther right in the left eye); far, none beyond the panels'
# asymmetry. compare runs both eyes: metrics.csv with an eye column, summary.json per eye and both.
# About 15 s.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SRC=$(cd "$(dirname "$0")/../.." && pwd)
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/hmd_eyes
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
PY=/usr/bin/python3
command -v oiiotool >/dev/null || { [ -z "${FOVSIM_REQUIRE_OIIO:-}" ] && { echo "no oiiotool: skipping" >&2; exit 77; }; }
DISP="hmd:eyenavgs,width=128,ipd=64"

# A card of side 2H straight ahead at distance Z (alpha-tested, white: coverage 1 where it is).
card() { # NAME H Z
  $PY "$SRC/tests/cli/make_vrs_quad_gltf.py" "$T/$1.gltf" "$2" 1 0 white white MASK
  printf '{"assets": [{"name": "q", "gltf": "%s.gltf"}], "instances": [{"asset": "q", "translation": [0, 0, %s]}],
 "camera": [{"time": 0, "position": [0, 0, 0], "target": [0, 0, -1]}]}\n' "$1" "-$3" >"$T/$1.json"
}
card near 0.02 0.5
card far 20 1000
for s in near far; do
  "$BIN" render "$T/$s.json" --display "$DISP" --frames 1 --taa off --rings off --out "$T/$s" >"$T/$s.txt" 2>&1
  check "render $s card on an hmd display exits 0, both eyes and the joined frame" bash -c \
    "test -s '$T/$s/frame.0000.exr' && test -s '$T/$s/eye-left/frame.0000.exr' && test -s '$T/$s/eye-right/frame.0000.exr'"
done

check "the joined frame: multiView left, right; oiiotool extracts the right view, equal to the right eye's frame" bash -c "
  oiiotool --info -v '$T/near/frame.0000.exr' | grep -q 'multiView: \"left\", \"right\"' &&
  oiiotool '$T/near/frame.0000.exr' --ch R=right.R,G=right.G,B=right.B,A=right.A,coverage=right.coverage -o '$T/r.exr' &&
  oiiotool '$T/r.exr' '$T/near/eye-right/frame.0000.exr' --diff --fail 0 >/dev/null &&
  ! oiiotool '$T/r.exr' '$T/near/eye-left/frame.0000.exr' --diff --fail 0 >/dev/null"

# The card's coverage centroid in each eye against the pinhole of docs/hmd.md: f = W / (tan R - tan L),
# the principal point at f (-tan L) from the left edge and H / 2 + f (tan U + tan D) / 2 from the top.
cat >"$T/where.py" <<'PY'
import math, subprocess, sys
def centroid(path):
    out = subprocess.run(["oiiotool", "--dumpdata", "--info", path], capture_output=True, text=True, check=True).stdout
    sx = sy = n = 0.0
    w = h = 0
    for line in out.splitlines():
        line = line.strip()
        if line.startswith("Pixel ("):
            xy, vals = line[len("Pixel ("):].split("):")
            x, y = (int(v) for v in xy.split(","))
            c = float(vals.split()[4])
            sx += c * (x + 0.5); sy += c * (y + 0.5); n += c
            w, h = max(w, x + 1), max(h, y + 1)
    return sx / n, sy / n, w, h
fov = {"left": (-0.942, 0.698, -0.942, 0.733), "right": (-0.698, 0.942, -0.942, 0.733)}  # L, R, D, U (eyenavgs)
z, ipd, kind = float(sys.argv[2]), 0.064, sys.argv[3]
got, want, pp = {}, {}, {}
for eye, ex in (("left", -ipd / 2), ("right", ipd / 2)):
    x, y, w, h = centroid("%s/eye-%s/frame.0000.exr" % (sys.argv[1], eye))
    L, R, D, U = (math.tan(a) for a in fov[eye])
    f = w / (R - L)
    cx, cy = f * -L, h / 2 + f * (U + D) / 2
    got[eye], want[eye], pp[eye], fpx = (x, y), (cx + f * (0 - ex) / z, cy), cx, f
    print("%s eye: card at (%.2f, %.2f), computed (%.2f, %.2f), principal point (%.2f, %.2f)" % (
        eye, x, y, want[eye][0], want[eye][1], cx, cy))
    assert abs(x - want[eye][0]) < 1 and abs(y - want[eye][1]) < 1, (eye, got[eye], want[eye])
# the disparity beyond the panels' asymmetry (each eye's card from its own principal point)
stereo = (got["left"][0] - pp["left"]) - (got["right"][0] - pp["right"])
expect = fpx * ipd / z
print("disparity beyond the panels' asymmetry: %.2f px, f * ipd / z = %.2f" % (stereo, expect))
assert abs(stereo - expect) < 1, (stereo, expect)
assert kind == "far" or stereo > 3  # near: crossed, the card farther right in the left eye
PY
check "near card (0.5 m): each eye's card where its pinhole puts it, disparity f*ipd/z within 1 px" $PY "$T/where.py" "$T/near" 0.5 near
check "far card (1000 m): each eye's card at its principal point's column, within 1 px (no disparity)" $PY "$T/where.py" "$T/far" 1000 far

# ---- a binocular EyeLink recording feeds each eye its own samples: each eye's gaze angle is the one a
# planar display shows with --eye left / --eye right (both placed by visual angle)
B="$SRC/../shared/gaze/eyelink_asc_eyelinker/bino500.asc"
if [ -f "$B" ]; then
  "$BIN" render forest --display hmd:eyenavgs,width=96 --gaze "$B" --frames 3 --out "$T/bino" >/dev/null 2>&1
  for e in left right; do
    "$BIN" render forest --gaze "$B" --eye $e --frames 3 --width 96 --height 96 --out "$T/bino_$e" >/dev/null 2>&1
  done
  deg() { oiiotool --info -v "$1" | sed -n 's/.*fovsim:gaze_deg: //p' | head -1; }
  check "binocular EyeLink: each eye's gaze is that eye's samples (left differs from right)" $PY -c "
import sys
a = [[float(v) for v in s.split(',')] for s in sys.argv[1:]]  # hmd left, planar left, hmd right, planar right
assert all(abs(x - y) < 1e-3 for x, y in zip(a[0], a[1])) and all(abs(x - y) < 1e-3 for x, y in zip(a[2], a[3])), a
assert max(abs(x - y) for x, y in zip(a[0], a[2])) > 0.1, a
" "$(deg "$T/bino/eye-left/frame.0002.exr")" "$(deg "$T/bino_left/frame.0002.exr")" \
    "$(deg "$T/bino/eye-right/frame.0002.exr")" "$(deg "$T/bino_right/frame.0002.exr")"
fi

# ---- compare: both eyes, metrics per eye, summary per eye and both
"$BIN" compare forest --display "hmd:eyenavgs,width=96" --frames 2 --supersample 1 --out "$T/cmp" >"$T/cmp.txt" 2>&1
check "compare on an hmd display exits 0" test $? -eq 0
check "metrics.csv: an eye column, both eyes' rows; summary.json: eyes and both, coverage of both the ratio of sums" $PY -c "
import csv, json
rows = list(csv.DictReader(open('$T/cmp/metrics.csv')))
assert rows and {r['eye'] for r in rows} == {'left', 'right'}, rows[:2]
s = json.load(open('$T/cmp/summary.json'))
L, R = s['eyes']['left'], s['eyes']['right']
for m, b in zip(L['modes'], s['both']['modes']):
    mr = [x for x in R['modes'] if x['mode'] == m['mode']][0]
    for rl, rr, rb in zip(m['rings'], mr['rings'], b['rings']):
        ref = rl['ref_coverage_px'] + rr['ref_coverage_px']
        assert abs(rb['coverage_ratio'] - (rl['coverage_px'] + rr['coverage_px']) / ref) < 1e-4, (rl, rr, rb)
        assert abs(rb['flip'] - (rl['flip'] + rr['flip']) / 2) < 1e-5
"
width() { oiiotool --info "$1" | head -1 | sed 's/.*: *\([0-9]*\) x.*/\1/'; }
check "the compare frame: both grids side by side (twice an eye's width), the layers part multi-view" bash -c "
  oiiotool --info -v -a '$T/cmp/compare.0001.exr' | grep -q 'multiView: \"left\", \"right\"' &&
  [ $(width "$T/cmp/compare.0001.exr") -eq \$((2 * $(width "$T/cmp/eye-left/compare.0001.exr"))) ]"
expect_exit "bench refuses an hmd display" 2 "$BIN" bench forest --display "$DISP" --frames 1
summary
