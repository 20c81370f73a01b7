#!/usr/bin/env bash
# fovsim check (docs/check.md): a baseline passes against itself with every
# difference 0; the same options over a changed scene (a tree's alpha cutoff, the tree seen only
# beyond 15 degrees of the gaze) fail with ring 1 named and ring 0 not; tolerances per ring
# override; frame time is judged only with --tol-time; a missing or damaged baseline is one line and its documented exit status, before
# anything is drawn; the JUnit file has the required elements and escapes what it quotes.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/check
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

# A tree right of the display centre (the gaze), beyond the 15-degree ring: ring 0 sees only sky.
scene() {
  cat >"$T/side.json" <<EOF
{
  "comment": "tests/cli/test_check.sh: a tree right of the gaze, beyond 15 degrees; sky elsewhere",
  "display": {"width": 64, "height": 36, "hfov": 90},
  "assets": [{"name": "tree", "generator": "tree", "params": {"alpha_cutoff": $1}}],
  "instances": [{"asset": "tree", "translation": [2.5, 0, 0]}],
  "camera": [{"time": 0, "position": [0, 0.5, 3], "target": [0, 0.5, 0]},
             {"time": 1, "position": [0, 0.5, 3.5], "target": [0, 0.5, 0]}]
}
EOF
}
# junit FILE TESTS FAILURES: the required elements and attributes, and the counts
junit() {
  python3 - "$@" <<'EOF'
import sys, xml.etree.ElementTree as ET
path, tests, failures = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
root = ET.parse(path).getroot()
assert root.tag == "testsuites", root.tag
suites = root.findall("testsuite")
assert len(suites) == 1, suites
s = suites[0]
for a in ("name", "tests", "failures"):
    assert a in s.attrib, a
cases = s.findall("testcase")
assert int(s.get("tests")) == len(cases) == tests, (s.get("tests"), len(cases), tests)
failed = [c for c in cases if c.find("failure") is not None]
assert int(s.get("failures")) == len(failed) == failures, (s.get("failures"), len(failed), failures)
for c in cases:
    assert c.get("name") and c.get("classname"), c.attrib
for c in failed:
    assert c.find("failure").get("message"), c.attrib
EOF
}
# failures FILE: "image ring metric" of every failure in a check's check.json, one a line
failures() {
  python3 -c 'import json,sys; [print(f["image"], f["ring"], f.get("metric", "-")) for f in json.load(open(sys.argv[1]))["failures"]]' "$1"
}

OPTS=("$T/side.json" --width 64 --height 36 --frames 3 --supersample 2 --rings '15:1:0,*:1/2:0')
ENV=(--cache "$T/cache" --quiet)
scene 0.5

# ---- record
"$BIN" check --record "$T/base" "${OPTS[@]}" "${ENV[@]}" >"$T/rec.txt" 2>"$T/err.txt"
check "record exits 0" test $? -eq 0
check "record: frames, metrics, summary, run record and check.json" \
  bash -c "cd '$T/base' && ls compare.0000.exr compare.0002.exr metrics.csv summary.json fovsim-run.txt check.json >/dev/null"
check "record: check.json holds the command, the compare options (not --cache) and the version" python3 -c "
import json; c = json.load(open('$T/base/check.json'))
assert c['role'] == 'baseline' and c['fovsim'] and c['argv'][:3] == ['fovsim', 'check', '--record'], c
assert c['compare_argv'][0] == 'compare' and '--rings' in c['compare_argv'] and '--cache' not in c['compare_argv']
assert c['tolerances']['coverage_ratio'] == '0.05' and c['tolerances']['frame_time_ratio'] == 'off'"

# ---- a baseline passes against itself, every difference 0
"$BIN" check --baseline "$T/base" "${ENV[@]}" --junit "$T/pass.xml" >"$T/out.txt" 2>"$T/err.txt"
check "the baseline against itself exits 0" test $? -eq 0
check "... and says PASS" grep -q '^fovsim check: PASS' "$T/out.txt"
check "... every change 0 (pixels included)" \
  grep -q 'coverage_ratio 0 (0.05), rmse 0 (0.01), alpha_rmse 0 (0.01), flip 0 (0.01)' "$T/out.txt"
