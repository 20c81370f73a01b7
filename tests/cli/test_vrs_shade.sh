#!/usr/bin/env bash
# VRS foveation, part 2 (docs/foveation.md "Variable-rate shading: coarse shading"): drawing with
# coarse shading emulated in the shaders. The 1x1 rate is bit-identical to --foveation off, also
# where it meets coarse tiles around a moved gaze; on a quad with a colour gradient every coarse
# pixel holds one value, the gradient's value at the coarse pixel's centre; hashed and stochastic
# alpha decide once per coarse pixel; a 1-texel checkerboard at 2x2 reads the mip level one above
# the full rate's; compare takes vrs; the plan shows the VRS twins.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SRC=$(cd "$(dirname "$0")/../.." && pwd)
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/vrs_shade
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
for tool in oiiotool idiff; do command -v $tool >/dev/null || { echo "no $tool: skipped"; exit 77; }; done
PY=/usr/bin/python3
CHECK="$PY $SRC/tests/cli/vrs_check.py"
F=frame.0000.exr
render() { "$BIN" render "$@" --quiet >/dev/null 2>"$T/render_err.txt" || cat "$T/render_err.txt" >&2; }

# ---- the plan: each forward pass and its VRS twin
"$BIN" plan forest --foveation vrs >"$T/plan.txt" 2>&1
check "plan: one full-resolution ring" grep -q '^rings      off (full resolution)' "$T/plan.txt"
check "plan: the passes' VRS twins (forward_vrs.geom, VRS 1)" \
  grep -q '(VRS: each pass above draws the 1x1 tiles; its twin + shaders/forward_vrs.geom \[VRS 1\]' "$T/plan.txt"
"$BIN" plan forest >"$T/plan_rings.txt" 2>&1
check "plan without vrs: no twin" bash -c "! grep -q 'forward_vrs' '$T/plan_rings.txt'"

# ---- 1x1 everywhere is --foveation off, bit for bit, one frame and with TAA over four
render forest --width 160 --height 90 --frames 1 --foveation off --out "$T/off1"
render forest --width 160 --height 90 --frames 1 --foveation vrs --vrs '*:1x1' --out "$T/v1"
check "*:1x1 = --foveation off, bit-identical (1 frame)" idiff -q -fail 0 -warn 0 "$T/off1/$F" "$T/v1/$F"
render forest --width 160 --height 90 --frames 4 --foveation off --out "$T/off4"
render forest --width 160 --height 90 --frames 4 --foveation vrs --vrs '*:1x1' --out "$T/v4"
check "*:1x1 = --foveation off, bit-identical (TAA, frame 4)" \
  idiff -q -fail 0 -warn 0 "$T/off4/frame.0003.exr" "$T/v4/frame.0003.exr"
render forest --width 160 --height 90 --frames 1 --foveation vrs --vrs '*:2x2' --out "$T/v2"
check "... and *:2x2 is not (the test can fail)" bash -c "! idiff -q -fail 0 -warn 0 '$T/off1/$F' '$T/v2/$F' >/dev/null 2>&1"
check "the EXR header says vrs" bash -c "exrheader '$T/v2/$F' | grep -A1 'fovsim:foveation' | grep -q 'vrs \*:2x2, 16 px tiles'"
check "the run record says vrs" grep -q '^foveation: vrs, vrs: \*:2x2' "$T/v2/fovsim-run.txt"

# ---- the map follows the rendered gaze: around it 1x1 (= off), elsewhere 4x4
printf '# fixation up left\nt,x,y\n0,0.2,0.2\n10,0.2,0.2\n' >"$T/gaze.csv"
render forest --width 320 --height 180 --frames 1 --foveation off --gaze "$T/gaze.csv" --out "$T/goff"
render forest --width 320 --height 180 --frames 1 --foveation vrs --vrs '5:1x1,*:4x4' --gaze "$T/gaze.csv" --out "$T/gvrs"
same_box() { # BOX: the two frames agree bit for bit in BOX (oiiotool --cut geometry, rows top-down)
  oiiotool "$T/goff/$F" --cut "$1" -o "$T/a.exr" && oiiotool "$T/gvrs/$F" --cut "$1" -o "$T/b.exr" &&
    idiff -q -fail 0 -warn 0 "$T/a.exr" "$T/b.exr" >/dev/null 2>&1
}
check "around the gaze (64, 36) the 1x1 tiles are --foveation off's pixels" same_box 24x24+52+24
check "at the centre they are not (4x4)" bash -c "$(declare -f same_box); T='$T' F='$F'; ! same_box 24x24+148+78"
check "nor at the gaze's mirror image below (the map is not upside down)" \
  bash -c "$(declare -f same_box); T='$T' F='$F'; ! same_box 24x24+52+132"

# ---- a quad with a colour gradient (one triangle each side of its diagonal), white texture
quad() { # NAME H REPEAT OFFSET TEXTURE COLOURS MODE
  $PY "$SRC/tests/cli/make_vrs_quad_gltf.py" "$T/$1.gltf" "$2" "$3" "$4" "$5" "$6" "$7"
  printf '{"display": {"width": 64, "height": 64, "hfov": 90}, "assets": [{"name": "q", "gltf": "%s.gltf"}],
 "instances": [{"asset": "q"}], "camera": [{"time": 0, "position": [0, 0, 1], "target": [0, 0, 0]}]}\n' "$1" >"$T/$1.json"
}
quad grad 1.05 1 0 white gradient OPAQUE
render "$T/grad.json" --frames 1 --foveation off --out "$T/grad_off"
check "full rate: the gradient differs inside 2x2 blocks (the check can fail)" \
  bash -c "! $CHECK uniform '$T/grad_off/$F' 2 2 0,1,2 >/dev/null"
