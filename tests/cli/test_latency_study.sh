#!/usr/bin/env bash
# The latency study end to end (docs/latency.md "A latency study"): compare --gaze-latency 0,150
# renders each latency into its own folder; each folder's post_saccade.csv holds the foveal error
# of the frames after each landing, its summary.json the same figures aggregated (recomputed here
# from the CSV), metrics.csv the event per frame; latency.csv collects the summaries; 150 ms of
# latency raises the foveal error of traditional alpha testing after the saccades. Tiny sizes.
set -u
BIN=${FOVSIM_BIN:?set by CMake}
T=${FOVSIM_TEST_OUT:-/tmp/fovsim_test}/latency_study
rm -rf "$T"; mkdir -p "$T"
. "$(dirname "$0")/harness.sh"

# A 1 kHz trace: fixations at x 0.25 and 0.75 joined by two 30 ms saccades, ending 0.33 and 0.73 s.
/usr/bin/python3 - "$T" <<'EOF'
import sys
with open(sys.argv[1] + "/saccades.csv", "w") as f:
    f.write("t,x,y\n")
    for k in range(1001):
        t = k / 1000
        if t < 0.3: x = 0.25
        elif t < 0.33: x = 0.25 + 0.5 * (t - 0.3) / 0.03
        elif t < 0.7: x = 0.75
        elif t < 0.73: x = 0.75 - 0.5 * (t - 0.7) / 0.03
        else: x = 0.25
        f.write("%.3f,%.6f,0.5\n" % (t, x))
EOF

S=$T/study
"$BIN" compare forest --gaze "$T/saccades.csv" --gaze-latency 0,150 --rings 5:1:0,15:1/2:0,*:1/4:0 \
  --width 160 --height 90 --frames 24 --fps 24 --supersample 1 --samples 8 --taa off --quiet --out "$S" \
  >"$T/log.txt" 2>&1
check "the study runs" test -s "$S/latency.csv"
check "a folder per latency" test -s "$S/latency-0/summary.json" -a -s "$S/latency-150/summary.json"
check "the table names the study" grep -q "^latency study: foveal error after saccades" "$T/log.txt"
if command -v gnuplot >/dev/null; then check "latency.png" test -s "$S/latency.png"; fi

check "post_saccade.csv, summary.json, metrics.csv and latency.csv agree" /usr/bin/python3 - "$S" <<'EOF'
import csv, json, math, sys
S = sys.argv[1]
rows = list(csv.DictReader(open(S + "/latency.csv")))
assert [(r["latency_ms"], r["mode"]) for r in rows] == [("0", "traditional"), ("150", "traditional"),
                                                       ("0", "hashed"), ("150", "hashed")], rows
for lat in ("0", "150"):
    d = "%s/latency-%s" % (S, lat)
    summ = json.load(open(d + "/summary.json"))
    post = list(csv.DictReader(open(d + "/post_saccade.csv")))
    events = {}
    for r in csv.DictReader(open(d + "/metrics.csv")):
        if r["mode"] == "traditional" and r["ring"] == "-1":
            events[int(r["frame"])] = r["gaze_event"]
    assert set(events.values()) <= {"fixation", "saccade", "pursuit", "lost"}, events
    counts = summ["gaze_events"]["frames"]
    for e in ("fixation", "saccade", "pursuit", "lost"):
        assert counts[e] == sum(1 for v in events.values() if v == e), (e, counts)
    landings = sorted({float(r["landing_time"]) for r in post})
    assert len(landings) == 2 and abs(landings[0] - 0.33) < 0.02 and abs(landings[1] - 0.73) < 0.02, landings
    assert summ["gaze_events"]["landings_measured"] == 2
    for m in summ["modes"]:
        mine = [r for r in post if r["mode"] == m["mode"]]
        assert mine, m["mode"]
        for r in mine:
            f = int(r["frame"])
            assert events[f] != "saccade", (f, events[f])
            assert 0 <= float(r["ms_after"]) < 150 and 0 <= int(r["frames_after"]) < 4, r
            assert abs(float(r["time"]) - f / 24) < 1e-6 and float(r["time"]) >= float(r["landing_time"]), r
        p = m["post_saccade"]
        n = len(mine)
        rmse = sum(float(r["fovea_rmse"]) for r in mine) / n
        flip = sum(float(r["fovea_flip"]) for r in mine) / n
        cov = sum(float(r["fovea_coverage"]) * int(r["fovea_pixels"]) for r in mine)
        ref = sum(float(r["fovea_ref_coverage"]) * int(r["fovea_pixels"]) for r in mine)
        assert p["frames"] == n and abs(p["rmse"] - rmse) < 1e-6 and abs(p["flip"] - flip) < 1e-6, (p, rmse, flip)
        assert abs(p["coverage_ratio"] - cov / ref) < 1e-4, (p, cov / ref)
        by = p["by_frame_after_landing"]
        assert sum(b["frames"] for b in by) == n, by
        row = [r for r in rows if r["latency_ms"] == lat and r["mode"] == m["mode"]][0]
        assert int(row["post_saccade_frames"]) == n and abs(float(row["fovea_rmse"]) - p["rmse"]) < 1e-6, row
        assert abs(float(row["fovea_flip"]) - p["flip"]) < 1e-6, row
# The rings lag the true gaze by 150 ms: the fovea is drawn by a coarse ring after each landing.
t = {r["latency_ms"]: float(r["fovea_rmse"]) for r in rows if r["mode"] == "traditional"}
assert t["150"] > t["0"] * 1.2, t
EOF

check "report.html shows the post-saccade error" /usr/bin/python3 - "$S/latency-150" <<'EOF'
import json, sys
d = sys.argv[1]
html = open(d + "/report.html").read()
p = json.load(open(d + "/summary.json"))["modes"][1]["post_saccade"]
assert "<h2>After saccades</h2>" in html
cell = 'data-k="modes.1.post_saccade.rmse">%.15g</td>' % p["rmse"]
assert cell in html, cell
k0 = 'data-k="modes.1.post_saccade.by_frame_after_landing.0.flip">%.15g</td>' % p["by_frame_after_landing"][0]["flip"]
assert k0 in html, k0
EOF

# A trace without saccades: nothing to compare after them, said; latency.csv without a plot.
printf 't,x,y\n0,0.4,0.5\n1,0.4,0.5\n' >"$T/still.csv"
mkdir -p "$T/still" && touch "$T/still/latency.png"
"$BIN" compare forest --gaze "$T/still.csv" --gaze-latency 0,50 --width 64 --height 36 --frames 3 --supersample 1 \
  --samples 2 --taa off --out "$T/still" >"$T/still.txt" 2>&1
check "no saccade: exit 0" test $? -eq 0
check "  says so" grep -q "^no saccade landed in the measured frames" "$T/still.txt"
check "  latency.csv with 0 post-saccade frames, no (stale) latency.png" \
  bash -c "test ! -e '$T/still/latency.png' && awk -F, 'NR > 1 && \$3 != 0 {bad = 1} END {exit bad}' '$T/still/latency.csv'"

expect_exit "a latency named twice" 2 "$BIN" compare forest --gaze-latency 0,20,20
expect_exit "a list outside compare" 2 "$BIN" render forest --gaze-latency 0,20
expect_exit "an empty item" 2 "$BIN" compare forest --gaze-latency 0,,20
summary
