#!/usr/bin/env bash
# report.html in a real browser (headless Chromium, Debian's `chromium`; scripts/setup.sh installs
# it): the page's script runs without an error (body data-ok set, no data-error, no console
# message), every number of summary.json's modes is in the summary table and equal to it, the
# charts are there, and a screenshot of each page stays in the test output. Pages of a compare
# with the frame scrubber, of one with a video, and of bench --accuracy. Skipped (exit 77, with a
# line saying so) only where there is no Chromium.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/report_browser
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
CHROME=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$CHROME" ]; then
  echo "SKIP: chromium is not installed (scripts/setup.sh installs Debian's chromium for this test)" >&2
  exit 77
fi
REF=(--supersample 2 --samples 8 --cache "$T/cache")

# browse DIR NAME: DIR/report.html's DOM after its scripts ran into $T/NAME.dom, the browser's log
# into $T/NAME.log, a screenshot into $T/NAME.png
browse() {
  local url="file://$(cd "$1" && pwd)/report.html"
  timeout 120 "$CHROME" --headless --disable-gpu --no-sandbox --no-first-run --user-data-dir="$T/profile" \
    --enable-logging=stderr --v=0 --virtual-time-budget=3000 --dump-dom "$url" >"$T/$2.dom" 2>"$T/$2.log"
  timeout 120 "$CHROME" --headless --disable-gpu --no-sandbox --no-first-run --user-data-dir="$T/profile" \
    --hide-scrollbars --window-size=1280,2400 --screenshot="$T/$2.png" "$url" >/dev/null 2>&1
}
# page_ok NAME: the script marked the page built and nothing failed
page_ok() {
  grep -q '<body[^>]*data-ok="1"' "$T/$1.dom" || { echo "  no data-ok in the DOM" >&2; return 1; }
  ! grep -q '<body[^>]*data-error' "$T/$1.dom" || { grep -o '<body[^>]*>' "$T/$1.dom" >&2; return 1; }
  ! grep -a 'CONSOLE' "$T/$1.log" >&2
}
# table_matches NAME SUMMARY: every number under summary.json's "modes" is a cell of the DOM's
# table with that key, and equal to it
table_matches() {
  /usr/bin/python3 - "$T/$1.dom" "$2" <<'PY'
import json, sys
from html.parser import HTMLParser
class P(HTMLParser):
    def __init__(self):
        super().__init__(); self.cells = {}; self.key = None
    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "td" and "data-k" in a:
            self.key = a["data-k"]; self.cells[self.key] = ""
    def handle_endtag(self, tag):
        if tag == "td": self.key = None
    def handle_data(self, d):
        if self.key is not None: self.cells[self.key] += d
p = P(); p.feed(open(sys.argv[1]).read())
want = {}
def walk(v, k):
    if isinstance(v, dict):
        for n, x in v.items(): walk(x, k + "." + n if k else n)
    elif isinstance(v, list):
        for i, x in enumerate(v): walk(x, k + "." + str(i))
    elif isinstance(v, (int, float)) and not isinstance(v, bool):
        want[k] = v
walk({"modes": json.load(open(sys.argv[2]))["modes"]}, "")
bad = [k for k in want if k not in p.cells or float(p.cells[k]) != float(want[k])]
if bad or len(want) < 10:
    print("  %d of %d numbers missing or different, e.g. %s" % (len(bad), len(want), bad[:3]), file=sys.stderr)
    sys.exit(1)
print("  %d numbers equal" % len(want), file=sys.stderr)
PY
}
export -f table_matches; export T
is_png() { [ -s "$1" ] && [ "$(head -c 8 "$1" | od -An -c | tr -d ' ')" = '211PNG\r\n032\n' ]; }

