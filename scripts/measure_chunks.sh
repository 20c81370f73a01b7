#!/usr/bin/env bash
# How far a chunked sweep differs from an unbroken run (docs/cluster.md "Frame chunks"):
# the forest with TAA, hashed and traditional, the demo tour gaze, split into chunks of C frames
# with W frames of warm-up, against one unbroken compare. Prints, per W, the largest and mean
# per-pixel difference (linear RGB, oiiotool --diff on each mode's layers) over the frames that
# start a chunk, and the change of the sequence's mean FLIP and coverage ratio per mode.
# usage: scripts/measure_chunks.sh [OUT] [FRAMES] [CHUNK] [W...]
set -euo pipefail
BIN=${FOVSIM_BIN:-$(cd "$(dirname "$0")/.." && pwd)/build/fovsim}
OUT=$(realpath -m "${1:-out/measure_chunks}"); FRAMES=${2:-96}; CHUNK=${3:-24}; shift $(( $# > 3 ? 3 : $# ))
WS=("$@"); [ ${#WS[@]} -gt 0 ] || WS=(0 4 8 16 32 64)
mkdir -p "$OUT"; cd "$OUT"
cat >m.json <<JSON
{ "scenes": ["forest"], "gaze": ["builtin:demo_tour"], "modes": ["traditional", "hashed"], "taa": ["on"],
  "width": 320, "height": 180, "frames": $FRAMES, "reference": {"supersample": 2}, "cache": "cache" }
JSON
"$BIN" sweep m.json --local 1 --out whole --quiet >/dev/null && "$BIN" merge whole >/dev/null
printf '%-6s %-12s %12s %12s %14s %14s\n' W mode "max |diff|" "mean |diff|" "d FLIP mean" "d cov. ratio"
for W in "${WS[@]}"; do
  "$BIN" sweep m.json --local 1 --out "w$W" --chunk-frames "$CHUNK" --warmup "$W" --quiet >/dev/null
  "$BIN" merge "w$W" >/dev/null
  for mode in traditional hashed; do
    max=0; sum=0; n=0
    for t in "w$W"/tasks/*; do
      first=$(sed -n 's/^chunk: from frame \([0-9]*\).*/\1/p' "$t/fovsim-run.txt"); [ -n "$first" ] || continue
      f=$(printf 'compare.%04d.exr' "$first")
      d=$(oiiotool "whole/tasks/"*/"$f" --subimage layers --ch "$mode.R,$mode.G,$mode.B" \
                   "$t/$f" --subimage layers --ch "$mode.R,$mode.G,$mode.B" --diff 2>&1 || true)
      mx=$(sed -n 's/.*Max error *= *\([0-9.e+-]*\).*/\1/p' <<<"$d" | head -1)
      mn=$(sed -n 's/.*Mean error *= *\([0-9.e+-]*\).*/\1/p' <<<"$d" | head -1)
      max=$(python3 -c "print(max($max, ${mx:-0}))"); sum=$(python3 -c "print($sum + ${mn:-0})"); n=$((n + 1))
    done
    a=$(grep ",$mode," whole/accuracy.csv | cut -d, -f7,8); b=$(grep ",$mode," "w$W/accuracy.csv" | cut -d, -f7,8)
    python3 - "$W" "$mode" "$max" "$sum" "$n" "$a" "$b" <<'PY'
import sys
w, mode, mx, s, n, a, b = sys.argv[1:]
fa, ca = map(float, a.split(',')); fb, cb = map(float, b.split(','))
print(f"{w:<6} {mode:<12} {float(mx):12.5f} {float(s)/max(int(n),1):12.6f} {fb-fa:+14.6f} {cb-ca:+14.5f}")
PY
  done
done
