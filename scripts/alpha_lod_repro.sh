#!/usr/bin/env bash
# Reproduces the measurements of docs/hashed-alpha.md "Coverage at distance" and "Alpha LOD clamp":
# walls of 60 randomly turned MegaKit plants at distance D (over 0.9 D x 0.44 D
# of a 90 deg view, +-10 % in depth), 320x180, rings and TAA off, one frame, still camera,
# traditional/stochastic/hashed against the exact reference. SEEDS walls per case (scatter seeds
# 1..SEEDS), their coverage summed, because a wall of 60 small plants covers only 10-1400 pixels.
#   scripts/alpha_lod_repro.sh OUT [--seeds N] [--assets A,B] [--distances D,D] [--frames F]
#                              [-- compare options]
# e.g. scripts/alpha_lod_repro.sh out/alod -- --supersample 1 --alpha-lod-max 6
# --frames F (> 1): F frames with TAA on (still camera), the last frame measured.
# Default: 8 seeds, Clover_1 and Flower_3_Group, 32/64/128 m. FOVSIM_SHARED: the shared assets.
# Prints per asset, distance and mode: coverage / reference coverage (summed over the walls), the
# reference's covered pixels, and the mean RMSE and FLIP of the walls.
set -eu
BIN=${FOVSIM_BIN:-build/fovsim}
OUT=${1:?usage: alpha_lod_repro.sh OUT [--seeds N] [--assets A,B] [--distances D,D] [-- compare options]}
shift
SEEDS=8 ASSETS=Clover_1,Flower_3_Group DISTANCES=32,64,128 FRAMES=1
while [ $# -gt 0 ]; do
  case $1 in
  --seeds) SEEDS=$2; shift 2 ;;
  --assets) ASSETS=$2; shift 2 ;;
  --distances) DISTANCES=$2; shift 2 ;;
  --frames) FRAMES=$2; shift 2 ;;
  --) shift; break ;;
  *) echo "alpha_lod_repro.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
SHARED=$(cd "${FOVSIM_SHARED:-$(dirname "$0")/../../shared}/assets/quaternius_megakit_set_a" && pwd)
mkdir -p "$OUT"
wall() { # ASSET D SEED FILE
  python3 - "$SHARED" "$1" "$2" "$3" "$4" <<'PY'
import json, sys
shared, asset, D, seed, out = sys.argv[1], sys.argv[2], float(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
json.dump({"display": {"width": 320, "height": 180, "hfov": 90},
           "assets": [{"name": "p", "gltf": f"{shared}/{asset}.gltf"}],
           "instances": [{"asset": "p", "scatter": {"count": 60, "seed": seed, "random_yaw": True,
               "min": [-0.45 * D, 1.5 - 0.22 * D, -1.1 * D], "max": [0.45 * D, 1.5 + 0.22 * D, -0.9 * D]}}],
           "camera": [{"time": 0, "position": [0, 1.5, 0], "target": [0, 1.5, -D]}]}, open(out, "w"))
PY
}
for asset in ${ASSETS//,/ }; do
  for D in ${DISTANCES//,/ }; do
    : >"$OUT/${asset}_$D.csv"
    for seed in $(seq 1 "$SEEDS"); do
      wall "$asset" "$D" "$seed" "$OUT/${asset}_${D}_$seed.json"
      TAA=off; [ "$FRAMES" -gt 1 ] && TAA=on
      "$BIN" compare --scene "$OUT/${asset}_${D}_$seed.json" --rings off --taa $TAA --frames "$FRAMES" \
        --modes traditional,stochastic,hashed --out "$OUT/cmp" --replace --quiet "$@" >/dev/null
      awk -F, -v last=$((FRAMES - 1)) 'NR>1 && $4==-1 && $1==last' "$OUT/cmp/metrics.csv" >>"$OUT/${asset}_$D.csv"
    done
    echo -n "$asset $D m: "
    awk -F, '{c[$3]+=$6*$5; r[$3]+=$7*$5; e[$3]+=$9; f[$3]+=$11; n[$3]++; if (!($3 in o)) o[$3]=++k}
      END {for (m in o) s[o[m]]=m; for (i=1;i<=k;i++) {m=s[i]; printf "%s %.3f (ref %d px, rmse %.4f, flip %.4f)  ", m, c[m]/r[m], r[m], e[m]/n[m], f[m]/n[m]}; print ""}' \
      "$OUT/${asset}_$D.csv"
  done
done
