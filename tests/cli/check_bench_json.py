#!/usr/bin/env python3
"""check_bench_json.py: checks the work and process counters of `fovsim bench --format json`
(used by test_cli.sh; not a test itself: CMake registers only tests/cli/test_*.sh).

usage: check_bench_json.py FILE known|unknown [--foveation-saves-fragments]

known: every count is an integer >= 0, each stage's counts add up to its configuration's
(all_frames sums, exact), full-screen stages (TAA resolve) submit one primitive per frame, the
composite an even number of them (its display rectangles, two triangles each), and the per-frame medians lie within [min, max]. unknown (no GL_ARB_pipeline_statistics_query,
or FOVSIM_NO_PIPELINE_STATS): every count is -1. Either way CPU time and minor page faults are
numbers >= 0 (faults integers). --foveation-saves-fragments: the foveated configuration of the
first mode shades fewer fragments than full resolution over the same frames.
"""
import json
import sys

COUNTS = ("vs_invocations", "primitives", "fs_invocations")
SUMMARY = ("median", "p10", "p90", "min", "max")


def fail(msg):
    print("check_bench_json: " + msg, file=sys.stderr)
    sys.exit(1)


def is_int(v):
    return isinstance(v, int) and not isinstance(v, bool)


def main():
    path, mode = sys.argv[1], sys.argv[2]
    saves = "--foveation-saves-fragments" in sys.argv[3:]
    j = json.load(open(path))
    frames = j["frames"]
    if j.get("pipeline_statistics") is not (mode == "known"):
        fail("pipeline_statistics is %r, expected %s" % (j.get("pipeline_statistics"), mode))
    for c in j["configs"]:
        name = c["name"]
        for k in ("cpu_ms", "minor_faults"):
            for s in SUMMARY:
                v = c[k][s]
                if not isinstance(v, (int, float)) or v < 0:
                    fail("%s: %s.%s = %r" % (name, k, s, v))
                if k == "minor_faults" and not is_int(v):
                    fail("%s: minor_faults.%s = %r is not an integer" % (name, s, v))
        for q in COUNTS:
            cq = c[q]
            vals = [cq[s] for s in SUMMARY] + [cq["all_frames"]]
            stage_sum = 0
            for st in c["stages"]:
                vals += [st[q + "_median"], st[q + "_all_frames"]]
                stage_sum += st[q + "_all_frames"]
            if not all(is_int(v) for v in vals):
                fail("%s: %s: not all integers: %r" % (name, q, vals))
            if mode == "unknown":
                if any(v != -1 for v in vals):
                    fail("%s: %s: unknown counts must be -1, got %r" % (name, q, vals))
                continue
            if any(v < 0 for v in vals):
                fail("%s: %s: negative count in %r" % (name, q, vals))
            if stage_sum != cq["all_frames"]:
                fail("%s: %s: stages add up to %d, the configuration says %d" % (name, q, stage_sum, cq["all_frames"]))
            if not cq["min"] <= cq["median"] <= cq["max"] or cq["all_frames"] < frames * cq["min"]:
                fail("%s: %s: inconsistent summary %r" % (name, q, cq))
        if mode == "known":
            if c["fs_invocations"]["median"] <= 0 or c["primitives"]["median"] <= 0:
                fail("%s: nothing drawn? %r" % (name, c))
            for st in c["stages"]:
                if "resolve" in st["name"]:
                    if st["primitives_all_frames"] != frames or st["vs_invocations_median"] < 3:
                        fail("%s: full-screen stage %s: %r" % (name, st["name"], st))
                if st["name"] == "composite":
                    if st["primitives_all_frames"] < 2 * frames or st["primitives_all_frames"] % 2:
                        fail("%s: composite stage: %r" % (name, st))
            if abs(c["fragments_per_pixel"] - c["fs_invocations"]["median"] / j["display_pixels"]) > 1e-3:
                fail("%s: fragments_per_pixel disagrees with fs_invocations" % name)
        elif c["fragments_per_pixel"] != -1:
            fail("%s: fragments_per_pixel must be -1 when unknown" % name)
    if saves:
        full = [c for c in j["configs"] if c["rings"] == "*:1:0"][0]
        fov = [c for c in j["configs"] if c["rings"] != "*:1:0"][0]
        if not fov["fs_invocations"]["all_frames"] < full["fs_invocations"]["all_frames"]:
            fail("foveated shades %d fragments, full resolution %d" % (fov["fs_invocations"]["all_frames"],
                                                                      full["fs_invocations"]["all_frames"]))
    print("ok")


main()
