#!/usr/bin/env python3
"""make_corpus.py: writes the seed corpus of the fuzz targets (tests/fuzz/corpus/<target>/) and
fuzz_assets.h (the small glTF side files the glTF and scene targets put in their scratch folder).

Every seed comes from the repository's own inputs: built-in, study and example scenes, the scripted
gaze traces (cut to their first lines), tests/data, the documents the unit tests write inline, the
ring layouts the docs and tests use, and hand-made glTF/GLB files of one triangle. One tiny CC0
asset (Quaternius MegaKit Petal_1, 528-byte buffer, ../shared/assets) is inlined when ../shared is
there. Nothing large is copied; the EyeLink recordings (GPL-3) and the Tobii recording stay in
../shared. Rerun after changing it:  python3 tests/fuzz/make_corpus.py   (replaces corpus/*)
"""
import base64
import json
import os
import shutil
import struct
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared"))
CORPUS = os.path.join(HERE, "corpus")


def read(rel):
    with open(os.path.join(ROOT, rel), "rb") as f:
        return f.read()


def head_lines(data, n):
    return b"".join(data.splitlines(keepends=True)[:n])


# ---- tiny glTF pieces -------------------------------------------------------------------------

def png_rgba(w, h, pixels):
    """A PNG of RGBA8 pixels (list of 4-tuples, row-major)."""
    raw = b"".join(b"\x00" + bytes(v for p in pixels[y * w:(y + 1) * w] for v in p) for y in range(h))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


# 4x4 baseline JPEG (ffmpeg -f lavfi -i color=c=0x80ff40:s=4x4 -frames:v 1 -q:v 8), 225 bytes.
JPEG_4X4 = bytes.fromhex(
    "ffd8ffe000104a46494600010200000100010000fffe00104c61766335392e33372e31303000ffdb0043000810101310"
    "131616161616161a181a1b1b1b1a1a1a1a1b1b1b1d1d1d2222221d1d1d1b1b1d1d202022222526252323222326262828"
    "2830302e2e38383a454553ffc4004c000101000000000000000000000000000000070101010000000000000000000000"
    "0000000607100100000000000000000000000000000000110100000000000000000000000000000000ffc00011080004"
    "000403012200021100031100ffda000c03010002110311003f00a2009a87bfffd9")
assert len(JPEG_4X4) == 225

TEX_PNG = png_rgba(2, 2, [(255, 255, 255, 0), (40, 160, 40, 255), (90, 200, 60, 128), (30, 90, 20, 64)])

# One triangle: positions, normals, uvs (float32), indices (uint16, padded to 4).
POS = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
NRM = struct.pack("<9f", 0, 0, 1, 0, 0, 1, 0, 0, 1)
UV = struct.pack("<6f", 0, 0, 1, 0, 0, 1)
IDX = struct.pack("<3H", 0, 1, 2) + b"\x00\x00"
BUF = POS + NRM + UV + IDX  # 104 bytes


def tri_doc(buffer_uri, image, extra_images=()):
    """The triangle glTF: MASK material with a texture; `image` is the images[0] entry."""
    return {
        "asset": {"version": "2.0", "generator": "fovsim tests/fuzz/make_corpus.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "tri"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                    "indices": 3, "material": 0}]}],
        "materials": [{"name": "leaf", "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": True,
                       "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1],
                                                "baseColorTexture": {"index": 0}}}],
        "textures": [{"sampler": 0, "source": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 33071}],
        "images": [image] + list(extra_images),
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 36},
            {"buffer": 0, "byteOffset": 72, "byteLength": 24},
            {"buffer": 0, "byteOffset": 96, "byteLength": 6},
        ],
        "buffers": [{"byteLength": len(BUF), **({"uri": buffer_uri} if buffer_uri else {})}],
    }


def data_uri(mime, b):
    return "data:%s;base64,%s" % (mime, base64.b64encode(b).decode())


def compact(doc):
    return json.dumps(doc, separators=(",", ":")).encode()


def glb(doc, bin_chunk):
    js = compact(doc)
    js += b" " * (-len(js) % 4)
    bin_chunk += b"\x00" * (-len(bin_chunk) % 4)
    body = struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(bin_chunk), b"BIN\x00") + bin_chunk
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def glb_with_image(img, mime):
    """Everything in the BIN chunk: the triangle's buffer, then the image through a bufferView."""
    doc = tri_doc(None, {"bufferView": 4, "mimeType": mime, "name": "tex"})
    bin_chunk = BUF + img
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(BUF), "byteLength": len(img)})
    doc["buffers"][0]["byteLength"] = len(bin_chunk)
    return glb(doc, bin_chunk)


