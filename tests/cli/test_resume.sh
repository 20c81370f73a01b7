#!/usr/bin/env bash
# Output folders (README "Output folders"): every folder records the
# configuration that wrote it; --resume keeps the complete frames of the same configuration and
# draws the rest, byte-identical to an uninterrupted run (TAA history included); another
# configuration is refused unless --replace; a compare's metrics and FovVideoVDP files never
# outlive the run that wrote them.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/resume
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
SRC=${FOVSIM_SOURCE:?set by CMake}

# same_frames A B N [NAME]: frames 0..N-1 of folders A and B are byte-identical
same_frames() {
  local a=$1 b=$2 n=$3 name=${4:-frame} i f
  for ((i = 0; i < n; i++)); do
    f=$(printf '%s.%04d.exr' "$name" "$i")
    cmp -s "$a/$f" "$b/$f" || { echo "  $f differs or is missing" >&2; return 1; }
  done
}
# interrupted SRC DST FRAMES...: DST as a run killed after writing only FRAMES of SRC would leave it
interrupted() {
  local src=$1 dst=$2 name; shift 2
  name=$(sed -n 's/^name: //p' "$src/fovsim-run.txt")
  mkdir -p "$dst"
  sed 's/^complete: yes$/complete: no/' "$src/fovsim-run.txt" >"$dst/fovsim-run.txt"
  for i in "$@"; do cp "$src/$(printf '%s.%04d.exr' "$name" "$i")" "$dst/"; done
}

# ---- render with TAA: a moving camera, a gaze trace, hashed alpha (the history matters)
R=(forest --width 96 --height 54 --frames 10 --gaze builtin:demo_tour --alpha hashed --quiet)
"$BIN" render "${R[@]}" --out "$T/full" >/dev/null
check "the record says the run completed" grep -qx 'complete: yes' "$T/full/fovsim-run.txt"
check "the record names the frames" grep -qx 'frames: 10' "$T/full/fovsim-run.txt"
interrupted "$T/full" "$T/taa" 0 1 2 3 6
"$BIN" render "${R[@]}" --out "$T/taa" --resume >"$T/out.txt" 2>"$T/err.txt"
check "resume with TAA exits 0" test $? -eq 0
check "resume with TAA: every frame equals the uninterrupted run's" same_frames "$T/full" "$T/taa" 10
check "resume with TAA: says it kept 5 frames and drew them again for the history" \
  grep -q 'resumed: kept 5 complete frames of the earlier run; drew 5 of them again without writing them' "$T/out.txt"
check "resume with TAA: wrote the 5 missing frames" grep -q '^wrote 5 frames' "$T/out.txt"
check "resume: the record says complete" grep -qx 'complete: yes' "$T/taa/fovsim-run.txt"
# A kept frame is kept: its file is not rewritten (its inode stays).
ino=$(stat -c %i "$T/taa/frame.0002.exr")
"$BIN" render "${R[@]}" --out "$T/taa" --resume >"$T/out.txt" 2>&1
check "resume of a complete run writes nothing" grep -q '^wrote 0 frames' "$T/out.txt"
check "resume of a complete run leaves the frames' files" test "$(stat -c %i "$T/taa/frame.0002.exr")" = "$ino"
# A damaged kept frame is drawn again, with a warning.
interrupted "$T/full" "$T/bad" 0 1 2 3
head -c 300 "$T/full/frame.0002.exr" >"$T/bad/frame.0002.exr"
"$BIN" render "${R[@]}" --out "$T/bad" --resume >"$T/out.txt" 2>"$T/err.txt"
check "resume past a truncated frame exits 0" test $? -eq 0
check "resume: the truncated frame is named in a warning" grep -q 'frame.0002.exr: cannot be read back; it is drawn again' "$T/err.txt"
check "resume past a truncated frame: every frame equals the uninterrupted run's" same_frames "$T/full" "$T/bad" 10
# Fewer frames than the earlier run: the later frames go.
"$BIN" render "${R[@]/10/6}" --out "$T/bad" --resume >/dev/null 2>&1
check "resume with fewer frames removes the later ones" test -f "$T/bad/frame.0005.exr" -a ! -e "$T/bad/frame.0006.exr"

