#!/usr/bin/python3
"""Mixed-mode and tension hard cases on the default path, traced until the load falls below 10 % of its
peak: the eccentric-notch beam under displacement control and under a force (whose control hands over to
path following past the peak), the double-edge-notched prism in tension (whose snap-back needs path
following, then IMPL-EX), and the L-shaped panel under path following. One rank, the shipped scenes as they
are. Writes docs/benchmarks/hard_cases.json, hard_cases.md and hard_cases.png (about a minute).

Usage: benchmarks/hard_cases.py [--report]
"""
import csv
import json
import os
import sys
import tempfile

from common import EXE, OUT, RESULTS_DIR, ROOT, run_timed, save_results, pyplot, save_figure

JSON = os.path.join(RESULTS_DIR, "hard_cases.json")


def scene(name):
    return os.path.join(ROOT, "options", name + ".opts")


def force_variant():
    """The eccentric-notch beam with its displacement region turned into a 4 kN force."""
    path = os.path.join(tempfile.mkdtemp(prefix="pdbench_"), "eccentric_force.opts")
    with open(scene("eccentric_notch_2d")) as f, open(path, "w") as g:
        g.writelines(l for l in f if not l.startswith(("-pd_region2_kind", "-pd_region2_dofs", "-pd_region2_displacement")))
    return [path, "-pd_region2_kind", "force", "-pd_region2_force", "0,-4000"]


# name, what, options file and extra options, curve abscissa
CASES = [
    ("eccentric_displacement", "eccentric-notch beam, displacement control", lambda: [scene("eccentric_notch_2d")], "cmod_m"),
    ("eccentric_force", "eccentric-notch beam, 4 kN force (load control)", force_variant, "cmod_m"),
    ("den_tension", "double-edge-notched prism in tension, displacement control", lambda: [scene("den_tension_2d")], "cmod_m"),
    ("l_panel", "L-shaped panel, path following (-pd_control arclength)", lambda: [scene("l_panel_2d")], "disp_m"),
]


def run_case(opts):
    out = tempfile.mkdtemp(prefix="pdbench_")
    cmd = [EXE, "-options_file"] + opts + ["-pd_output_dir", out]
    with open(os.path.join(out, "log.txt"), "w") as log:
        code, wall, cpu, _ = run_timed(cmd, 1800, log)
    s = json.load(open(os.path.join(out, "summary.json")))
    rows = list(csv.DictReader(open(os.path.join(out, "curve.csv"))))
    return code, cpu, s, rows


def main():
    res = {"cases": {}}
    for name, what, opts, xkey in CASES:
        code, cpu, s, rows = run_case(opts())
        fb = s.get("path_following_from")
        res["cases"][name] = {
            "what": what, "exit": code, "status": s["status"], "cpu_s": cpu, "steps": s["steps"], "newton_its": s["newton_its"],
            "ksp_its": s["ksp_its"], "peak_load_N": s["peak_load_N"], "final_load_N": s["final_load_N"], "dissipated_J":
            float(rows[-1]["dissipated_J"]), "handover_step": fb["step"] if fb else 0, "implex_from_step": fb["implex_from_step"] if fb else 0,
            "x": xkey, "curve": [[float(r[xkey]), float(r["load_N"])] for r in rows]}
        print(name, s["status"], "%.1f s" % cpu, flush=True)
    save_results(JSON, res)
    report(res)


def report(res):
    lines = ["# Hard cases on the default path", "",
             "Written by `benchmarks/hard_cases.py` from `hard_cases.json`: the shipped 2D scenes at their own spacing (5 mm; the "
             "L-panel 10 mm), one rank, each traced until the load falls below 10 % of its peak. Plain control hands over to path "
             "following where it finds no equilibrium (`-pd_control_fallback`), and path following to IMPL-EX where Newton "
             "cannot settle which softened bonds load and which unload (docs/arclength.md, \"The default path\"). CPU times "
             "are the runs' own.", "",
             "| case | status | steps | path following from step | IMPL-EX from step | Newton | KSP | peak (N) | final / peak | "
             "dissipated (J) | CPU (s) |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for name in [c[0] for c in CASES]:
        c = res["cases"][name]
        lines.append("| %s | %s | %d | %s | %s | %d | %d | %.1f | %.3f | %.4f | %.1f |" % (
            c["what"], c["status"].split(":")[0], c["steps"], c["handover_step"] or "-", c["implex_from_step"] or "-", c["newton_its"],
            c["ksp_its"], c["peak_load_N"], c["final_load_N"] / c["peak_load_N"], c["dissipated_J"], c["cpu_s"]))
    e, f = res["cases"]["eccentric_displacement"], res["cases"]["eccentric_force"]
    lines += ["", "The eccentric-notch beam's peak under a force is %.2f %% from its peak under displacement control; at 10 %% of the "
              "peak the two have dissipated %.4f and %.4f J. The curves: `hard_cases.png`." % (
                  100 * (f["peak_load_N"] / e["peak_load_N"] - 1), f["dissipated_J"], e["dissipated_J"]), ""]
    with open(os.path.join(OUT, "hard_cases.md"), "w") as fo:
        fo.write("\n".join(lines))
    try:
        plt = pyplot()
    except ImportError:
        return
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    panels = [("eccentric-notch beam", ["eccentric_displacement", "eccentric_force"], "CMOD (mm)"),
              ("double-edge-notched prism", ["den_tension"], "notch opening (mm)"),
              ("L-shaped panel", ["l_panel"], "load-point displacement (mm)")]
    for ax, (title, names, xlabel) in zip(axes, panels):
        for n in names:
            c = res["cases"][n]
            x = [1e3 * p[0] for p in c["curve"]]
            y = [1e-3 * p[1] for p in c["curve"]]
            ax.plot(x, y, ".-", ms=2, lw=1, label=c["what"].split(", ")[-1])
            if c["handover_step"]:
                k = c["handover_step"] - 1
                ax.plot([x[k]], [y[k]], "o", mfc="none", color="k", label="path following from here")
            if c["implex_from_step"]:
                k = c["implex_from_step"] - 1
                ax.plot([x[k]], [y[k]], "s", mfc="none", color="r", label="IMPL-EX from here")
        ax.set_title(title)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("load (kN)")
        ax.legend(fontsize=7)
    save_figure(fig, "hard_cases.png", dpi=110)


if __name__ == "__main__":
    if "--report" in sys.argv:
        report(json.load(open(JSON)))
    else:
        main()