def features_doc():
    """Node hierarchy (matrix and TRS), a camera, a non-indexed primitive with normalized integer
    attributes (KHR_mesh_quantization), COLOR_0, a sparse accessor, a BLEND material, uint8
    indices, an unused image, data: URIs."""
    pos_b = struct.pack("<12b", 0, 0, 0, 127, 0, 0, 0, 127, 0, 127, 127, 0)  # VEC3 byte, padded below
    pos_b = b"".join(pos_b[i:i + 3] + b"\x00" for i in range(0, 12, 3))       # 4-byte aligned elements
    col = struct.pack("<16B", 255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 128, 255, 255, 255, 0)
    uv = struct.pack("<8H", 0, 0, 65535, 0, 0, 65535, 65535, 65535)
    idx = struct.pack("<6B", 0, 1, 2, 2, 1, 3) + b"\x00\x00"
    sp_i = struct.pack("<H", 2) + b"\x00\x00"
    sp_v = struct.pack("<3f", 1.5, 1.5, 0.25)
    parts = [pos_b, col, uv, idx, sp_i, sp_v, POS]
    offs, o = [], 0
    for p in parts:
        offs.append(o)
        o += len(p)
    buf = b"".join(parts)
    views = [{"buffer": 0, "byteOffset": offs[i], "byteLength": len(p)} for i, p in enumerate(parts)]
    views[0]["byteStride"] = 4
    return {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_mesh_quantization", "KHR_materials_emissive_strength"],
        "extensionsRequired": ["KHR_mesh_quantization"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"children": [1, 2], "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5, 0, -2, 1]},
            {"mesh": 0, "translation": [1, 2, 3], "rotation": [0, 0.7071068, 0, 0.7071068], "scale": [2, 2, 2]},
            {"mesh": 1, "children": [3]},
            {"camera": 0, "translation": [0, 1, 5]},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100, "aspectRatio": 1.5}}],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 4}, "material": 1, "mode": 4},
                            {"attributes": {"POSITION": 6}, "mode": 4}]},
        ],
        "materials": [
            {"name": "quantized", "alphaMode": "MASK", "alphaCutoff": 0.3,
             "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 0}},
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}},
            {"name": "glass", "alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.8, 0.5]}},
        ],
        "textures": [{"sampler": 0, "source": 0}],
        "samplers": [{"wrapS": 33648, "wrapT": 33071}],
        "images": [{"uri": data_uri("image/png", TEX_PNG)}, {"uri": data_uri("image/jpeg", JPEG_4X4)}],
        "accessors": [
            {"bufferView": 0, "componentType": 5120, "normalized": True, "count": 4, "type": "VEC3"},
            {"bufferView": 1, "componentType": 5121, "normalized": True, "count": 4, "type": "VEC4"},
            {"bufferView": 2, "componentType": 5123, "normalized": True, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5121, "count": 6, "type": "SCALAR"},
            {"bufferView": 6, "componentType": 5126, "count": 3, "type": "VEC3",
             "sparse": {"count": 1, "indices": {"bufferView": 4, "componentType": 5123},
                        "values": {"bufferView": 5}}},
            {"componentType": 5126, "count": 3, "type": "VEC3",
             "sparse": {"count": 1, "indices": {"bufferView": 4, "componentType": 5123},
                        "values": {"bufferView": 5}}},
            {"bufferView": 6, "componentType": 5126, "count": 3, "type": "VEC3"},
        ],
        "bufferViews": views,
        "buffers": [{"byteLength": len(buf), "uri": data_uri("application/octet-stream", buf)}],
    }


def petal_seed():
    """Quaternius MegaKit Petal_1 (CC0) from ../shared: its 528-byte buffer inlined, its texture
    (a 445 KB PNG) replaced by the side file tex.png."""
    g = os.path.join(SHARED, "assets", "quaternius_megakit_set_a", "Petal_1.gltf")
    b = os.path.join(SHARED, "assets", "quaternius_megakit_set_a", "Petal_1.bin")
    if not (os.path.exists(g) and os.path.exists(b)):
        return None
    doc = json.load(open(g))
    doc["buffers"][0]["uri"] = data_uri("application/octet-stream", open(b, "rb").read())
    for im in doc.get("images", []):
        im["uri"] = "tex.png"
    return compact(doc)


