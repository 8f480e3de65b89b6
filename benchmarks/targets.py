#!/usr/bin/python3
"""Where the implicit path stands against its speed and memory targets, read from the committed data of
the studies that measure them (it runs nothing): accuracy_cost.json (the tuned explicit path against the
implicit one on the Gregoire D = 50 mm beams), solve_profile.json (the default scene), size_effect.json
(the 3D D = 200 and 400 mm beams under IMPL-EX on two ranks), explicit_beam.json (their explicit runs)
and softening_convergence.json (the D = 50 mm beams at dx = 1.25 mm). Writes docs/benchmarks/targets.md.

Usage: benchmarks/targets.py [--report]   (either way it only reads the data and writes the table)
"""
import argparse
import os

import accuracy_cost
from common import RESULTS_DIR, load_results, write_lines

KINDS = {"un": "unnotched", "fn": "notch 0.2 D", "hn": "notch 0.5 D"}


def data(name):
    path = os.path.join(RESULTS_DIR, name)
    return load_results(path) if os.path.exists(path) else {}


def explicit_ratio(acc, dx):
    """Explicit over implicit CPU time on the half-notched D = 50 mm beam at dx, both CPU times, the peaks'
    relative difference and the curves' RMS difference over the implicit peak."""
    c = accuracy_cost.paths_compared(acc, "gregoire_d50_hn", dx)
    if not c:
        return None
    ri, re_, dp, rms = c
    return re_["cpu"] / ri["cpu"], ri["cpu"], re_["cpu"], dp, rms


def row(target, measured, source, met):
    return "| %s | %s | %s | %s |" % (target, measured, source, "yes" if met else "no" if met is not None else "not measured")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--report", action="store_true")
    ap.parse_args()
    acc, prof, size, beam, conv = (data(n) for n in ("accuracy_cost.json", "solve_profile.json", "size_effect.json", "explicit_beam.json",
                                                      "softening_convergence.json"))
    rows = []
    for dx, want in ((0.005, 3), (0.0025, 5)):
        r = explicit_ratio(acc, dx)
        if r:
            rows.append(row("D = 50 mm half-notched, dx = %g mm: the tuned explicit run takes at least %d times the implicit CPU time, "
                            "at equal accuracy" % (1e3 * dx, want),
                            "%.2f times (%.1f s against %.1f s); peaks %+.2f %% apart, curves %.2f %% RMS of the peak" % (
                                r[0], r[2], r[1], 100 * r[3], 100 * r[4]),
                            "accuracy_cost.json", r[0] >= want and abs(r[3]) <= 0.01 and r[4] <= 0.01))
    d = prof.get("default/dx=0.005")
    rows.append(row("The default scene (`make run`) in under 10 s", "%.1f s of wall time" % d["wall_s"] if d else "-", "solve_profile.json",
                    d["wall_s"] < 10 if d else None))
    for D, limit in ((200, 600), (400, 3600)):
        for kind in ("un", "fn", "hn"):
            r = size.get("D=%d/%s/dx=0.005/implex=0.03" % (D, kind))
            done = bool(r) and r.get("status", "").startswith("separated")
            rows.append(row("D = %d mm %s, 3D, dx = 5 mm, traced to 10 %% of its peak in under %d minutes on 2 ranks" % (D, KINDS[kind], limit // 60),
                            "%.0f s, %s" % (r["wall"], r["status"]) if r else "-", "size_effect.json",
                            (done and r["wall"] < limit) if r else None))
    for kind in ("un", "fn", "hn"):
        r = beam.get("D=200/%s/dx=0.005/ranks=2" % kind)
        ratio = r["explicit"]["wall_s"] / r["implicit"]["wall_s"] if r else None
        # how close each explicit run (load-point and, where run, CMOD control) came to the implicit curve
        notes = []
        for control, rc in (("load-point", r), ("CMOD", beam.get("D=200/%s/dx=0.005/ranks=2/control=cmod" % kind))):
            if rc:
                e = rc["explicit"]
                equal = abs(e["peak_diff"] or 1) <= 0.01 and e["rms_diff"] <= 0.01
                notes.append("%s control: %.1f times, peaks %+.2f %% apart, curves %.2f %% RMS of the peak (%s)" % (
                    control, e["wall_s"] / rc["implicit"]["wall_s"], 100 * (e["peak_diff"] or 0), 100 * e["rms_diff"],
                    "equal accuracy" if equal else "not of equal accuracy"))
        rows.append(row("D = 200 mm %s: the explicit run takes at least 10 times the implicit one (wall, 2 ranks)" % KINDS[kind],
                        "; ".join(notes) if r else "-", "explicit_beam.json", ratio >= 10 if r else None))
    for name, runs in (("size_effect.json", [(k, v) for k, v in size.items() if v.get("nodes", 0) >= 200000 and "memory_MB" in v]),
                       ("softening_convergence.json", [(k, v) for k, v in conv.items() if v.get("nodes", 0) >= 200000 and "peak_rss_bytes" in v])):
        for k, v in sorted(runs):
            b = (v["memory_MB"] * 2 ** 20 if "memory_MB" in v else v["peak_rss_bytes"]) / v["bonds"]
            rows.append(row("Non-linear 3D run of 200,000 nodes or more in at most 300 bytes per bond: %s" % k,
                            "%.0f bytes per bond (%d nodes, %d bonds)" % (b, v["nodes"], v["bonds"]), name, b <= 300))
    lines = ["# Speed and memory targets against the committed data", "",
             "Written by `benchmarks/targets.py`, which runs nothing: it reads the data files of the studies named in the "
             "third column (in `docs/benchmarks/`) and compares them with the implicit path's targets. Ratios are of "
             "times taken one after the other in one invocation of the study that owns them; memory is the peak resident "
             "set over the bonds (summed over the ranks where a run used two).", "",
             "| target | measured | data | met |", "|---|---|---|---|"] + rows
    write_lines("targets.md", lines)


if __name__ == "__main__":
    main()
