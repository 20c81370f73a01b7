#!/usr/bin/env python3
"""check_bench_json.py: checks the work and process counters of `fovsim bench --format json`
(used by test_cli.sh; not a test itself: CMake registers only tests/cli/test_*.sh).

usage: check_bench_json.py FILE known|unknown [--foveation-saves-fragments] [--ring-lod U1,...]

known: every count is an integer >= 0, each stage's counts add up to its configuration's
(all_frames sums, exact), full-screen stages (TAA resolve) submit one primitive per frame, the
composite at least one (its cells: points, and two triangles per cell cut by the display's edge), and the per-frame medians lie within [min, max]. unknown (no GL_ARB_pipeline_statistics_query,
or FOVSIM_NO_PIPELINE_STATS): every count is -1. Either way CPU time and minor page faults are
numbers >= 0 (faults integers). --foveation-saves-fragments: the foveated configuration of the
first mode shades fewer fragments than full resolution over the same frames.

Covered fragments (docs/benchmarks.md "Work counts") are counted by the counting variant, with or
without the extension: integers >= 0, stages add up to the configuration, full-screen stages (not
"geometry") cover the pixels they draw (the composite and the list resolve: the display), each
ring's covered_fragments_by_pass adds up to the ring, geometry_covered_fragments_all_frames is the
geometry stages' sum, and covered_fragment_ideal_speedup is full resolution's geometry covered
fragments / the first foveated configuration's. Footprint bytes (bytes_read, bytes_written) are
known integers that add up over the stages.

--ring-lod U1,...: the run had ring LOD with these keep fractions (known counts). Every mode has
"M, foveated" (drawn without it) and "M, foveated + ring LOD" over the same stages, and an entry in
ring_lod_vs_rings whose count ratios are the configurations' totals' ratios. Counts, never times:
a ring with u = 1 does exactly the same work in both (identity law, same culling bounds); a ring
with u < 1 draws at least as many instances (its culling bounds hold the enlarged cards); the
outermost ring, when simplified, shades fewer fragments (on llvmpipe every sub-pixel card costs a
4x4 block, and a fraction u of them is drawn). Without --ring-lod: no ring LOD configuration.
"""
import json
import sys

COUNTS = ("vs_invocations", "primitives", "fs_invocations", "clipped_primitives")  # pipeline statistics
COVERED = "covered_fragments"  # the counting variant's
BYTES = ("bytes_read", "bytes_written")  # from the targets' footprints
SUMMARY = ("median", "p10", "p90", "min", "max")


def fail(msg):
    print("check_bench_json: " + msg, file=sys.stderr)
    sys.exit(1)


def is_int(v):
    return isinstance(v, int) and not isinstance(v, bool)


def check_ring_lod(j, u):
    """The ring LOD configurations of a known-count run with keep fractions u (list of str)."""
    if j["ring_lod"].split(" (u = ")[-1] != ",".join(u) + ")":
        fail("ring_lod is %r, expected keep fractions %s" % (j["ring_lod"], u))
    cfg = {c["name"]: c for c in j["configs"]}
    pairs = [(cfg[n[: -len(" + ring LOD")]], c) for n, c in cfg.items() if n.endswith(", foveated + ring LOD")]
    if not pairs or len(pairs) != len(j["ring_lod_vs_rings"]):
        fail("%d ring LOD configurations, %d comparisons" % (len(pairs), len(j["ring_lod_vs_rings"])))
    for plain, lod in pairs:
        if plain["ring_lod_u"] != "off" or lod["ring_lod_u"] != ",".join(u):
            fail("%s / %s: ring_lod_u %r / %r" % (plain["name"], lod["name"], plain["ring_lod_u"], lod["ring_lod_u"]))
        if plain["rings"] != lod["rings"] or plain["shaded_pixels"] != lod["shaded_pixels"]:
            fail("%s: not the same rings as %s" % (lod["name"], plain["name"]))
        ps, ls = plain["stages"], lod["stages"]
        if [s["name"] for s in ps] != [s["name"] for s in ls]:
            fail("%s: other stages than %s" % (lod["name"], plain["name"]))
        rings = [k for k, s in enumerate(ps) if s["name"].startswith("ring ") and "taa" not in s["name"]]
        if len(rings) != len(u):
            fail("%s: %d ring stages for %d keep fractions" % (lod["name"], len(rings), len(u)))
        for i, k in enumerate(rings):
            a, b = ps[k], ls[k]
            ia, ib = plain["ring_instances_median"][i], lod["ring_instances_median"][i]
            if float(u[i]) == 1.0:
                if any(a[q + "_all_frames"] != b[q + "_all_frames"] for q in COUNTS + (COVERED,) + BYTES) or ia != ib:
                    fail("%s: ring %d keeps every card but its work differs: %r / %r" % (lod["name"], i, a, b))
            elif ib < ia:
                fail("%s: ring %d draws %r instances, %r without ring LOD" % (lod["name"], i, ib, ia))
        o = rings[-1]
        if float(u[-1]) < 1.0 and not 0 < ls[o]["fs_invocations_all_frames"] < ps[o]["fs_invocations_all_frames"]:
            fail("%s: outermost ring shades %d fragments, %d without ring LOD" % (
                lod["name"], ls[o]["fs_invocations_all_frames"], ps[o]["fs_invocations_all_frames"]))
    for e in j["ring_lod_vs_rings"]:
        plain, lod = cfg[e["without"]], cfg[e["name"]]
        if e["without"] != e["name"].replace(" + ring LOD", ""):
            fail("ring_lod_vs_rings: %s compared with %s" % (e["name"], e["without"]))
        if not e["frame_ms_ratio"] > 0 or not e["cpu_ms_ratio"] > 0:
            fail("ring_lod_vs_rings: %r" % e)
        for q in COUNTS:
            if abs(e[q + "_ratio"] - lod[q]["all_frames"] / plain[q]["all_frames"]) > 1e-3:
                fail("ring_lod_vs_rings: %s: %s_ratio %r" % (e["name"], q, e[q + "_ratio"]))
        if [s["name"] for s in e["stages"]] != [s["name"] for s in lod["stages"]]:
            fail("ring_lod_vs_rings: %s: stages" % e["name"])
        if not all(s["wall_ms_ratio"] > 0 and s["fs_invocations_ratio"] > 0 for s in e["stages"]):
            fail("ring_lod_vs_rings: %s: %r" % (e["name"], e["stages"]))