# ---- scene, gaze, rings ------------------------------------------------------------------------

A = '"assets": [{"name": "f", "generator": "fern", "params": {"texture_size": 16}}]'
I = '"instances": [{"asset": "f"}]'

SCENE_TRI = """{
  "comment": "fuzz seed: the side file tri.gltf (one MASK triangle) with every top-level key",
  "display": {"width": 320, "height": 200, "hfov": 75},
  "alpha_mode": "hashed",
  "light": {"direction": [0, -2, 0.5], "color": [2, 2, 2], "ambient": [0.1, 0.1, 0.1], "sky": [0, 0, 0]},
  "assets": [
    {"name": "tri", "gltf": "tri.gltf"},
    {"name": "fern", "generator": "fern", "params": {"seed": 3, "size": 0.5, "frond_count": 3, "texture_size": 16, "alpha_cutoff": 0.4}},
    {"name": "fence", "generator": "fence", "params": {"length": 2, "height": 1, "cell_size": 0.25, "texture_size": 8, "wire_texels": 2}},
    {"name": "tree", "generator": "tree", "params": {"height": 2, "crown_radius": 1, "card_count": 3, "card_size": 0.5, "texture_size": 8}},
    {"name": "grass", "generator": "grass", "params": {"extent": 2, "card_count": 4, "blade_height": 0.2, "texture_size": 8}}
  ],
  "instances": [
    {"asset": "tri", "translation": [1, 0, 0], "rotation_deg": [0, 45, 0], "scale": [1, 2, 1]},
    {"asset": "fern", "scatter": {"count": 5, "seed": 7, "min": [-1, 0, -1], "max": [1, 0, 1], "scale": [0.5, 1.5], "random_yaw": true},
     "sway": {"amplitude": 0.1, "frequency": 0.7, "direction": [1, 0, 0.3], "height": 1, "wavelength": 4}},
    {"asset": "fence", "scale": 0.5}, {"asset": "tree"}, {"asset": "grass"}
  ],
  "camera": [
    {"time": 0, "position": [0, 1, 4], "target": [0, 0.5, 0], "hfov": 60},
    {"time": 0.5, "position": [0, 1, 5], "target": [0, 0.5, 0]},
    {"time": 1.5, "position": [3, 1, 5], "target": [0, 0.5, 0], "cut": true},
    {"time": 2, "position": [3, 2, 5], "target": [0, 0.5, 0]}
  ],
  "materials": {"leaf": {"alpha_mode": "castano", "alpha_cutoff": 0.3, "double_sided": false, "alpha_lod_max": 5},
                "fronds": {"alpha_mode": "mipscale"}},
  "rings": "10:1:0,25:1/2:0,*:1/4:0.5",
  "taa": {"enabled": true, "blend": 0.1, "gamma": 1, "sparse": 0.28, "jitter_length": 16}
}
"""

EYELINK_MONO = ("** DATE: test\n"
                "MSG\t100 DISPLAY_COORDS 0 0 99 49\n"
                "   5656.2  233.84 -41.107  1.4823 -0.60013\n"
                "START\t1000 \tRIGHT\tSAMPLES\tEVENTS\n"
                "SAMPLES\tGAZE\tRIGHT\tRATE\t2000.00\tTRACKING\tCR\tFILTER\t2\n"
                "1000\t  10.0\t  20.0\t 1000.0\t...\n"
                "1000\t  20.0\t  30.0\t 1000.0\t...\n"
                "SFIX R   1001\n"
                "1001\t   .\t   .\t    0.0\t...\n"
                "SBLINK R 1001\n"
                "1002\t  50.0\t  25.0\t 1000.0\tI..\n"
                "END\t1002 \tSAMPLES\tEVENTS\tRES\t 35.18\t 35.14\n"
                "5000\t  50.0\t  25.0\t 1000.0\t...\n"
                "INPUT\t5001\t0\n"
                "START\t6000 \tRIGHT\tSAMPLES\tEVENTS\n"
                "6000\t  -10.0\t  60.0\t 1000.0\t...\n"
                "END\t6001\n")
