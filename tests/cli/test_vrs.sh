#!/usr/bin/env bash
# VRS foveation, part 1 (docs/foveation.md "Variable-rate shading (VRS): the rate map"): `fovsim
# plan --foveation vrs` prints the rate map's shares and ideal saving, the scene keys equal the
# options, the commands that do not draw VRS yet refuse it in one line, --foveation off is --rings
# off, and bad values get one-line errors.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/vrs
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
FOREST="$(dirname "$0")/../../scenes/builtin/forest.json"

# ---- plan: shares per rate that sum to 100 %, the saving, the tile grid, the rings beside it
"$BIN" plan forest --foveation vrs >"$T/plan.txt" 2>&1
check "plan names the tile grid" grep -q '^foveation  vrs: .* per 16 x 16 tile (80 x 45 tiles)' "$T/plan.txt"
check "plan prints the auto map's shares: 1x1 at the centre, 4x4 outside" \
  bash -c "grep -Eq '^  1x1 +[0-9.]+ % of display pixels' '$T/plan.txt' && grep -Eq '^  4x4 +[0-9.]+ % of display pixels' '$T/plan.txt'"
sum=$(awk '/^  [124]x[124] +[0-9.]+ % of display pixels/ {s += $2} END {printf "%.1f", s}' "$T/plan.txt")
check "the shares sum to 100 % (got $sum)" bash -c "awk 'BEGIN {exit !($sum >= 99.6 && $sum <= 100.4)}'"
check "plan prints the ideal saving and the rings' beside it" \
  bash -c "grep -Eq 'ideal shading saving [0-9.]+ %' '$T/plan.txt' && grep -Eq 'the rings would shade [0-9.]+ %' '$T/plan.txt'"
"$BIN" plan forest --foveation vrs --vrs '10:1x1,*:4x4' --vrs-tile 32 >"$T/explicit.txt" 2>&1
check "an explicit map: its bands, its tile, only its rates" \
  bash -c "grep -q '^vrs        10:1x1,\*:4x4, gaze' '$T/explicit.txt' && grep -q '32 x 32 tile (40 x 23 tiles)' '$T/explicit.txt' && [ \$(grep -Ec '^  [124]x[124] +[0-9.]+ %' '$T/explicit.txt') -eq 2 ]"
"$BIN" plan forest --foveation vrs --vrs '*:4x4' >"$T/all4.txt" 2>&1
check "all 4x4 saves 15/16" grep -q 'ideal shading saving 93.8 %' "$T/all4.txt"
"$BIN" plan forest >"$T/rings.txt" 2>&1
check "without --foveation vrs the plan has no VRS lines" bash -c "! grep -q '^vrs\|^foveation' '$T/rings.txt'"

# ---- the scene keys equal the options
sed 's/^{/{"foveation": "vrs", "vrs": "10:1x1,*:4x4", "vrs_tile": 32,/' "$FOREST" >"$T/forest_vrs.json"
"$BIN" plan "$T/forest_vrs.json" | grep -v '^scene ' >"$T/key.txt" 2>&1
grep -v '^scene ' "$T/explicit.txt" >"$T/explicit_noscene.txt"
check "the scene's foveation, vrs and vrs_tile print what the options do" diff "$T/key.txt" "$T/explicit_noscene.txt"

