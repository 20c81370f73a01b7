#!/usr/bin/env bash
# Work counts of `fovsim bench` (docs/benchmarks.md "Work counts"): covered fragments are exact,
# so a quad of known size covers exactly its pixels, in every alpha mode (they count before the
# alpha test), and a ring's hole receives no counted fragments when the ring culls what only its
# hole shows. Counts only, never times (llvmpipe is deterministic in them).
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SRC=$(cd "$(dirname "$0")/../.." && pwd)
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/counts
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

# A 256 x 256 display with hfov 90 has a focal length of 128 pixels: a square of side 0.125 one
# unit in front of the camera spans 16 x 16 pixels, its edges on pixel boundaries (120 and 136);
# scaled by 2 in x, 32 x 16.
/usr/bin/python3 "$SRC/tests/cli/make_quad_gltf.py" "$T/opaque.gltf" 0.0625 OPAQUE
/usr/bin/python3 "$SRC/tests/cli/make_quad_gltf.py" "$T/mask.gltf" 0.0625 MASK
for k in opaque mask; do
  cat >"$T/$k.json" <<JSON
{"display": {"width": 256, "height": 256, "hfov": 90},
 "assets": [{"name": "quad", "gltf": "$k.gltf"}],
 "instances": [{"asset": "quad", "scale": [2, 1, 1]}],
 "camera": [{"time": 0, "position": [0, 0, 1], "target": [0, 0, 0]}]}
JSON
done
cat >"$T/small.json" <<JSON
{"display": {"width": 256, "height": 256, "hfov": 90},
 "assets": [{"name": "quad", "gltf": "opaque.gltf"}],
 "instances": [{"asset": "quad"}],
 "camera": [{"time": 0, "position": [0, 0, 1], "target": [0, 0, 0]}]}
JSON

# covered FILE CONFIG STAGE: covered fragments of a stage over all frames (the frame's with STAGE "frame")
covered() {
  /usr/bin/python3 -c "
import json, sys
c = json.load(open(sys.argv[1]))['configs'][int(sys.argv[2])]
print(c['covered_fragments']['all_frames'] if sys.argv[3] == 'frame' else
      [s for s in c['stages'] if s['name'].startswith(sys.argv[3])][0]['covered_fragments_all_frames'])" "$@"
}
eq() { [ "$1" = "$2" ] || { echo "  got $1, expected $2" >&2; return 1; }; }

# ---- a quad of known size covers exactly its pixels: opaque, and alpha-tested in two modes
"$BIN" bench "$T/opaque.json" --frames 3 --warmup 0 --rings off --taa off --format json >"$T/opaque_b.json" 2>"$T/err.txt"
check "opaque 32x16 quad: 512 covered fragments per frame" eq "$(covered "$T/opaque_b.json" 0 forward.opaque)" $((3 * 512))
check "opaque quad: the frame's covered fragments are the pass's" eq "$(covered "$T/opaque_b.json" 0 frame)" $((3 * 512))
# footprint bytes (passes/pass_bytes.h): rings off, TAA off, the forward targets of the 256 x 256
# display, RGBA16F colour + R16F coverage + 32-bit depth written once (14 bytes), depth read once (4)
bytes() {
  /usr/bin/python3 -c "
import json, sys
s = json.load(open(sys.argv[1]))['configs'][0]['stages'][0]
print(s['bytes_read_all_frames'], s['bytes_written_all_frames'])" "$1"
}
check "opaque quad: footprint bytes of the forward pass" eq "$(bytes "$T/opaque_b.json")" "$((3 * 65536 * 4)) $((3 * 65536 * 14))"
check "opaque quad: bench JSON consistent" /usr/bin/python3 "$SRC/tests/cli/check_bench_json.py" "$T/opaque_b.json" known
"$BIN" bench "$T/mask.json" --frames 2 --warmup 0 --rings off --taa off --modes traditional,hashed \
  --format json >"$T/mask_b.json" 2>"$T/err.txt"
check "alpha-tested quad, traditional: 512 covered fragments per frame" eq "$(covered "$T/mask_b.json" 0 'forward.mask[traditional]')" $((2 * 512))
check "alpha-tested quad, hashed: 512 covered fragments per frame" eq "$(covered "$T/mask_b.json" 1 'forward.mask[hashed]')" $((2 * 512))
check "alpha-tested quad: no covered fragments in the opaque pass" eq "$(covered "$T/mask_b.json" 0 frame)" $((2 * 512))
check "alpha-tested quad: bench JSON consistent" /usr/bin/python3 "$SRC/tests/cli/check_bench_json.py" "$T/mask_b.json" known
FOVSIM_NO_PIPELINE_STATS=1 "$BIN" bench "$T/opaque.json" --frames 2 --warmup 0 --rings off --taa off \
  --format json >"$T/nostats.json" 2>"$T/err.txt"
check "without pipeline statistics: covered fragments still counted" eq "$(covered "$T/nostats.json" 0 frame)" $((2 * 512))
check "without pipeline statistics: bench JSON consistent" /usr/bin/python3 "$SRC/tests/cli/check_bench_json.py" "$T/nostats.json" unknown

# ---- a ring's hole: the 16 x 16 quad at the gaze lies in ring 1's hole (20 degrees: 46 pixels).
# Culled, ring 1 counts no fragment; drawn, it covers its 4 x 4 quarter-resolution pixels.
for c in on off; do
  "$BIN" bench "$T/small.json" --frames 2 --warmup 0 --rings "20:1:0,*:1/4:0" --ring-cull $c --taa off \
    --format json >"$T/cull_$c.json" 2>"$T/err.txt"
done
check "ring cull on: ring 0 covers the quad's 256 pixels per frame" eq "$(covered "$T/cull_on.json" 1 'ring 0')" $((2 * 256))
check "ring cull on: ring 1's hole receives no counted fragments" eq "$(covered "$T/cull_on.json" 1 'ring 1')" 0
check "ring cull off: ring 1 covers the quad's 4x4 ring pixels per frame" eq "$(covered "$T/cull_off.json" 1 'ring 1')" $((2 * 16))
check "ring cull off: bench JSON consistent" /usr/bin/python3 "$SRC/tests/cli/check_bench_json.py" "$T/cull_off.json" known
check "covered-fragment ideal: full resolution 256 / foveated (256 + 16)" /usr/bin/python3 -c "
import json, sys; j = json.load(open(sys.argv[1]))
sys.exit(abs(j['covered_fragment_ideal_speedup'] - 256 / 272) > 1e-4)" "$T/cull_off.json"

# ---- the text report: the counts' columns and the covered-fragment ideal
"$BIN" bench "$T/small.json" --frames 2 --warmup 0 --rings "20:1:0,*:1/4:0" --taa off >"$T/text.md" 2>"$T/err.txt"
check "text: work table has primitives after clipping, covered fragments and their ratio" \
  grep -q "| primitives after clipping | covered fragments | bytes read (footprints) | bytes written (footprints) | shaded fragments | invocations / covered |" "$T/text.md"
check "text: the covered-fragment ideal beside the pixel ideal" grep -q '^covered-fragment ideal 1.00x' "$T/text.md"
summary
