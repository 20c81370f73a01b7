#!/usr/bin/env bash
# The eye tracker end to end (docs/latency.md): after a saccade, ceil(L * fps / 1000) frames show
# the true gaze from a coarse ring (read from the ring.id channel the composite wrote); --gaze-loss
# full draws lost frames as --rings off draws them; --gaze-latency 0 is today's output; the scene
# key equals the option; plan and the run record name the tracker; bad values get one line.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/gaze_tracker
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

W=320; H=180
BASE=(forest --width $W --height $H --rings 8:1:0,20:1/2:0,*:1/8:0 --fps 24 --taa off --alpha traditional --quiet)

# A 1 kHz trace: fixation at x 0.3, a saccade landing at x 0.7 at 0.5 s (frame 12 at 24 fps).
/usr/bin/python3 - "$T" <<'EOF'
import sys
d = sys.argv[1]
with open(d + "/saccade.csv", "w") as f:
    f.write("t,x,y\n")
    for k in range(1001):
        f.write("%.3f,%s,0.5\n" % (k / 1000, "0.3" if k < 500 else "0.7"))
with open(d + "/gap.csv", "w") as f:  # tracking lost from 0.2 to 0.4 s (frames 5 to 9)
    f.write("t,x,y,confidence\n")
    for k in range(1001):
        f.write("%.3f,0.3,0.4,%d\n" % (k / 1000, 0 if 200 < k < 400 else 1))
EOF

# ring_at FILE X Y: the ring.id the composite wrote at pixel (X, Y)
ring_at() {
  oiiotool "$1" --ch ring.id --cut "1x1+$2+$3" -o "$T/px.exr" >/dev/null 2>&1 &&
    oiiotool --dumpdata "$T/px.exr" | awk '/Pixel/ {printf "%d\n", $NF}'
}
# coarse_frames DIR: frames 12..17 (after the landing) whose true gaze (x 0.7) took a ring > 0
coarse_frames() {
  local n=0 i r
  for i in 12 13 14 15 16 17; do
    r=$(ring_at "$1/frame.00$i.exr" $((W * 7 / 10)) $((H / 2)))
    [ -n "$r" ] && [ "$r" -gt 0 ] && n=$((n + 1))
  done
  echo $n
}

# ---- latency: ceil(L * 24 / 1000) frames after the landing show the true fovea coarse
for L in 0 50 100; do
  "$BIN" render "${BASE[@]}" --frames 18 --debug-channels --gaze "$T/saccade.csv" --gaze-latency $L \
    --out "$T/lat$L" >/dev/null 2>&1
done
check "latency 0: no frame after the landing shows the true gaze from a coarse ring" [ "$(coarse_frames "$T/lat0")" = 0 ]
check "latency 50 ms at 24 fps: ceil(1.2) = 2 frames" [ "$(coarse_frames "$T/lat50")" = 2 ]
check "latency 100 ms at 24 fps: ceil(2.4) = 3 frames" [ "$(coarse_frames "$T/lat100")" = 3 ]
check "frames carry the true gaze beside the rendered one" \
  bash -c "oiiotool --info -v '$T/lat50/frame.0012.exr' | grep -q 'fovsim:true_gaze: 0.7, 0.5' &&
           oiiotool --info -v '$T/lat50/frame.0012.exr' | grep -q 'fovsim:gaze: 0.3, 0.5'"
check "the run record names the tracker" grep -q '^gaze tracker: latency 50 ms, rate trace, noise 0 deg seed 0, loss hold$' "$T/lat50/fovsim-run.txt"

# ---- defaults: --gaze-latency 0 (and a seed without noise) draw today's frames
"$BIN" render "${BASE[@]}" --frames 14 --debug-channels --gaze "$T/saccade.csv" --out "$T/plain" >/dev/null 2>&1
check "--gaze-latency 0 draws the frames drawn without it" \
  bash -c "idiff -q '$T/plain/frame.0013.exr' '$T/lat0/frame.0013.exr' >/dev/null"