# ---- a camera cut resets the history: a resume after it redraws only from the cut
# (the held grazing study cuts at 2 s and 4 s: frames 8 and 16 at 4 fps)
C=("$SRC/scenes/studies/fence_grazing_2m_held.json" --width 64 --height 36 --fps 4 --frames 12 --alpha hashed --quiet)
"$BIN" render "${C[@]}" --out "$T/cut_full" >/dev/null
interrupted "$T/cut_full" "$T/cut" 0 1 2 3 4 5 6 7 8 9
"$BIN" render "${C[@]}" --out "$T/cut" --resume >"$T/out.txt" 2>&1
check "resume after a cut: frames equal" same_frames "$T/cut_full" "$T/cut" 12
check "resume after a cut: only frames 8 and 9 drawn again" grep -q 'kept 10 complete frames .*; drew 2 of them again' "$T/out.txt"

# A camera path edited between the runs is another configuration (the content hash leaves the
# camera out: the reference cache keys each frame's matrices instead), so --resume refuses it.
cp "$SRC/scenes/studies/fence_grazing_2m_held.json" "$T/cam.json"
"$BIN" render "$T/cam.json" --width 32 --height 18 --frames 2 --out "$T/cam" --quiet >/dev/null 2>&1
sed -i '0,/"time": 0,/s//"time": 0.01,/' "$T/cam.json"
expect_exit "an edited camera path is another configuration -> 2" 2 "$BIN" render "$T/cam.json" --width 32 --height 18 --frames 2 --out "$T/cam" --quiet --resume
check "  the scene's settings are named" grep -q "(scene: .*settings" "$T/err.txt"

# ---- TAA off: frames are independent, kept ones are not drawn at all
"$BIN" render "${R[@]}" --taa off --out "$T/off_full" >/dev/null
interrupted "$T/off_full" "$T/off" 0 1 2 3
"$BIN" render "${R[@]}" --taa off --out "$T/off" --resume >"$T/out.txt" 2>&1
check "resume without TAA: frames equal" same_frames "$T/off_full" "$T/off" 10
check "resume without TAA: nothing drawn again" bash -c "grep -q 'kept 4 complete frames of the earlier run$' '$T/out.txt'"

# ---- kill -9 for real, then --resume (the kill may land after the last frame on a fast machine:
# then the resume has nothing left to draw, and the frames must still be equal)
K=(fence --width 48 --height 27 --frames 150 --fps 48 --gaze builtin:demo_tour --alpha stochastic --quiet)
"$BIN" render "${K[@]}" --out "$T/kill_full" >/dev/null
"$BIN" render "${K[@]}" --out "$T/kill" >/dev/null 2>&1 &
pid=$!
for _ in $(seq 1 400); do [ -e "$T/kill/frame.0020.exr" ] && break; kill -0 $pid 2>/dev/null || break; sleep 0.02; done
kill -KILL $pid 2>/dev/null; wait $pid 2>/dev/null
grep -qx 'complete: no' "$T/kill/fovsim-run.txt" || echo "note: the run ended before the kill" >&2
"$BIN" render "${K[@]}" --out "$T/kill" --resume >"$T/out.txt" 2>&1
check "resume after kill -9 exits 0" test $? -eq 0
check "resume after kill -9: all 150 frames equal the uninterrupted run's" same_frames "$T/kill_full" "$T/kill" 150
check "resume after kill -9: no temporary file left" test -z "$(find "$T/kill" -name '*.tmp*')"

