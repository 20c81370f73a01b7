#!/usr/bin/env bash
# What makes `fovsim demo` faster must not change what it shows (docs/compare.md "Where the time
# goes"): the modes of a frame are measured on several threads, so a mode's metrics and maps must
# be the ones it gets measured alone; the demo writes PIZ frames (the same pixels as ZIP), which the
# OpenEXR tools read; --compression zip still gives ZIP; --verbose says where the time went. The
# frame worker (frame i measured and written while frame i + 1's reference is drawn) runs in every
# compare: every check here goes through it.
# Small sizes, few frames: about 20 s.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/demo_speed
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
for tool in exrheader exrinfo oiiotool ffmpeg python3; do
  command -v $tool >/dev/null || { echo "FAIL '$tool' is not installed (scripts/setup.sh installs it)" >&2; exit 1; }
done

SMALL=(--width 160 --height 90 --frames 6 --gaze builtin:demo_tour --supersample 2 --samples 8 --cache "$T/cache"
       --video off --previews 0)
# rows MODE CSV: MODE's rows of metrics.csv without the frame_ms column (a time, never the same twice)
rows() {
  python3 - "$1" "$2" <<'EOF'
import csv, sys
r = list(csv.DictReader(open(sys.argv[2])))
for row in r:
    if row["mode"] == sys.argv[1]:
        row.pop("frame_ms")
        print(sorted(row.items()))
EOF
}

# ---- three modes measured at once (two threads on two cores: modes 0 and 2 on one, 1 on the other)
# against each mode alone (one thread). Shared scratch between the threads (the temporal error's
# warp, a FLIP buffer) would make the rows differ.
"$BIN" compare forest "${SMALL[@]}" --modes traditional,hashed,a2c --out "$T/all" --quiet >/dev/null 2>"$T/all.err"
check "compare with three modes exits 0" test $? -eq 0
for m in hashed a2c; do
  "$BIN" compare forest "${SMALL[@]}" --modes "$m" --out "$T/$m" --quiet >/dev/null 2>"$T/$m.err"
  check "compare --modes $m exits 0" test $? -eq 0
  rows "$m" "$T/all/metrics.csv" >"$T/$m.all.rows"
  rows "$m" "$T/$m/metrics.csv" >"$T/$m.alone.rows"
  check "$m: rows measured (not an empty comparison)" test "$(wc -l <"$T/$m.alone.rows")" -ge 6
  check "$m: its metrics.csv rows are the same measured beside two modes as alone" cmp -s "$T/$m.all.rows" "$T/$m.alone.rows"
  for ch in flip error; do
    oiiotool --fail 0 --warn 0 "$T/all/compare.0005.exr" --subimage layers --ch "$m.$ch" "$T/$m/compare.0005.exr" --subimage layers \
      --ch "$m.$ch" --diff >"$T/$m.$ch.diff" 2>&1
    check "$m: frame 5's $ch map is the same beside two modes as alone" grep -q "PASS" "$T/$m.$ch.diff"
  done
done
# Not vacuous: the modes measure differently, so equal rows are not equal by construction.
check "hashed and a2c rows differ" bash -c "! cmp -s '$T/hashed.alone.rows' '$T/a2c.alone.rows'"

# ---- the demo's frames: PIZ unless --compression is given; the pixels those of ZIP
"$BIN" demo "${SMALL[@]}" --out "$T/demo_piz" --verbose >/dev/null 2>"$T/demo_piz.err"
check "demo exits 0" test $? -eq 0
check "demo frames are PIZ-compressed" bash -c "exrheader '$T/demo_piz/compare.0003.exr' | grep -qi 'piz'"
"$BIN" demo "${SMALL[@]}" --out "$T/demo_zip" --compression zip --quiet >/dev/null 2>"$T/demo_zip.err"
check "demo --compression zip exits 0" test $? -eq 0
check "demo --compression zip frames are ZIP-compressed" \
  bash -c "exrheader '$T/demo_zip/compare.0003.exr' | grep -i 'compression' | grep -qi zip"
for part in 0 1; do
  oiiotool --fail 0 --warn 0 "$T/demo_piz/compare.0003.exr" --subimage "$part" "$T/demo_zip/compare.0003.exr" --subimage "$part" \
    --diff >"$T/piz_zip.$part.diff" 2>&1
  check "part $part: PIZ and ZIP frames hold the same pixels" grep -q "PASS" "$T/piz_zip.$part.diff"
done
check "exrinfo reads the PIZ frame" exrinfo_reads "$T/demo_piz/compare.0003.exr" "piz"
check "ffmpeg decodes the PIZ frame to what it decodes the ZIP frame to" \
  bash -c "a=\$(ffmpeg -v error -i '$T/demo_piz/compare.0003.exr' -f md5 -) && [ -n \"\$a\" ] && [ \"\$a\" = \"\$(ffmpeg -v error -i '$T/demo_zip/compare.0003.exr' -f md5 -)\" ]"
check "the run record holds the compression used" grep -q "compression: piz" "$T/demo_piz/fovsim-run.txt"
# --verbose: one TIME line per phase, and the total
for phase in modes reference prepare wait finish total; do
  check "--verbose prints the $phase phase's time" grep -qE "^TIME: demo $phase +[0-9.]+ s wall +[0-9.]+ s CPU" "$T/demo_piz.err"
done
for job in metrics outputs; do
  check "--verbose prints the worker's $job time" grep -qE "^TIME: demo worker $job +[0-9.]+ s wall +[0-9.]+ s CPU" "$T/demo_piz.err"
done
check "--verbose prints the EXR writer threads' CPU time" grep -qE "^TIME: demo EXR writer threads [0-9.]+ s CPU" "$T/demo_piz.err"
check "without --verbose, no TIME lines" bash -c "! grep -q '^TIME' '$T/demo_zip.err'"

# ---- a full disk while the worker writes the frames: exit 6, one line naming the file, no partial
# frame, no temporary file, and no metrics.csv, summary.json or report
if mkdir -p "$T/full" && mount -t tmpfs -o size=900k tmpfs "$T/full" 2>/dev/null; then
  "$BIN" demo "${SMALL[@]}" --frames 12 --out "$T/full/demo" --quiet >/dev/null 2>"$T/full.err"
  rc=$?
  check "full disk -> exit 6" test $rc -eq 6
  check "full disk: one line naming a file and the full disk" \
    bash -c "grep -q 'demo/.*No space left' '$T/full.err' && [ \$(wc -l <'$T/full.err') -eq 1 ]"
  check "full disk: no temporary file left" test -z "$(find "$T/full" -name '*.tmp*')"
  check "full disk: no metrics.csv, summary.json or report.html" \
    bash -c "! ls '$T/full/demo/metrics.csv' '$T/full/demo/summary.json' '$T/full/demo/report.html' 2>/dev/null | grep -q ."
  bad=0; n=0
  for f in "$T"/full/demo/compare.*.exr; do [ -e "$f" ] || continue; n=$((n+1)); exrheader "$f" >/dev/null 2>&1 || bad=1; done
  check "full disk: every frame left ($n) is complete" test $bad -eq 0
  check "full disk: it ran out before the last frame" test ! -e "$T/full/demo/compare.0011.exr"
  umount "$T/full"
else
  echo "skip full-disk checks: cannot mount a tmpfs (not root?)" >&2
fi

summary
