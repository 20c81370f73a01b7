#!/usr/bin/env bash
# fovsim merge refuses a task's files that fovsim did not write whole (docs/cluster.md): a
# metrics.csv cut mid-row, one without a column merge reads, a row short of a field, an empty
# field, and a summary.json that is not valid JSON or not an object; each is one line naming
# file:line (and exit 6), never merged with 0, another column's value or null in its place.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/merge_damaged
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"
cd "$T" || exit 1

cat >m.json <<'EOF2'
{ "scenes": ["fence"], "modes": ["traditional"], "width": 64, "height": 36, "frames": 2,
  "reference": {"supersample": 1}, "cache": "cache" }
EOF2
timeout 300 "$BIN" sweep m.json --local 1 --out good --quiet >/dev/null 2>&1
check "the sweep runs" test $? -eq 0
timeout 60 "$BIN" merge good >"$T/out.txt" 2>"$T/err.txt"
check "an undamaged sweep merges (exit 0, nothing on stderr)" bash -c "test $? -eq 0 && test ! -s '$T/err.txt'"

# damaged NAME PYTHON: a copy of the sweep whose one task's files PYTHON changes (csv = its
# metrics.csv, js = its summary.json, as paths)
damaged() {
  rm -rf "$1"; cp -r good "$1"
  local task; task=$(ls -d "$1"/tasks/*/ | head -1)
  python3 - "$task/metrics.csv" "$task/summary.json" <<EOF2
import sys
csv, js = sys.argv[1], sys.argv[2]
$2
EOF2
}
rows() { test "$(tail -n +2 good/tasks/*/metrics.csv | wc -l)" -ge 2; }
check "the task has rows to damage" rows

damaged cut "t = open(csv).read(); open(csv, 'w').write(t[:-6])"
expect_exit "metrics.csv cut mid-row -> 6" 6 timeout 60 "$BIN" merge cut
check "  names the file and the last line" bash -c "grep -q 'metrics.csv:$(wc -l <good/tasks/*/metrics.csv): the row is cut short' '$T/err.txt'"

damaged nocol "
rows = [l.split(',') for l in open(csv).read().splitlines()]
k = rows[0].index('coverage_ratio')
open(csv, 'w').write(''.join(','.join(r[:k] + r[k + 1:]) + '\n' for r in rows))"
expect_exit "metrics.csv without the coverage_ratio column -> 6" 6 timeout 60 "$BIN" merge nocol
check "  names the file, line 1 and the column" grep -q "metrics.csv:1: the header has no column 'coverage_ratio'" "$T/err.txt"

damaged short "
lines = open(csv).read().splitlines()
lines[2] = lines[2].rsplit(',', 1)[0]
open(csv, 'w').write('\n'.join(lines) + '\n')"
expect_exit "a row one field short -> 6" 6 timeout 60 "$BIN" merge short
check "  names the file and line 3" grep -q "metrics.csv:3: 16 fields, the header has 17" "$T/err.txt"

damaged empty "
lines = open(csv).read().splitlines()
f = lines[1].split(','); f[1] = ''; lines[1] = ','.join(f)
open(csv, 'w').write('\n'.join(lines) + '\n')"
expect_exit "an empty field -> 6" 6 timeout 60 "$BIN" merge empty
check "  names the file, line 2 and the column" grep -q "metrics.csv:2: field 2 (time) is empty" "$T/err.txt"

damaged badjson "t = open(js).read(); open(js, 'w').write(t[:len(t) // 2])"
expect_exit "summary.json cut in half -> 6" 6 timeout 60 "$BIN" merge badjson
check "  names the file with line and column" grep -q 'summary.json:[0-9]*:[0-9]*: not valid JSON' "$T/err.txt"

damaged notobj "open(js, 'w').write('[1, 2]\n')"
expect_exit "summary.json not an object -> 6" 6 timeout 60 "$BIN" merge notobj
check "  says what it expected" grep -q 'summary.json: expected a JSON object' "$T/err.txt"

summary
