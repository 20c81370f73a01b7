#!/usr/bin/env bash
# scripts/device_check.sh (docs/benchmarks.md "On a GPU: the device check") checked on llvmpipe
# with --quick --allow-software: it refuses a software renderer without the flag, runs the bench
# matrix and the calibration, and writes a report whose rows and goal lines come from the JSON it
# gathered. The GPU numbers themselves can only come from a GPU.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SRC=$(cd "$(dirname "$0")/../.." && pwd)
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/device_check
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
BUILD=$(dirname "$BIN")
DC="$SRC/scripts/device_check.sh"

"$DC" --build "$BUILD" --out "$T/refused" --doc-dir "$T/refused-doc" --no-tests >"$T/refused.txt" 2>&1
check "a software renderer is refused without --allow-software" grep -q "device_check: no GPU: the renderer is llvmpipe" "$T/refused.txt"
check "nothing is written when refused" test ! -e "$T/refused-doc/gpu-llvmpipe.md"
"$DC" --bogus >"$T/bogus.txt" 2>&1
check "an unknown argument is named" grep -q "unknown argument '--bogus'" "$T/bogus.txt"

"$DC" --build "$BUILD" --out "$T/out" --doc-dir "$T/doc" --quick --allow-software --no-tests >"$T/run.txt" 2>&1
check "the run says it is done" grep -q "^device_check: done in" "$T/run.txt"
check "no step failed" bash -c "! grep -q 'failed' '$T/run.txt'"
MD="$T/doc/gpu-llvmpipe.md"
check "the report is named after the renderer" test -s "$MD"
check "a quick run says it is not a measurement" grep -q "not a measurement" "$MD"
check "16 matrix rows (2 sizes x 2 layouts x 2 TAA x 2 modes)" test "$(grep -c '^| [0-9]*x[0-9]* |' "$MD")" -eq 16
# The goals' counts are recomputed from the JSON the report gathered.
/usr/bin/python3 - "$T/doc/gpu-llvmpipe.json" "$MD" <<'PY' && ok "goal counts agree with the rows" || fail "goal counts agree with the rows"
import json, re, sys
d = json.load(open(sys.argv[1])); md = open(sys.argv[2]).read()
rows = d['rows']
assert len(rows) == 16 and len(d['bench']) == 8, (len(rows), len(d['bench']))
fov = [r for r in rows if r['fraction'] is not None]
n = sum(1 for r in fov if r['fraction'] >= 0.8)
assert '%d of %d configurations' % (n, len(fov)) in md
for r in rows:  # each row's fraction is its speed-up over its ideal
    assert abs(r['fraction'] - r['speedup'] / r['covered_ideal']) < 1e-9
    assert r['covered_ideal'] > 1.0, r  # the forest's rings always cut covered fragments
PY
check "the calibrated model is in the report" grep -q "^| composite | [0-9]" "$MD"
check "the model file was kept" /usr/bin/python3 -c "import json,sys; m=json.load(open(sys.argv[1])); assert 'llvmpipe' in m['renderer']" "$T/out/cost-model.json"
summary