check "... pixel differences 0" grep -q 'pixel_2x2 0 (0.75), pixel_rmse 0 (0.05)' "$T/out.txt"
check "... nothing differs from the baseline's run" grep -q "what differs from the baseline's run (fovsim-run.txt): nothing" "$T/out.txt"
check "... the run went to DIR-next, with its verdict" \
  python3 -c "import json; c = json.load(open('$T/base-next/check.json')); assert c['verdict'] == 'pass' and c['failures'] == []"
check "... no diff images" bash -c "! ls '$T/base-next'/diff.*.exr 2>/dev/null"
check "... JUnit: 3 frames x (2 modes + reference) + the run, none failed" junit "$T/pass.xml" 10 0
check "... nothing on stderr" test ! -s "$T/err.txt"

# ---- the same options over a changed scene: a regression in ring 1 (and the whole display) only
scene 0.3
"$BIN" check --baseline "$T/base" "${ENV[@]}" --junit "$T/fail.xml" >"$T/out.txt" 2>"$T/err.txt"
check "a changed cutoff exits 1" test $? -eq 1
check "... and says REGRESSION, rings 1 and all" grep -q '^fovsim check: REGRESSION .*rings 1, all)' "$T/out.txt"
failures "$T/base-next/check.json" >"$T/fails.txt"
check "... traditional's coverage ratio in ring 1 is named" grep -qx 'traditional 1 coverage_ratio' "$T/fails.txt"
check "... traditional's pixels in ring 1 are named" grep -qx 'traditional 1 pixel_rmse' "$T/fails.txt"
check "... ring 0 (sky only) is never named" bash -c "! grep -q '^[a-z]* 0 ' '$T/fails.txt'"
check "... the report's table names ring 1" grep -qE '^  traditional +1 +coverage_ratio +0-2 ' "$T/out.txt"
check "... the scene is what differs from the baseline's run" grep -q "run (fovsim-run.txt): scene$" "$T/out.txt"
check "... a diff image per failing frame" \
  bash -c "for f in 0 1 2; do head -c 4 '$T/base-next/diff.000'\$f.exr | od -An -tx1 | grep -q '76 2f 31 01' || exit 1; done"
# Traditional fails in all three frames. Hashed's coverage ratio on this 32 x 18 ring moves by about
# the tolerance (0.05-0.10 with the level keys of 2026-12-02; 0.01-0.05 before), so which of its frames
# fail depends on the hash values: the JUnit count is checked against check.json's failing cases.
NFAIL=$(python3 -c 'import json,sys; print(len({(f["frame"], f["image"]) for f in json.load(open(sys.argv[1]))["failures"]}))' \
  "$T/base-next/check.json")
check "... traditional fails in every frame" python3 -c "
import json; f = json.load(open('$T/base-next/check.json'))['failures']
assert {x['frame'] for x in f if x['image'] == 'traditional'} == {0, 1, 2}, f"
check "... JUnit: the failing cases are failures ($NFAIL: traditional's 3 frames and hashed's that moved)" \
  junit "$T/fail.xml" 10 "$NFAIL"
check "... verdict regression in check.json" \
  python3 -c "import json; c = json.load(open('$T/base-next/check.json')); assert c['verdict'] == 'regression'"
grep -E '^  traditional +1 +coverage_ratio' "$T/out.txt" | sed 's/^/  measured: /' >&2
grep -A2 '^largest change' "$T/out.txt" | sed 's/^/  measured: /' >&2

# Tolerances given now override the baseline's, per ring.
LOOSE=(--tol-rmse off --tol-alpha-rmse off --tol-flip off --tol-temporal off --tol-pixel off --tol-pixel-rmse off)
"$BIN" check --baseline "$T/base" "${ENV[@]}" "${LOOSE[@]}" --tol-coverage '0=0,1=1,all=1' >"$T/out.txt" 2>&1
check "tolerances per ring: loose in ring 1 and the whole display passes" test $? -eq 0
"$BIN" check --baseline "$T/base" "${ENV[@]}" "${LOOSE[@]}" --tol-coverage '1,1=0.01' >"$T/out.txt" 2>&1
check "tolerances per ring: tight in ring 1 fails there" test $? -eq 1
check "... only the coverage ratio of ring 1" python3 -c "
import json; f = json.load(open('$T/base-next/check.json'))['failures']
assert f and all(x['ring'] == 1 and x['metric'] == 'coverage_ratio' for x in f), f"

