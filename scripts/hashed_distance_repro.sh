#!/usr/bin/env bash
# Reproduces the measurements of docs/hashed-alpha.md "Coverage at distance":
# walls of a MegaKit plant at 4/16/64/256 m (320x180) and a width sweep at 64 m, rings and TAA
# off, one frame, traditional/stochastic/hashed against the exact reference.
#   scripts/hashed_distance_repro.sh [OUT] [--supersample S]   (default OUT out/hashed_distance, S 4)
# Prints "mode coverage/reference=ratio" for the whole display per case.
set -eu
BIN=${FOVSIM_BIN:-build/fovsim}
OUT=${1:-out/hashed_distance}; shift || true
SHARED=$(cd "$(dirname "$0")/../../shared/assets/quaternius_megakit_set_a" && pwd)
mkdir -p "$OUT"
wall() { # ASSET D COUNT FILE: instances over 0.9 D x 0.44 D of the view, +-10 % in depth
  python3 - "$SHARED" "$1" "$2" "$3" "$4" <<'PY'
import json, sys
shared, asset, D, n, out = sys.argv[1], sys.argv[2], float(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
json.dump({"display": {"width": 320, "height": 180, "hfov": 90},
           "assets": [{"name": "p", "gltf": f"{shared}/{asset}.gltf"}],
           "instances": [{"asset": "p", "scatter": {"count": n, "seed": 1, "random_yaw": True,
               "min": [-0.45 * D, 1.5 - 0.22 * D, -1.1 * D], "max": [0.45 * D, 1.5 + 0.22 * D, -0.9 * D]}}],
           "camera": [{"time": 0, "position": [0, 1.5, 0], "target": [0, 1.5, -D]}]}, open(out, "w"))
PY
}
run() { # SCENE W H [compare options]
  local s=$1 w=$2 h=$3; shift 3
  "$BIN" compare --scene "$s" --rings off --taa off --frames 1 --width "$w" --height "$h" \
    --modes traditional,stochastic,hashed --out "$OUT/cmp" --no-cache --quiet "$@" >/dev/null
  awk -F, 'NR>1 && $4==-1 {printf "%s %.4f/%.4f=%.3f  ",$3,$6,$7,$8}' "$OUT/cmp/metrics.csv"; echo
}
for asset in Plant_1_Big Bush_Common; do
  for dc in 4:3 16:12 64:100 256:1500; do
    D=${dc%:*}; n=${dc#*:}
    wall $asset $D $n "$OUT/${asset}_$D.json"
    echo -n "$asset $D m 320x180: "; run "$OUT/${asset}_$D.json" 320 180 "$@"
  done
  for w in 1280 640 320 160 80; do
    echo -n "$asset 64 m ${w}px: "; run "$OUT/${asset}_64.json" $w $((w * 9 / 16)) "$@"
  done
done