EYELINK_REMOTE = ("MSG\t99 -3 GAZE_COORDS 0.00 0.00 199.00 99.00\n"
                  "START\t100 \tLEFT\tSAMPLES\tEVENTS\n"
                  "SAMPLES\tGAZE\tLEFT\tHTARGET\tRATE\t 250.00\tTRACKING\tCR\tFILTER\t2\n"
                  "100.5\t  100.0\t  50.0\t  228.0\t... \t 4717.0\t 2908.0\t  611.2 .............\n"
                  "104.5\t  .\t  .\t  0.0\t... \t 4717.0\t 2908.0\t  611.2 MANTBL........\n"
                  "END\t105\n")
EYELINK_BINO = ("MSG\t1 DISPLAY_COORDS 0 0 999 999\r\n"
                "START\t10 \tLEFT\tRIGHT\tSAMPLES\r\n"
                "10\t100\t200\t1\t300\t400\t1\t5\t5\t5\t5\t.....\r\n"
                "12\t100\t200\t1\t.\t.\t0.0\t5\t5\t5\t5\t...C.\r\n"
                "END\t12\r\n")
EYELINK_BINO2 = ("** EYELINK\nMSG\t1 DISPLAY_COORDS 0 0 1023 767\nSTART\t10 \tLEFT\tRIGHT\tSAMPLES\n"
                 "SAMPLES\tGAZE\tLEFT\tRIGHT\tRATE\t500.00\tTRACKING\tCR\tFILTER\t2\n"
                 "10\t1.0\t2.0\t3.0\t4\t5\t6\t.....\n12\t11.0\t12.0\t3.0\t14\t15\t6\t.....\nEND\t12\n")
# Nine lines of EyeNavGS's user101_treehill.csv (Ding et al. 2025, arXiv:2506.02380, Apache-2.0;
# docs/gaze-formats.md "EyeNavGS"): the header and four left/right frames.
EYENAV = "ViewIndex,FOV1,FOV2,FOV3,FOV4,PositionX,PositionY,PositionZ,QuaternionX,QuaternionY,QuaternionZ,QuaternionW,GazePosX,GazePosY,GazePosZ,GazeQX,GazeQY,GazeQZ,GazeQW,Timestamp\n0,-0.942,0.698,-0.942,0.733,-1.765,0.744,-1.562,0.175,0.032,-0.027,0.984,-1.758,0.745,-1.538,0.012,-0.007,-0.046,0.999,0\n1,-0.698,0.942,-0.942,0.733,-1.703,0.742,-1.567,0.175,0.032,-0.027,0.984,-1.694,0.742,-1.544,0.012,0.019,-0.035,0.999,4\n0,-0.942,0.698,-0.942,0.733,-1.767,0.744,-1.567,0.163,0.031,-0.026,0.986,-1.76,0.745,-1.543,-0.081,0.001,-0.042,0.996,14\n1,-0.698,0.942,-0.942,0.733,-1.705,0.742,-1.571,0.163,0.031,-0.026,0.986,-1.695,0.742,-1.549,-0.081,0.03,-0.027,0.996,17\n0,-0.942,0.698,-0.942,0.733,-1.769,0.744,-1.572,0.152,0.03,-0.025,0.988,-1.762,0.745,-1.549,-0.091,0.003,-0.039,0.995,28\n1,-0.698,0.942,-0.942,0.733,-1.707,0.741,-1.576,0.152,0.03,-0.025,0.988,-1.697,0.742,-1.554,-0.09,0.031,-0.024,0.995,31\n0,-0.942,0.698,-0.942,0.733,-1.771,0.743,-1.576,0.144,0.029,-0.024,0.989,-1.763,0.745,-1.553,-0.098,0.002,-0.038,0.995,42\n1,-0.698,0.942,-0.942,0.733,-1.709,0.741,-1.58,0.144,0.029,-0.024,0.989,-1.699,0.742,-1.558,-0.097,0.03,-0.024,0.995,45\n"
TOBII = ('{"ts":3000,"s":0,"pts":622438,"pv":4}\n'
         '{"ts":2000,"s":0,"gidx":2,"l":5,"gp":[0.3,0.4]}\n'
         '{"ts":1500,"s":0,"gidx":1,"eye":"left","gp":[9,9]}\n'
         '\n'
         '{"ts":1000,"s":0,"gidx":1,"l":5,"gp":[0.1,0.2]}\n'
         '{"ts":1000,"s":0,"gidx":1,"gp3":[1.5,-2.0e1,3]}\n'
         '{"ts":4000,"s":1,"gidx":4,"l":5,"gp":[0.0,0.0]}\n'
         '{ "ts" : 3000 , "s" : 0 , "ac" : [ -0.039 , -10.146 , 0.840 ] , "x" : {"a":[true,false,null,"\\u00e9\\n"]} }\n'
         '{"ts":5000,"s":0,"gp":[0.5,0.6]}')
