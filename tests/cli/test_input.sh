#!/usr/bin/env bash
# Hostile and malformed input (README "Exit status", "Limits"): every case exits with its documented
# status, prints exactly one line on stderr naming the file and what was expected, leaves no output
# behind, and never echoes control characters from the input.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SHARED=${FOVSIM_SHARED:?set by CMake}
SRC=${FOVSIM_SOURCE:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/input
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

# tiny settings, so that a case the old code accepted still ends quickly
SMALL=(--frames 1 --width 32 --height 32)
# ---- --modes: an empty list or item is a usage error with a message (defect 6)
for cmd in compare bench; do
  extra=(--samples 2 --supersample 1 --no-cache); [ $cmd = bench ] && extra=(--warmup 0)
  for v in '' ',' 'traditional,' ',hashed' 'traditional,,hashed'; do
    expect_exit "$cmd --modes '$v' -> 2 with a message" 2 "$BIN" $cmd fence --modes "$v" "${SMALL[@]}" "${extra[@]}" --out "$T/modes"
    check "$cmd --modes '$v' says what it expects" grep -q "modes: expected alpha modes separated by commas" "$T/err.txt"
  done
done
check "--modes errors create nothing" test ! -e "$T/modes"

# ---- control characters from input are escaped in messages (defect 5): a scene key with an ESC
# sequence and a forged second "fovsim:" line, a glTF path with a raw newline, a material name
# from a glTF file with both; each message stays one line and shows the bytes as \x1b, \n
printf '{"assets": [{"name": "f", "generator": "fence"}], "instances": [{"asset": "f"}], "\\u001b[31mkey\\nfovsim: error: forged": 1}' >"$T/esc_key.json"
expect_exit "ESC and newline in a scene key -> 3, one line" 3 "$BIN" plan "$T/esc_key.json"
check "the scene key is shown escaped" grep -qF 'esc_key.json: \x1b[31mkey\nfovsim: error: forged: unknown key' "$T/err.txt"
printf '{"assets": [{"name": "a", "gltf": "no\\nsuch.gltf"}], "instances": [{"asset": "a"}]}' >"$T/nl_path.json"
expect_exit "newline in a glTF path -> 6, one line" 6 "$BIN" plan "$T/nl_path.json"
check "the glTF path is shown escaped" grep -qF 'no\nsuch.gltf: cannot open' "$T/err.txt"
mkdir -p "$T/escmat"; cp "$SHARED"/assets/quaternius_megakit_set_a/{Fern_1.gltf,Fern_1.bin,Leaves.png} "$T/escmat/"
python3 - "$T/escmat/Fern_1.gltf" <<'PY'
import json, sys
j = json.load(open(sys.argv[1])); j['materials'][0]['name'] = 'x\x1b[2J\nfovsim: error: forged'
json.dump(j, open(sys.argv[1], 'w'))
PY
printf '{"assets": [{"name": "a", "gltf": "escmat/Fern_1.gltf"}], "instances": [{"asset": "a"}], "materials": {"nope": {"alpha_mode": "hashed"}}}' >"$T/esc_mat.json"
expect_exit "ESC in a glTF material name listed in a message -> 3, one line" 3 "$BIN" plan "$T/esc_mat.json"
check "the material name is shown escaped" grep -qF 'x\x1b[2J\nfovsim: error: forged' "$T/err.txt"

# ---- a glTF nested 20,000 levels deep (defect 2): exit 4 naming the file, not a segfault (with its
# buffer and image next to it, tinygltf parsed it and crashed converting the extras)
cp "$SHARED"/assets/quaternius_megakit_set_a/{Fern_1.bin,Leaves.png} "$T/"
python3 - "$SHARED/assets/quaternius_megakit_set_a/Fern_1.gltf" "$T/deep.gltf" <<'PY'
import sys
t = open(sys.argv[1]).read().rstrip()
assert t.endswith('}')
open(sys.argv[2], 'w').write(t[:-1] + ',"extras":' + '[' * 20000 + ']' * 20000 + '}')
PY
expect_exit "glTF nested 20000 deep -> 4" 4 "$BIN" render --scene "$T/deep.gltf" "${SMALL[@]}" --out "$T/deep"
check "deep glTF: the message names the file and the limit" grep -q "deep.gltf: JSON nested deeper than 64 arrays and objects" "$T/err.txt"
check "deep glTF creates nothing" test ! -e "$T/deep"

# ---- glTF URIs (defects 7 and 10): each names a regular file under the glTF file's folder (or
# --asset-root); a directory is said to be one (it was "out of memory", exit 9), and a URI that
# leaves the folder is refused without reading the file or quoting its size
mkdir -p "$T/uri/sub/adir" "$T/uri/tex"
cp "$SHARED"/assets/quaternius_megakit_set_a/{Fern_1.gltf,Fern_1.bin,Leaves.png} "$T/uri/sub/"
cp "$SHARED"/assets/quaternius_megakit_set_a/Leaves.png "$T/uri/tex/"
ln -sf /etc/passwd "$T/uri/sub/link.bin"
python3 - "$T/uri/sub" <<'PY'
import json, sys
d = sys.argv[1]
def w(name, key, uri):
    j = json.load(open(d + '/Fern_1.gltf')); j[key][0]['uri'] = uri; json.dump(j, open(d + '/' + name, 'w'))
w('dir.gltf', 'buffers', 'adir')
w('passwd.gltf', 'buffers', '../../../../../../../../../../etc/passwd')
w('absolute.gltf', 'buffers', '/etc/passwd')
w('link.gltf', 'buffers', 'link.bin')
w('imgdir.gltf', 'images', 'adir')
w('sibling.gltf', 'images', '../tex/Leaves.png')
PY
expect_exit "buffer URI names a directory -> 4" 4 "$BIN" render --scene "$T/uri/sub/dir.gltf" "${SMALL[@]}" --out "$T/uri/o1"
check "directory URI: says what it is" grep -q "dir.gltf: URI 'adir' is a directory, expected a file" "$T/err.txt"
expect_exit "image URI names a directory -> 4" 4 "$BIN" plan "$T/uri/sub/imgdir.gltf"
check "directory image URI: says what it is" grep -q "imgdir.gltf: images\[0\] (Leaves): URI 'adir' is a directory" "$T/err.txt"
expect_exit "URI ../../etc/passwd -> 4" 4 "$BIN" render --scene "$T/uri/sub/passwd.gltf" "${SMALL[@]}" --out "$T/uri/o2"
check "../ URI: refused by the rule, no size quoted" bash -c "grep -q \"leaves the glTF file's folder\" '$T/err.txt' && ! grep -Eq '[0-9]{3,}|passwd.*bytes|File size' '$T/err.txt'"
expect_exit "absolute URI -> 4" 4 "$BIN" plan "$T/uri/sub/absolute.gltf"
check "absolute URI: refused" grep -q "URI '/etc/passwd' is an absolute path" "$T/err.txt"
expect_exit "symlink out of the folder -> 4" 4 "$BIN" plan "$T/uri/sub/link.gltf"
check "symlink URI: refused, no size quoted" bash -c "grep -q \"URI 'link.bin' leaves the glTF file's folder\" '$T/err.txt' && ! grep -q 'File size' '$T/err.txt'"
expect_exit "sibling folder without --asset-root -> 4" 4 "$BIN" plan "$T/uri/sub/sibling.gltf"
check "--asset-root widens the rule" bash -c "'$BIN' plan '$T/uri/sub/sibling.gltf' --asset-root '$T/uri' >/dev/null 2>'$T/err.txt'"
check "--asset-root does not open /etc" bash -c "! '$BIN' plan '$T/uri/sub/passwd.gltf' --asset-root '$T/uri' >/dev/null 2>&1"
expect_exit "--asset-root not a folder -> 2" 2 "$BIN" plan "$T/uri/sub/sibling.gltf" --asset-root "$T/uri/nope"
# a scene naming a device or FIFO as its glTF: refused by what it is, not read until memory runs out
printf '{"assets": [{"name": "z", "gltf": "/dev/zero"}], "instances": [{"asset": "z"}]}' >"$T/devzero.json"
expect_exit "a scene whose glTF is /dev/zero -> 4" 4 timeout 60 "$BIN" plan "$T/devzero.json"
check "  says it is not a regular file" grep -q '/dev/zero.*not a regular file' "$T/err.txt"
check "the shipped example scene still loads" bash -c "'$BIN' plan '$SRC/scenes/examples/megakit_garden.json' >/dev/null"
for f in "$SHARED"/assets/*/*.gltf "$SHARED"/assets/*/*.glb; do
  check "shared asset loads: $(basename "$f")" bash -c "'$BIN' plan --scene '$f' >/dev/null 2>&1"
done
check "URI errors create nothing" test ! -e "$T/uri/o1" -a ! -e "$T/uri/o2"

# ---- a 256 KB PNG declaring 16384x16384 (defect 3): refused from its header (it took 146 s and
# 2.1 GB before); the budget is per image and per scene, and a flag raises it. Memory is capped
# here so that a regression fails instead of eating the machine.
mkdir -p "$T/png"
cp "$SHARED"/assets/quaternius_megakit_set_a/{Fern_1.gltf,Fern_1.bin,Leaves.png} "$T/png/"
python3 - "$T/png" <<'PY'
import json, struct, sys, zlib
d = sys.argv[1]
def chunk(t, b): return struct.pack('>I', len(b)) + t + b + struct.pack('>I', zlib.crc32(t + b) & 0xffffffff)
def png(path, w, h):
    c = zlib.compressobj(9); row = b'\0' * (w + 1)
    idat = b''.join(c.compress(row) for _ in range(h)) + c.flush()
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 0, 0, 0, 0))
                           + chunk(b'IDAT', idat) + chunk(b'IEND', b''))
