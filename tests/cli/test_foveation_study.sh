#!/usr/bin/env bash
# compare --foveation rings,vrs,off (issue 33 part 4; docs/foveation.md "Rings or VRS for
# alpha-tested foliage"): one compare run per foveation, all measured in the same rings, each
# counting what a GPU would shade, and foveation.csv with the modes side by side. And the coverage
# study on the fence dolly: under VRS's coarse tiles traditional alpha testing loses the fence,
# hashed keeps it within 10 % of the reference. TAA off there: the alpha test's own decision, not
# TAA's (docs/foveation.md has both). About 10 s.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/foveation_study
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
PY=/usr/bin/python3

"$BIN" compare forest --foveation vrs,off,rings --modes traditional,hashed --width 160 --height 90 --frames 3 \
  --supersample 1 --out "$T/f" --quiet >"$T/f.txt" 2>"$T/f.err"
check "compare --foveation vrs,off,rings exits 0" test $? -eq 0
check "a run folder per foveation, each complete" bash -c "for f in rings vrs off; do test -s '$T/f/foveation-'\$f/summary.json || exit 1; done"
check "foveation.csv: rings, vrs, off in that order, every mode, the same measurement rings, finite" $PY -c "
import csv, json, math, sys
rows = list(csv.DictReader(open('$T/f/foveation.csv')))
fov = []
for r in rows:
    if r['foveation'] not in fov:
        fov.append(r['foveation'])
assert fov == ['rings', 'vrs', 'off'], fov
rings = {f: sorted({r['ring'] for r in rows if r['foveation'] == f}) for f in fov}
assert rings['rings'] == rings['vrs'] == rings['off'] and '-1' in rings['vrs'] and len(rings['vrs']) >= 2, rings
for r in rows:
    for k in ('coverage_ratio', 'flip', 'shaded_per_px', 'frame_ms_median'):
        assert math.isfinite(float(r[k])) and float(r[k]) >= 0, (k, r)
# each run's summary says how it was measured: every one in the rings run's rings
m = {f: json.load(open('$T/f/foveation-%s/summary.json' % f))['measurement_rings'] for f in fov}
assert m['vrs'] == m['off'] == m['rings'], m
# shaded/px is the run's own count: its summary's shaded_fragments_median per display pixel
for f in fov:
    s = json.load(open('$T/f/foveation-%s/summary.json' % f))
    for md in s['modes']:
        got = [float(r['shaded_per_px']) for r in rows if r['foveation'] == f and r['mode'] == md['mode']][0]
        assert abs(got - md['shaded_fragments_median'] / (160 * 90)) < 1e-5, (f, md, got)
sh = {r['foveation']: float(r['shaded_per_px']) for r in rows if r['mode'] == 'traditional'}
assert sh['vrs'] < sh['off'], sh  # coarse shading shades less than full resolution
"
check "the table: the modes under each foveation" bash -c "grep -q '^foveation study' '$T/f.txt' && grep -qE '^hashed +rings ' '$T/f.txt' && grep -qE '^ +vrs ' '$T/f.txt'"

# ---- the coverage study: fence dolly, 320 x 180, auto rate map (its outer ring: coarse tiles, 2x2 and coarser
# but for a few 1x2 and 2x1 along its inner border)
"$BIN" compare fence --foveation vrs,off --modes traditional,hashed --taa off --width 320 --height 180 --frames 6 \
  --supersample 2 --out "$T/fence" --quiet >/dev/null 2>"$T/fence.err"
check "fence study exits 0" test $? -eq 0
check "fence: traditional loses the fence in VRS's coarse tiles, hashed keeps it within 10 % of the reference" $PY -c "
import csv
rows = list(csv.DictReader(open('$T/fence/foveation.csv')))
cov = {(r['foveation'], r['mode'], r['ring']): float(r['coverage_ratio']) for r in rows}
outer = max(int(r['ring']) for r in rows)  # the outermost measurement ring: coarse tiles
assert outer >= 1, outer
t_vrs, t_off = cov[('vrs', 'traditional', str(outer))], cov[('vrs', 'traditional', '0')]
print('traditional outer ring: vrs %.3f, full resolution %.3f; hashed vrs %.3f' % (
    t_vrs, cov[('off', 'traditional', str(outer))], cov[('vrs', 'hashed', str(outer))]))
assert t_vrs < 0.5 * cov[('off', 'traditional', str(outer))], cov
assert t_vrs < 0.05, cov
for k in range(1, outer + 1):
    h = cov[('vrs', 'hashed', str(k))]
    assert abs(h - 1.0) <= 0.10, (k, h)
"

# ---- refusals, one line each
expect_exit "render refuses a foveation list" 2 "$BIN" render --foveation rings,vrs --frames 1 --out "$T/r"
expect_exit "a foveation given twice" 2 "$BIN" compare --foveation vrs,vrs --frames 1 --out "$T/r"
expect_exit "an unknown foveation" 2 "$BIN" compare --foveation rings,tiles --frames 1 --out "$T/r"
expect_exit "a foveation study and a latency study at once" 2 "$BIN" compare --foveation rings,vrs --gaze-latency 0,50 --frames 1 --out "$T/r"
expect_exit "--vrs without vrs in the list" 2 "$BIN" compare --foveation rings,off --vrs '*:2x2' --frames 1 --out "$T/r"
summary
