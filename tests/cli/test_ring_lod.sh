#!/usr/bin/env bash
# Ring LOD from the command line and scene files (docs/ring-lod.md): `fovsim plan` shows
# it only for scenes with foliage to thin, the scene key equals the option, frames say what they
# drew, a folder drawn without it is another configuration, and bad values get one-line errors.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SHARED=${FOVSIM_SHARED:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/ring_lod
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

R=8:1:0,20:1/2:0,*:1/8:0
SMALL=(--width 160 --height 90 --rings "$R")

# ---- plan: the variant and its line only where MASK primitives hold card aggregates
"$BIN" plan forest "${SMALL[@]}" --ring-lod simplify >"$T/forest.txt" 2>&1
check "forest: the MASK pass compiles RING_LOD" grep -q 'forward.mask\[traditional\].*RING_LOD 1' "$T/forest.txt"
check "forest: the plan says the reduced rings choose u per card" grep -q '^ring LOD   keep fraction u per ring = 1,card,card of the cards of 2 MASK primitives (17856 cards in the scene).*card: each card.s own u = its area in ring pixels' "$T/forest.txt"
"$BIN" plan forest "${SMALL[@]}" --ring-lod simplify:1,1/2,1/16 >"$T/forest_u.txt" 2>&1
check "forest, explicit: the plan names each ring's keep fraction" grep -q '^ring LOD   keep fraction u per ring = 1,0.5,0.0625 of the cards' "$T/forest_u.txt"
"$BIN" plan forest "${SMALL[@]}" >"$T/forest_off.txt" 2>&1
check "forest without --ring-lod: no variant, no line" bash -c "! grep -q 'RING_LOD\|ring LOD' '$T/forest_off.txt'"
"$BIN" plan fence "${SMALL[@]}" --ring-lod simplify >"$T/fence.txt" 2>&1
check "fence (one card): nothing compiled, and the plan says why" bash -c "! grep -q RING_LOD '$T/fence.txt' && grep -q 'ring LOD (no MASK primitive has 16 or more cards)' '$T/fence.txt'"
"$BIN" plan "$SHARED/assets/quaternius_megakit_set_a/Grass_Wispy_Tall.gltf" "${SMALL[@]}" --ring-lod simplify >"$T/opaque.txt" 2>&1
check "a scene without MASK materials compiles nothing new" bash -c "! grep -q RING_LOD '$T/opaque.txt' && grep -q 'ring LOD (no MASK primitive' '$T/opaque.txt'"
"$BIN" plan forest --width 160 --height 90 --rings off --ring-lod simplify >"$T/fine.txt" 2>&1
check "foveation off (one full-resolution ring) keeps every card: nothing compiled" bash -c "! grep -q RING_LOD '$T/fine.txt' && grep -q 'ring LOD (every ring keeps all cards)' '$T/fine.txt'"

# ---- the scene key equals the option; the frames carry the keep fractions; u = 1 is no LOD
sed 's/^{/{"ring_lod": "simplify",/' "$(dirname "$0")/../../scenes/builtin/forest.json" >"$T/forest_lod.json"
"$BIN" render forest "${SMALL[@]}" --alpha hashed --frames 2 --ring-lod simplify --out "$T/opt" >/dev/null 2>&1
"$BIN" render "$T/forest_lod.json" "${SMALL[@]}" --alpha hashed --frames 2 --out "$T/key" >/dev/null 2>&1
check "the scene's \"ring_lod\" draws what --ring-lod draws" bash -c "idiff -q '$T/opt/frame.0001.exr' '$T/key/frame.0001.exr' >/dev/null"
check "the scene's key compiles RING_LOD, and --ring-lod off overrides it" bash -c "'$BIN' plan '$T/forest_lod.json' ${SMALL[*]} | grep -q RING_LOD && ! '$BIN' plan '$T/forest_lod.json' ${SMALL[*]} --ring-lod off | grep -q RING_LOD"
check "frames name the keep fractions (fovsim:ring_lod_u)" bash -c "oiiotool --info -v '$T/opt/frame.0000.exr' | grep -q 'fovsim:ring_lod_u: \"1,card,card\"'"
check "the record names the option" grep -q '^ring lod: simplify$' "$T/opt/fovsim-run.txt"
"$BIN" render forest "${SMALL[@]}" --alpha hashed --frames 2 --out "$T/plain" >/dev/null 2>&1
"$BIN" render forest "${SMALL[@]}" --alpha hashed --frames 2 --ring-lod simplify:1,1,1 --out "$T/ones" >/dev/null 2>&1
check "u = 1 in every ring: the same pixels as no ring LOD" bash -c "idiff -q '$T/plain/frame.0001.exr' '$T/ones/frame.0001.exr' >/dev/null"
check "simplify: other pixels than no ring LOD" bash -c "! idiff -q '$T/plain/frame.0001.exr' '$T/opt/frame.0001.exr' >/dev/null 2>&1"
expect_exit "a folder drawn without ring LOD is another configuration" 2 "$BIN" render forest "${SMALL[@]}" --alpha hashed --frames 2 --ring-lod simplify --out "$T/plain" --resume
check "... and the message names the setting" grep -q "ring lod: 'simplify' now, 'default' there" "$T/err.txt"

# ---- bad values: one line naming the option or the JSON key, exit 2 / 3
expect_exit "--ring-lod with a keep fraction per ring missing -> 2" 2 "$BIN" plan forest "${SMALL[@]}" --ring-lod simplify:1,1/2
check "... says how many it expected" grep -q -- '--ring-lod: ring LOD: 2 keep fractions for 3 rings (expected one per ring)' "$T/err.txt"
expect_exit "--ring-lod simplify:0 -> 2" 2 "$BIN" plan forest "${SMALL[@]}" --ring-lod simplify:1,1,0
expect_exit "--ring-lod sometimes -> 2" 2 "$BIN" plan forest "${SMALL[@]}" --ring-lod sometimes
printf '{"ring_lod": 3, "assets": [{"name": "f", "generator": "fence"}], "instances": [{"asset": "f"}]}' >"$T/num.json"
expect_exit "\"ring_lod\": 3 -> 3" 3 "$BIN" plan "$T/num.json"
check "... names the key" grep -q 'num.json: ring_lod' "$T/err.txt"
printf '{"ring_lod": "simplify:2", "assets": [{"name": "f", "generator": "fence"}], "instances": [{"asset": "f"}]}' >"$T/two.json"
expect_exit "\"ring_lod\": \"simplify:2\" -> 3" 3 "$BIN" plan "$T/two.json"
check "... names the key and what was expected" grep -q 'two.json: ring_lod: expected "off", "simplify", "simplify:area=A" or "simplify:U1,U2,..."' "$T/err.txt"
sed 's/^{/{"ring_lod": "simplify:1,1",/' "$(dirname "$0")/../../scenes/builtin/forest.json" >"$T/count.json"
expect_exit "a scene's keep fractions that do not match the rings -> 2" 2 "$BIN" plan "$T/count.json" "${SMALL[@]}"
check "... names the scene and ring_lod" grep -q 'count.json: ring_lod: ring LOD: 2 keep fractions for 3 rings' "$T/err.txt"
summary
