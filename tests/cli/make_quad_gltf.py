#!/usr/bin/env python3
"""make_quad_gltf.py OUT.gltf H OPAQUE|MASK: a glTF of one square of side 2 H in the plane z = 0,
centred on the origin, facing +Z, white (alpha 1), with an OPAQUE or MASK material (used by
test_counts.sh; not a test itself: CMake registers only tests/cli/test_*.sh)."""
import base64
import json
import struct
import sys

h = float(sys.argv[2]); mode = sys.argv[3]
pos = [(-h,-h,0),(h,-h,0),(h,h,0),(-h,h,0)]
nrm = [(0,0,1)]*4
idx = [0,1,2,0,2,3]
data = b"".join(struct.pack("<3f",*p) for p in pos) + b"".join(struct.pack("<3f",*n) for n in nrm) + struct.pack("<6I",*idx)
g = {"asset":{"version":"2.0"},
 "buffers":[{"byteLength":len(data),"uri":"data:application/octet-stream;base64,"+base64.b64encode(data).decode()}],
 "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":48},{"buffer":0,"byteOffset":96,"byteLength":24}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[-h,-h,0],"max":[h,h,0]},
              {"bufferView":1,"componentType":5126,"count":4,"type":"VEC3"},
              {"bufferView":2,"componentType":5125,"count":6,"type":"SCALAR"}],
 "materials":[{"name":"quad","pbrMetallicRoughness":{"baseColorFactor":[1,1,1,1]},"alphaMode":mode} | ({"alphaCutoff":0.5} if mode=="MASK" else {})],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1},"indices":2,"material":0}]}],
 "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0}
json.dump(g, open(sys.argv[1],"w"))