# ---- another configuration: refused with the setting named, unless --replace
expect_exit "another configuration -> 2" 2 "$BIN" render "${R[@]}" --alpha traditional --out "$T/full"
check "the refusal names the setting and both values" grep -q "holds the output of another configuration (alpha: 'traditional' now, 'hashed' there); --replace" "$T/err.txt"
check "the refused run left the frames" same_frames "$T/taa" "$T/full" 10
expect_exit "another --name -> 2" 2 "$BIN" render "${R[@]}" --name other --out "$T/full"
"$BIN" render "${R[@]/10/3}" --alpha traditional --out "$T/full" --replace >/dev/null 2>&1
check "--replace exits 0 and writes the new frames" test $? -eq 0 -a -f "$T/full/frame.0002.exr"
check "--replace removes the earlier run's frames" test ! -e "$T/full/frame.0003.exr"
check "--replace rewrites the record" grep -qx 'alpha: traditional' "$T/full/fovsim-run.txt"
# frames no record describes (an older fovsim's, or someone else's)
mkdir -p "$T/legacy"; cp "$T/off_full/frame.0000.exr" "$T/legacy/"
expect_exit "frames without a record -> 2" 2 "$BIN" render "${R[@]}" --out "$T/legacy"
check "the refusal says no record describes them" grep -q 'holds frames frame.####.exr that no fovsim-run.txt describes' "$T/err.txt"
expect_exit "--resume and --replace -> 2" 2 "$BIN" render "${R[@]}" --out "$T/legacy" --resume --replace
expect_exit "plan --resume -> 2" 2 "$BIN" plan forest --resume
mkdir -p "$T/dirrec/fovsim-run.txt"
expect_exit "a record that is a directory -> 6" 6 "$BIN" render "${R[@]}" --out "$T/dirrec" --replace

# ---- reference: frames are independent; a resume draws only the missing ones
F=(fence --width 64 --height 36 --frames 4 --supersample 2 --no-cache --quiet)
"$BIN" reference "${F[@]}" --out "$T/ref_full" >/dev/null
interrupted "$T/ref_full" "$T/ref" 0 2
"$BIN" reference "${F[@]}" --out "$T/ref" --resume >"$T/out.txt" 2>&1
check "reference resume: frames equal" same_frames "$T/ref_full" "$T/ref" 4 reference
check "reference resume: drew 2" grep -q '^wrote 2 reference frames' "$T/out.txt"

# ---- compare: a resume draws every frame for the metrics, writes the missing ones; metrics,
# summary and FovVideoVDP files belong to the last run that finished
P=(fence --width 64 --height 36 --frames 4 --gaze builtin:demo_tour --supersample 2 --cache "$T/cache" --quiet)
"$BIN" compare "${P[@]}" --out "$T/cmp_full" >/dev/null
interrupted "$T/cmp_full" "$T/cmp" 0 1
"$BIN" compare "${P[@]}" --out "$T/cmp" --resume >"$T/out.txt" 2>&1
check "compare resume: frames equal" same_frames "$T/cmp_full" "$T/cmp" 4 compare
# every column but the last (frame_ms, a timing)
check "compare resume: metrics equal but for the timing column" \
  cmp -s <(rev "$T/cmp_full/metrics.csv" | cut -d, -f2- | rev) <(rev "$T/cmp/metrics.csv" | cut -d, -f2- | rev)
check "compare resume: the record says complete" grep -qx 'complete: yes' "$T/cmp/fovsim-run.txt"
"$BIN" compare "${P[@]}" --out "$T/fv" --export-fvvdp >/dev/null 2>&1
check "compare --export-fvvdp wrote PNGs" test -f "$T/fv/fvvdp/hashed/hashed.0003.png"
: >"$T/fv/fvvdp/mine.txt" # the user's own file there stays
"$BIN" render "${R[@]/10/2}" --out "$T/fv" --replace >/dev/null 2>&1
check "--replace of a compare folder by a render: metrics.csv and summary.json gone" \
  test ! -e "$T/fv/metrics.csv" -a ! -e "$T/fv/summary.json"
check "--replace: FovVideoVDP's PNGs and files gone" \
  test -z "$(find "$T/fv/fvvdp" -name '*.png' -o -name 'display.json' -o -name 'fixation.csv')"
check "--replace: the user's own file in fvvdp/ stays" test -f "$T/fv/fvvdp/mine.txt"
check "--replace: the compare's frames gone" test -z "$(ls "$T/fv" | grep compare)"

summary