# Back to the recorded scene: passes again, and the earlier diff images are gone.
scene 0.5
"$BIN" check --baseline "$T/base" "${ENV[@]}" >"$T/out.txt" 2>&1
check "the restored scene passes again" test $? -eq 0
check "... and leaves no diff image of the earlier check" bash -c "! ls '$T/base-next'/diff.*.exr 2>/dev/null"

# Frame time only when asked for: any time over 0 x the baseline's fails, as a case of the run.
"$BIN" check --baseline "$T/base" "${ENV[@]}" "${LOOSE[@]}" --tol-coverage off --tol-time 0 --junit "$T/time.xml" \
  >"$T/out.txt" 2>&1
check "--tol-time 0 fails on frame time" test $? -eq 1
check "... in the run's JUnit case alone" junit "$T/time.xml" 10 1
check "... named frame_time_ratio" grep -q 'name="run" classname="check.base.run">' "$T/time.xml"
check "... of each mode" bash -c "grep -cE '^  (traditional|hashed) +all +frame_time_ratio +run' '$T/out.txt' | grep -qx 2"

# ---- the JUnit file escapes what it quotes (the baseline's folder name)
cp -r "$T/base" "$T/odd&<\"name\">"
"$BIN" check --baseline "$T/odd&<\"name\">" "${ENV[@]}" --junit "$T/odd.xml" >/dev/null 2>&1
check "a baseline named with &, <, > and quotes checks" test $? -eq 0
check "... and its JUnit file is well-formed" junit "$T/odd.xml" 10 0
check "... naming it escaped" grep -q 'odd&amp;&lt;&quot;name&quot;&gt;' "$T/odd.xml"

# ---- usage
expect_exit "--baseline refuses compare's options" 2 "$BIN" check --baseline "$T/base" --width 32
check "... saying the baseline holds them" grep -q "would change what the baseline recorded: a check runs the options in .*check.json" "$T/err.txt"
expect_exit "neither --record nor --baseline" 2 "$BIN" check fence
expect_exit "--record refuses --out" 2 "$BIN" check --record "$T/x" fence --out "$T/y"
expect_exit "--record refuses --name" 2 "$BIN" check --record "$T/x" fence --name n
expect_exit "a bad tolerance" 2 "$BIN" check --baseline "$T/base" --tol-coverage 9=0.1
expect_exit "a hexadecimal tolerance (0x10 would read as 16)" 2 "$BIN" check --baseline "$T/base" --tol-coverage 0x10
check "the hexadecimal tolerance: what is expected" grep -q "expected a decimal number" "$T/err.txt"
expect_exit "--junit into a missing folder" 2 "$BIN" check --baseline "$T/base" --junit "$T/no/such/dir/j.xml"
expect_exit "--out as the baseline itself" 2 "$BIN" check --baseline "$T/base" --out "$T/base/"
check "usage errors create nothing" test ! -e "$T/x" -a ! -e "$T/y"
"$BIN" check --help >"$T/out.txt"
check "check --help exits 0 and documents the tolerances" grep -q -- '--tol-pixel-rmse' "$T/out.txt"
check "fovsim --help lists check" bash -c "'$BIN' --help | grep -q '^  check '"

