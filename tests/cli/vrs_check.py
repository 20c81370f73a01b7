#!/usr/bin/env python3
"""vrs_check.py: checks of VRS coarse shading on a frame of test_vrs_shade.sh's quad (not a test
itself). Pixels are read with `oiiotool --dumpdata --info` (image rows top-down, as the rate map's).
Blocks are the coarse pixels of a rate W x H aligned to the top-left corner; those near the quad's
diagonals (where its two triangles meet) are skipped: one triangle covers each of the others whole.

  vrs_check.py uniform EXR W H CHANNELS   every block holds one value per channel (exactly); fails
                                          when any does not, or fewer than half the blocks count
  vrs_check.py centre EXR OFF W H TOL     each block's value equals the full-rate frame OFF's mean of
                                          the four pixels around the block's centre, within TOL
                                          (the attribute is affine on screen: that mean is its value
                                          at the centre, up to the half-float EXR's rounding)
  vrs_check.py spread EXR LO HI           the R channel's (max - min) / mean lies in [LO, HI]
  vrs_check.py flat EXR REF TOL           every pixel's R lies within TOL (relative) of REF's mean R
  vrs_check.py values EXR CHANNEL         prints the distinct values of one channel
CHANNELS: comma-separated indices (0 R, 1 G, 2 B, 3 A, 4 coverage)."""
import subprocess, sys


def read(path):
    out = subprocess.run(["oiiotool", "--dumpdata", "--info", path], capture_output=True, text=True, check=True).stdout
    px = {}
    for line in out.splitlines():
        line = line.strip()
        if line.startswith("Pixel ("):
            xy, vals = line[len("Pixel ("):].split("):")
            x, y = (int(v) for v in xy.split(","))
            px[x, y] = [float(v) for v in vals.split()]
    w = 1 + max(x for x, _ in px)
    h = 1 + max(y for _, y in px)
    return px, w, h


def blocks(width, height, bw, bh):
    """The whole blocks away from both diagonals: (x0, y0)."""
    for y0 in range(0, height - bh + 1, bh):
        for x0 in range(0, width - bw + 1, bw):
            cx, cy = x0 + 0.5 * bw, y0 + 0.5 * bh
            near = 0.5 * (bw + bh) + 1
            if abs(cx - cy) < near or abs(cx + cy - width) < near:
                continue
            yield x0, y0


def uniform(path, bw, bh, channels):
    px, w, h = read(path)
    n = bad = 0
    for x0, y0 in blocks(w, h, bw, bh):
        n += 1
        lead = px[x0, y0]
        if any(px[x0 + i, y0 + j][c] != lead[c] for i in range(bw) for j in range(bh) for c in channels):
            bad += 1
    total = (w // bw) * (h // bh)
    print(f"{path}: {bad} of {n} blocks of {bw}x{bh} hold more than one value (channels {channels})")
    return bad == 0 and 2 * n >= total


def centre(path, off, bw, bh, tol):
    px, w, h = read(path)
    ref, _, _ = read(off)
    worst = 0.0
    n = 0
    for x0, y0 in blocks(w, h, bw, bh):
        cx, cy = x0 + bw // 2, y0 + bh // 2
        for c in range(3):
            mean = sum(ref[cx + i, cy + j][c] for i in (-1, 0) for j in (-1, 0)) / 4.0
            worst = max(worst, abs(px[x0, y0][c] - mean))
        n += 1
    print(f"{path}: {n} blocks of {bw}x{bh}: largest difference from the full rate's value at the centre {worst:.3g}")
    return n > 0 and worst <= tol


def spread(path, lo, hi):
    px, _, _ = read(path)
    r = [v[0] for v in px.values()]
    s = (max(r) - min(r)) / (sum(r) / len(r))
    print(f"{path}: R spread {s:.4f} (min {min(r):.4g}, max {max(r):.4g})")
    return lo <= s <= hi


def flat(path, refpath, tol):
    px, _, _ = read(path)
    ref, _, _ = read(refpath)
    mean = sum(v[0] for v in ref.values()) / len(ref)
    worst = max(abs(v[0] - mean) for v in px.values()) / mean
    print(f"{path}: R at most {worst:.4f} (relative) from {refpath}'s mean {mean:.4g}")
    return worst <= tol


def main(a):
    if a[0] == "uniform":
        return uniform(a[1], int(a[2]), int(a[3]), [int(c) for c in a[4].split(",")])
    if a[0] == "centre":
        return centre(a[1], a[2], int(a[3]), int(a[4]), float(a[5]))
    if a[0] == "spread":
        return spread(a[1], float(a[2]), float(a[3]))
    if a[0] == "flat":
        return flat(a[1], a[2], float(a[3]))
    if a[0] == "values":
        px, _, _ = read(a[1])
        print(" ".join(str(v) for v in sorted({p[int(a[2])] for p in px.values()})))
        return True
    raise SystemExit(f"vrs_check.py: unknown check {a[0]}")


if __name__ == "__main__":
    sys.exit(0 if main(sys.argv[1:]) else 1)
