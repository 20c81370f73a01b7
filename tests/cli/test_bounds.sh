#!/usr/bin/env bash
# Resource bounds and hangs (README "Limits", and two silent refusals): every input path
# is refused by what it is before it is opened (a FIFO hung, /dev/zero was read for 512 MiB); a PNG
# whose pixel data inflates past its declared size is refused without inflating it (2 GiB for a
# 1x1 PNG); a message quoting an 8 MB data: URI stays short; SIGTERM to `sweep --local 2` stops its
# tasks too; a scene nested too deep says so; a folder named like a built-in scene does not hide it.
# Part 9 (Tobii record length, out of memory) is tests/unit/test_gaze.c.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SHARED=${FOVSIM_SHARED:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/bounds
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
cd "$T" || exit 1
SMALL=(--frames 1 --width 32 --height 32)

# ---- part 7: a FIFO or device as any input is refused at once (each case under a timeout: the old
# code waited for a writer forever). Nothing ever writes to these FIFOs.
mkfifo fifo.gltf fifo.json fifo.csv fifo.bin
expect_exit "a FIFO as the glTF scene -> 4" 4 timeout 20 "$BIN" plan --scene fifo.gltf
check "  says it is a FIFO" grep -q 'fifo.gltf: is a FIFO (named pipe), not a regular file; expected a glTF file' "$T/err.txt"
expect_exit "a FIFO as the scene file -> 6" 6 timeout 20 "$BIN" plan fifo.json
check "  says it is a FIFO" grep -q 'fifo.json: is a FIFO (named pipe), not a regular file, expected a scene file' "$T/err.txt"
printf '{"assets": [{"name": "z", "gltf": "fifo.gltf"}], "instances": [{"asset": "z"}]}' >scene_fifo.json
expect_exit "a scene whose glTF is a FIFO -> 4" 4 timeout 20 "$BIN" plan scene_fifo.json
mkdir -p buf
cp "$SHARED"/assets/quaternius_megakit_set_a/{Fern_1.gltf,Leaves.png} buf/
mkfifo buf/Fern_1.bin
expect_exit "a glTF whose buffer is a FIFO -> 4" 4 timeout 20 "$BIN" plan --scene buf/Fern_1.gltf
check "  names the URI" grep -q "URI 'Fern_1.bin' is not a regular file" "$T/err.txt"
expect_exit "a FIFO as the gaze trace -> 6" 6 timeout 20 "$BIN" render fence --gaze fifo.csv "${SMALL[@]}" --out o_fifo
check "  says it is a FIFO" grep -q 'fifo.csv: is a FIFO (named pipe), not a regular file, expected a gaze trace' "$T/err.txt"
# /dev/zero: refused as a device, not read up to the 512 MiB limit (memory capped: a regression fails)
cap="ulimit -v 1000000;"; ldd "$BIN" 2>/dev/null | grep -q libasan && cap=""
expect_exit "--gaze /dev/zero -> 6, unread" 6 bash -c "$cap exec timeout 20 '$BIN' render fence --gaze /dev/zero --frames 1 --width 32 --height 32 --out o_zero"
check "  says it is a device" grep -q '/dev/zero: is a character device, not a regular file, expected a gaze trace' "$T/err.txt"
expect_exit "a FIFO as a check baseline's check.json -> 6" 6 bash -c "mkdir -p base && mkfifo base/check.json && exec timeout 20 '$BIN' check --baseline base"
check "FIFO cases create nothing" test ! -e o_fifo -a ! -e o_zero

# ---- part 8: a PNG declaring 1x1 pixels whose IDAT inflates to 256 MiB (257 KB of zeros), interlaced
# (stb_image accepted the extra data after inflating all of it: exit 0, ~300 MB). Memory is capped so
# that a regression fails rather than eats the machine. A valid interlaced PNG still loads.
mkdir -p png
cp "$SHARED"/assets/quaternius_megakit_set_a/{Fern_1.gltf,Fern_1.bin} png/
python3 - png <<'PY'
import json, struct, sys, zlib
d = sys.argv[1]
def chunk(t, b): return struct.pack('>I', len(b)) + t + b + struct.pack('>I', zlib.crc32(t + b) & 0xffffffff)
def png(path, w, h, interlace, raw):
    c = zlib.compressobj(9); z = b''; blk = b'\0' * (1 << 20)
    while raw > 0:
        k = min(raw, len(blk)); z += c.compress(blk[:k]); raw -= k
    z += c.flush()
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 6, 0, 0, interlace))
                           + chunk(b'IDAT', z) + chunk(b'IEND', b''))