CSV_SMALL = "# comment\nt,x,y,confidence\n0,0.2,0.4,1\n0.5,0.6,0.8,0.3\n0.5,0.4,0.2,0.9\n1,1.2,-0.1,1\n"

RINGS = [
    "auto", "off", " off\n", "*:1:0", "*:1/16:-1.5", "*:0.0625:0", "10:1:0,*:1/4:0", "10:1:0,*:0.5:0",
    "10:1:0,25:1/2:0,*:1/4:0", "10:1:0,25:1/2:0,*:1/4:0.5", "10:1:0,25:1/2:0,*:1/8:0",
    "10:1:0,25:0.5:0,*:0.25:0.5", "0.001:1:-0.25,*:1/16:0", "0.0001:1:0,0.0002:1/16:0,*:1/16:0",
    "0.01:1:0,3:1:0,10:1/2:0,30:1/4:0,60:1/8:0,*:1/16:0", "1:1:0,30:1/2:0,60:1/4:0,89:1/8:0,*:1/8:0",
    "20:1/2:0,89.5:1/2:0,100:1/4:0,*:1/4:0", "1:1:0,2:1:0,3:1/2:0,4:1/2:0,5:1/4:0,6:1/8:0,7:1/16:0,*:1/16:2",
    "3.5662193:1:0,7.765125:1/2:0,15.38302:1/4:0,26.872522:1/8:0,*:1/16:0",
    "5.689322:1:0,11.726324:1/2:0,21.719414:1/4:0,34.564426:1/8:0,*:1/16:0",
    "21.719414:1:0,34.564426:1/2:0,47.247437:1/4:0,*:1/8:0",
    # refused ones (tests/unit/test_fov_ring.c)
    "10:0.3:0,*:0.25:0", "10:1/0:0,*:1:0", "10:1/32:0,*:1/32:0", "20:1:0,10:0.5:0,*:0.25:0", "10:1:0,20:0.5:0",
    "*:1:0,10:0.5:0,*:0.5:0", "1:1:0,2:1:0,3:1:0,4:1:0,5:1:0,6:1:0,7:1:0,8:1:0,*:1:0", "10:1:0,*:0.25:0,",
    "10x:1:0,*:1:0", "10::0,*:1:0", "nan:1:0,*:1:0", "1e40:1:0,*:1:0", "10:1:nan,*:1:0", "auto x",
]


