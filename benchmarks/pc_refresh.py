#!/usr/bin/python3
"""Levers of the linear solves of 3D models under GAMG. When to rebuild the preconditioner: every third assembly (the earlier default),
never (built once, from the elastic tangent), or when the Krylov solver finds it stale (the default for
3D models under GAMG, src/solve/pc_refresh.c); and, with the last, one Chebyshev smoothing step per
multigrid level instead of two, and with every row of the matrix rewritten at each assembly. The Gregoire D = 100 mm half-notched beam, dx = 5 mm (14,000 nodes), to
CMOD 0.12 mm, past its peak. The same beam under path following with IMPL-EX to CMOD 30 um: the path
direction's and the first correction's Krylov solves started from the last ones (the default) or from zero, and
whole assemblies.
Path following's linear tolerances: matched to Newton's need (the default: the corrector's solve stops at
half of Newton's tolerance, the predictor's direction at 1e-4) against fixed ones (-ksp_rtol 1e-8 for every
solve) and the solves before that (fixed, and GMRES preconditioned on the left), on the D = 100 mm beam
under IMPL-EX and the D = 50 mm half-notched beam (3,500 nodes) traced to 10 % of its peak, implicit and
under IMPL-EX. Each configuration of a beam runs one after the other in one invocation. CPU times are
the runs' own (wait4); ratios are taken on the default's. Writes docs/benchmarks/pc_refresh.json and
pc_refresh.md (about 30 minutes on one core).

Usage: benchmarks/pc_refresh.py [d100] [d100_implex] [d50_arclength] [d50_implex] [--report]   (the beams named, all by default)
"""
import csv
import json
import os
import sys
import tempfile

from common import EXE, OUT, RESULTS_DIR, ROOT, curve_difference, load_results, run_timed, save_results

JSON = os.path.join(RESULTS_DIR, "pc_refresh.json")
# beam -> scene, options every configuration gets, what it is
BEAMS = {"d100": ("gregoire_d100_hn.opts", ["-pd_stop_cmod", "1.2e-4"],
                  "D = 100 mm half-notched, dx = 5 mm, 14,000 nodes, GAMG, to CMOD 0.12 mm"),
         "d100_implex": ("gregoire_d100_hn.opts", ["-pd_control", "arclength", "-pd_arclength_implex", "0.03", "-pd_stop_cmod", "3e-5"],
                         "D = 100 mm half-notched, dx = 5 mm, 14,000 nodes, GAMG, path following with IMPL-EX 0.03 to CMOD 30 um"),
         "d50_arclength": ("gregoire_d50_hn.opts", ["-pd_control", "arclength", "-pd_stop_fraction", "0.1", "-pd_stop_cmod", "0",
                                                    "-pd_lambda_max", "4", "-pd_steps", "800"],
                           "D = 50 mm half-notched, dx = 5 mm, 3,500 nodes, GAMG, path following (CMOD, limiter) to 10 % of the peak"),
         "d50_implex": ("gregoire_d50_hn.opts", ["-pd_control", "arclength", "-pd_arclength_implex", "0.03", "-pd_stop_fraction", "0.1",
                                                 "-pd_stop_cmod", "0", "-pd_lambda_max", "4", "-pd_steps", "800"],
                        "D = 50 mm half-notched, dx = 5 mm, 3,500 nodes, GAMG, path following with IMPL-EX 0.03 to 10 % of the peak")}
# path following's linear solves: fixed tolerances for every solve, and the solves before they were matched to Newton's need
# (with the equilibrium tolerance IMPL-EX steps had then)
FIXED = ("fixed linear tolerances", ["-ksp_rtol", "1e-8", "-pd_arclength_rtol", "1e-7"])
PREVIOUS = ("previous linear solves", ["-ksp_rtol", "1e-8", "-ksp_pc_side", "left", "-pd_augmented_ksp_type", "gmres",
                                       "-pd_augmented_ksp_pc_side", "left", "-pd_arclength_rtol", "1e-7"])
