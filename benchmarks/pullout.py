#!/usr/bin/python3
"""Pull-out of a bar under the bond-slip law (options/pullout.opts, options/pullout_inclined.opts): a 12 mm bar bonded
over 60 mm in an elastic 150 mm concrete cube, pulled out by 6 mm, on its chain of lattice nodes or embedded, along x
and along a direction no lattice has. The force against the loaded end's slip, next to the law's
tau(s) pi d L (fib Model Code 2010, pull-out, good bond, f_cm = 38 MPa), which it follows where the bond
stress is uniform along the bar. Writes docs/benchmarks/pullout.json, pullout.md and pullout.png (a minute).

Usage: benchmarks/pullout.py [--report]
"""
import json
import math
import os
import sys
import tempfile

from common import curve_rows, EXE, RESULTS_DIR, ROOT, load_results, run_timed, save_results, pyplot, save_figure, write_lines

JSON = os.path.join(RESULTS_DIR, "pullout.json")
D, L, FCM = 0.012, 0.06, 38e6
SLIPS = (0.1e-3, 0.2e-3, 0.5e-3, 1e-3, 1.5e-3, 2e-3, 3e-3, 4e-3, 5e-3, 5.9e-3)  # an embedded bar's end slips 6 mm less its anchor's give
SOFTENING = ["-pd_law", "nonlinear", "-pd_ft", "3e6", "-pd_Gf", "100"]
# (scene, options): the bar on its chain of lattice nodes, the same bar embedded (on nodes of its own at its true
# places, anchored to the concrete), and an embedded bar along (0.8, 0.36, 0.48), which no lattice direction holds
CASES = {"on its chain of nodes, along x": ("pullout", []), "embedded, along x": ("pullout", ["-pd_bar0_embedded", "true"]),
         "embedded, along (0.8, 0.36, 0.48)": ("pullout_inclined", []),
         "embedded, along (0.8, 0.36, 0.48), dx = 5 mm": ("pullout_inclined", ["-pd_dx", "0.005"]),
         # in concrete that cracks (the non-linear law, f_t = 3 MPa, G_F = 100 N/m): an embedded bar's anchor ties behind
         # its nodes soften under the bond stress (docs/reinforcement.md)
         "on its chain of nodes, along x, softening concrete": ("pullout", SOFTENING),
         "embedded, along x, softening concrete": ("pullout", SOFTENING + ["-pd_bar0_embedded", "true"])}


def law_force(s):
    """tau(s) pi d L (N): s1 = 1 mm, s2 = 2 mm, s3 = 0.6 d, tau_max = 2.5 sqrt(f_cm), tau_f = 0.4 tau_max."""
    tmax, s1, s2, s3 = 2.5 * math.sqrt(FCM / 1e6) * 1e6, 1e-3, 2e-3, 0.6 * D
    tau = tmax * (s / s1) ** 0.4 if s <= s1 else tmax if s <= s2 else tmax - 0.6 * tmax * (min(s, s3) - s2) / (s3 - s2)
    return tau * math.pi * D * L


def command(case):
    scene, extra = CASES[case]
    return ["-options_file", os.path.join("options", scene + ".opts")] + extra


def measure():
    res = {"runs": {}}
    for case in CASES:
        out = tempfile.mkdtemp(prefix="pdbench_")
        with open(os.path.join(out, "log"), "w") as log:
            code, wall, cpu, _ = run_timed([EXE] + [os.path.join(ROOT, a) if a.startswith("options/") else a for a in command(case)] +
                                           ["-pd_output_dir", out], 1200, log)
        rows = curve_rows(out)
        with open(os.path.join(out, "summary.json")) as f:
            bars = json.load(f)["bars"]
        res["runs"][case] = {"exit": code, "cpu_s": round(cpu, 2), "steps": len(rows), "newton": int(sum(r["newton_its"] for r in rows)),
                             "bar_nodes": bars["bar_nodes"], "anchor_nodes": bars["anchor_nodes"],
                             "curve": [[r["slip_m"], r["load_N"]] for r in rows]}
        print(case, {k: v for k, v in res["runs"][case].items() if k != "curve"}, flush=True)
    save_results(JSON, res)


def at(curve, s):
    """The force at slip s, linear between the rows."""
    for (s0, f0), (s1, f1) in zip(curve, curve[1:]):
        if s0 <= s <= s1:
            return f0 + (f1 - f0) * (s - s0) / (s1 - s0)
    return float("nan")


def report():
    stored = load_results(JSON)["runs"]
    runs = {c: stored[c] for c in CASES if c in stored}
    lines = ["# Pull-out under the bond-slip law", "",
             "Written by `benchmarks/pullout.py` from `pullout.json`. `options/pullout.opts`: a 12 mm bar bonded over L = 60 mm in an "
             "elastic 150 mm concrete cube (dx = 10 mm), pulled out by 6 mm in 60 increments, its bar on the chain of lattice nodes "
             "along x or embedded (on nodes of its own at its true places, anchored to the concrete of their lattice cells: "
             "docs/reinforcement.md), `options/pullout_inclined.opts`, the same bar embedded along (0.8, 0.36, 0.48), and the first two "
             "in concrete that cracks (the non-linear law, f_t = 3 MPa, G_F = 100 N/m), where an embedded bar's anchor ties behind "
             "its nodes soften under the bond stress. Force "
             "against the slip of the loaded end, over the law's tau(s) pi d L (fib Model Code 2010, pull-out, good bond, f_cm = "
             "38 MPa: tau_max = %.2f MPa). Below s1 the bond stress is not uniform: the loaded end slips more than the rest of the "
             "bar, by the bar's stretch and the concrete's, and the force is below the law at the loaded end's slip." %
             (2.5 * math.sqrt(FCM / 1e6)), "",
             "| bar | bar nodes | anchor nodes | steps | Newton | CPU (s) |", "|---|---|---|---|---|---|"]
    for case, r in runs.items():
        lines.append("| %s | %d | %d | %d | %d | %.1f |" % (case, r["bar_nodes"], r["anchor_nodes"], r["steps"], r["newton"], r["cpu_s"]))
    lines += ["", "Force over tau(s) pi d L:", "", "| slip (mm) | tau(s) pi d L (N) | " + " | ".join(runs) + " |",
              "|---|---|" + "---|" * len(runs)]
    for s in SLIPS:
        lines.append("| %.1f | %.0f | %s |" % (1e3 * s, law_force(s), " | ".join("%.4f" % (at(r["curve"], s) / law_force(s)) for r in runs.values())))
    lines += ["", "![force against slip](pullout.png)", "", "Commands: " + "; ".join(
        "`build/pdimplicit %s`" % " ".join(command(c)) for c in runs)]
    write_lines("pullout.md", lines)
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    xs = [1e-5 * i for i in range(1, 601)]
    ax.plot([1e3 * x for x in xs], [law_force(x) / 1e3 for x in xs], "k--", label="tau(s) pi d L (fib MC2010)")
    for (case, r), mark in zip(runs.items(), "osd^vx"):
        ax.plot([1e3 * s for s, _ in r["curve"]], [f / 1e3 for _, f in r["curve"]], mark + "-", ms=3, label=case)
    ax.set_xlabel("slip of the loaded end (mm)")
    ax.set_ylabel("pull-out force (kN)")
    ax.legend(fontsize=7)
    save_figure(fig, "pullout.png", dpi=100)


if __name__ == "__main__":
    if "--report" not in sys.argv[1:]:
        measure()
    report()
