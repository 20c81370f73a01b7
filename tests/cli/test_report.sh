#!/usr/bin/env bash
# The pictures for people (docs/compare.md "Video and report page"): compare --video writes an MP4
# of the grid that ffprobe decodes with one frame per measured frame at part 0's size (padded to
# even), --video off or no ffmpeg gives PNG previews and report.html's scrubber, a failing ffmpeg
# leaves no video.mp4, demo makes a video by default, and report.html escapes the folder's name.
# The page in a browser: test_report_browser.sh. 160x90-ish, 5 frames: a few seconds.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/report
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
for tool in ffmpeg ffprobe python3; do
  command -v $tool >/dev/null || { echo "FAIL '$tool' is not installed (scripts/setup.sh installs it)" >&2; exit 1; }
done
REF=(--supersample 2 --samples 8 --cache "$T/cache")
# run CMD OUT [OPTION...]: 161x91 (an odd grid: the video pads it), 5 frames; compare draws forest
run() {
  local scene=(forest); [ "$1" = demo ] && scene=()
  "$BIN" "$1" "${scene[@]}" --width 161 --height 91 --frames 5 "${REF[@]}" --out "$2" --quiet "${@:3}" >"$2.txt" 2>"$2.err"
}
# part0_size EXR: "W H" of part 0 (the grid)
part0_size() {
  /usr/bin/python3 -c "
import OpenImageIO as oiio,sys
i=oiio.ImageInput.open(sys.argv[1]); s=i.spec(); print(s.width, s.height); i.close()" "$1"
}

# ---- --video on: ffprobe decodes every frame, part 0's size padded to even
run compare "$T/v" --video on; rc=$?
check "compare --video on exits 0" test $rc -eq 0
read -r W H < <(part0_size "$T/v/compare.0000.exr")
EW=$(( (W + 1) / 2 * 2 )); EH=$(( (H + 1) / 2 * 2 ))
probe=$(ffprobe -v error -count_frames -select_streams v:0 \
  -show_entries stream=codec_name,width,height,pix_fmt,nb_read_frames,color_transfer -of default=nw=1 "$T/v/video.mp4" 2>&1)
check "video.mp4 is H.264" grep -qx "codec_name=h264" <<<"$probe"
check "video.mp4 has the 5 frames" grep -qx "nb_read_frames=5" <<<"$probe"
check "video.mp4 is ${EW}x${EH} (part 0 ${W}x${H}, padded to even)" \
  bash -c "grep -qx 'width=$EW' <<<'$probe' && grep -qx 'height=$EH' <<<'$probe'"
check "video.mp4 is yuv420p, sRGB transfer" bash -c "grep -qx pix_fmt=yuv420p <<<'$probe' && grep -qx color_transfer=iec61966-2-1 <<<'$probe'"
check "no temporary or log file is left" bash -c "! ls -A '$T/v' | grep -q -e '\.tmp\.' -e ffmpeg.log"
check "no previews beside a video" test ! -e "$T/v/preview"
check "report.html shows the video" grep -q '<video id="video" src="video.mp4"' "$T/v/report.html"
check "the hints name video.mp4, not a recipe to make one" \
  bash -c "grep -qF \"xdg-open '$T/v/video.mp4'\" '$T/v.txt' && ! grep -q 'ffmpeg -framerate' '$T/v.txt'"
# The first frame's middle pixel of the video is the grid's, sRGB-encoded (within the codec's error).
/usr/bin/python3 - "$T/v" <<'PY' >"$T/pixel.txt" 2>&1
import OpenImageIO as oiio, subprocess, sys
d = sys.argv[1]
i = oiio.ImageInput.open(d + "/compare.0000.exr"); s = i.spec(); px = i.read_image(0, 0, 0, 3, "float"); i.close()
w, h = s.width, s.height
ew, eh = (w + 1) // 2 * 2, (h + 1) // 2 * 2
raw = subprocess.run(["ffmpeg", "-v", "error", "-i", d + "/video.mp4", "-frames:v", "1", "-f", "rawvideo",
                      "-pix_fmt", "rgb24", "-"], capture_output=True, check=True).stdout
assert len(raw) == ew * eh * 3, len(raw)
def srgb(l):
    l = min(max(l, 0.0), 1.0)
    return 255 * (12.92 * l if l <= 0.0031308 else 1.055 * l ** (1 / 2.4) - 0.055)