def main():
    if os.path.isdir(CORPUS):
        shutil.rmtree(CORPUS)
    out = {}

    def put(target, name, data):
        if isinstance(data, str):
            data = data.encode()
        out.setdefault(target, []).append((name, data))

    # scene_json: the repository's scene files and the unit tests' documents
    for d in ("scenes/builtin", "scenes/studies", "scenes/examples"):
        for f in sorted(os.listdir(os.path.join(ROOT, d))):
            if f.endswith(".json"):
                put("scene_json", d.split("/")[1] + "_" + f, read(d + "/" + f))
    put("scene_json", "tri_every_key.json", SCENE_TRI)
    put("scene_json", "minimal.json", "{" + A + "," + I + "}")
    put("scene_json", "hmd_display.json", '{"display": {"kind": "hmd", "preset": "quest-pro", "width": 1440, '
        '"ipd": 64, "fov_right": [-41, 52, 41, -52]},' + A + "," + I + "}")
    put("scene_json", "missing_gltf.json", '{"assets": [{"name": "f", "gltf": "no_such_file.gltf"}],' + I + "}")

    # gltf: selector byte 0 = written as .gltf, 1 = as .glb (fuzz_gltf.c)
    put("gltf", "tri_files.gltf", b"\x00" + compact(tri_doc("buf.bin", {"uri": "tex.png"})))
    put("gltf", "tri_data_uri.gltf", b"\x00" + compact(tri_doc(data_uri("application/octet-stream", BUF),
                                                               {"uri": data_uri("image/png", TEX_PNG)})))
    put("gltf", "tri_png.glb", b"\x01" + glb_with_image(TEX_PNG, "image/png"))
    put("gltf", "tri_jpeg.glb", b"\x01" + glb_with_image(JPEG_4X4, "image/jpeg"))
    put("gltf", "tri_jpeg_as_gltf.glb", b"\x00" + glb_with_image(JPEG_4X4, "image/jpeg"))
    put("gltf", "features.gltf", b"\x00" + compact(features_doc()))
    p = petal_seed()
    if p:
        put("gltf", "megakit_petal_1.gltf", b"\x00" + p)

    # gaze: selector byte = format (0 auto, 1 csv, 2 pupil, 3 eyelink, 4 tobii) + 5 * eye + 20 * confidence
    for f in sorted(os.listdir(os.path.join(ROOT, "gaze_paths"))):
        if f.endswith(".csv"):
            put("gaze", "csv_" + f, b"\x01" + head_lines(read("gaze_paths/" + f), 40))
    put("gaze", "auto_csv_small.csv", b"\x00" + CSV_SMALL.encode())
    put("gaze", "csv_keep_all.csv", bytes([1 + 20]) + CSV_SMALL.encode())
    pupil = read("tests/data/pupil_gaze_positions.csv")
    put("gaze", "pupil_gaze_positions.csv", b"\x02" + pupil)
    put("gaze", "auto_pupil_head.csv", b"\x00" + head_lines(pupil, 8))
    for name, text in (("mono", EYELINK_MONO), ("remote", EYELINK_REMOTE), ("bino", EYELINK_BINO), ("bino2", EYELINK_BINO2)):
        put("gaze", "eyelink_%s.asc" % name, b"\x03" + text.encode())
        put("gaze", "auto_eyelink_%s.asc" % name, b"\x00" + text.encode())
    for eye in (1, 2, 3):
        put("gaze", "eyelink_bino2_eye%d.asc" % eye, bytes([3 + 5 * eye]) + EYELINK_BINO2.encode())
    put("gaze", "tobii.json", b"\x04" + TOBII.encode())
    put("gaze", "auto_tobii.json", b"\x00" + TOBII.encode())
    for eye in (0, 1, 2, 3):  # detected from its header (the selector's format is auto), each eye choice
        put("gaze", "auto_eyenav_eye%d.csv" % eye, bytes([5 * eye]) + EYENAV.encode())

    for i, r in enumerate(RINGS):
        put("rings", "%02d.txt" % i, r)

    total = 0
    for target, files in out.items():
        d = os.path.join(CORPUS, target)
        os.makedirs(d)
        for name, data in files:
            with open(os.path.join(d, name), "wb") as f:
                f.write(data)
            total += len(data)
            if len(data) > 8192:
                sys.exit("seed %s/%s is %d bytes: keep seeds small" % (target, name, len(data)))
    print("corpus: %s, %d bytes" % (", ".join("%s %d" % (t, len(f)) for t, f in out.items()), total))

    # The side files fuzz_gltf.c and fuzz_scene_json.c write into their scratch folder.
    def carr(name, b):
        lines = ["static const unsigned char %s[%d] = {" % (name, len(b))]
        for i in range(0, len(b), 16):
            lines.append("    " + ", ".join("0x%02x" % v for v in b[i:i + 16]) + ",")
        lines.append("};")
        return "\n".join(lines)

    tri = compact(tri_doc("buf.bin", {"uri": "tex.png"}))
    with open(os.path.join(HERE, "fuzz_assets.h"), "w") as f:
        f.write("/* fuzz_assets.h: generated by tests/fuzz/make_corpus.py, do not edit.\n"
                " * The side files the glTF and scene targets write into their scratch folder: tri.gltf (one MASK\n"
                " * triangle referencing buf.bin and tex.png by URI), buf.bin, tex.png (2x2 RGBA). */\n"
                "#ifndef FOVSIM_FUZZ_ASSETS_H\n#define FOVSIM_FUZZ_ASSETS_H\n\n")
        f.write("static const char k_tri_gltf[] =\n")
        s = tri.decode()
        for i in range(0, len(s), 96):
            f.write('    "%s"\n' % s[i:i + 96].replace("\\", "\\\\").replace('"', '\\"'))
        f.write("    ;\n")
        f.write(carr("k_buf_bin", BUF) + "\n")
        f.write(carr("k_tex_png", TEX_PNG) + "\n\n#endif\n")


if __name__ == "__main__":
    main()