check "without the tracker the record and the frames say nothing of it" \
  bash -c "! grep -q 'gaze tracker' '$T/plain/fovsim-run.txt' && ! oiiotool --info -v '$T/plain/frame.0013.exr' | grep -q true_gaze"

# ---- loss: full draws the lost frames as foveation off draws them; hold keeps the rings
"$BIN" render "${BASE[@]}" --frames 12 --gaze "$T/gap.csv" --gaze-loss full --out "$T/full" >/dev/null 2>&1
"$BIN" render "${BASE[@]}" --frames 12 --gaze "$T/gap.csv" --gaze-loss hold --out "$T/hold" >/dev/null 2>&1
"$BIN" render "${BASE[@]}" --frames 12 --gaze "$T/gap.csv" --rings off --out "$T/off" >/dev/null 2>&1
check "full: a lost frame says so" bash -c "oiiotool --info -v '$T/full/frame.0007.exr' | grep -q 'fovsim:full_res: 1'"
# the composite blends identical full-resolution rings: equal to within a half-float step
check "full: a lost frame equals the frame drawn with --rings off" \
  bash -c "idiff -fail 0.001 '$T/full/frame.0007.exr' '$T/off/frame.0007.exr' >/dev/null"
check "hold: the same lost frame keeps its rings (differs from --rings off)" \
  bash -c "! idiff -fail 0.001 '$T/hold/frame.0007.exr' '$T/off/frame.0007.exr' >/dev/null"
check "full: a tracked frame keeps its rings" \
  bash -c "! idiff -fail 0.001 '$T/full/frame.0003.exr' '$T/off/frame.0003.exr' >/dev/null &&
           idiff -q '$T/full/frame.0003.exr' '$T/hold/frame.0003.exr' >/dev/null"

# ---- the scene key equals the option; plan prints it; the CLI wins
sed 's/^{/{"gaze": {"latency": 50},/' "$(dirname "$0")/../../scenes/builtin/forest.json" >"$T/forest_lat.json"
"$BIN" render "$T/forest_lat.json" "${BASE[@]:1}" --frames 14 --debug-channels --gaze "$T/saccade.csv" --out "$T/key" >/dev/null 2>&1
check "the scene's \"gaze\": {\"latency\"} draws what --gaze-latency draws" \
  bash -c "idiff -q '$T/key/frame.0013.exr' '$T/lat50/frame.0013.exr' >/dev/null"
check "plan prints the tracker" bash -c "'$BIN' plan '$T/forest_lat.json' --gaze-rate 90 | grep -q '^tracker    latency 50 ms, rate 90 Hz, noise 0 deg seed 0, loss hold'"
check "plan without a tracker prints no line" bash -c "! '$BIN' plan forest | grep -q '^tracker'"
check "--gaze-latency 0 overrides the scene's" bash -c "! '$BIN' plan '$T/forest_lat.json' --gaze-latency 0 | grep -q '^tracker'"

# ---- bad values: one line naming the option or the JSON path
expect_exit "--gaze-loss blink" 2 "$BIN" render forest --gaze-loss blink
expect_exit "--gaze-latency -5" 2 "$BIN" render forest --gaze-latency -5
expect_exit "--gaze-noise 31" 2 "$BIN" render forest --gaze-noise 31
sed 's/^{/{"gaze": {"loss": "blink"},/' "$(dirname "$0")/../../scenes/builtin/forest.json" >"$T/bad.json"
"$BIN" plan "$T/bad.json" >/dev/null 2>"$T/bad.txt"; rc=$?
check "a bad scene key: exit 3 and one line naming gaze.loss" \
  bash -c "[ $rc -ne 0 ] && [ \$(wc -l <'$T/bad.txt') -eq 1 ] && grep -q 'gaze.loss' '$T/bad.txt'"

summary
