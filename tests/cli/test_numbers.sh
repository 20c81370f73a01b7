#!/usr/bin/env bash
# Numbers are range-checked as the 32-bit floats they are used as (README "Limits", numbers): an option
# whose value is in range as a double but 0 or denormal as a float (1e-300, 1e-40) is refused with
# one line and exit 2, never taken as 0 (which reads as "the default" everywhere); a scene file's
# the same with exit 3; a glTF camera whose horizontal field of view is outside (1, 179) degrees
# is said aloud (a warning naming it) when the display's replaces it.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/numbers
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

for o in "--fps 1e-300" "--fps 1e-40" "--fps 0.0001" "--taa-blend 1e-300" "--hash-scale 1e-300" "--taa-gamma 1e-300" \
         "--taa-sparse 1e-300" "--fade-n 1e-40"; do
  # shellcheck disable=SC2086
  expect_exit "plan $o -> 2" 2 timeout 60 "$BIN" plan fence --frames 2 $o
  check "  names ${o%% *} and the value" grep -q -- "${o%% *}: expected .* got '${o#* }'" "$T/err.txt"
done
check "--fps 0.001, the slowest, is accepted" bash -c "timeout 60 '$BIN' plan fence --frames 2 --fps 0.001 >/dev/null"
check "--hash-scale 0.3 is accepted" bash -c "timeout 60 '$BIN' plan fence --frames 2 --alpha hashed --hash-scale 0.3 >/dev/null"

# A scene file's TAA settings: the same rule (exit 3, the JSON path named)
for k in blend gamma sparse; do
  printf '{"assets": [{"name": "f", "generator": "fence"}], "instances": [{"asset": "f"}], "camera": [{"time": 0, "position": [0,1,5], "target": [0,1,0]}], "taa": {"%s": 1e-300}}' "$k" >"$T/taa_$k.json"
  expect_exit "scene taa.$k 1e-300 -> 3" 3 timeout 60 "$BIN" plan "$T/taa_$k.json"
  check "  names taa.$k" grep -q "taa_$k.json: taa.$k: expected" "$T/err.txt"
done

# gltf FILE YFOV: a one-triangle glTF whose own camera has that vertical fov (radians), aspect 1
gltf() {
  python3 - "$@" <<'EOF2'
import base64, json, struct, sys
pos = struct.pack('<9f', -1, 0, 0, 1, 0, 0, 0, 1, 0)
json.dump({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
           "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0.5, 3]}],
           "cameras": [{"type": "perspective", "perspective": {"yfov": float(sys.argv[2]), "aspectRatio": 1.0, "znear": 0.1}}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-1, 0, 0], "max": [1, 1, 0]}],
           "bufferViews": [{"buffer": 0, "byteLength": 36}],
           "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64," + base64.b64encode(pos).decode()}]},
          open(sys.argv[1], "w"))
EOF2
}
gltf "$T/narrow.gltf" 0.005   # 0.29 degrees
gltf "$T/wide.gltf" 3.13      # 179.4 degrees
gltf "$T/fine.gltf" 0.8       # 45.8 degrees
for g in narrow wide; do
  timeout 60 "$BIN" plan "$T/$g.gltf" >"$T/out.txt" 2>"$T/err.txt"
  check "glTF camera too $g: still runs (exit 0)" test $? -eq 0
  check "  with one warning naming its field of view and the display's" \
    bash -c "test \$(wc -l <'$T/err.txt') -eq 1 && grep -q \"$g.gltf: its camera's horizontal field of view, [0-9.]* degrees, is not in (1, 179); the display's 90 degrees is used instead\" '$T/err.txt'"
done
timeout 60 "$BIN" plan "$T/fine.gltf" >"$T/out.txt" 2>"$T/err.txt"
check "a glTF camera of 45.8 degrees: no warning" bash -c "test $? -eq 0 && test ! -s '$T/err.txt'"

summary