# ---- a missing or damaged baseline: one line, its exit status, nothing drawn
expect_exit "a missing baseline exits 6" 6 "$BIN" check --baseline "$T/nothing" "${ENV[@]}"
check "... naming check.json and how to record one" grep -q "nothing/check.json: cannot open: .*not a baseline of fovsim check: record one" "$T/err.txt"
check "... creating no folder" test ! -e "$T/nothing-next"
damaged() { rm -rf "$T/$1" "$T/$1-next"; cp -r "$T/base" "$T/$1"; }
damaged trunc; head -c 100 "$T/base/check.json" >"$T/trunc/check.json"
expect_exit "a truncated check.json exits 2" 2 "$BIN" check --baseline "$T/trunc" "${ENV[@]}"
check "... naming file:line:column" grep -q 'trunc/check.json:[0-9]*:[0-9]*: not valid JSON' "$T/err.txt"
damaged argv0; sed -i 's/\["compare",/["render",/' "$T/argv0/check.json"
expect_exit "a check.json whose options are not compare's exits 2" 2 "$BIN" check --baseline "$T/argv0" "${ENV[@]}"
check "... naming the JSON path" grep -q 'argv0/check.json: compare_argv\[0\]: expected "compare"' "$T/err.txt"
damaged bogus; sed -i 's/"--rings",/"--bogus", "--rings",/g' "$T/bogus/check.json"
expect_exit "a check.json with an unknown option exits 2" 2 "$BIN" check --baseline "$T/bogus" "${ENV[@]}"
check "... naming check.json and the option" grep -q "bogus/check.json: compare_argv: .*unknown option '--bogus'" "$T/err.txt"
damaged role; sed -i 's/"role":[^,]*,/"role": "next",/' "$T/role/check.json"
expect_exit "a check's own output used as a baseline exits 2" 2 "$BIN" check --baseline "$T/role" "${ENV[@]}"
damaged frame; head -c 300 "$T/base/compare.0001.exr" >"$T/frame/compare.0001.exr"
expect_exit "a truncated baseline frame exits 6" 6 "$BIN" check --baseline "$T/frame" "${ENV[@]}"
check "... naming the frame" grep -q 'frame/compare.0001.exr' "$T/err.txt"
damaged csv; rm "$T/csv/metrics.csv"
expect_exit "a baseline without metrics.csv exits 6" 6 "$BIN" check --baseline "$T/csv" "${ENV[@]}"
check "... naming it" grep -q 'csv/metrics.csv: cannot open' "$T/err.txt"
damaged rows; awk -F, -v OFS=, 'NR == 3 { $8 = "x" } 1' "$T/base/metrics.csv" >"$T/rows/metrics.csv"
expect_exit "a damaged metrics.csv row exits 6" 6 "$BIN" check --baseline "$T/rows" "${ENV[@]}"
check "... naming file:line" grep -q 'rows/metrics.csv:3:' "$T/err.txt"
# options a baseline never records (the machine's, check's own) are refused, not obeyed (docs/check.md
# "Recording a baseline"): a check.json carrying --cache would otherwise send the reference cache elsewhere
damaged cache; sed -i 's|"--rings",|"--cache", "'"$T"'/evil-cache", "--rings",|' "$T/cache/check.json"
expect_exit "a check.json storing --cache DIR exits 2" 2 "$BIN" check --baseline "$T/cache" --quiet
check "... naming check.json, the JSON path and --cache" \
  grep -q "cache/check.json: compare_argv\[[0-9]*\]: '--cache' is never stored in a baseline" "$T/err.txt"
check "... and the cache it names is not touched" test ! -e "$T/evil-cache"
n=0
for o in '"--no-cache"' '"--gpu", "0"' '"--gpu=0"' '"--out", "x"' '"--replace"' '"--tol-rmse=1"' '"--verbose"'; do
  n=$((n+1)); damaged "machine$n"; sed -i 's|"--rings",|'"$o"', "--rings",|' "$T/machine$n/check.json"
  name=${o#\"}; name=${name%%[\"=]*}
  expect_exit "a check.json storing $o exits 2" 2 "$BIN" check --baseline "$T/machine$n" "${ENV[@]}"
  check "... naming $name" grep -q "machine$n/check.json: compare_argv\[[0-9]*\]: '$name' is never stored" "$T/err.txt"
done
check "... none of them ran" bash -c "! ls -d '$T'/cache-next '$T'/machine*-next 2>/dev/null"
check "a damaged baseline draws nothing" bash -c "! ls -d '$T'/{trunc,argv0,bogus,role,frame,csv,rows}-next 2>/dev/null"

# ---- recording again replaces the baseline
"$BIN" check --record "$T/base" "${OPTS[@]}" --frames 2 "${ENV[@]}" >/dev/null 2>&1
check "recording again into a baseline replaces it" test $? -eq 0 -a ! -e "$T/base/compare.0002.exr"

summary
