#!/usr/bin/env bash
# The docs' recipes still work: every fenced block marked ```sh runnable in README.md and
# docs/*.md runs, in the files' order, with bash -e in one scratch folder, and must exit 0
# (docs/testing.md "The docs' recipes"). `fovsim` there is the build's binary at a small size:
# a wrapper appends --width 96 --height 54 --frames 3 (and a 1x1 reference) to the commands that
# draw, so a block runs as written, only smaller. Before the blocks, the folders they read are
# made the same way: out/demo (`fovsim demo`) and out/render (`fovsim render --out out/render`).
# Every PNG a block writes from frames must be one display-sized image (96x54), not a grid or a
# padded layer.
# About 10 s.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SRC=${FOVSIM_SOURCE:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/docs
rm -rf "$T"; mkdir -p "$T/bin" "$T/blocks" "$T/work"
. "$(dirname "$0")/harness.sh"
for tool in oiiotool ffmpeg; do
  command -v $tool >/dev/null || { echo "FAIL '$tool' is not installed (scripts/setup.sh installs it)" >&2; exit 1; }
done

cat >"$T/bin/fovsim" <<SH
#!/usr/bin/env bash
# fovsim for the docs' runnable blocks (tests/cli/test_docs.sh): the build's binary, smaller.
small=(--width 96 --height 54 --frames 3)
ref=(--supersample 1 --cache "$T/cache")
case "\${1:-}" in
  render) exec "$BIN" "\$@" "\${small[@]}" ;;
  reference|compare|demo) exec "$BIN" "\$@" "\${small[@]}" "\${ref[@]}" ;;
  check) # --baseline refuses options that change the run: --record stores the small ones
    for a in "\$@"; do [ "\$a" = --record ] && exec "$BIN" "\$@" "\${small[@]}" "\${ref[@]}"; done
    exec "$BIN" "\$@" --cache "$T/cache" ;;
  *) exec "$BIN" "\$@" ;;
esac
SH
chmod +x "$T/bin/fovsim"
export PATH="$T/bin:$PATH"

# run_blocks DIR FILE...: extracts FILEs' runnable blocks into DIR and runs them in $T/work; its
# status is 1 when a block failed (each failure is reported with its file:line).
run_blocks() {
  local dir=$1 list bad=0; shift
  list=$(cd "$SRC" && /usr/bin/python3 "$SRC/tests/cli/docs_blocks.py" "$dir" "$@") || return 1
  while read -r block where; do
    [ -n "$block" ] || continue
    if (cd "$T/work" && bash -e -o pipefail "$block") </dev/null >"$block.log" 2>&1; then
      echo "     ran $where" >&2
    else
      echo "  the block at $where failed:" >&2; tail -5 "$block.log" >&2; bad=1
    fi
    echo "$where" >>"$dir/ran.txt"
  done <<<"$list"
  return $bad
}

# The runner itself: a failing block fails it, an unclosed one is an error.
mkdir -p "$T/self"
printf '# t\n\n```sh runnable\ntrue\n```\n\n```sh runnable\nfalse\necho after\n```\n' >"$T/self/fail.md"
printf '```sh runnable\ntrue\n' >"$T/self/open.md"
run_blocks "$T/self" "$T/self/fail.md" 2>/dev/null; rc=$?
check "a block that fails fails the test" [ $rc -ne 0 ]
check "... and the blocks before it ran" [ "$(wc -l <"$T/self/ran.txt")" -eq 2 ]
check "an unclosed block is an error" bash -c "! /usr/bin/python3 '$SRC/tests/cli/docs_blocks.py' '$T/self' '$T/self/open.md' 2>/dev/null"

# The folders the blocks read, and the repository's inputs they name.
(cd "$T/work" && ln -s "$SRC/scenes" scenes && ln -s "$SRC/gaze_paths" gaze_paths &&
 fovsim demo >demo.log 2>&1 && fovsim render --out out/render >render.log 2>&1)
check "the blocks' input folders (a small demo and render)" [ -e "$T/work/out/demo/compare.0002.exr" \
  -a -e "$T/work/out/render/frame.0002.exr" ]

mapfile -t docs < <(cd "$SRC" && ls README.md docs/*.md)
run_blocks "$T/blocks" "${docs[@]}"
check "every runnable block of README.md and docs/*.md exits 0" [ $? -eq 0 ]
# Guards against testing nothing: the recipes that matter are marked.
for f in README.md docs/compare.md docs/check.md docs/cluster.md; do
  check "$f has runnable blocks, and they ran" grep -q "^$f:" "$T/blocks/ran.txt"
done

# Every PNG a recipe writes from the frames is display-sized: a layer, not part 0's grid-sized
# canvas (merge's accuracy.png is a plot; preview/ holds compare's previews of the grid for
# report.html, grid-sized by design).
pngs=$(cd "$T/work" && find . -name '*.png' ! -name 'accuracy*.png' ! -path '*/preview/*' | sort)
check "the recipes wrote PNGs" [ -n "$pngs" ]
check "the sweep recipe's merge wrote its table" [ -s "$T/work/out/sweep/tiny/metrics.csv" ]
while read -r p; do
  [ -n "$p" ] || continue
  size=$(/usr/bin/python3 -c "import struct,sys; d=open(sys.argv[1],'rb').read(24); print('%dx%d' % struct.unpack('>II', d[16:24]))" "$T/work/$p")
  check "$p is 96x54 (got $size)" [ "$size" = 96x54 ]
done <<<"$pngs"
summary