# ---- the commands that do not draw VRS yet refuse it in one line, exit 2 (render and compare draw
# it: test_vrs_shade.sh; plain bench: test_vrs_counts.sh; bench --accuracy: test_vrs_accuracy.sh)
expect_exit "bench --calibrate --foveation vrs refuses" 2 "$BIN" bench forest --calibrate --foveation vrs --frames 1
check "  ... saying which commands draw it" grep -q 'VRS is drawn by render, compare, bench (and --accuracy) and a sweep manifest.s .rings.: .vrs.; this command does not draw it' "$T/err.txt"
expect_exit "demo --foveation vrs refuses" 2 "$BIN" demo --foveation vrs --frames 1 --out "$T/d"
check "  ... and writes nothing" test ! -e "$T/d"
expect_exit "a scene with \"foveation\": \"vrs\" refuses to bench --calibrate" 2 "$BIN" bench "$T/forest_vrs.json" --calibrate --frames 1
check "  ... naming the scene's key" grep -q 'forest_vrs.json: "foveation": "vrs": VRS is drawn by render, compare, bench' "$T/err.txt"
check "--rings on the command line chooses rings over the scene's \"foveation\": \"vrs\"" \
  bash -c "'$BIN' plan '$T/forest_vrs.json' --rings aggressive >'$T/over.txt' && grep -q '^rings      aggressive' '$T/over.txt' && ! grep -q '^vrs' '$T/over.txt'"

# ---- --foveation off is --rings off
"$BIN" plan forest --foveation off >"$T/off.txt" 2>&1
"$BIN" plan forest --rings off >"$T/rings_off.txt" 2>&1
check "plan: --foveation off prints what --rings off does" diff "$T/off.txt" "$T/rings_off.txt"
"$BIN" render forest --width 160 --height 90 --frames 1 --foveation off --out "$T/fo" >/dev/null 2>&1
"$BIN" render forest --width 160 --height 90 --frames 1 --rings off --out "$T/ro" >/dev/null 2>&1
check "render: --foveation off draws what --rings off draws" bash -c "idiff -q '$T/fo/frame.0000.exr' '$T/ro/frame.0000.exr' >/dev/null"
check "the run record names --foveation" grep -q '^foveation: off, vrs: default, vrs tile: 0$' "$T/fo/fovsim-run.txt"
sed 's/^{/{"foveation": "off",/' "$FOREST" >"$T/forest_off.json"
check "the scene's \"foveation\": \"off\" is rings off, and --foveation rings overrides it" \
  bash -c "'$BIN' plan '$T/forest_off.json' | grep -q '^rings      off' && '$BIN' plan '$T/forest_off.json' --foveation rings | grep -q '^rings      auto'"

# ---- bad values: one line each
expect_exit "--vrs with a rate that does not exist" 2 "$BIN" plan forest --foveation vrs --vrs '10:3x3,*:4x4'
check "  ... names the band and the rate" grep -q "^.*--vrs: band 1: rate '3x3' is not one of" "$T/err.txt"
expect_exit "--vrs with unsorted borders" 2 "$BIN" plan forest --foveation vrs --vrs '25:1x1,10:2x2,*:4x4'
expect_exit "--vrs without '*'" 2 "$BIN" plan forest --foveation vrs --vrs '10:1x1,25:2x2'
expect_exit "--vrs-tile 12" 2 "$BIN" plan forest --foveation vrs --vrs-tile 12
check "  ... lists the sizes" grep -q "vrs-tile: expected 8, 16 or 32, got '12'" "$T/err.txt"
expect_exit "--foveation ring (misspelt)" 2 "$BIN" plan forest --foveation ring
expect_exit "--foveation off with a ring layout" 2 "$BIN" plan forest --foveation off --rings auto
expect_exit "--vrs with --foveation rings" 2 "$BIN" plan forest --foveation rings --vrs auto
sed 's/^{/{"vrs": "10:1x1",/' "$FOREST" >"$T/bad_vrs.json"
expect_exit "a scene's bad \"vrs\": exit 3, naming the key" 3 "$BIN" plan "$T/bad_vrs.json"
check "  ... and the band" grep -q 'vrs.*band 1.*last band' "$T/err.txt"
sed 's/^{/{"vrs_tile": 24,/' "$FOREST" >"$T/bad_tile.json"
expect_exit "a scene's bad \"vrs_tile\"" 3 "$BIN" plan "$T/bad_tile.json"
sed 's/^{/{"foveation": "off", "rings": "auto",/' "$FOREST" >"$T/bad_off.json"
expect_exit "a scene's \"foveation\": \"off\" with \"rings\": \"auto\"" 3 "$BIN" plan "$T/bad_off.json"
summary