for r in 2x2 4x4 2x4 4x2; do
  w=${r%x*}; h=${r#*x}
  render "$T/grad.json" --frames 1 --foveation vrs --vrs "*:$r" --out "$T/grad_$r"
  check "$r: every coarse pixel one triangle covers holds one value (colour and coverage)" \
    $CHECK uniform "$T/grad_$r/$F" "$w" "$h" 0,1,2,4
  # Half-float EXR: values below 0.5 are stored within 1.2e-4; the four-pixel mean adds as much.
  # Half a pixel's error in the centre would show as 3e-3 (the gradient is 6e-3 per pixel).
  check "$r: ... the gradient's value at the coarse pixel's centre (within 5e-4)" \
    $CHECK centre "$T/grad_$r/$F" "$T/grad_off/$F" "$w" "$h" 5e-4
done

# ---- the alpha test decides once per coarse pixel: a card of alpha 0.5, minified (hash noise on)
quad card 2 16 0 half white MASK
for a in hashed stochastic; do
  render "$T/card.json" --frames 1 --alpha $a --foveation off --out "$T/card_${a}_off"
  check "$a, full rate: coverage differs inside 2x2 blocks (the check can fail)" \
    bash -c "! $CHECK uniform '$T/card_${a}_off/$F' 2 2 4 >/dev/null"
  for r in 2x2 4x4; do
    w=${r%x*}; h=${r#*x}
    render "$T/card.json" --frames 1 --alpha $a --foveation vrs --vrs "*:$r" --out "$T/card_${a}_$r"
    check "$a $r: no coarse pixel is partly discarded (coverage 0 or 1 over all of it)" \
      $CHECK uniform "$T/card_${a}_$r/$F" "$w" "$h" 4
    check "$a $r: ... and some are kept, some discarded" \
      bash -c "$CHECK values '$T/card_${a}_$r/$F' 4 | grep -qx '0.0 1.0'"
  done
done

# ---- LOD: a 1-texel checkerboard at one texel per pixel (a quarter texel off the pixel grid). Full
# rate reads level 0 (the checkers, bilinear); at 2x2 the footprint is 2 texels: level 1, flat grey,
# the checkerboard's mean. Level 0 at the coarse centres would be 25 % off it.
quad checker 2 2 0.00390625 checker white OPAQUE
render "$T/checker.json" --frames 1 --foveation off --out "$T/checker_off"
check "full rate: the checkers show (level 0)" $CHECK spread "$T/checker_off/$F" 0.3 2
render "$T/checker.json" --frames 1 --foveation vrs --vrs '*:2x2' --out "$T/checker_2x2"
check "2x2: level 1, the checkerboard's mean, everywhere (within 1 %)" \
  $CHECK flat "$T/checker_2x2/$F" "$T/checker_off/$F" 0.01

# ---- --a2c-sharpen: fwidth(alpha) across coarse pixels, as a GPU's derivatives under VRS. Inside a
# coarse pixel fwidth is 0, which made every edge hard: no pixel of partial coverage at 4x4 (before
# the fix, 0 of 57600 on the fence at 320 x 180; at 160 x 90 the fence's mips are flat there and the
# edges are hard either way); with the neighbours' alpha, the edges stay antialiased.
for v in 1x1 4x4; do
  "$BIN" render fence --alpha a2c --a2c-sharpen --foveation vrs --vrs "*:$v" --taa off --width 320 --height 180 \
    --frames 1 --out "$T/a2c_$v" --quiet >/dev/null 2>&1
done
check "a2c sharpened at 4x4: partial coverage at the edges, at least a quarter as often as at 1x1" $PY -c "
import subprocess, sys
def partial(p):
    out = subprocess.run(['oiiotool', '--dumpdata', '--info', p], capture_output=True, text=True, check=True).stdout
    c = [float(l.split('):')[1].split()[4]) for l in out.splitlines() if l.strip().startswith('Pixel (')]
    return sum(0.02 < v < 0.98 for v in c), len(c)
full, n = partial('$T/a2c_1x1/$F')
coarse, _ = partial('$T/a2c_4x4/$F')
print('partial coverage: 1x1 %d, 4x4 %d of %d pixels' % (full, coarse, n))
sys.exit(not (full > 0.05 * n and coarse >= 0.25 * full))"

# ---- compare draws VRS too
"$BIN" compare forest --foveation vrs --frames 2 --width 160 --height 90 --out "$T/cmp" >"$T/cmp.txt" 2>&1
check "compare --foveation vrs runs and writes its summary" test -s "$T/cmp/summary.json"
check "  its table and summary.json name the rate map, not only the one full-resolution ring" bash -c \
  "grep -q '(160x90, vrs auto, 16 px tiles, TAA on)' '$T/cmp.txt' && grep -q '\"foveation\": \"vrs auto, 16 px tiles\"' '$T/cmp/summary.json'"

summary