# the mean over a block in the middle of the first tile (H.264 blurs single pixels)
x0, y0, n = w // 6 - 8, h // 4 - 8, 16
err = 0
for c in range(3):
    a = sum(srgb(float(px[y][x][c])) for y in range(y0, y0 + n) for x in range(x0, x0 + n)) / n / n
    b = sum(raw[(y * ew + x) * 3 + c] for y in range(y0, y0 + n) for x in range(x0, x0 + n)) / n / n
    err = max(err, abs(a - b))
print(err)
sys.exit(0 if err < 6 else 1)
PY
check "the video's pixels are the grid's in sRGB (largest block mean difference $(tail -1 "$T/pixel.txt") of 255)" test $? -eq 0

# ---- --video off (compare's default): previews and the scrubber
run compare "$T/p"; rc=$?
check "compare exits 0" test $rc -eq 0
check "compare writes no video by default" test ! -e "$T/p/video.mp4"
check "without a video the hints give the ffmpeg recipe" grep -q 'ffmpeg -framerate' "$T/p.txt"
check "one preview PNG per frame" test "$(ls "$T/p/preview" | grep -c '^frame\.000[0-4]\.png$')" -eq 5
check "report.html has the scrubber" grep -q '<input type="range" id="scrub" min="0" max="4"' "$T/p/report.html"
check "report.html has no external resource" bash -c "! grep -Eiq '(src|href)=\"(https?:)?//' '$T/p/report.html'"

# ---- --previews N: at most N previews, evenly spaced from the first frame; 0: none
run compare "$T/p2" --previews 2; rc=$?
check "--previews 2: frames 0 and 3 of 5 (every third)" \
  bash -c "test $rc -eq 0 && test \"\$(ls '$T/p2/preview' | tr '\n' ' ')\" = 'frame.0000.png frame.0003.png '"
check "--previews 2: the scrubber has two steps" grep -q '<input type="range" id="scrub" min="0" max="1"' "$T/p2/report.html"
run compare "$T/p0" --previews 0; rc=$?
check "--previews 0: no preview folder" bash -c "test $rc -eq 0 && test ! -e '$T/p0/preview'"

# ---- no ffmpeg on PATH: one line saying how to install it, previews instead, exit 0
mkdir -p "$T/nobin"
PATH="$T/nobin" run compare "$T/n" --video on; rc=$?
check "--video on without ffmpeg exits 0" test $rc -eq 0
check "it says how to install ffmpeg" grep -q "ffmpeg is not installed.*apt install ffmpeg" "$T/n.txt"
check "without ffmpeg: no video.mp4, previews" bash -c "test ! -e '$T/n/video.mp4' && test -s '$T/n/preview/frame.0004.png'"

# ---- an ffmpeg that fails: no video.mp4, no temporary file, a line naming ffmpeg.log, non-zero exit
mkdir -p "$T/badbin"; printf '#!/bin/sh\necho broken encoder >&2\nexit 3\n' >"$T/badbin/ffmpeg"; chmod +x "$T/badbin/ffmpeg"
PATH="$T/badbin:$PATH" run compare "$T/f" --video on; rc=$?
check "a failing ffmpeg fails the run (exit $rc)" test $rc -ne 0
check "a failing ffmpeg leaves no video.mp4 nor its temporary file" \
  bash -c "test ! -e '$T/f/video.mp4' && ! ls -A '$T/f' | grep -q '\.tmp\.'"
check "the message names ffmpeg.log" grep -q "ffmpeg.log" "$T/f.err"
check "the frames and summary are still written" test -s "$T/f/summary.json"

# ---- demo: a video by default; --video off turns it off
run demo "$T/d"; rc=$?
check "demo exits 0" test $rc -eq 0
check "demo writes video.mp4 by default" test -s "$T/d/video.mp4"
check "demo writes report.html" test -s "$T/d/report.html"
run demo "$T/d" --video off; rc=$?
check "demo --video off: no video.mp4 (an earlier run's removed), previews" \
  bash -c "test $rc -eq 0 && test ! -e '$T/d/video.mp4' && test -d '$T/d/preview'"

# ---- a folder name with markup is escaped in the page
X="$T/x<b>&\"y"
run compare "$X"; rc=$?
check "compare into a folder named with markup exits 0" test $rc -eq 0
check "report.html escapes the folder's name" bash -c "grep -qF 'x&lt;b&gt;&amp;&quot;y' '$X/report.html' && ! grep -qF 'x<b>' '$X/report.html'"

expect_exit "--video maybe is refused" 2 "$BIN" compare forest --video maybe --out "$T/bad"
check "--video maybe writes nothing" test ! -e "$T/bad"
summary
