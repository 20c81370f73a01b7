#!/usr/bin/env bash
# The alpha LOD clamp from the command line and the scene file (docs/hashed-alpha.md "Alpha LOD
# clamp"): bad values are one-line errors naming the option or the JSON path; `fovsim plan` shows
# the ALPHA_LOD_CLAMP variant only when a material has a clamp; the run record and the EXR header
# say which clamp drew the frames.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
SHARED=${FOVSIM_SHARED:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/alpha_lod
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
KIT=$(cd "$SHARED/assets/quaternius_megakit_set_a" && pwd)
scene() { # FILE [MATERIALS-JSON]: 3 Clover_1 at 20 m, 32x18
  printf '{"display": {"width": 32, "height": 18, "hfov": 90}, "assets": [{"name": "c", "gltf": "%s/Clover_1.gltf"}],
 "instances": [{"asset": "c", "scatter": {"count": 3, "seed": 1, "min": [-3, 0, -22], "max": [3, 2, -18]}}],
 "camera": [{"time": 0, "position": [0, 1, 0], "target": [0, 1, -20]}]%s}\n' "$KIT" "${2:+, \"materials\": $2}" >"$1"
}
scene "$T/plain.json"

# ---- bad values: exit 2 (usage), one line naming the option and what it expects
for v in -1 16.5 abc 4x nan inf 1e400 ''; do
  expect_exit "--alpha-lod-max '$v' -> 2" 2 "$BIN" render "$T/plain.json" --frames 1 --alpha-lod-max "$v" --out "$T/bad"
  check "--alpha-lod-max '$v' says what it expects" grep -q "alpha-lod-max: expected a mip level in \[0, 16\] or off, got '$v'" "$T/err.txt"
done
check "bad --alpha-lod-max creates nothing" test ! -e "$T/bad"
# ---- in the scene file: exit 3, the JSON path
for v in 17 -0.5 '"4"' true null; do
  scene "$T/badmat.json" "{\"Leaves\": {\"alpha_lod_max\": $v}}"
  expect_exit "materials.Leaves.alpha_lod_max $v -> 3" 3 "$BIN" plan "$T/badmat.json"
  check "alpha_lod_max $v: the message names the path and the range" \
    grep -q "badmat.json: materials.Leaves.alpha_lod_max: expected a number in \[0, 16\]" "$T/err.txt"
done

# ---- the plan: the variant only where a material has a clamp
"$BIN" plan "$T/plain.json" >"$T/plan_none.txt" 2>&1
check "no clamp asked: no ALPHA_LOD_CLAMP variant" bash -c "! grep -q 'ALPHA_LOD_CLAMP\|alpha LOD' '$T/plan_none.txt'"
"$BIN" plan "$T/plain.json" --alpha-lod-max 4 >"$T/plan_cli.txt" 2>&1
check "--alpha-lod-max 4: the MASK pass compiles ALPHA_LOD_CLAMP" grep -q "forward.mask\[traditional\].*ALPHA_LOD_CLAMP 1" "$T/plan_cli.txt"
check "--alpha-lod-max 4: the plan names the material and level" grep -q "^alpha LOD .*: Leaves 4;" "$T/plan_cli.txt"
scene "$T/mat.json" '{"Leaves": {"alpha_lod_max": 5.5}}'
"$BIN" plan "$T/mat.json" --alpha hashed >"$T/plan_mat.txt" 2>&1
check "material alpha_lod_max 5.5: the hashed pass compiles it" grep -q "forward.mask\[hashed\].*ALPHA_LOD_CLAMP 1" "$T/plan_mat.txt"
check "material alpha_lod_max 5.5: named in the plan" grep -q "^alpha LOD .*: Leaves 5.5;" "$T/plan_mat.txt"
"$BIN" plan "$T/mat.json" --alpha-lod-max 3 >"$T/plan_both.txt" 2>&1
check "the material's own clamp wins over --alpha-lod-max" grep -q "^alpha LOD .*: Leaves 5.5;" "$T/plan_both.txt"
"$BIN" plan "$T/mat.json" --alpha-lod-max off >"$T/plan_off.txt" 2>&1
check "--alpha-lod-max off: no variant, the scene's neither" bash -c "! grep -q 'ALPHA_LOD_CLAMP\|alpha LOD' '$T/plan_off.txt'"

# ---- the run record and the EXR header
"$BIN" render "$T/plain.json" --frames 1 --quiet --alpha-lod-max 4 --out "$T/r4" >/dev/null 2>&1
check "the run record has the clamp" grep -qx "alpha lod max: 4" "$T/r4/fovsim-run.txt"
check "the EXR header has the clamp" grep -qa "fovsim:alpha_lod_max" "$T/r4/frame.0000.exr"
check "... and names the material and level" grep -qa "Leaves 4" "$T/r4/frame.0000.exr"
"$BIN" render "$T/plain.json" --frames 1 --quiet --out "$T/r0" >/dev/null 2>&1
check "without a clamp, neither" bash -c "! grep -q 'alpha lod max' '$T/r0/fovsim-run.txt' && ! grep -qa 'fovsim:alpha_lod_max' '$T/r0/frame.0000.exr'"
expect_exit "another clamp in the same folder is another configuration -> refused" 2 \
  "$BIN" render "$T/plain.json" --frames 1 --quiet --alpha-lod-max 5 --out "$T/r4"

summary
