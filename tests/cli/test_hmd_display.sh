#!/usr/bin/env bash
# The hmd display (docs/hmd.md "The display"): fovsim plan prints each eye (field of view, panel,
# principal point and pixels per degree there, computed here on their own from the angles, IPD,
# refresh); every other command given an hmd display, by --display or by the scene's "display",
# refuses with one line and exit 2 and writes nothing; a planar display plans and draws as before;
# bad --display values and bad scene "display" objects get one line naming the key or JSON path.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SRC=${FOVSIM_SOURCE:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/hmd_display
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

# ---- plan prints both eyes; the figures from the test's own tangent-space arithmetic
"$BIN" plan fence --display hmd:eyenavgs >"$T/plan.txt" 2>"$T/plan.err"
check "plan --display hmd:eyenavgs exits 0" test $? -eq 0
/usr/bin/python3 - "$T/plan.txt" <<'EOF' >"$T/figures.txt" 2>&1
import math, re, sys
text = open(sys.argv[1]).read()
# The EyeNavGS recordings' angles (radians), 1800 px wide, the height for square pixels.
eyes = {"left": (-0.942, 0.698, 0.733, -0.942), "right": (-0.698, 0.942, 0.733, -0.942)}
W = 1800
bad = 0
for name, (l, r, u, d) in eyes.items():
    sx, sy = math.tan(r) - math.tan(l), math.tan(u) - math.tan(d)
    H = round(W * sy / sx)
    f = W / sx
    cx, cy = -math.tan(l) * f, math.tan(u) * f
    ppd = f * math.pi / 180
    m = re.search(r"^  %s +eye +fov left ([-+.0-9]+) right ([-+.0-9]+) up ([-+.0-9]+) down ([-+.0-9]+) deg .*"
                  r"panel (\d+) x (\d+), principal point \(([.0-9]+), ([.0-9]+)\) px, ([.0-9]+) x ([.0-9]+) px/deg"
                  r" there, at x ([-+.0-9]+) mm$" % name, text, re.M)
    if not m:
        print("no line for the %s eye" % name); bad = 1; continue
    g = [float(v) for v in m.groups()]
    want = [math.degrees(l), math.degrees(r), math.degrees(u), math.degrees(d), W, H, cx, cy, ppd, ppd,
            -31.5 if name == "left" else 31.5]
    tol = [0.006] * 4 + [0, 0, 0.06, 0.06, 0.006, 0.006, 0.06]
    for i, (a, b, t) in enumerate(zip(g, want, tol)):
        if abs(a - b) > t:
            print("%s eye, field %d: printed %g, computed %g" % (name, i, a, b)); bad = 1
if not re.search(r"^hmd +hmd:eyenavgs: 72 Hz, IPD 63 mm", text, re.M):
    print("no hmd line with 72 Hz, IPD 63 mm"); bad = 1
sys.exit(bad)
EOF
check "plan prints each eye's angles, panel, principal point, ppd and place ($(tr '\n' ' ' <"$T/figures.txt"))" \
  test -z "$(cat "$T/figures.txt")"

"$BIN" plan fence --display hmd:quest-pro,width=1440,ipd=64 >"$T/qp.txt" 2>&1
check "plan names the keys given: width (height for square pixels), ipd" \
  grep -q '^hmd *hmd:quest-pro,width=1440,height=1480,ipd=64: 90 Hz, IPD 64 mm' "$T/qp.txt"

# ---- a planar display plans as before: no hmd line, --display planar changes nothing
"$BIN" plan fence >"$T/planar.txt" 2>&1
"$BIN" plan fence --display planar >"$T/planar2.txt" 2>&1
check "planar plan has no hmd line" bash -c "! grep -q '^hmd' '$T/planar.txt'"
check "--display planar plans what no --display plans" cmp -s "$T/planar.txt" "$T/planar2.txt"

# ---- render and compare draw it, one run per eye (test_hmd_eyes.sh); the others refuse, one line,
# exit 2, nothing written
for c in reference bench; do
  expect_exit "$c --display hmd:eyenavgs: exit 2, one line" 2 "$BIN" $c fence --display hmd:eyenavgs --out "$T/out_$c" --quiet
  check "$c: the line says render and compare draw it" \
    grep -qxF "fovsim: error: $c: an hmd display is drawn by render and compare (one run per eye) and view; fovsim $c draws one view (docs/hmd.md)" "$T/err.txt"
  check "$c wrote nothing" test ! -e "$T/out_$c"
done
expect_exit "demo refuses an hmd display" 2 "$BIN" demo --display hmd:eyenavgs --out "$T/out_demo" --quiet
check "demo wrote nothing" test ! -e "$T/out_demo"

# ---- the scene file's "display": kind hmd plans and render draws both eyes; kind planar draws
sed 's/"display": *{[^}]*}/"display": {"kind": "hmd", "preset": "eyenavgs", "ipd": 60, "width": 64}/' \
  "$SRC/scenes/builtin/fence.json" >"$T/fence_hmd.json"
check "the scene copy has an hmd display" grep -q '"kind": "hmd"' "$T/fence_hmd.json"
"$BIN" plan "$T/fence_hmd.json" >"$T/scene_plan.txt" 2>&1
check "plan of an hmd scene prints its hmd" grep -q '^hmd *hmd:eyenavgs,width=64,height=66,ipd=60: 72 Hz, IPD 60 mm' "$T/scene_plan.txt"
"$BIN" render "$T/fence_hmd.json" --frames 1 --out "$T/out_scene" --quiet >/dev/null 2>&1
check "render of an hmd scene draws both eyes into one multi-view frame" bash -c \
  "test -f '$T/out_scene/eye-left/frame.0000.exr' && test -f '$T/out_scene/eye-right/frame.0000.exr' && oiiotool --info -v '$T/out_scene/frame.0000.exr' | grep -q 'multiView'"
"$BIN" render "$T/fence_hmd.json" --display planar --width 64 --height 36 --frames 1 --out "$T/out_planar" --quiet
check "--display planar draws an hmd scene's planar display" test -f "$T/out_planar/frame.0000.exr"

# ---- bad values: one line naming the option's key or the JSON path
expect_exit "--display ipd=abc" 2 "$BIN" plan fence --display hmd:quest-pro,ipd=abc
check "--display ipd=abc names the key" \
  grep -qxF "fovsim: error: --display: key 'ipd': expected millimetres in 40..90, got 'abc'" "$T/err.txt"
expect_exit "--display unknown preset" 2 "$BIN" plan fence --display hmd:rift
check "--display unknown preset lists the presets" grep -qF "unknown preset 'rift' (presets: quest-pro, eyenavgs, custom)" "$T/err.txt"
expect_exit "--display without hmd:" 2 "$BIN" plan fence --display vr
for bad in '{"kind": "hmd", "preset": "eyenavgs", "ipd": 30}|display.ipd' \
           '{"kind": "hmd", "preset": "eyenavgs", "fov_left": [-50, 40, 40]}|display.fov_left' \
           '{"kind": "hmd"}|display: missing "preset"' \
           '{"kind": "stereo"}|display.kind' \
           '{"kind": "hmd", "preset": "eyenavgs", "hfov": 90}|display.hfov'; do
  json=${bad%%|*}; want=${bad#*|}
  sed "s/\"display\": *{[^}]*}/\"display\": $json/" "$SRC/scenes/builtin/fence.json" >"$T/bad.json"
  expect_exit "scene display $json: exit 3, one line" 3 "$BIN" plan "$T/bad.json"
  check "scene display $json names $want" grep -qF "$want" "$T/err.txt"
done

summary
