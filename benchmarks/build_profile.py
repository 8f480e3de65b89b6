#!/usr/bin/python3
"""What a change to the code did to the default 3D path's time: the Gregoire D = 200 mm half-notched beam (3D,
dx = 5 mm, 56,000 nodes) under its default path following (IMPL-EX, damage error 0.03 per step) to 10 % of its
peak on two ranks with -log_view, run by a baseline binary (built from an earlier commit) and by this build,
one after the other in one invocation, so that their ratio is taken on the same machine at the same time.
Records wall times, the solve stage's event times, iterations and how far the curves are apart (every column
of curve.csv but the wall time). Writes docs/benchmarks/build_profile.json (one entry per change, by label)
and build_profile.md.

Usage: benchmarks/build_profile.py --label TEXT --baseline PATH --baseline-commit SHA [--repeat N]
       benchmarks/build_profile.py --report
"""
import argparse
import csv
import json
import os
import re
import subprocess
import tempfile

from common import EXE, OUT, RESULTS_DIR, ROOT, load_results, run_timed, store_result

JSON = os.path.join(RESULTS_DIR, "build_profile.json")
SCENE = ["-options_file", os.path.join(ROOT, "options", "gregoire_d200_hn.opts"), "-pd_control", "arclength", "-pd_stop_fraction", "0.1",
         "-pd_arclength_implex", "0.03"]
RANKS = 2
# events reported: pdimplicit's own (include/pd_log.h) and the Krylov solves
EVENTS = ["PDBondForce", "PDBondTangent", "PDAssembly", "PDTangentProduct", "PDHistory", "PDEnergy", "KSPSolve", "PCSetUp"]


def parse_log(path):
    """Seconds per event of the 'PD solve' stage (its lines come last) and that stage's time."""
    ev, solve = {}, None
    for line in open(path):
        m = re.match(r"^\s*\d+:\s+PD solve:\s+(\S+)", line)
        if m:
            solve = float(m.group(1))
        p = line.split()
        if p and p[0] in EVENTS and len(p) > 4:
            ev[p[0]] = float(p[3])
    return ev, solve


def run(exe):
    out = tempfile.mkdtemp(prefix="pdbuild_")
    logf = os.path.join(out, "log_view.txt")
    cmd = ["mpiexec", "-n", str(RANKS), exe] + SCENE + ["-pd_output_dir", out, "-log_view", ":" + logf]
    with open(os.path.join(out, "stdout.txt"), "w") as f:
        code, wall, _, _ = run_timed(cmd, 3600, f)
    s = json.load(open(os.path.join(out, "summary.json")))
    ev, solve = parse_log(logf)
    rows = list(csv.DictReader(open(os.path.join(out, "curve.csv"))))
    return {"exit": code, "wall_s": wall, "solve_stage_s": solve, "events_s": ev, "status": s["status"], "steps": s.get("steps"),
            "newton_its": s.get("newton_its"), "ksp_its": s.get("ksp_its"), "peak_N": s.get("peak_load_N"),
            "peak_rss_bytes": s.get("memory", {}).get("peak_rss_bytes"), "bonds": s.get("bonds"), "rows": rows}


def compare(a, b):
    """Columns of curve.csv (but the wall time) where the two runs differ, with the largest relative difference."""
    if len(a) != len(b):
        return {"rows": [len(a), len(b)]}
    diff = {}
    for k in a[0]:
        if k == "wall_s":
            continue
        d = max(abs(float(x[k]) - float(y[k])) / max(abs(float(x[k])), 1e-300) for x, y in zip(a, b))
        if d > 0:
            diff[k] = d
    return diff


def commit():
    return subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()


def report():
    res = load_results(JSON)
    lines = ["# A change's effect on the default 3D path", "",
             "Written by `benchmarks/build_profile.py` from `build_profile.json`. The Gregoire D = 200 mm half-notched beam (3D, "
             "dx = 5 mm, 56,000 nodes) under its default path following (IMPL-EX, damage error 0.03 per step) to 10 % of its peak, "
             "two ranks, `-log_view`: a binary built from the baseline commit and one built from the change's, one after the other "
             "in one invocation. Event times are the solve stage's (s, the largest over the ranks); the ratio is of wall times. "
             "Curves: the columns of curve.csv (all but the wall time) in which the two runs differ, with the largest relative "
             "difference; none means the same bits. Peak memory: the ranks' largest resident sets summed, as `summary.json` "
             "reports it (- where the entry predates the column).", ""]
    for label in sorted(res, key=lambda k: res[k]["order"]):
        r = res[label]
        lines += ["## " + label, "", "| build | commit | wall (s) | solve stage (s) | " + " | ".join(EVENTS) + " | steps / Newton / Krylov | peak (N) | peak memory (MB) |",
                  "|---|---|---|---|" + "---|" * len(EVENTS) + "---|---|---|"]
        for name in ("baseline", "change"):
            x = r[name]
            mem = "%.0f" % (x["peak_rss_bytes"] / 1e6) if x.get("peak_rss_bytes") else "-"
            lines.append("| %s | %s | %.1f | %.1f | %s | %s / %s / %s | %.1f | %s |" % (
                name, x["commit"], x["wall_s"], x["solve_stage_s"], " | ".join("%.1f" % x["events_s"].get(e, 0) for e in EVENTS), x["steps"],
                x["newton_its"], x["ksp_its"], x["peak_N"], mem))
        lines += ["", "Wall time of the change over the baseline's: %.2f. Curves: %s." % (
            r["change"]["wall_s"] / r["baseline"]["wall_s"],
            ", ".join("%s %.1e" % (k, v) for k, v in sorted(r["curve_difference"].items())) or "none"), ""]
    lines += ["Command: `benchmarks/build_profile.py --label TEXT --baseline PATH --baseline-commit SHA` (PATH a binary built from "
              "the baseline commit); each run is `mpiexec -n 2 build/pdimplicit " + " ".join(SCENE).replace(ROOT + os.sep, "") + " -log_view`.", ""]
    open(os.path.join(OUT, "build_profile.md"), "w").write("\n".join(lines))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--label")
    ap.add_argument("--baseline")
    ap.add_argument("--baseline-commit")
    ap.add_argument("--report", action="store_true")
    a = ap.parse_args()
    if not a.report:
        base = run(a.baseline)
        new = run(EXE)
        base["commit"], new["commit"] = a.baseline_commit, commit()
        diff = compare(base.pop("rows"), new.pop("rows"))
        store_result(JSON, a.label, {"order": len(load_results(JSON)), "baseline": base, "change": new, "curve_difference": diff})
    report()


if __name__ == "__main__":
    main()
