#!/usr/bin/env python3
"""vrs_counts.py: brute-force CPU counts for test_vrs_counts.sh (not a test itself).

  make OUT.gltf TRIS.json W H N SEED  N random triangles (0.5 to 12 pixels across) in the plane z = 0,
                                      seen by the camera at (0, 0, 1) looking at the origin with hfov
                                      90 on a W x H display (focal length W/2 pixels); their window
                                      positions (origin bottom-left) go to TRIS.json.
  count TRIS.json W H RW RH           prints "covered shaded split": the pixels whose centres the
                                      triangles cover (summed over triangles), the distinct (triangle,
                                      coarse pixel) pairs with a covered pixel, coarse pixels RW x RH
                                      aligned from the display's top-left corner (as
                                      common/vrs_shade.glsl), and how many of those pairs have covered
                                      pixels on both sides of a boundary of llvmpipe's 64-row tiles
                                      (only where H is not a multiple of RH).

Vertices lie on a 1/64-pixel grid (exact in float and on llvmpipe's 1/256 grid, so the rasteriser
sees the same triangles), and no pixel centre lies on an edge (generated again if one does), so
the count needs no fill rule: exact integer arithmetic in 1/64 pixels decides every pixel."""
import json, random, struct, sys, base64

SUB = 64  # grid steps per pixel


def edge(a, b, p):
    return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])


def covered_pixels(t, w, h):
    """Window pixels (x, y) whose centre lies strictly inside triangle t (grid units), or None when
    a centre lies on an edge or the triangle is degenerate."""
    a, b, c = t
    area = edge(a, b, c)
    if area == 0:
        return None
    xs, ys = [v[0] for v in t], [v[1] for v in t]
    out = []
    for py in range(max(0, min(ys) // SUB - 1), min(h, max(ys) // SUB + 2)):
        for px in range(max(0, min(xs) // SUB - 1), min(w, max(xs) // SUB + 2)):
            p = (px * SUB + SUB // 2, py * SUB + SUB // 2)
            e = [edge(a, b, p), edge(b, c, p), edge(c, a, p)]
            if 0 in e:
                return None
            if all(x > 0 for x in e) or all(x < 0 for x in e):
                out.append((px, py))
    return out


def make(out, tris_path, w, h, n, seed):
    rng = random.Random(seed)
    tris = []
    while len(tris) < n:
        size = rng.uniform(0.5, 12.0) * SUB
        cx, cy = rng.uniform(2, w - 2) * SUB, rng.uniform(2, h - 2) * SUB
        t = [(int(cx + rng.uniform(-size, size) / 2), int(cy + rng.uniform(-size, size) / 2)) for _ in range(3)]
        t = [(min(max(x, 0), w * SUB), min(max(y, 0), h * SUB)) for x, y in t]
        if covered_pixels(t, w, h) is not None:
            tris.append(t)
    json.dump(tris, open(tris_path, "w"))
    f = w / 2.0  # focal length in pixels: hfov 90
    pos = [((x / SUB - w / 2.0) / f, (y / SUB - h / 2.0) / f, 0.0) for t in tris for x, y in t]
    count = len(pos)
    data = b"".join(struct.pack("<3f", *p) for p in pos) + struct.pack("<3f", 0, 0, 1) * count
    data += struct.pack("<2f", 0, 0) * count + struct.pack("<%dI" % count, *range(count))
    views = [(0, 12 * count), (12 * count, 12 * count), (24 * count, 8 * count), (32 * count, 4 * count)]
    lo = [min(p[i] for p in pos) for i in range(3)]
    hi = [max(p[i] for p in pos) for i in range(3)]
    g = {"asset": {"version": "2.0"},
         "buffers": [{"byteLength": len(data),
                      "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
         "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": m} for o, m in views],
         "accessors": [{"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3", "min": lo, "max": hi},
                       {"bufferView": 1, "componentType": 5126, "count": count, "type": "VEC3"},
                       {"bufferView": 2, "componentType": 5126, "count": count, "type": "VEC2"},
                       {"bufferView": 3, "componentType": 5125, "count": count, "type": "SCALAR"}],
         "materials": [{"name": "tris", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1]},
                        "alphaMode": "OPAQUE", "doubleSided": True}],
         "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                     "indices": 3, "material": 0}]}],
         "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
    json.dump(g, open(out, "w"))


def count(tris_path, w, h, rw, rh):
    covered = shaded = split = 0
    for t in json.load(open(tris_path)):
        px = covered_pixels([tuple(v) for v in t], w, h)
        covered += len(px)
        cells = {(x // rw, (h - 1 - y) // rh) for x, y in px}
        shaded += len(cells)
        # Coarse pixels the triangle covers on both sides of a boundary between llvmpipe's 64-row
        # tiles (rows counted from the window's bottom): the GPU count may count these twice.
        parts = {(x // rw, (h - 1 - y) // rh, y // 64) for x, y in px}
        split += len(parts) - len(cells)
    print(covered, shaded, split)


if __name__ == "__main__":
    a = sys.argv
    if a[1] == "make":
        make(a[2], a[3], int(a[4]), int(a[5]), int(a[6]), int(a[7]))
    else:
        count(a[2], int(a[3]), int(a[4]), int(a[5]), int(a[6]))
