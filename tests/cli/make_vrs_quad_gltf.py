#!/usr/bin/env python3
"""make_vrs_quad_gltf.py OUT.gltf H REPEAT OFFSET TEXTURE COLOURS OPAQUE|MASK: a square of side 2 H
in the plane z = 0, centred on the origin, facing +Z, for test_vrs_shade.sh (not a test itself).
Its uv run OFFSET..REPEAT + OFFSET; TEXTURE is the base colour texture, embedded as a PNG: white
(1x1 white), checker (64x64, black and white texels) or half (64x64, white, alpha 0.5); COLOURS:
gradient (vertex colours (0,0,0), (1,0,0), (1,1,0), (0,1,0) around the corners, one gradient per
triangle) or white."""
import base64, json, struct, sys, zlib

out, h, rep, off, tex, colours, mode = (sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]),
                                        sys.argv[5], sys.argv[6], sys.argv[7])

def png(w, hgt, pixel):
    raw = b"".join(b"\0" + b"".join(bytes(pixel(x, y)) for x in range(w)) for y in range(hgt))
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, hgt, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))

images = {"white": lambda: png(1, 1, lambda x, y: (255, 255, 255, 255)),
          "checker": lambda: png(64, 64, lambda x, y: (255, 255, 255, 255) if (x + y) % 2 else (0, 0, 0, 255)),
          "half": lambda: png(64, 64, lambda x, y: (255, 255, 255, 128))}
image = images[tex]()
pos = [(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)]
nrm = [(0, 0, 1)] * 4
uv = [(u + off, v + off) for u, v in [(0, rep), (rep, rep), (rep, 0), (0, 0)]]
col = [(0, 0, 0, 1), (1, 0, 0, 1), (1, 1, 0, 1), (0, 1, 0, 1)] if colours == "gradient" else [(1, 1, 1, 1)] * 4
idx = [0, 1, 2, 0, 2, 3]
data = (b"".join(struct.pack("<3f", *p) for p in pos) + b"".join(struct.pack("<3f", *n) for n in nrm) +
        b"".join(struct.pack("<2f", *t) for t in uv) + b"".join(struct.pack("<4f", *c) for c in col) +
        struct.pack("<6I", *idx))
views = [(0, 48), (48, 48), (96, 32), (128, 64), (192, 24)]
material = {"name": "quad", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "baseColorTexture": {"index": 0}},
            "alphaMode": mode, "doubleSided": True}
if mode == "MASK":
    material["alphaCutoff"] = 0.5
g = {"asset": {"version": "2.0"},
     "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
     "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in views],
     "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-h, -h, 0], "max": [h, h, 0]},
                   {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                   {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                   {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC4"},
                   {"bufferView": 4, "componentType": 5125, "count": 6, "type": "SCALAR"}],
     "images": [{"uri": "data:image/png;base64," + base64.b64encode(image).decode()}],
     "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
     "textures": [{"source": 0, "sampler": 0}],
     "materials": [material],
     "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "COLOR_0": 3},
                                 "indices": 4, "material": 0}]}],
     "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
json.dump(g, open(out, "w"))
