#!/usr/bin/env bash
# Gaze in degrees (docs/gaze-formats.md, "Degrees"): an EyeLink fixation 10 deg right and 5 deg up
# of a screen's centre is drawn 10 deg right and 5 deg up on the display (the frame's gaze_deg);
# --gaze-map normalized draws what the same trace as display-normalised fovsim CSV draws (today's
# placement); the scene keys equal the options; plan and the run record name them; bad values get
# one line naming the option or the JSON path.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/gaze_degrees
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

BASE=(fence --width 96 --height 54 --frames 2 --fps 24 --taa off --alpha traditional --overlay --quiet)

# fix.asc: 1024x768 screen seen from 2000 px (END ... RES as the block's mean pixels per degree),
# 1 s at 500 Hz fixating (10 deg, 5 deg up); fix.csv: the same samples as pixels / screen size.
/usr/bin/python3 - "$T" <<'EOF'
import math, sys
d = sys.argv[1]
D = 2000.0
u, v = D * math.tan(math.radians(10)), -D * math.tan(math.radians(5))
x, y = 512 + u, 384 + v
with open(d + "/fix.asc", "w") as f:
    f.write("** CONVERTED FROM fix.edf\nMSG\t900 DISPLAY_COORDS 0 0 1023 767\n")
    f.write("START\t1000 \tLEFT\tSAMPLES\tEVENTS\nSAMPLES\tGAZE\tLEFT\tRATE\t500.00\n")
    for k in range(500):
        f.write("%d\t%.2f\t%.2f\t1000.0\t...\n" % (1000 + 2 * k, x, y))
    res = lambda o: math.pi / 180 * (D + o * o / D)
    f.write("END\t2000 \tSAMPLES\tEVENTS\tRES\t%.4f\t%.4f\n" % (res(u), res(v)))
with open(d + "/fix.csv", "w") as f:
    f.write("t,x,y\n")
    for k in range(500):
        f.write("%.3f,%.9g,%.9g\n" % (k * 0.002, float("%.2f" % x) / 1024, float("%.2f" % y) / 768))
EOF

# gaze_deg FILE: the frame's fovsim:gaze_deg attribute, "X Y"
gaze_deg() { oiiotool --info -v "$1" | sed -n 's/.*fovsim:gaze_deg: *\([-0-9.e]*\), *\([-0-9.e]*\).*/\1 \2/p' | head -1; }
near() { awk -v a="$1" -v b="$2" -v e="$3" 'BEGIN { d = a - b; exit !(d <= e && d >= -e) }'; }
export -f near

"$BIN" render "${BASE[@]}" --gaze "$T/fix.asc" --out "$T/angle" >/dev/null 2>&1
"$BIN" render "${BASE[@]}" --gaze "$T/fix.asc" --gaze-map normalized --out "$T/norm" >/dev/null 2>&1
"$BIN" render "${BASE[@]}" --gaze "$T/fix.csv" --out "$T/csv" >/dev/null 2>&1
read -r ax ay <<<"$(gaze_deg "$T/angle/frame.0001.exr")"
read -r nx ny <<<"$(gaze_deg "$T/norm/frame.0001.exr")"
check "by angle (default): the fixation is at 10 deg, 5 deg up on the display (got ${ax:-?}, ${ay:-?})" \
  bash -c "[ -n '${ax:-}' ] && near '$ax' 10 0.05 && near '$ay' 5 0.05"
check "normalized: stretched, not at 10 deg (got ${nx:-?})" bash -c "[ -n '${nx:-}' ] && ! near '$nx' 10 1"
check "--gaze-map normalized draws what the display-normalised trace draws (today's placement)" \
  bash -c "idiff -q '$T/norm/frame.0001.exr' '$T/csv/frame.0001.exr' >/dev/null"
check "by angle draws other frames" bash -c "! idiff -q '$T/angle/frame.0001.exr' '$T/csv/frame.0001.exr' >/dev/null 2>&1"

# ---- --gaze-screen supplies (and overrides) the geometry: 1024 px = 400 mm, so 2000 px = 781.25 mm
"$BIN" render "${BASE[@]}" --gaze "$T/fix.asc" --gaze-screen 400x300@781.25 --out "$T/screen" >/dev/null 2>&1
read -r sx sy <<<"$(gaze_deg "$T/screen/frame.0001.exr")"
check "--gaze-screen with the same geometry: 10 deg again (got ${sx:-?})" bash -c "[ -n '${sx:-}' ] && near '$sx' 10 0.05"

# ---- the scene keys equal the options; plan and the run record name them
sed 's/^{/{"gaze": {"map": "normalized"},/' "$(dirname "$0")/../../scenes/builtin/fence.json" >"$T/fence_norm.json"
"$BIN" render "$T/fence_norm.json" "${BASE[@]:1}" --gaze "$T/fix.asc" --out "$T/key" >/dev/null 2>&1
check "the scene's \"gaze\": {\"map\": \"normalized\"} draws what --gaze-map normalized draws" \
  bash -c "idiff -q '$T/key/frame.0001.exr' '$T/norm/frame.0001.exr' >/dev/null"
check "plan prints the placement" bash -c "'$BIN' plan '$T/fence_norm.json' --gaze-screen 82x52deg | grep -q '^gaze map   normalized, recording geometry 82x52deg$'"
check "--gaze-map angle overrides the scene's; by default plan prints no line" \
  bash -c "! '$BIN' plan '$T/fence_norm.json' --gaze-map angle | grep -q '^gaze map' && ! '$BIN' plan fence | grep -q '^gaze map'"
check "the run record names the placement" grep -q '^gaze map: normalized, screen from the file$' "$T/norm/fovsim-run.txt"
check "by default the run record says nothing of it" bash -c "! grep -q '^gaze map' '$T/angle/fovsim-run.txt'"

# ---- bad values: one line naming the option or the JSON path, nothing written
for v in 520x290 0x290@600 520x290@600mm 82x52 200x52deg abc; do
  expect_exit "--gaze-screen $v" 2 "$BIN" render "${BASE[@]}" --gaze "$T/fix.asc" --gaze-screen "$v" --out "$T/bad"
  grep -q -- "--gaze-screen" "$T/err.txt" || fail "--gaze-screen $v: the message names the option"
done
expect_exit "--gaze-map stretch" 2 "$BIN" render "${BASE[@]}" --gaze-map stretch --out "$T/bad"
check "nothing written for a bad value" test ! -e "$T/bad"
sed 's/^{/{"gaze": {"screen": "520x290"},/' "$(dirname "$0")/../../scenes/builtin/fence.json" >"$T/bad.json"
"$BIN" plan "$T/bad.json" >/dev/null 2>"$T/bad.txt"; rc=$?
check "a bad scene key: non-zero exit and one line naming gaze.screen" \
  bash -c "[ $rc -ne 0 ] && [ \$(wc -l <'$T/bad.txt') -eq 1 ] && grep -q 'gaze.screen' '$T/bad.txt'"

summary