# IMPL-EX steps in equilibrium to the implicit steps' tolerance instead of their own (src/solve/arclength.c)
IMPLEX_TIGHT = ("equilibrium to 1e-7", ["-pd_arclength_rtol", "1e-7"])
# label -> options, per beam
CONFIGS = {"d100": [("rebuilt when stale (default)", []), ("every third assembly", ["-snes_lag_preconditioner", "3"]),
                    ("never rebuilt", ["-snes_lag_preconditioner", "-2"]),
                    ("rebuilt when stale, one smoothing step", ["-mg_levels_ksp_max_it", "1"]),
                    # every row of the AIJ matrix rewritten at every assembly (the earlier default; docs/solvers.md "Assembly")
                    ("rebuilt when stale, whole assembly", ["-pd_assembly_changed_rows", "false"])],
           # IMPL-EX: two Krylov solves per step; the path direction's and the first correction's started from zero instead
           # of from the last ones (docs/arclength.md), and every row of the matrix rewritten at each assembly
           "d100_implex": [("default", []), ("solves from zero", ["-pd_arclength_guess", "false"]),
                           ("whole assembly", ["-pd_assembly_changed_rows", "false"]), IMPLEX_TIGHT, FIXED, PREVIOUS],
           "d50_arclength": [("default", []), FIXED, PREVIOUS],
           "d50_implex": [("default", []), IMPLEX_TIGHT, FIXED, PREVIOUS]}
EVENTS = ["PCSetUp", "PCApply", "MatMult", "KSPSolve", "PDAssembly"]


def events(path):
    ev = {}
    for line in open(path):
        p = line.split()
        if p and p[0] in EVENTS and len(p) > 4:
            ev[p[0]] = ev.get(p[0], 0) + float(p[3])
    return ev


def run(beam, extra):
    scene, common, _ = BEAMS[beam]
    out = tempfile.mkdtemp(prefix="pdrefresh_")
    logf = os.path.join(out, "log_view.txt")
    with open(os.path.join(out, "stdout.txt"), "w") as f:
        code, wall, cpu, _ = run_timed([EXE, "-options_file", os.path.join(ROOT, "options", scene), "-pd_output_dir", out,
                                        "-log_view", ":" + logf, *common, *extra], 7200, f)
    s = json.load(open(os.path.join(out, "summary.json")))
    rows = list(csv.DictReader(open(os.path.join(out, "curve.csv"))))
    return {"exit": code, "status": s["status"], "cpu_s": round(cpu, 1), "wall_s": round(wall, 1), "newton_its": s["newton_its"],
            "ksp_its": s["ksp_its"], "peak_N": s["peak_load_N"], "events_s": events(logf),
            "curve": [[float(r["cmod_m"]), float(r["load_N"])] for r in rows]}


def report():
    res = load_results(JSON)
    lines = ["# Linear solves under GAMG: when to rebuild the preconditioner, and what else they cost", "",
             "Written by `benchmarks/pc_refresh.py` from `pc_refresh.json`. One rank; the configurations of a beam ran one after "
             "the other in one invocation, and the ratios are of CPU time (the run's own, from wait4) over the default's. "
             "Event times are `-log_view`'s for the whole run (s). Peak and RMS curve difference against the default.", ""]
    for beam, (scene, common, what) in BEAMS.items():
        runs = res.get(beam)
        if not runs:
            continue
        ref = runs[CONFIGS[beam][0][0]]
        lines += ["## %s" % what, "",
                  "| configuration | CPU (s) | CPU over default's | Newton | KSP | PCSetUp (s) | PCApply (s) | MatMult (s) | PDAssembly (s) | "
                  "peak (N) | peak vs default | RMS vs default | status |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for label, extra in CONFIGS[beam]:
            r = runs[label]
            e = r["events_s"]
            lines.append("| %s | %.1f | %.2f | %d | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %+.3f %% | %.3f %% | %s |" % (
                label, r["cpu_s"], r["cpu_s"] / ref["cpu_s"], r["newton_its"], r["ksp_its"], e.get("PCSetUp", 0), e.get("PCApply", 0),
                e.get("MatMult", 0), e.get("PDAssembly", 0), r["peak_N"], 100 * (r["peak_N"] / ref["peak_N"] - 1), 100 * curve_difference(ref, r), r["status"]))
        lines += ["", "Commands:", ""]
        lines += [("    build/pdimplicit -options_file options/%s %s %s" % (scene, " ".join(common), " ".join(extra))).rstrip()
                  for _, extra in CONFIGS[beam]]
        lines.append("")
    open(os.path.join(OUT, "pc_refresh.md"), "w").write("\n".join(lines))


if __name__ == "__main__":
    args = sys.argv[1:]
    if "--report" not in args:
        for beam in [b for b in BEAMS if not args or b in args]:
            runs = {}
            for label, extra in CONFIGS[beam]:
                runs[label] = run(beam, extra)
                print(beam, label, {k: v for k, v in runs[label].items() if k != "curve"}, flush=True)
            res = load_results(JSON)
            res[beam] = runs
            save_results(JSON, res)
    report()