# ---- a compare without a video: the scrubber over the previews
"$BIN" compare forest --width 160 --height 90 --frames 4 "${REF[@]}" --out "$T/c" --quiet >"$T/c.txt" 2>&1
check "compare exits 0" test $? -eq 0
browse "$T/c" scrub
check "scrubber page: the script ran without an error or console message" page_ok scrub
check "scrubber page: the table's numbers equal summary.json's" table_matches scrub "$T/c/summary.json"
check "scrubber page: the scrubber and its first frame" bash -c "grep -q 'id=\"scrub\"' '$T/scrub.dom' && grep -q 'src=\"preview/frame.0000.png\"' '$T/scrub.dom'"
check "scrubber page: a coverage chart per ring and the display" \
  bash -c "grep -q 'id=\"coverage-ring-1\"' '$T/scrub.dom' && grep -q 'id=\"coverage-ring0\"' '$T/scrub.dom'"
check "scrubber page: a screenshot ($T/scrub.png)" is_png "$T/scrub.png"
# A page whose script fails is caught (the check above can fail).
sed 's/document.body.dataset.ok = /undefined_function(); document.body.dataset.ok = /' "$T/c/report.html" >"$T/c/broken.html"
mv "$T/c/report.html" "$T/c/good.html"; mv "$T/c/broken.html" "$T/c/report.html"
browse "$T/c" broken
check "a page with a script error is caught" bash -c "! page_ok broken 2>/dev/null"
mv "$T/c/good.html" "$T/c/report.html"

# ---- a compare with a video
"$BIN" compare forest --width 160 --height 90 --frames 4 "${REF[@]}" --out "$T/v" --video on --quiet >"$T/v.txt" 2>&1
check "compare --video on exits 0" test $? -eq 0
browse "$T/v" video
check "video page: the script ran without an error or console message" page_ok video
check "video page: the table's numbers equal summary.json's" table_matches video "$T/v/summary.json"
check "video page: the video element" grep -q '<video id="video" src="video.mp4"' "$T/video.dom"
check "video page: a screenshot ($T/video.png)" is_png "$T/video.png"

# ---- FovVideoVDP's JODs (the stand-in pyfvvdp of tests/cli/fake_fvvdp, as test_security.sh runs it)
if /usr/bin/python3 -c 'import numpy' 2>/dev/null; then
  SRC=$(cd "$(dirname "$0")/../.." && pwd)
  mkdir -p "$T/fakebin"; ln -sf /usr/bin/python3 "$T/fakebin/python3"
  env PATH="$T/fakebin:$PATH" PYTHONPATH="$SRC/tests/cli/fake_fvvdp" PYTHONDONTWRITEBYTECODE=1 \
    "$BIN" compare fence --width 32 --height 18 --frames 2 "${REF[@]}" --fvvdp --out "$T/j" --quiet >"$T/j.txt" 2>&1
  check "compare --fvvdp (stand-in) exits 0" test $? -eq 0
  browse "$T/j" jod
  check "JOD page: the script ran without an error or console message" page_ok jod
  check "JOD page: the table holds the JODs, equal to summary.json's" bash -c \
    "grep -q 'FovVideoVDP JOD' '$T/jod.dom' && grep -q 'data-k=\"modes.1.fvvdp_jod\"' '$T/jod.dom' && table_matches jod '$T/j/summary.json'"
fi

# ---- bench --accuracy: the accuracy plot with its Pareto front
"$BIN" bench fence --accuracy --modes traditional,hashed --width 64 --height 36 --frames 3 --warmup 1 "${REF[@]}" \
  --out "$T/a" --quiet >"$T/a.txt" 2>&1
check "bench --accuracy exits 0" test $? -eq 0
browse "$T/a" accuracy
check "accuracy page: the script ran without an error or console message" page_ok accuracy
check "accuracy page: the plot, its Pareto front, lower is better" \
  bash -c "grep -q 'id=\"accuracy\"' '$T/accuracy.dom' && grep -q 'Pareto front' '$T/accuracy.dom' && grep -q 'lower is better' '$T/accuracy.dom'"
check "accuracy page: accuracy.csv's rows" test "$(grep -c 'data-k="accuracy\.[0-9]*\.mode"' "$T/accuracy.dom")" -eq 16
check "accuracy page: a screenshot ($T/accuracy.png)" is_png "$T/accuracy.png"
summary