def check_covered(j, c):
    """Covered fragments of configuration c (known with or without pipeline statistics)."""
    name, frames, px = c["name"], j["frames"], j["display_pixels"]
    for q in BYTES:  # footprint bytes: known integers, stages add up to the configuration
        vals = [c[q]["all_frames"]] + [st[q + "_all_frames"] for st in c["stages"]]
        if not all(is_int(v) and v >= 0 for v in vals) or sum(vals[1:]) != vals[0]:
            fail("%s: %s: %r" % (name, q, vals))
    cq = c[COVERED]
    vals = [cq[s] for s in SUMMARY] + [cq["all_frames"]] + [st[COVERED + "_all_frames"] for st in c["stages"]]
    if not all(is_int(v) and v >= 0 for v in vals):
        fail("%s: covered fragments: not all integers >= 0: %r" % (name, vals))
    if sum(st[COVERED + "_all_frames"] for st in c["stages"]) != cq["all_frames"]:
        fail("%s: covered fragments: stages do not add up to %d" % (name, cq["all_frames"]))
    geom = 0
    for st in c["stages"]:
        v = st[COVERED + "_all_frames"]
        if st["geometry"]:
            geom += v
            byp = st.get("covered_fragments_by_pass")
            if byp is not None and sum(p["all_frames"] for p in byp) != v:
                fail("%s: %s: covered fragments by pass %r do not add up to %d" % (name, st["name"], byp, v))
        elif st["name"] in ("composite", "list resolve") and v != frames * px:
            fail("%s: %s covers %d fragments, expected %d frames x %d pixels" % (name, st["name"], v, frames, px))
    if geom != c["geometry_covered_fragments_all_frames"]:
        fail("%s: geometry_covered_fragments_all_frames %r, the stages say %d" % (
            name, c["geometry_covered_fragments_all_frames"], geom))


def main():
    path, mode = sys.argv[1], sys.argv[2]
    saves = "--foveation-saves-fragments" in sys.argv[3:]
    lod_u = sys.argv[sys.argv.index("--ring-lod") + 1].split(",") if "--ring-lod" in sys.argv else None
    j = json.load(open(path))
    if lod_u is not None and mode == "known":
        check_ring_lod(j, lod_u)
    elif j["ring_lod"] != "off" or "ring_lod_vs_rings" in j or any(
            "ring LOD" in c["name"] or c["ring_lod_u"] != "off" for c in j["configs"]):
        fail("ring LOD configurations in a run without ring LOD")
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
        check_covered(j, c)
        if mode == "known":
            if c["fs_invocations"]["median"] <= 0 or c["primitives"]["median"] <= 0:
                fail("%s: nothing drawn? %r" % (name, c))
            for st in c["stages"]:
                if "resolve" in st["name"]:
                    if st["primitives_all_frames"] != frames or st["vs_invocations_median"] < 3:
                        fail("%s: full-screen stage %s: %r" % (name, st["name"], st))
                if st["name"] == "composite":
                    if st["primitives_all_frames"] < frames:
                        fail("%s: composite stage: %r" % (name, st))
            if abs(c["fragments_per_pixel"] - c["fs_invocations"]["median"] / j["display_pixels"]) > 1e-3:
                fail("%s: fragments_per_pixel disagrees with fs_invocations" % name)
        elif c["fragments_per_pixel"] != -1:
            fail("%s: fragments_per_pixel must be -1 when unknown" % name)
    fovs = [c for c in j["configs"] if c["rings"] != "*:1:0"]
    if fovs:
        full, fov = j["configs"][0], fovs[0]
        ideal = full["geometry_covered_fragments_all_frames"] / fov["geometry_covered_fragments_all_frames"]
        if abs(j["covered_fragment_ideal_speedup"] - ideal) > 1e-3 * ideal:
            fail("covered_fragment_ideal_speedup %r, the configurations say %r" % (j["covered_fragment_ideal_speedup"], ideal))
        # each foveated frame less its composite's time (>= 0) is no longer than the frame: the
        # medians keep that order, so the speedup without the composite is at least the speedup
        nc = j["speedup_without_composite"]
        if nc != -1 and not nc >= j["speedup"] - 1e-4:
            fail("speedup_without_composite %r below speedup %r" % (nc, j["speedup"]))
    if saves:
        full = [c for c in j["configs"] if c["rings"] == "*:1:0"][0]
        fov = [c for c in j["configs"] if c["rings"] != "*:1:0"][0]
        if not fov["fs_invocations"]["all_frames"] < full["fs_invocations"]["all_frames"]:
            fail("foveated shades %d fragments, full resolution %d" % (fov["fs_invocations"]["all_frames"],
                                                                      full["fs_invocations"]["all_frames"]))
    print("ok")


main()