# Adam7 bytes of a w x h RGBA8 image: per pass, rows of 1 + 4 * pass width
def adam7(w, h):
    n = 0
    for xo, yo, xs, ys in ((0,0,8,8), (4,0,8,8), (0,4,4,8), (2,0,4,4), (0,2,2,4), (1,0,2,2), (0,1,1,2)):
        pw, ph = max(0, (w - xo + xs - 1) // xs), max(0, (h - yo + ys - 1) // ys)
        n += ph * (1 + 4 * pw) if pw and ph else 0
    return n
png(d + '/bomb.png', 1, 1, 1, 256 << 20)
png(d + '/ok.png', 13, 7, 1, adam7(13, 7))
for name in ('bomb', 'ok'):
    j = json.load(open(d + '/Fern_1.gltf')); j['images'][0]['uri'] = name + '.png'
    json.dump(j, open('%s/%s.gltf' % (d, name), 'w'))
PY
check "the bomb PNG is small" test "$(stat -c %s png/bomb.png)" -lt 300000
cap="ulimit -v 200000;"; ldd "$BIN" 2>/dev/null | grep -q libasan && cap=""
expect_exit "PNG of 1x1 pixels inflating to 256 MiB -> 4" 4 bash -c "$cap exec timeout 60 '$BIN' plan --scene png/bomb.gltf"
check "  says it inflates past its declared size" grep -q "bomb.gltf: images\[0\] (Leaves): the PNG's pixel data inflates to more than the 5 bytes its 1x1 pixels need" "$T/err.txt"
check "a valid interlaced PNG loads" bash -c "'$BIN' plan --scene png/ok.gltf >/dev/null"

# ---- part 10: an 8 MB data: URI with a wrong byteLength: the message quotes a few hundred bytes
python3 - <<'PY'
import base64, json
data = base64.b64encode(b'\0' * (6 << 20)).decode()
json.dump({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}], "scene": 0,
           "buffers": [{"byteLength": 12, "uri": "data:application/octet-stream;base64," + data}]},
          open('datauri.gltf', 'w'))
PY
expect_exit "an 8 MB data: URI with a wrong byteLength -> 4" 4 "$BIN" plan --scene datauri.gltf
check "  the message is under 1000 bytes" test "$(wc -c <"$T/err.txt")" -lt 1000
check "  and still names the file and the URI's start" grep -q 'datauri.gltf: .*data:application/octet-stream;base64,AAAA.*\.\.\.\[[0-9]* bytes\]\.\.\.' "$T/err.txt"

# ---- also refused silently before: a scene nested 1001 deep (a "syntax error"); a folder named
# like a built-in scene in the current folder ("fence: is a directory")
python3 -c "open('deep.json', 'w').write('{\"assets\": ' + '[' * 1000 + ']' * 1000 + '}')"
expect_exit "a scene nested 1001 deep -> 3" 3 "$BIN" plan deep.json
check "  says it is too deep" grep -q 'deep.json:1: arrays and objects nested deeper than 1000' "$T/err.txt"
mkdir -p fence
check "a folder 'fence' does not hide the built-in" bash -c "'$BIN' plan fence >out_fence.txt 2>&1 && grep -q '^scene *builtin:fence' out_fence.txt"

# ---- part 11: SIGTERM to `sweep --local 2` stops both children (they were left running and
# writing), waits for them and exits 130. The children at the signal are the two scenes' reference
# jobs, which the sweep runs before the tasks (docs/cluster.md "References first"), each long
# enough (200 frames) to be running at the signal.
cat >m.json <<'EOF'
{ "scenes": ["fence", "tree"], "modes": ["traditional"], "width": 32, "height": 18, "frames": 200,
  "reference": {"supersample": 1}, "cache": "cache" }
EOF
"$BIN" sweep m.json --local 2 --out sw --quiet >sweep_out.txt 2>sweep_err.txt &
sweep=$!
# both children started
for _ in $(seq 1 1200); do
  [ "$(pgrep -P $sweep | wc -l)" -ge 2 ] && break
  kill -0 $sweep 2>/dev/null || break; sleep 0.05
done
kids=$(pgrep -P $sweep | tr '\n' ' ')
check "two children are running before the signal" test "$(echo $kids | wc -w)" -eq 2
[ "$(echo $kids | wc -w)" -eq 2 ] || { echo "  children: '$kids'; task folders:" >&2; ls sw/tasks >&2; }
kill -TERM $sweep
wait $sweep; rc=$?
check "sweep exits 130 after SIGTERM" test $rc -eq 130
[ $rc -eq 130 ] || { echo "  exit $rc; stderr:" >&2; cat sweep_err.txt >&2; }
check "  with one line saying so" grep -q 'interrupted (SIGTERM): [0-9]* of 2 tasks finished, [0-9]* stopped; run the sweep again to resume' sweep_err.txt
alive=""
for k in $kids; do kill -0 "$k" 2>/dev/null && alive="$alive $k"; done
check "no task outlives the sweep" test -z "$alive"
for k in $alive; do kill -KILL "$k" 2>/dev/null; done
"$BIN" sweep m.json --list --out sw >list.txt 2>&1
check "the stopped tasks resume: listed as incomplete or to do" grep -q '^0 done, ' list.txt

summary
