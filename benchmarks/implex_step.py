#!/usr/bin/python3
"""How the damage error per IMPL-EX step (-pd_arclength_implex) trades accuracy for time on a 3D beam: the
D = 200 mm fifth-notched Gregoire beam at dx = 5 mm on two ranks, traced by path following to 10 % of its peak
(the options of benchmarks/size_effect.py) at several errors, one after the other in one invocation. Peaks and
RMS load differences (over the CMOD range both reach, over the peak) are against the smallest error run. Writes
docs/benchmarks/implex_step.json and implex_step.md (about 7 minutes).

Usage: benchmarks/implex_step.py [--report] [--errors 0.06 0.03 0.015]
"""
import argparse
import os

import numpy as np

from common import RESULTS_DIR, load_results, run_scene, save_results, write_lines

JSON = os.path.join(RESULTS_DIR, "implex_step.json")
SCENE, DX, RANKS = "gregoire_d200_fn", 0.005, 2


def measure(errors):
    res = load_results(JSON)
    res.setdefault("runs", {})
    for t in errors:
        args = ["-pd_dx", str(DX), "-pd_control", "arclength", "-pd_stop_fraction", "0.1", "-pd_arclength_implex", str(t)]
        r = run_scene(SCENE, args, 3600, ranks=RANKS)
        rows = r["rows"] or []
        res["runs"]["%g" % t] = {"error": t, "options": args, "wall_s": round(r["wall"], 1), "exit": r["code"],
                                 "status": r["summary"]["status"] if r["summary"] else None, "steps": len(rows),
                                 "newton_its": r["summary"]["newton_its"] if r["summary"] else None,
                                 "ksp_its": r["summary"]["ksp_its"] if r["summary"] else None,
                                 "curve": [[q["cmod_m"], q["load_N"]] for q in rows]}
        print(t, {k: v for k, v in res["runs"]["%g" % t].items() if k != "curve"})
        save_results(JSON, res)


def report():
    res = load_results(JSON)
    runs = sorted(res["runs"].values(), key=lambda r: -r["error"])
    ref = min(runs, key=lambda r: r["error"])
    xs, ys = np.array([c[0] for c in ref["curve"]]), np.array([c[1] for c in ref["curve"]])
    peak = ys.max()
    lines = ["# The damage error per IMPL-EX step against accuracy and time", "",
             "Written by `benchmarks/implex_step.py` from `implex_step.json`. `options/%s.opts` at dx = %g mm on %d ranks, path "
             "following with IMPL-EX steps to 10 %% of the peak (`-pd_control arclength -pd_stop_fraction 0.1 -pd_arclength_implex "
             "ERROR`), the runs one after the other in one invocation. Peak and RMS differences (over the CMOD range both reach, over "
             "the peak) against the run with the smallest error; wall times as ratios to it." % (SCENE, 1e3 * DX, RANKS), "",
             "| damage error per step | steps | Newton | Krylov | wall (s) | wall / smallest error's | peak (N) | peak vs smallest error | RMS vs smallest error |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in runs:
        load = np.array([c[1] for c in r["curve"]])
        cm = np.array([c[0] for c in r["curve"]])
        keep = (cm >= xs[0]) & (cm <= xs[-1])
        rms = np.sqrt(np.mean((load[keep] - np.interp(cm[keep], xs, ys)) ** 2)) / peak
        lines.append("| %g | %d | %d | %d | %.1f | %.2f | %.0f | %+.2f %% | %.2f %% |" % (
            r["error"], r["steps"], r["newton_its"], r["ksp_its"], r["wall_s"], r["wall_s"] / ref["wall_s"], load.max(),
            100 * (load.max() / peak - 1), 100 * rms))
    write_lines("implex_step.md", lines)


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--errors", type=float, nargs="+", default=[0.06, 0.03, 0.015])
    ap.add_argument("--report", action="store_true")
    a = ap.parse_args()
    if not a.report:
        measure(a.errors)
    report()