png(d + '/huge.png', 16384, 16384)
png(d + '/big.png', 4096, 4096)
for name, uri in (('huge.gltf', 'huge.png'), ('big.gltf', 'big.png')):
    j = json.load(open(d + '/Fern_1.gltf')); j['images'][0]['uri'] = uri; json.dump(j, open(d + '/' + name, 'w'))
json.dump({"assets": [{"name": "b%d" % i, "gltf": "big.gltf"} for i in range(3)],
           "instances": [{"asset": "b%d" % i} for i in range(3)]}, open(d + '/three.json', 'w'))
PY
# (not under AddressSanitizer, which reserves terabytes of address space for its shadow memory)
cap="ulimit -v 1500000;"; ldd "$BIN" 2>/dev/null | grep -q libasan && cap=""
expect_exit "PNG declaring 16384x16384 -> 4, fast" 4 bash -c "$cap exec timeout 20 '$BIN' render --scene '$T/png/huge.gltf' --frames 1 --width 32 --height 32 --out '$T/png/o'"
check "huge PNG: the message gives the sizes and the flag" grep -q "huge.gltf: images\[0\] (Leaves): 16384x16384 is 256.0 Mpixel, over the budget of 64.0 Mpixel per image (--max-image-mpixels raises it)" "$T/err.txt"
check "huge PNG creates nothing" test ! -e "$T/png/o"
check "a 4096x4096 texture is within the budget" bash -c "'$BIN' plan '$T/png/big.gltf' >/dev/null"
expect_exit "--max-image-mpixels 8 refuses 16 Mpixel -> 4" 4 "$BIN" plan "$T/png/big.gltf" --max-image-mpixels 8
expect_exit "three 16 Mpixel assets over --max-scene-mpixels 40 -> 4" 4 "$BIN" plan "$T/png/three.json" --max-scene-mpixels 40
check "the scene budget message gives the total" grep -q "would bring the scene's images to 48.0 Mpixel, over the budget of 40.0 Mpixel per scene" "$T/err.txt"
check "--max-scene-mpixels 48 lets them through" bash -c "'$BIN' plan '$T/png/three.json' --max-scene-mpixels 48 >/dev/null"

summary
