#!/usr/bin/python3
"""Pull-out of a bar under the bond-slip law (options/pullout.opts): a 12 mm bar bonded over 60 mm in an
elastic 150 mm concrete cube, pulled out by 6 mm. The force against the loaded end's slip, next to the law's
tau(s) pi d L (fib Model Code 2010, pull-out, good bond, f_cm = 38 MPa), which it follows where the bond
stress is uniform along the bar. Writes docs/benchmarks/pullout.json, pullout.md and pullout.png (seconds).

Usage: benchmarks/pullout.py [--report]
"""
import math
import os
import sys
import tempfile

from common import curve_rows, EXE, RESULTS_DIR, ROOT, load_results, run_timed, save_results, pyplot, save_figure, write_lines

JSON = os.path.join(RESULTS_DIR, "pullout.json")
SCENE = os.path.join(ROOT, "options", "pullout.opts")
D, L, FCM = 0.012, 0.06, 38e6
SLIPS = (0.1e-3, 0.2e-3, 0.5e-3, 1e-3, 1.5e-3, 2e-3, 3e-3, 4e-3, 5e-3, 6e-3)


def law_force(s):
    """tau(s) pi d L (N): s1 = 1 mm, s2 = 2 mm, s3 = 0.6 d, tau_max = 2.5 sqrt(f_cm), tau_f = 0.4 tau_max."""
    tmax, s1, s2, s3 = 2.5 * math.sqrt(FCM / 1e6) * 1e6, 1e-3, 2e-3, 0.6 * D
    tau = tmax * (s / s1) ** 0.4 if s <= s1 else tmax if s <= s2 else tmax - 0.6 * tmax * (min(s, s3) - s2) / (s3 - s2)
    return tau * math.pi * D * L


def measure():
    out = tempfile.mkdtemp(prefix="pdbench_")
    with open(os.path.join(out, "log"), "w") as log:
        code, wall, cpu, _ = run_timed([EXE, "-options_file", SCENE, "-pd_output_dir", out], 600, log)
    rows = curve_rows(out)
    res = {"exit": code, "cpu_s": round(cpu, 2), "steps": len(rows), "newton": int(sum(r["newton_its"] for r in rows)),
           "curve": [[r["slip_m"], r["load_N"]] for r in rows]}
    save_results(JSON, res)


def at(curve, s):
    """The force at slip s, linear between the rows."""
    for (s0, f0), (s1, f1) in zip(curve, curve[1:]):
        if s0 <= s <= s1:
            return f0 + (f1 - f0) * (s - s0) / (s1 - s0)
    return float("nan")


def report():
    res = load_results(JSON)
    c = res["curve"]
    lines = ["# Pull-out under the bond-slip law", "",
             "Written by `benchmarks/pullout.py` from `pullout.json`. `options/pullout.opts`: a 12 mm bar bonded over L = 60 mm in an "
             "elastic 150 mm concrete cube (dx = 10 mm, 6 bar nodes), pulled out by 6 mm in 60 increments; %d steps, %d Newton "
             "iterations, %.1f s CPU. Force against the slip of the loaded end, and the law's tau(s) pi d L (fib Model Code 2010, "
             "pull-out, good bond, f_cm = 38 MPa: tau_max = %.2f MPa). Below s1 the bond stress is not uniform: the loaded end "
             "slips more than the rest of the bar, by the bar's stretch and the concrete's, and the force is below the law at "
             "the loaded end's slip." % (res["steps"], res["newton"], res["cpu_s"], 2.5 * math.sqrt(FCM / 1e6)), "",
             "| slip (mm) | force (N) | tau(s) pi d L (N) | ratio |", "|---|---|---|---|"]
    for s in SLIPS:
        f = at(c, s)
        lines.append("| %.1f | %.0f | %.0f | %.4f |" % (1e3 * s, f, law_force(s), f / law_force(s)))
    lines += ["", "![force against slip](pullout.png)", "", "Command: `build/pdimplicit -options_file options/pullout.opts`"]
    write_lines("pullout.md", lines)
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    xs = [1e-5 * i for i in range(1, 601)]
    ax.plot([1e3 * x for x in xs], [law_force(x) / 1e3 for x in xs], "k--", label="tau(s) pi d L (fib MC2010)")
    ax.plot([1e3 * s for s, _ in c], [f / 1e3 for _, f in c], "o-", ms=3, label="pdimplicit")
    ax.set_xlabel("slip of the loaded end (mm)")
    ax.set_ylabel("pull-out force (kN)")
    ax.legend()
    save_figure(fig, "pullout.png", dpi=100)


if __name__ == "__main__":
    if "--report" not in sys.argv[1:]:
        measure()
    report()
