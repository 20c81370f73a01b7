#!/usr/bin/env bash
# End-to-end tests of the fovsim binary: help, render, plan, the EXR files it writes (read by tools
# nobody here wrote: exrheader, exrinfo, oiiotool), and what bad input does (one-line message,
# distinct exit status, nothing left in the output directory).
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SHARED=${FOVSIM_SHARED:?set by CMake}
SRC=${FOVSIM_SOURCE:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/cli
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

# ---- help and version
check "help lists commands" bash -c "'$BIN' --help | grep -q 'render' && '$BIN' --help | grep -q 'bench'"
check "render --help lists options" bash -c "'$BIN' render --help | grep -q -- '--frames'"
check "version" bash -c "'$BIN' --version | grep -Eq '^fovsim [0-9]+\.[0-9]+\.[0-9]+$'"

# ---- render writes a complete, readable sequence
R="$T/render"
"$BIN" render --builtin forest --frames 3 --width 96 --height 54 --out "$R" --quiet >"$T/render.txt" 2>&1
check "render exits 0" test $? -eq 0
check "render writes 3 frames" test -f "$R/frame.0000.exr" -a -f "$R/frame.0001.exr" -a -f "$R/frame.0002.exr" -a ! -e "$R/frame.0003.exr"
check "no temporary files left" test -z "$(find "$R" -name '*.tmp*')"
check "render reports where" grep -q "$R/frame" "$T/render.txt"
check "exrheader reads it" bash -c "exrheader '$R/frame.0001.exr' | grep -q 'fovsim:renderer'"
check "exrheader: ZIP, half" bash -c "exrheader '$R/frame.0001.exr' | grep -qi 'zip' && exrheader '$R/frame.0001.exr' | grep -q 'coverage, 16-bit floating-point'"
check "exrinfo reads it" exrinfo_reads "$R/frame.0001.exr" "'coverage': half"
check "oiiotool --info -v" bash -c "oiiotool --info -v '$R/frame.0001.exr' | grep -q 'fovsim:frame: 1'"
oiiotool --stats "$R/frame.0002.exr" >"$T/stats.txt" 2>&1
check "oiiotool --stats: no NaN" bash -c "grep 'NanCount' '$T/stats.txt' | grep -Eq 'NanCount: 0 0 0 0 0 *$'"
check "oiiotool --stats: no Inf" bash -c "grep 'InfCount' '$T/stats.txt' | grep -Eq 'InfCount: 0 0 0 0 0 *$'"
check "channels R G B A coverage" bash -c "oiiotool --info -v '$R/frame.0000.exr' | grep -q 'channel list: A, B, coverage, G, R\|channel list: R, G, B, A, coverage'"

# ---- foveation: rings around a replayed gaze trace
F="$T/fov"
"$BIN" render --builtin forest --frames 4 --fps 2 --width 160 --height 90 --rings "10:1:0,25:1/2:0,*:1/4:0.5" \
  --gaze "$SRC/gaze_paths/fixation_saccade.csv" --debug-channels --out "$F" --quiet >/dev/null 2>"$T/err.txt"
check "foveated render exits 0" test $? -eq 0
check "debug channels written" bash -c "oiiotool --info -v '$F/frame.0003.exr' | grep -q 'ring.id'"
check "rings recorded in the header" bash -c "exrheader '$F/frame.0000.exr' | grep -q '10:1:0,25:1/2:0,\*:1/4:0.5'"
check "gaze recorded in the header" bash -c "exrheader '$F/frame.0000.exr' | grep -q 'fovsim:gaze_trace.*fixation_saccade.csv'"
printf 't,x,y\n0,0.5,0.5\n0.5,0.6,0.5\n' >"$T/short.csv"
"$BIN" render --builtin fence --frames 30 --width 64 --height 36 --gaze "$T/short.csv" --out "$T/short" --quiet >/dev/null 2>"$T/err.txt"
check "short trace: still renders" test $? -eq 0
check "short trace: said once" test "$(grep -c 'ends at 0.50 s' "$T/err.txt")" -eq 1
check "plan prints the rings" bash -c "'$BIN' plan forest | grep -q 'ring 0' && '$BIN' plan forest | grep -q 'ideal speedup'"
check "plan --rings off" bash -c "'$BIN' plan forest --rings off | grep -q 'rings      off'"
# The acuity margin (docs/foveation.md "Layouts"): the auto layout's blocks never exceed MAR at their
# ring's inner edge, for any gaze; an explicit layout that does is reported, not refused.
check "plan: the auto layout's acuity margin" bash -c "'$BIN' plan forest | grep -q 'acuity     margin 1.000x: blocks span at most 1.000x the MAR'"
check "plan: an explicit layout coarser than acuity says by how much" bash -c "'$BIN' plan forest --rings \"5.689322:1:0,11.726324:1/2:0,21.719414:1/4:0,34.564426:1/8:0,*:1/16:0\" | grep -q \"margin 0.678x: ring 4's blocks span up to 1.475x the MAR at its inner edge for some gazes, coarser than the acuity model by 47 %\""
expect_exit "bad --rings -> 2" 2 "$BIN" render --rings "10:1:0,5:1/2:0,*:1/4:0" --out "$T/bad9"
check "bad rings create nothing" test ! -e "$T/bad9"
printf 't,x,y\n0,0.5,0.5\n1,abc,0.5\n' >"$T/badgaze.csv"
expect_exit "bad gaze trace -> 5" 5 "$BIN" render --gaze "$T/badgaze.csv" --out "$T/bad10"
check "bad gaze names file:line:column" grep -q "badgaze.csv:3:2:" "$T/err.txt"
check "bad gaze creates nothing" test ! -e "$T/bad10"
expect_exit "missing gaze file -> 6" 6 "$BIN" render --gaze "$T/nope.csv" --out "$T/bad11"
expect_exit "--eye without --gaze -> 2" 2 "$BIN" render --eye left --out "$T/bad12"
"$BIN" bench --builtin fence --frames 3 --warmup 1 --width 160 --height 90 --rings "10:1:0,*:1/4:0" --format json >"$T/bench.json" 2>/dev/null
check "bench --format json is JSON with the speedup" python3 -c "
import json,sys; j=json.load(open('$T/bench.json')); c=j['configs']
assert len(c)==2 and c[0]['shaded_pixels']==160*90 and 0<c[1]['shaded_pixels']<160*90, c
assert j['ideal_speedup']>1 and j['speedup']>0 and 'achieved_fraction_of_ideal' in j"
# Work and process counters (docs/benchmarks.md, "What bench reports"): llvmpipe has
# GL_ARB_pipeline_statistics_query, so every count is an integer >= 0 and the stages add up to the frame;
# on the forest the foveated rings shade fewer fragments than full resolution; without the extension
# (FOVSIM_NO_PIPELINE_STATS) the counts are -1 / n/a, never 0.
check "bench JSON: counters of the fence" python3 "$SRC/tests/cli/check_bench_json.py" "$T/bench.json" known
"$BIN" bench --builtin forest --frames 2 --warmup 1 --width 160 --height 90 --rings "10:1:0,*:1/4:0" --format json >"$T/bench_forest.json" 2>/dev/null
check "bench JSON: forest counters, foveation shades fewer fragments" python3 "$SRC/tests/cli/check_bench_json.py" "$T/bench_forest.json" known --foveation-saves-fragments
FOVSIM_NO_PIPELINE_STATS=1 "$BIN" bench --builtin fence --frames 2 --warmup 1 --width 160 --height 90 --format json >"$T/bench_nostats.json" 2>/dev/null
check "bench JSON: counts unknown (-1) without the extension" python3 "$SRC/tests/cli/check_bench_json.py" "$T/bench_nostats.json" unknown
# Ring culling (docs/foveation.md): rings skip instances only their hole would show, so they draw
# fewer than with --ring-cull off, and fewer primitives; the same frames. Four rings (the auto layout
# at 320x180 before 2026-12-01's auto layout; the acuity-safe auto layout has two on so coarse a display).
BENCH_RINGS=21.719414:1:0,34.564426:1/2:0,47.247437:1/4:0,*:1/8:0
for c in on off; do
  "$BIN" bench --builtin forest --frames 2 --warmup 0 --width 320 --height 180 --taa off --ring-cull $c \
    --rings "$BENCH_RINGS" --format json >"$T/bench_cull_$c.json" 2>/dev/null
done
check "bench: rings cull what only their hole shows (fewer instances and primitives than --ring-cull off)" python3 -c "
import json; on, off = [json.load(open('$T/bench_cull_%s.json' % c))['configs'][1] for c in ('on', 'off')]
print('instances per ring', on['ring_instances_median'], 'vs', off['ring_instances_median'])
assert len(on['ring_instances_median']) > 2 and sum(on['ring_instances_median']) < sum(off['ring_instances_median'])
assert all(a <= b for a, b in zip(on['ring_instances_median'], off['ring_instances_median']))
assert on['primitives']['all_frames'] < off['primitives']['all_frames']"
# Ring LOD (docs/ring-lod.md): with --ring-lod bench adds "foveated + ring LOD" next to "foveated"
# per mode (the plain rings drawn without it), over the same frames, and their ratios per stage.
# Counts, not times: rings with u = 1 do exactly the same work in both; a simplified ring draws at
# least as many instances (its culling bounds hold the enlarged cards) and, on llvmpipe, shades
# fewer fragments in the outermost ring (u = 1/16: a sixteenth of the sub-pixel cards, each a
# 4x4 block there); check_bench_json.py. Without ring LOD nothing of it appears (the same script on
# the runs above).
"$BIN" bench --builtin forest --frames 2 --warmup 0 --width 320 --height 180 --taa off --modes traditional,hashed \
  --rings "$BENCH_RINGS" --ring-lod simplify:1,1,1/4,1/16 --format json >"$T/bench_lod.json" 2>/dev/null
check "bench --ring-lod: foveated + ring LOD beside foveated, same frames, u = 1 rings unchanged, outer ring cheaper" \
  python3 "$SRC/tests/cli/check_bench_json.py" "$T/bench_lod.json" known --ring-lod 1,1,0.25,0.0625
"$BIN" bench --builtin forest --frames 1 --warmup 0 --width 320 --height 180 --taa off --rings "$BENCH_RINGS" \
  --ring-lod simplify:1,1,1/2,1/8 >"$T/bench_lod.txt" 2>/dev/null
check "bench text with ring LOD: its rows and the table of ratios" bash -c "grep -q '^### builtin:forest, 320x180, alpha traditional, rings .*, ring LOD simplify:1,1,0.5,0.125 (u = 1,1,0.5,0.125)' '$T/bench_lod.txt' && grep -Eq '^\| traditional, foveated \+ ring LOD \| frame, wall clock incl. finish \(ms\) \| [0-9.]+ \|' '$T/bench_lod.txt' && grep -q '^Ring LOD against the same rings without it' '$T/bench_lod.txt' && grep -Eq '^\| traditional, foveated \+ ring LOD \| ring 3 \(1/8, all passes\) \| [0-9.]+ \| [0-9.]+ \| [0-9.]+x \| [0-9]+ \| [0-9]+ \| [0-9.]+x \| [0-9]+ \| [0-9]+ \| [0-9.]+x \| [0-9]+ \| [0-9]+ \|$' '$T/bench_lod.txt' && grep -Eq '^\| traditional, foveated \+ ring LOD \| \*\*frame, process CPU time\*\* \| [0-9.]+ \| [0-9.]+ \| [0-9.]+x \|' '$T/bench_lod.txt'"
"$BIN" bench --builtin fence --frames 1 --warmup 0 --width 160 --height 90 --rings "10:1:0,*:1/4:0" --ring-lod simplify \
  --format json >"$T/bench_lod_fence.json" 2>"$T/bench_lod_fence.err"
check "bench --ring-lod on a scene without card aggregates: not measured, says why" bash -c "grep -q 'ring LOD not measured (no MASK primitive has 16 or more cards)' '$T/bench_lod_fence.err' && python3 -c \"
import json; j = json.load(open('$T/bench_lod_fence.json')); assert len(j['configs']) == 2 and j['ring_lod'] == 'off'\""
expect_exit "--ring-cull maybe -> 2" 2 "$BIN" plan forest --ring-cull maybe
check "--ring-cull says what it expects" grep -q "ring-cull: expected on or off" "$T/err.txt"
expect_exit "--composite blurry -> 2" 2 "$BIN" plan forest --composite blurry
check "--composite says what it expects" grep -q "composite: expected tiled or per-pixel" "$T/err.txt"
check "plan: the composite draws tiles of one ring" bash -c "'$BIN' plan forest | grep -q 'COMPOSITE_TILE'"
check "plan: --composite per-pixel searches everywhere" bash -c "'$BIN' plan forest --composite per-pixel | grep -q 'every pixel searches its ring'"
"$BIN" bench --builtin fence --frames 2 --warmup 1 --width 160 --height 90 --rings off >"$T/bench.txt" 2>/dev/null
check "bench text: CPU time, page faults and work rows" bash -c "grep -Eq '^\| traditional, full resolution \| frame, process CPU time, all threads \(ms\) \| [0-9.]+ \|' '$T/bench.txt' && grep -Eq '\| frame, minor page faults \| [0-9]+ \|' '$T/bench.txt' && grep -Eq '\| frame, fragment shader invocations \| [0-9]+ \|' '$T/bench.txt' && grep -Eq '^\| traditional, full resolution \| forward.mask\[traditional\] \| [0-9]+ \| [0-9]+ \| [0-9]+ \| [0-9]+ \| [0-9]+ \| [0-9]+ \| [0-9]+ \| [0-9]+ \| [0-9.]+ \|$' '$T/bench.txt'"
FOVSIM_NO_PIPELINE_STATS=1 "$BIN" bench --builtin fence --frames 2 --warmup 1 --width 160 --height 90 --rings off >"$T/bench_nostats.txt" 2>/dev/null
check "bench text: n/a counts without the extension" bash -c "grep -q 'frame, fragment shader invocations | n/a | n/a' '$T/bench_nostats.txt' && grep -q 'forward.mask\[traditional\] | n/a | n/a | n/a |' '$T/bench_nostats.txt' && ! grep -Eq 'invocations \| 0 \|' '$T/bench_nostats.txt'"

"$BIN" render fence --gaze builtin:pursuit_circle --frames 2 --width 64 --height 36 --out "$T/bgaze" --quiet >/dev/null 2>&1
check "built-in gaze trace" bash -c "exrheader '$T/bgaze/frame.0001.exr' | grep -q 'builtin:pursuit_circle'"
expect_exit "unknown built-in gaze -> 6" 6 "$BIN" render --gaze builtin:nope --out "$T/bad13"
check "unknown built-in gaze lists the valid ones" grep -q "fixation_saccade" "$T/err.txt"

# ---- the demo (small): built-in forest, built-in tour trace, traditional vs hashed, instructions printed
"$BIN" demo --width 96 --height 54 --frames 3 --samples 2 --supersample 1 --cache "$T/cache" --out "$T/demo" --quiet >"$T/demo.txt" 2>&1
check "demo exits 0 and says how to look" bash -c "grep -q 'oiiotool' '$T/demo.txt' && test -f '$T/demo/compare.0002.exr'"
check "demo follows the tour trace" bash -c "exrheader '$T/demo/compare.0000.exr' | grep -q 'builtin:demo_tour'"
check "demo compares traditional and hashed" bash -c "grep -q '^traditional' '$T/demo.txt' && grep -q '^hashed' '$T/demo.txt' && test -f '$T/demo/metrics.csv' && test -f '$T/demo/summary.json'"

# ---- TAA settings: CLI, scene file, and the CLI winning over the scene
printf '{"assets": [{"name": "f", "generator": "fence"}], "instances": [{"asset": "f"}], "camera": [{"time": 0, "position": [0,1,5], "target": [0,1,0]}, {"time": 1, "position": [0,1,9], "target": [0,1,0]}], "taa": {"blend": 0.25, "gamma": 1.5, "sparse": 0.4, "jitter_length": 8}}' >"$T/taa.json"
check "scene file sets TAA controls" bash -c "'$BIN' plan '$T/taa.json' --alpha hashed | grep -q 'blend 0.25, gamma 1.50, sparse coverage kept within 0.40 of each pixel.s sample, Halton(2,3) jitter of 8 frames; reprojection through depth'"
check "CLI --taa-blend wins" bash -c "'$BIN' plan '$T/taa.json' --taa-blend 0.05 | grep -q 'blend 0.05'"
check "CLI --taa-sparse off wins" bash -c "'$BIN' plan '$T/taa.json' --alpha hashed --taa-sparse off | grep -q 'no sparse-coverage rule (off)'"
check "default sparse-coverage rule" bash -c "'$BIN' plan --builtin fence --frames 4 --alpha stochastic | grep -q 'sparse coverage kept within 0.95 of each pixel.s sample'"
check "the sparse-coverage rule for traditional too" bash -c "'$BIN' plan --builtin fence --frames 4 | grep -q 'sparse coverage kept within 0.95'"
check "disocclusion test where the camera moves" bash -c "'$BIN' plan --builtin fence --frames 4 | grep -q 'history whose nearest surface moved off the pixel dropped (depth)'"
check "--taa-disocclusion off" bash -c "'$BIN' plan --builtin fence --frames 4 --taa-disocclusion off | grep -q 'no disocclusion test (off)'"
check "no disocclusion test for a still camera" bash -c "! '$BIN' plan --builtin tree --frames 4 | grep -q 'disocclusion'"
expect_exit "--taa-disocclusion maybe -> 2" 2 "$BIN" plan --builtin fence --taa-disocclusion maybe
check "plan shows hashed's frame offset under TAA" bash -c "'$BIN' plan --builtin fence --frames 4 --alpha hashed | grep -q '^hash .*with TAA a golden-ratio offset per frame'"
check "plan shows --no-hash-offset" bash -c "'$BIN' plan --builtin fence --frames 4 --alpha hashed --no-hash-offset | grep -q '^hash .*with TAA no per-frame offset'"
check "the rule for hashed without its frame offset" bash -c "'$BIN' plan --builtin fence --frames 4 --alpha hashed --no-hash-offset | grep -q 'sparse coverage kept within 0.95'"
expect_exit "--taa-sparse 0 -> 2" 2 "$BIN" plan --builtin fence --taa-sparse 0
check "--taa-sparse 0 says what it expects" grep -q "expected off or a number in (0, 1]" "$T/err.txt"
# the resolve's variants (docs/taa.md, "A leaner resolve"): default, each control, and one-line errors
check "default TAA resolve: cross, Catmull-Rom, NaN per tap" bash -c "'$BIN' plan --builtin fence --frames 4 | grep -q 'clip box from the 5-tap cross, Catmull-Rom history, NaN checked per tap'"
check "--taa-neighbourhood 3x3 --taa-history bilinear --taa-nan set" bash -c "'$BIN' plan --builtin fence --frames 4 --taa-neighbourhood 3x3 --taa-history bilinear --taa-nan set | grep -q 'clip box from the 3x3, bilinear history, NaN checked per set of fetches'"
check "--taa-neighbourhood cross --taa-history catmull --taa-nan tap" bash -c "'$BIN' plan --builtin fence --frames 4 --taa-neighbourhood cross --taa-history catmull --taa-nan tap | grep -q 'clip box from the 5-tap cross, Catmull-Rom history, NaN checked per tap'"
"$BIN" render fence --frames 2 --width 64 --height 36 --taa-neighbourhood 3x3 --taa-history bilinear --taa-nan set --out "$T/taavariant" --quiet >/dev/null 2>&1
check "a non-default resolve compiles and renders" test -f "$T/taavariant/frame.0001.exr"
expect_exit "--taa-neighbourhood 4x4 -> 2" 2 "$BIN" plan --builtin fence --taa-neighbourhood 4x4
check "--taa-neighbourhood says what it expects" grep -q "taa-neighbourhood: expected 3x3 or cross, got '4x4'" "$T/err.txt"
expect_exit "--taa-history cubic -> 2" 2 "$BIN" plan --builtin fence --taa-history cubic
check "--taa-history says what it expects" grep -q "taa-history: expected catmull or bilinear, got 'cubic'" "$T/err.txt"
expect_exit "--taa-nan never -> 2" 2 "$BIN" plan --builtin fence --taa-nan never
check "--taa-nan says what it expects" grep -q "taa-nan: expected tap or set, got 'never'" "$T/err.txt"
check "--taa off" bash -c "! '$BIN' plan '$T/taa.json' --taa off | grep -q '^taa'"
printf '{"assets": [{"name": "f", "generator": "fence"}], "instances": [{"asset": "f"}], "taa": {"enabled": false}}' >"$T/notaa.json"
check "scene file turns TAA off" bash -c "! '$BIN' plan '$T/notaa.json' --frames 10 | grep -q '^taa'"
printf '{"assets": [{"name": "f", "generator": "fence"}], "instances": [{"asset": "f"}], "taa": {"blend": 2}}' >"$T/badtaa.json"
expect_exit "bad taa.blend -> 3" 3 "$BIN" plan "$T/badtaa.json"
check "bad taa.blend names the JSON path" grep -q "badtaa.json: taa.blend" "$T/err.txt"
printf '{"assets": [{"name": "f", "generator": "fence"}], "instances": [{"asset": "f"}], "taa": {"sparse": 1.5}}' >"$T/badsparse.json"
expect_exit "bad taa.sparse -> 3" 3 "$BIN" plan "$T/badsparse.json"
check "bad taa.sparse names the JSON path" grep -q "badsparse.json: taa.sparse" "$T/err.txt"
printf '{"assets": [{"name": "f", "generator": "fence"}], "instances": [{"asset": "f"}], "taa": {"sparse": false}}' >"$T/nosparse.json"
check "scene file turns the sparse-coverage margin off" bash -c "'$BIN' plan '$T/nosparse.json' --frames 4 --alpha hashed | grep -q 'no sparse-coverage rule (off)'"

# Wind sway: the plan shows the animation and the per-object motion path, and drops the motion path
# without TAA or with --object-motion off; bad values name the option or the JSON path.
check "plan: wind sways with per-object motion" bash -c "'$BIN' plan builtin:wind --frames 8 | grep -q 'animation  18 of 18 instances sway' && '$BIN' plan builtin:wind --frames 8 | grep -q 'reprojection through depth and per-object motion (instances sway)'"
check "plan: --object-motion off drops the motion path" bash -c "'$BIN' plan builtin:wind --frames 8 --object-motion off | grep -q 'per-object motion (no TAA, or --object-motion off)'"
check "plan: a static scene has no sway" bash -c "'$BIN' plan --builtin forest --frames 8 | grep -q 'sway and per-object motion (no instance sways)'"
expect_exit "--object-motion maybe -> 2" 2 "$BIN" plan builtin:wind --object-motion maybe
check "--object-motion says what it expects" grep -q "object-motion: expected on or off" "$T/err.txt"
printf '{"assets": [{"name": "t", "generator": "tree"}], "instances": [{"asset": "t", "sway": {"amplitude": 0.2, "frequency": -1}}]}' >"$T/badsway.json"
expect_exit "bad sway.frequency -> 3" 3 "$BIN" plan "$T/badsway.json"
check "bad sway.frequency names the JSON path" grep -q "badsway.json: instances\[0\].sway.frequency: expected a number in (0, 100]" "$T/err.txt"

# ---- a glTF file is a scene by itself
"$BIN" render --scene "$SHARED/assets/quaternius_megakit_set_a/Fern_1.gltf" --frames 1 --width 64 --height 64 --out "$T/gltf" --quiet >/dev/null 2>&1
check "render a .gltf directly" test -f "$T/gltf/frame.0000.exr"

# ---- plan
check "plan shows the mask pass" bash -c "'$BIN' plan --builtin fence | grep -q 'forward.mask\[traditional\]'"
check "opaque asset: no alpha variant even with --alpha hashed" bash -c \
  "out=\$('$BIN' plan --scene '$SHARED/assets/quaternius_megakit_set_a/Grass_Wispy_Tall.gltf' --alpha hashed) && echo \"\$out\" | grep -q forward.opaque && ! echo \"\$out\" | grep -q forward.mask"

# ---- bad input: message, distinct exit status, nothing created
expect_exit "unknown option -> 2" 2 "$BIN" render --frams 3 --out "$T/bad1"
long=--$(printf 'x%.0s' {1..80})
expect_exit "an unknown option longer than any -> 2" 2 "$BIN" render "$long=3" --out "$T/bad1"
check "... named whole in its message" grep -qF "unknown option '$long=3'" "$T/err.txt"
check "bad option creates nothing" test ! -e "$T/bad1"
expect_exit "unknown command -> 2" 2 "$BIN" rendr
expect_exit "bad --width -> 2" 2 "$BIN" render --width 10 --height 10 --out "$T/bad2"
printf '{"assets": [ {"name": "t", "generator": "tree"} ], "instances": [ {"asset": "t", "scale": "big"} ]}' >"$T/bad.json"
expect_exit "bad scene value -> 3" 3 "$BIN" render --scene "$T/bad.json" --out "$T/bad3"
check "bad scene creates nothing" test ! -e "$T/bad3"
check "bad scene message names file and JSON path" grep -q "bad.json: instances\[0\].scale" "$T/err.txt"
printf '{"assets": [' >"$T/syntax.json"
expect_exit "JSON syntax error -> 3" 3 "$BIN" render --scene "$T/syntax.json" --out "$T/bad4"
expect_exit "missing scene file -> 6" 6 "$BIN" render --scene "$T/nope.json" --out "$T/bad5"
head -c 200 "$SHARED/assets/polyhaven_fern_02_glb/fern_02.glb" >"$T/trunc.glb"
expect_exit "truncated .glb -> 4" 4 "$BIN" render --scene "$T/trunc.glb" --out "$T/bad6"
check "bad asset creates nothing" test ! -e "$T/bad6"
touch "$T/afile"
expect_exit "output path is a file -> 6" 6 "$BIN" render --frames 1 --width 32 --height 32 --out "$T/afile/x"
expect_exit "unknown alpha mode -> 2" 2 "$BIN" render --builtin fence --alpha hashd --out "$T/bad7"
check "unknown mode creates nothing" test ! -e "$T/bad7"

expect_exit "no such EGL device -> 7" 7 "$BIN" render --gpu 15 --frames 1 --out "$T/bad8"
check "no GL context creates nothing" test ! -e "$T/bad8"

# ---- output paths too long for the file system (README "Exit status"): refused with the other
# arguments (exit 2, one line, nothing drawn or created). The old code rendered, then failed the
# first write with exit 6, a message cut short and an empty folder left behind.
long_name=$(printf 'n%.0s' $(seq 250))
expect_exit "--name of 250 characters -> 2" 2 "$BIN" render --builtin fence --frames 1 --width 32 --height 18 --name "$long_name" --out "$T/bad14"
check "--name too long: the message says the limit" grep -q -- "--name 'nnnn.*(250 characters): expected at most 188 characters" "$T/err.txt"
check "--name too long creates nothing" test ! -e "$T/bad14"
expect_exit "compare --name of 250 characters -> 2" 2 "$BIN" compare fence --frames 1 --width 32 --height 18 --name "$long_name" --out "$T/bad15"
check "compare --name too long creates nothing" test ! -e "$T/bad15"
expect_exit "--out with a 300-character component -> 2" 2 "$BIN" render --builtin fence --frames 1 --out "$T/$(printf 'd%.0s' $(seq 300))/x"
expect_exit "--out of 1100 characters -> 2" 2 "$BIN" render --builtin fence --frames 1 --out "$T/$(printf 'd%.0s/' $(seq 550))"
check "--out too long creates nothing" test -z "$(ls -d "$T"/ddd* "$T"/d 2>/dev/null)"
expect_exit "--cache of 1000 characters -> 2" 2 "$BIN" reference fence --frames 1 --cache "$T/$(printf 'c%.0s/' $(seq 500))"
# The longest --name accepted does write (its temporary names fit in 255 characters).
max_name=$(printf 'm%.0s' $(seq 188))
"$BIN" render --builtin fence --frames 1 --width 32 --height 18 --name "$max_name" --out "$T/maxname" --quiet >/dev/null 2>"$T/err.txt"
check "--name of 188 characters renders" test $? -eq 0 -a -f "$T/maxname/$max_name.0000.exr"

# ---- a rerun tidies the folder (README "Output folders"): the temporary files of killed runs (their
# pid gone) are removed, those of a live process kept, and the frames of an earlier, longer run
# removed, so the folder holds exactly the new sequence. The old code left all of it. Temporary
# names carry the host (`.tmp.<host>.<pid>.<n>`): another host's are kept (a run there
# may be writing them; its pids mean nothing here); names without a host (older fovsim) are
# taken as this host's.
RR="$T/rerun"
"$BIN" render --builtin fence --frames 4 --width 32 --height 18 --out "$RR" --quiet >/dev/null 2>&1
sleep 0 & dead=$!; wait $dead
: >"$RR/.frame.0002.exr.tmp.$dead.0"; : >"$RR/.metrics.csv.tmp.$dead"; : >"$RR/.frame.0003.exr.tmp.$$.1"
host=$(uname -n | tr -c 'A-Za-z0-9\n-' '-')
[ ${#host} -le 32 ] || host="" # longer names are shortened with a hash (out_path_host): not redone here
other=x${host:1}; [ "$other" != "$host" ] || other=y${host:1} # another valid host name
if [ -n "$host" ]; then
  : >"$RR/.frame.0001.exr.tmp.$host.$dead.4"; : >"$RR/.frame.0001.exr.tmp.$other.$dead.5"
fi
"$BIN" render --builtin fence --frames 2 --width 32 --height 18 --out "$RR" --quiet >/dev/null 2>"$T/err.txt"
check "rerun with fewer frames exits 0" test $? -eq 0
check "rerun: frames 0-1 only" test -f "$RR/frame.0000.exr" -a -f "$RR/frame.0001.exr" -a ! -e "$RR/frame.0002.exr" -a ! -e "$RR/frame.0003.exr"
check "rerun: temporary files of dead processes removed" test ! -e "$RR/.frame.0002.exr.tmp.$dead.0" -a ! -e "$RR/.metrics.csv.tmp.$dead"
check "rerun: a live process's temporary file kept" test -e "$RR/.frame.0003.exr.tmp.$$.1"
rm -f "$RR/.frame.0003.exr.tmp.$$.1"
if [ -n "$host" ]; then
  check "rerun: this host's temporary file of a dead process removed" test ! -e "$RR/.frame.0001.exr.tmp.$host.$dead.4"
  check "rerun: another host's temporary file kept" test -e "$RR/.frame.0001.exr.tmp.$other.$dead.5"
  rm -f "$RR/.frame.0001.exr.tmp.$other.$dead.5"
else
  echo "note: host name over 32 characters; the host-named temporary checks did not run" >&2
fi
# kill -9 in the middle of a run, then a rerun: nothing of the killed run's temporaries is left.
"$BIN" render --builtin fence --frames 5000 --width 32 --height 18 --out "$RR" --quiet >/dev/null 2>&1 &
pid=$!
for _ in $(seq 1 100); do [ -e "$RR/frame.0003.exr" ] && break; sleep 0.1; done
kill -KILL "$pid"; wait "$pid" 2>/dev/null
: >"$RR/.frame.0009.exr.tmp.$pid.77" # what a kill during a write leaves (the timing may not hit one)
"$BIN" render --builtin fence --frames 1 --width 32 --height 18 --out "$RR" --quiet >/dev/null 2>&1
check "after kill -9 and a rerun: no temporary file, one frame and the record" bash -c "[ -z \"\$(find '$RR' -name '*.tmp*')\" ] && [ \"\$(ls '$RR' | tr '\n' ' ')\" = 'fovsim-run.txt frame.0000.exr ' ]"
check "after kill -9 and a rerun: the record says complete" grep -qx 'complete: yes' "$RR/fovsim-run.txt"

# ---- Ctrl-C: stops after the frame in flight, exit 130, every file left is complete
"$BIN" render --builtin forest --frames 5000 --width 64 --height 36 --out "$T/int" --quiet >/dev/null 2>"$T/err.txt" &
pid=$!
for _ in $(seq 1 100); do [ -e "$T/int/frame.0002.exr" ] && break; sleep 0.1; done
kill -INT "$pid"; wait "$pid"; rc=$?
check "SIGINT -> exit 130" test $rc -eq 130
check "SIGINT: one line" test "$(wc -l <"$T/err.txt")" -eq 1
check "SIGINT: no temporary file left" test -z "$(find "$T/int" -name '*.tmp*')"
check "SIGINT: stopped early" test ! -e "$T/int/frame.4999.exr"

# ---- a full disk: the run fails with an I/O error and leaves no partial frame
if mkdir -p "$T/full" && mount -t tmpfs -o size=160k tmpfs "$T/full" 2>/dev/null; then
  "$BIN" render --builtin forest --frames 40 --width 128 --height 72 --out "$T/full/seq" --quiet --compression none >/dev/null 2>"$T/err.txt"
  rc=$?
  check "full disk -> exit 6" test $rc -eq 6
  check "full disk: one line naming the file" bash -c "grep -q 'seq/frame\.[0-9]*\.exr: .*No space left' '$T/err.txt' && [ \$(wc -l <'$T/err.txt') -eq 1 ]"
  check "full disk: no temporary file left" test -z "$(find "$T/full" -name '*.tmp*')"
  bad=0
  for f in "$T"/full/seq/*.exr; do [ -e "$f" ] || continue; exrheader "$f" >/dev/null 2>&1 || bad=1; done
  check "full disk: every frame left is complete" test $bad -eq 0
  umount "$T/full"
  # Already full before the first frame (it once deadlocked the writer): the header write failed while the
  # EXR library held its context lock, and the error handler asked it for the user data: a hang
  # (killed by `timeout`, 124/137) with a 0-byte temporary file. Expected: exit 6, one line, nothing
  # left. render writes through the writer thread; reference writes the frame and its cache entry.
  # Two 4 KiB pages are left free: the folder's lock (fovsim-run.lock, naming its holder) and record
  # (fovsim-run.txt), written first, fit, the first frame does not; the record of a run that left
  # no frame is removed again, and the lock with the run.
  mount -t tmpfs -o size=64k tmpfs "$T/full"
  dd if=/dev/zero of="$T/full/filler" bs=4k count=14 2>/dev/null
  mkdir -p "$T/full/seq" "$T/full/cache"
  timeout -s KILL 60 "$BIN" render --builtin fence --frames 2 --width 32 --height 18 --out "$T/full/seq" --quiet >/dev/null 2>"$T/err.txt"
  rc=$?
  check "disk full from the start: render -> exit 6, no hang (exit $rc)" test $rc -eq 6
  check "disk full from the start: render, one line naming a frame" bash -c "grep -q 'seq/frame\.[0-9]*\.exr: cannot write EXR' '$T/err.txt' && [ \$(wc -l <'$T/err.txt') -eq 1 ]"
  [ "$(wc -l <"$T/err.txt")" -eq 1 ] && grep -q 'No space left' "$T/err.txt" || cat -v "$T/err.txt" >&2 # shown when unexpected
  check "disk full from the start: render leaves no file" test -z "$(ls -A "$T/full/seq")"
  timeout -s KILL 60 "$BIN" reference fence --frames 1 --width 32 --height 18 --supersample 1 --cache "$T/full/cache" --out "$T/full/seq" --quiet >/dev/null 2>"$T/err.txt"
  rc=$?
  check "disk full from the start: reference -> exit 6, no hang (exit $rc)" test $rc -eq 6
  check "disk full from the start: reference, one line" test "$(wc -l <"$T/err.txt")" -eq 1
  check "disk full from the start: reference leaves no file" test -z "$(ls -A "$T/full/seq" "$T/full/cache" | grep -v ':$' | grep .)"
  # Wholly full (one page: the lock's): the record cannot be written; exit 6, one line naming it,
  # nothing left.
  dd if=/dev/zero of="$T/full/filler2" bs=4k count=1 2>/dev/null
  timeout -s KILL 60 "$BIN" render --builtin fence --frames 2 --width 32 --height 18 --out "$T/full/seq" --quiet >/dev/null 2>"$T/err.txt"
  rc=$?
  check "disk wholly full: render -> exit 6 (exit $rc)" test $rc -eq 6
  check "disk wholly full: one line naming the record" bash -c "grep -q 'seq/fovsim-run.txt: cannot write: No space left' '$T/err.txt' && [ \$(wc -l <'$T/err.txt') -eq 1 ]"
  check "disk wholly full: render leaves no file" test -z "$(ls -A "$T/full/seq")"
  umount "$T/full"
else
  echo "note: cannot mount a small tmpfs here (not root?); full-disk case not exercised" >&2
fi

summary
