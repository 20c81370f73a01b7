#!/usr/bin/env bash
# Progress off a terminal (docs/compare.md "Progress in a log"): with stderr a file, render,
# compare and reference print plain progress lines (frames done/total, rate, elapsed, ETA),
# every frame at --progress-interval 0; --quiet prints none; on a terminal (a pty from
# script(1)) the line is redrawn with '\r' instead. Small sizes: a few seconds.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/progress
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

# lines LABEL TOTAL FILE: every line of FILE is a progress line of LABEL out of TOTAL frames, the
# counts rise, the last is TOTAL/TOTAL; prints the number of lines. Fails on any other line.
lines() {
  /usr/bin/python3 - "$1" "$2" "$3" <<'PY'
import re, sys
label, total, path = sys.argv[1], int(sys.argv[2]), sys.argv[3]
pat = re.compile(r'^' + re.escape(label) + r' (\d+)/(\d+) \((\d+)%\), ([0-9]+\.[0-9]{2}) frames/s, '
                 r'([0-9]+\.[0-9]) s elapsed, ETA ([0-9]+s|[0-9]+m[0-9]{2}s|[0-9]+h[0-9]{2}m|unknown)$')
prev, n = 0, 0
for line in open(path, encoding='utf-8').read().splitlines():
    m = pat.match(line)
    if not m:
        sys.exit(f'not a progress line of "{label}": {line!r}')
    done, tot, pct = int(m[1]), int(m[2]), int(m[3])
    if tot != total or not prev < done <= total or pct != 100 * done // total:
        sys.exit(f'wrong count (after {prev}, of {total}): {line!r}')
    if float(m[4]) <= 0:
        sys.exit(f'no rate: {line!r}')
    prev, n = done, n + 1
if n and prev != total:
    sys.exit(f'the last line is {prev}/{total}')
print(n)
PY
}

# A render of 12 frames, stderr a file: a line per frame at interval 0.
"$BIN" render fence --width 64 --height 36 --frames 12 --progress-interval 0 --out "$T/r" >"$T/r.out" 2>"$T/r.err"
check "render: exit 0" [ $? -eq 0 ]
n=$(lines frame 12 "$T/r.err") || { cat "$T/r.err" >&2; n=0; }
check "render, stderr a file, interval 0: one progress line per frame (got $n)" [ "$n" = 12 ]

# At a 1 s interval: the first frame's line, the last frame's, and between them at most one a
# second (how many depends on the machine's speed, so only those two are counted on).
"$BIN" render fence --width 64 --height 36 --frames 12 --progress-interval 1 --out "$T/r" --replace \
  >"$T/r1.out" 2>"$T/r1.err"
n=$(lines frame 12 "$T/r1.err") || { cat "$T/r1.err" >&2; n=0; }
check "render at a 1 s interval: well-formed lines, at least 2 (got $n)" [ "$n" -ge 2 ]
check "render at a 1 s interval: the first line is frame 1/12, the last 12/12" \
  bash -c "head -1 '$T/r1.err' | grep -q '^frame 1/12 ' && tail -1 '$T/r1.err' | grep -q '^frame 12/12 '"

# --quiet: nothing on stderr.
"$BIN" render fence --width 64 --height 36 --frames 12 --progress-interval 0 --quiet --out "$T/r" --replace \
  >"$T/q.out" 2>"$T/q.err"
check "render --quiet: no progress line" [ ! -s "$T/q.err" ]

# compare counts reference passes, and prints frames.
REF=(--supersample 1 --cache "$T/cache")
"$BIN" compare fence --width 64 --height 36 --frames 4 "${REF[@]}" --progress-interval 0 --out "$T/c" \
  >"$T/c.out" 2>"$T/c.err"
n=$(lines "compare frame" 4 "$T/c.err") || { cat "$T/c.err" >&2; n=0; }
check "compare, stderr a file: one line per frame (got $n)" [ "$n" = 4 ]
# ... and ends with how to look at its folder, as demo does.
check "compare prints how to look at the frames" grep -qF "oiiotool --info -v '$T/c/compare.0000.exr'" "$T/c.out"
check "compare's layer hint crops to the layer (--fullpixels)" grep -qF -- "--subimage layers --fullpixels" "$T/c.out"
touch "$T/c/report.html"
"$BIN" compare fence --width 64 --height 36 --frames 4 "${REF[@]}" --quiet --out "$T/c" --replace >"$T/c2.out" 2>"$T/c2.err"
check "compare --quiet: no progress line" [ ! -s "$T/c2.err" ]
check "a folder's report.html is the first hint" \
  bash -c "grep -A1 '^look at it' '$T/c2.out' | tail -1 | grep -qF \"xdg-open '$T/c/report.html'\""

"$BIN" reference fence --width 64 --height 36 --frames 3 --supersample 1 --cache "$T/cache2" --progress-interval 0 \
  --out "$T/ref" >"$T/ref.out" 2>"$T/ref.err"
n=$(lines "reference frame" 3 "$T/ref.err") || { cat "$T/ref.err" >&2; n=0; }
check "reference, stderr a file: one line per frame (got $n)" [ "$n" = 3 ]

# On a terminal: the line is redrawn in place ('\r'), never the plain lines.
if command -v script >/dev/null; then
  script -qec "'$BIN' render fence --width 64 --height 36 --frames 12 --progress-interval 0 --out '$T/r' --replace" \
    /dev/null >"$T/tty.txt" 2>&1
  check "render on a terminal: the line redrawn with CR" grep -qF $'\rframe 12/12' "$T/tty.txt"
  check "render on a terminal: no plain progress line" bash -c "! grep -q 'frames/s' '$T/tty.txt'"
else
  echo "skip the terminal case: script(1) is not installed" >&2
fi

expect_exit "--progress-interval -1 refused" 2 "$BIN" render fence --progress-interval -1 --out "$T/bad"
check "... and nothing written" [ ! -e "$T/bad" ]
expect_exit "--progress-interval on plan refused" 2 "$BIN" plan fence --progress-interval 1
summary
