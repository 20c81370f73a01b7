#!/usr/bin/env bash
# VRS foveation beside rings (issue 33 part 4; docs/foveation.md "Rings or VRS for alpha-tested
# foliage"): bench --accuracy has vrs rows, measured in the same rings as the others, and a sweep
# manifest's "rings": "vrs" runs its task's compare under VRS and merges beside the ring layouts.
# An all-4x4 rate map on a tiny forest, so VRS changes what traditional covers: about 10 s.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/vrs_accuracy
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
command -v gnuplot >/dev/null || { echo "gnuplot is not installed: skipping" >&2; exit 77; }
cd "$T" || exit 1

# ---- bench --accuracy: vrs rows for every mode x TAA, finite, and coarse shading changes them
"$BIN" bench forest --accuracy --modes traditional,hashed --width 160 --height 90 --frames 2 --warmup 1 \
  --supersample 1 --vrs '*:4x4' --out acc --quiet >acc.txt 2>&1; rc=$?
check "bench --accuracy --vrs exits 0" test $rc -eq 0
check "accuracy.csv: vrs rows, finite, traditional's coverage not the rings' under 4x4 shading" python3 -c "
import csv, math
rows = list(csv.DictReader(open('acc/accuracy.csv')))
assert len(rows) == 16, len(rows)
row = {(r['mode'], r['rings'], r['taa']): r for r in rows}
for m in ('traditional', 'hashed'):
    assert [(r['rings'], r['taa']) for r in rows if r['mode'] == m][-2:] == [('vrs', 'off'), ('vrs', 'on')]
    for t in ('off', 'on'):
        v = row[(m, 'vrs', t)]
        for k in ('rmse', 'flip', 'temporal_error', 'alpha_rmse', 'coverage_ratio_ring0', 'flip_ring0'):
            assert math.isfinite(float(v[k])) and float(v[k]) >= 0, (k, v)
        # a GPU's coarse-shading invocations (shaded fragments, the work axis; fs_invocations too,
        # which with TAA also holds llvmpipe's own count of the full-screen resolve): one per
        # primitive and 4x4 coarse pixel it covers, fewer than the covered pixels
        sh, cov = int(v['shaded_fragments_median']), int(v['covered_fragments_median'])
        assert sh > 0 and cov > sh, v
        assert t == 'on' or int(v['fs_invocations_median']) == sh, v
        d = row[(m, 'off', t)]  # full resolution shades every covered fragment
        assert int(d['shaded_fragments_median']) == int(d['covered_fragments_median']), d
        # measured in the same rings as the others: the same per-ring columns are filled
        assert v.keys() == row[(m, 'default', t)].keys()
t, r = row[('traditional', 'vrs', 'off')], row[('traditional', 'default', 'off')]
# a 4x4 alpha test decides for 16 pixels at once: thin leaves are lost or grown, not as the rings
assert abs(float(t['coverage_ratio_ring0']) - float(r['coverage_ratio_ring0'])) > 0.05, (t, r)
assert float(t['flip']) != float(r['flip']), (t, r)
"
check "accuracy.md: the vrs rows and what they are" bash -c "[ \$(grep -c '^| [a-z *]* | vrs | o[nf]* |' acc/accuracy.md) -eq 4 ] && grep -q '^- vrs: one full-resolution pass, coarse shading at the rate map \*:4x4, 16 px tiles' acc/accuracy.md"
check "the plots: a pentagon for VRS" bash -c "grep -q \"pt 14 ps 1.4 lc rgb 'black' t 'VRS (coarse shading)'\" acc/accuracy.gp && grep -q 'pt 15 ' acc/accuracy-fragments.gp && head -c 8 acc/accuracy.png | od -c | grep -q 'P   N   G'"
expect_exit "bench --calibrate --foveation vrs stays refused (plain bench takes it: test_vrs_counts.sh)" 2 "$BIN" bench forest --calibrate --foveation vrs --frames 1
"$BIN" bench forest --accuracy --foveation vrs --modes traditional --width 64 --height 36 --frames 1 --warmup 0 \
  --supersample 1 --out acc_fv --quiet >/dev/null 2>&1
check "bench --accuracy --foveation vrs is taken (the matrix as without it)" bash -c "[ \$? -eq 0 ] && [ \$(tail -n +2 acc_fv/accuracy.csv | wc -l) -eq 8 ]"

# ---- a sweep's "rings": "vrs": the task's compare runs --foveation vrs, merged beside the default
cat >m.json <<'EOF'
{
  "scenes": ["forest"],
  "modes": ["traditional", "hashed"],
  "rings": ["default", "vrs"],
  "width": 160, "height": 90, "frames": 2,
  "reference": {"supersample": 1},
  "options": ["--vrs", "*:4x4"],
  "cache": "cache"
}
EOF
"$BIN" sweep m.json --list --out sw >list.txt 2>&1
check "sweep --list: 2 tasks, the vrs one named rings-vrs and running --foveation vrs" bash -c "grep -q '^0 done, 0 incomplete, 2 to do' list.txt && grep \"'fovsim' 'compare'\" list.txt | grep 'rings-vrs' | grep -q \"'--foveation' 'vrs'\" && [ \$(grep -c \"'--foveation' 'vrs'\" list.txt) -eq 1 ]"
"$BIN" sweep m.json --local 1 --out sw --quiet >/dev/null 2>&1
check "sweep with a vrs task exits 0" test $? -eq 0
check "the vrs task ran under VRS, the default one not" bash -c "grep -q '^foveation: vrs,' sw/tasks/*rings-vrs*/fovsim-run.txt && grep -q '^foveation: unset,' sw/tasks/*rings-default*/fovsim-run.txt"
"$BIN" merge sw >merge.txt 2>&1
check "merge exits 0" test $? -eq 0
check "merged: rings default and vrs side by side, and they differ for traditional" python3 -c "
import csv
rows = list(csv.DictReader(open('sw/accuracy.csv')))
got = sorted((r['rings'], r['mode']) for r in rows)
assert got == [('default', 'hashed'), ('default', 'traditional'), ('vrs', 'hashed'), ('vrs', 'traditional')], got
m = list(csv.DictReader(open('sw/metrics.csv')))
assert {r['rings'] for r in m} == {'default', 'vrs'}
cov = {}
for r in m:
    if r['mode'] == 'traditional' and r['ring'] == '-1':
        cov.setdefault(r['rings'], []).append(r)
assert cov['default'] and len(cov['default']) == len(cov['vrs']) == 2, cov
# the same frames, the same reference coverage; VRS's 4x4 alpha test covers otherwise
for d, v in zip(cov['default'], cov['vrs']):
    assert d['frame'] == v['frame'] and d['ref_coverage'] == v['ref_coverage'], (d, v)
    assert abs(float(d['coverage']) - float(v['coverage'])) > 0.01, (d, v)
"
summary
