#!/usr/bin/env bash
# The comparison grid's annotation (docs/compare.md "The grid"): labels, gaze marker and ring
# borders go into part 0 only. With --grid-annotate on and off, metrics.csv and summary.json are
# the same but for the timing columns, the `layers` part is the same bit for bit, and part 0
# differs at the gaze marker; each mode's label swatch has the mode's own colour whatever the
# order of --modes. 160x90, 2 frames, a coarse reference: a few seconds.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
PY=/usr/bin/python3 # Debian's, with python3-numpy and python3-openimageio (scripts/setup.sh)
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/grid_annotate
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
"$PY" -c 'import numpy, OpenImageIO' || { echo "FAIL $PY lacks numpy or OpenImageIO (scripts/setup.sh installs them)" >&2; exit 1; }

# run NAME [OPTION...]: forest at 160x90, 2 frames, the gaze away from the centre
run() {
  local name=$1; shift
  "$BIN" compare forest --width 160 --height 90 --frames 2 --gaze builtin:demo_tour --supersample 1 --samples 8 \
    --no-cache --quiet --out "$T/$name" "$@" >"$T/$name.txt" 2>"$T/$name.err" || { cat "$T/$name.err" >&2; return 1; }
}
check "compare --grid-annotate on (hashed,traditional) exits 0" run on --modes hashed,traditional --grid-annotate on
check "compare --grid-annotate off exits 0" run off --modes hashed,traditional --grid-annotate off
check "compare, default annotation (traditional,hashed) exits 0" run swapped --modes traditional,hashed

# Timing columns (their values are the machine's, not the run's): frame_ms in metrics.csv,
# frame_ms_median and relative_time in summary.json. Everything else must be equal.
check "metrics.csv: equal with and without the annotation but for frame_ms" "$PY" - "$T/on" "$T/off" <<'PY'
import csv, sys
rows = []
for d in sys.argv[1:]:
    r = list(csv.DictReader(open(f"{d}/metrics.csv")))
    assert r and "frame_ms" in r[0], d
    for x in r:
        del x["frame_ms"]
    rows.append(r)
assert rows[0] == rows[1], "metrics.csv differs"
PY
check "summary.json: equal with and without the annotation but for the timings" "$PY" - "$T/on" "$T/off" <<'PY'
import json, sys
def strip(d):
    s = json.load(open(f"{d}/summary.json"))
    for m in s["modes"]:
        del m["frame_ms_median"], m["relative_time"]
    return s
a, b = strip(sys.argv[1]), strip(sys.argv[2])
assert a == b, "summary.json differs"
PY

# part 0 and part 1 of frame 1 (the gaze has moved off the centre by then)
check "layers equal, part 0 differs at the gaze marker only when annotated" "$PY" - "$T/on" "$T/off" <<'PY'
import sys, OpenImageIO as oiio, numpy as np
def parts(d):
    i = oiio.ImageInput.open(f"{d}/compare.0001.exr")
    grid = i.read_image(format="float"); spec0 = i.spec()
    assert i.seek_subimage(1, 0) and i.spec().getattribute("name") == "layers"
    layers = i.read_image(format="float"); names = list(i.spec().channelnames)
    i.close()
    return spec0, grid, layers, names
s_on, g_on, l_on, n_on = parts(sys.argv[1])
s_off, g_off, l_off, n_off = parts(sys.argv[2])
assert n_on == n_off and np.array_equal(l_on, l_off), "the layers part differs"
gx, gy = s_on.getattribute("fovsim:gaze")
w, h = 160, 90
assert g_on.shape[:2] == (3 * h, 3 * w), g_on.shape  # 3 columns (2 modes, reference) x 3 rows
x, y = int(gx * w), int(gy * h)
assert (x, y) != (w // 2, h // 2), "the gaze never left the centre"
for col in range(3):
    for row in range(3 if col < 2 else 2):  # the reference's column has no third tile: the legend
        on, off = g_on[row * h + y, col * w + x, :3], g_off[row * h + y, col * w + x, :3]
        assert np.allclose(on, [1, 0, 1]), (col, row, on)  # the marker's magenta centre
        assert not np.allclose(off, [1, 0, 1]), (col, row, off)
# the annotation only adds: far from labels, marker and ring borders part 0 is the same
assert np.array_equal(g_on[h - 2, w - 2], g_off[h - 2, w - 2])
print("grid annotation on:", s_on.getattribute("fovsim:grid"), file=sys.stderr)
assert "annotation off" in s_off.getattribute("fovsim:grid")
assert "3 rows" in s_on.getattribute("fovsim:grid") and "annotation on" in s_on.getattribute("fovsim:grid")
PY

# The label swatch, at (2..10, 2..10) of each tile (compare_grid.h; text scale 1 below 300 rows),
# has the mode's colour from FS_ALPHA_MODES (hashed #2ca02c, traditional #1f77b4), linear.
check "a mode's swatch colour does not depend on the order of --modes" "$PY" - "$T/on" "$T/swapped" <<'PY'
import sys, OpenImageIO as oiio, numpy as np
def lin(hexv):
    c = np.array([(hexv >> s & 255) / 255 for s in (16, 8, 0)])
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
want = {"hashed": lin(0x2ca02c), "traditional": lin(0x1f77b4)}
seen = {}
for d in sys.argv[1:]:
    i = oiio.ImageInput.open(f"{d}/compare.0000.exr")
    modes = i.spec().getattribute("fovsim:modes").split(",")
    g = i.read_image(format="float"); i.close()
    for col, m in enumerate(modes):
        for row in range(3):
            px = g[row * 90 + 5, col * 160 + 5, :3]
            assert np.allclose(px, want[m], atol=2e-3), (d, m, row, px, want[m])
            seen.setdefault(m, []).append(tuple(px))
for m, v in seen.items():
    assert len(set(v)) == 1 and len(v) == 6, (m, v)
PY

expect_exit "--grid-annotate maybe -> 2" 2 "$BIN" compare forest --grid-annotate maybe --out "$T/bad"
check "no folder left by the bad option" test ! -e "$T/bad"
expect_exit "render --grid-annotate off -> 2" 2 "$BIN" render forest --grid-annotate off --out "$T/bad2"
summary
