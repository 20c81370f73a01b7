#!/usr/bin/env python3
"""device_report.py: the report of scripts/device_check.sh (docs/benchmarks.md "On a GPU: the device
check"). Reads OUT/bench-*.json, OUT/cost-model.json and OUT/calibrate.txt, judges the issue's GPU
goals (foveated >= 0.8 of the covered-fragment ideal; hashed <= 1.15x traditional) and writes
DOC/gpu-<renderer>.md and DOC/gpu-<renderer>.json (the bench JSON gathered in one file)."""
import argparse
import glob
import json
import os
import re
import sys

COVERED_GOAL = 0.8   # foveated speed-up / covered-fragment ideal
HASHED_GOAL = 1.15   # hashed frame time / traditional's, same layout


def slug(renderer):
    """A file name from a renderer string: 'NVIDIA H100 80GB HBM3/PCIe/SSE2' -> 'nvidia-h100-80gb-hbm3'."""
    head = renderer.split('/')[0].split('(')[0]
    s = re.sub(r'[^a-z0-9]+', '-', head.lower()).strip('-')
    return s or 'unknown'


def config(run, mode, foveated):
    want = '%s, %s' % (mode, 'foveated' if foveated else 'full resolution')
    for c in run['configs']:
        if c['name'] == want:
            return c
    return None


def rows(runs):
    """One row per (size, rings, TAA, mode): full and foveated medians, speed-up, covered ideal."""
    out = []
    for name, run in runs:
        m = re.match(r'bench-(\d+x\d+)-(\w+)-taa(on|off)\.json', name)
        if not m:
            continue
        for mode in ('traditional', 'hashed'):
            full, fov = config(run, mode, False), config(run, mode, True)
            if not full or not fov:
                continue
            tf, tv = full['frame_ms']['median'], fov['frame_ms']['median']
            cf, cv = full['geometry_covered_fragments_all_frames'], fov['geometry_covered_fragments_all_frames']
            ideal = cf / cv if cf > 0 and cv > 0 else None
            speed = tf / tv if tv > 0 else None
            out.append({'size': m.group(1), 'rings': m.group(2), 'taa': m.group(3), 'mode': mode,
                        'full_ms': tf, 'foveated_ms': tv, 'speedup': speed, 'covered_ideal': ideal,
                        'fraction': speed / ideal if speed and ideal else None,
                        'hashed_vs_traditional_full': full['relative_to_traditional'],
                        'hashed_vs_traditional_foveated': fov['relative_to_traditional']})
    return out


def fmt(v, spec='%.2f'):
    return '-' if v is None else spec % v


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument('--out', required=True)
    ap.add_argument('--doc-dir', required=True)
    ap.add_argument('--tests', default='not run')
    ap.add_argument('--seconds', type=int, default=0)
    ap.add_argument('--quick', action='store_true')
    a = ap.parse_args()

    runs = []
    for f in sorted(glob.glob(os.path.join(a.out, 'bench-*.json'))):
        with open(f) as fh:
            runs.append((os.path.basename(f), json.load(fh)))
    if not runs:
        sys.exit('device_report.py: %s: no bench-*.json' % a.out)
    first = runs[0][1]
    renderer, machine = first['renderer'], first.get('machine', '?')
    table = rows(runs)
    model = None
    if os.path.exists(os.path.join(a.out, 'cost-model.json')):
        with open(os.path.join(a.out, 'cost-model.json')) as fh:
            model = json.load(fh)
    calib = ''
    if os.path.exists(os.path.join(a.out, 'calibrate.txt')):
        with open(os.path.join(a.out, 'calibrate.txt')) as fh:
            calib = fh.read().strip()

    fov_rows = [r for r in table if r['fraction'] is not None]
    cov_ok = [r for r in fov_rows if r['fraction'] >= COVERED_GOAL]
    hashed = [r for r in table if r['mode'] == 'hashed']
    hashed_ok = [r for r in hashed if r['hashed_vs_traditional_full'] <= HASHED_GOAL
                 and r['hashed_vs_traditional_foveated'] <= HASHED_GOAL]

    name = slug(renderer)
    md = ['# fovsim on %s' % renderer, '']
    if a.quick:
        md += ['**Quick run (--quick): small sizes and 3 frames, to check the script; not a measurement.**', '']
    md += ['Written by `scripts/device_check.sh` (docs/benchmarks.md "On a GPU: the device check") in %d s.' % a.seconds,
           '', '- renderer: %s' % renderer, '- machine: %s' % machine, '- test suite: %s' % a.tests,
           '- frames: %d measured after %d warm-up, builtin forest, gaze at the centre' % (first['frames'], first['warmup']),
           '', '## Goals', '',
           '- foveated >= %.2f of the covered-fragment ideal: %d of %d configurations' % (COVERED_GOAL, len(cov_ok), len(fov_rows)),
           '- hashed <= %.2fx traditional (full resolution and foveated): %d of %d configurations' % (HASHED_GOAL, len(hashed_ok), len(hashed)),
           '', '## Bench matrix', '',
           'Frame time is the median wall clock to glFinish (ms). Speed-up = full / foveated; the covered-fragment '
           'ideal = full resolution\'s covered fragments / the foveated frame\'s (stages that draw the scene).', '',
           '| size | rings | TAA | mode | full ms | foveated ms | speed-up | covered ideal | fraction | hashed/trad full | hashed/trad foveated |',
           '|---|---|---|---|---|---|---|---|---|---|---|']
    for r in table:
        md.append('| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |' % (
            r['size'], r['rings'], r['taa'], r['mode'], fmt(r['full_ms']), fmt(r['foveated_ms']), fmt(r['speedup']),
            fmt(r['covered_ideal']), fmt(r['fraction']), fmt(r['hashed_vs_traditional_full'], '%.3f'),
            fmt(r['hashed_vs_traditional_foveated'], '%.3f')))
    md += ['', '## Cost model', '']
    if model is None:
        md.append('No model: `bench --calibrate` failed (see the log).')
    else:
        md += ['`bench --calibrate` output:', '', '```', calib, '```']
    md.append('')
    os.makedirs(a.doc_dir, exist_ok=True)
    base = os.path.join(a.doc_dir, 'gpu-%s' % name)
    for path, text in ((base + '.md', '\n'.join(md)),
                       (base + '.json', json.dumps({'renderer': renderer, 'machine': machine, 'tests': a.tests,
                                                    'quick': a.quick, 'rows': table, 'cost_model': model,
                                                    'bench': dict(runs)}, indent=1))):
        with open(path + '.tmp', 'w') as fh:
            fh.write(text)
        os.replace(path + '.tmp', path)
    print('device_report.py: wrote %s.md and %s.json' % (base, base))


if __name__ == '__main__':
    main()
