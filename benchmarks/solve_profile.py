#!/usr/bin/python3
"""Where an implicit softening run spends its time, from PETSc's -log_view, and what the solver's levers
change: the Gregoire D = 50 mm half-notched beam (the default scene) under displacement control to CMOD
0.2 mm, each configuration run one after the other in one invocation so that their ratios are taken on
the same machine state. Writes docs/benchmarks/solve_profile.json and solve_profile.md.

Usage: benchmarks/solve_profile.py [--dx 5e-3] [--configs "default,previous defaults"] [--jobs 1] [--timeout 1800] [--report]
--configs runs only the configurations named (all by default); --jobs 2 runs two at a time, one a core (the
CPU times stay each run's own; at dx = 2.5 mm a run takes tens of minutes).
"""
import argparse
import csv
import json
import os
import re
import tempfile
from concurrent.futures import ThreadPoolExecutor

from common import EXE, RESULTS_DIR, OUT, ROOT, curve_difference, load_results, run_timed, save_results, store_result

RESULTS = os.path.join(RESULTS_DIR, "solve_profile.json")
SCENE = os.path.join(ROOT, "options", "gregoire_d50_hn.opts")
# configurations compared: label -> extra options. "limiter cap 1" is the most resolved curve (one bond event
# per Newton iteration), the reference that peaks and curves are measured against besides the default
REFERENCE = "limiter cap 1"
EARLIER_CAP = "earlier limiter cap"
CONFIGS = {"default": [], REFERENCE: ["-pd_limiter_max_bonds", "1"],
           # the defaults before the increment's first Newton iteration became a limiter stage (design note 42),
           # block ICC(0) was rebuilt every sixth assembly instead of every third (src/solve/pc_refresh.c), GMRES
           # preconditioned on the right with linear solves stopped at Newton's tolerance, later assemblies
           # rewrote only the rows that changed, Krylov solves applied the tangent from the bond scalars and
           # GAMG took over from block ICC(0) at 2,000 nodes (docs/solvers.md), and each alone
           "previous defaults": ["-pd_limiter_settle_first", "true", "-snes_lag_preconditioner", "3", "-ksp_pc_side", "left",
                                 "-pd_assembly_changed_rows", "false", "-pd_tangent_product", "matrix", "-pc_type", "bjacobi",
                                 "-pd_mat_type", "sbaij", "-pd_tangent_with_residual", "false"],
           # the defaults before FGMRES replaced right-preconditioned GMRES, the AIJ diagonal was read through an
           # index, the tangent scalars came from the residual's bond loop and a residual after a limiter grant
           # recomputed only the rows it changed, and each alone (the residual's rows need the residual's
           # displacement record, which its tangent scalars keep: "tangent's own loop" turns off both)
           "last defaults": ["-ksp_type", "gmres", "-ksp_gmres_restart", "60", "-pd_diagonal_index", "false",
                             "-pd_tangent_with_residual", "false"],
           "GMRES": ["-ksp_type", "gmres", "-ksp_gmres_restart", "60"],
           "diagonal by search": ["-pd_diagonal_index", "false"],
           "tangent's own loop": ["-pd_tangent_with_residual", "false"],
           "whole residual after a grant": ["-pd_residual_rows", "false"],
           "block ICC(0)": ["-pc_type", "bjacobi", "-pd_mat_type", "sbaij", "-ksp_pc_side", "right"],
           # GAMG asked for where the model is below the 2,000 nodes it is the default from
           "GAMG": ["-pc_type", "gamg", "-ksp_pc_side", "right"],
           "whole assembly": ["-pd_assembly_changed_rows", "false"],
           # the preconditioning matrix with every bond, as before it kept only those up to 2.25 grid spacings
           "whole preconditioning matrix": ["-pd_pc_reach", "0"], "preconditioning reach 1.75": ["-pd_pc_reach", "1.75"],
           "matrix product": ["-pd_tangent_product", "matrix"],
           # the product from the bond scalars looped over the bond list, as before it looped over the stencil's
           # offsets (docs/design.md, point 60)
           "bond-list product": ["-pd_stencil_product", "false"],
           "settle first": ["-pd_limiter_settle_first", "true"], "preconditioner lag 3": ["-snes_lag_preconditioner", "3"],
           # (GMRES: FGMRES preconditions on the right only)
           "left preconditioned": ["-ksp_type", "gmres", "-ksp_gmres_restart", "60", "-ksp_pc_side", "left"],
           # right preconditioning with linear solves stopped at Newton's tolerance is the default: the row
           # repeats the default's run and shows the machine's noise
           "right preconditioned": ["-ksp_pc_side", "right"],
           # looser equilibrium: fewer iterations here, but not kept (docs/solvers.md)
           "snes_rtol 1e-5": ["-snes_rtol", "1e-5"], "snes_rtol 1e-4": ["-snes_rtol", "1e-4"],
           "no predictor": ["-pd_predictor", "false"],
           # the default cap before it rose from 10 to 15 events per 150,000 bonds (docs/solvers.md): options
           # computed from the bond count of this spacing's default run
           EARLIER_CAP: lambda bonds: ["-pd_limiter_max_bonds", str(max(10, int(10 * bonds / 150000 + 0.5)))],
           "limiter cap 5": ["-pd_limiter_max_bonds", "5"], "limiter cap 20": ["-pd_limiter_max_bonds", "20"], "limiter cap 40": ["-pd_limiter_max_bonds", "40"],
           "limiter cap 80": ["-pd_limiter_max_bonds", "80"], "no limiter cap": ["-pd_limiter_max_bonds", "0"],
           # linear solves and preconditioner: a fixed linear tolerance instead of Eisenstat-Walker, block ICC with
           # one level of fill, and the preconditioner built from the (positive) secant stiffness instead of the
           # indefinite tangent
           "linear rtol 1e-2": ["-snes_ksp_ew", "false", "-ksp_rtol", "1e-2"],
           "ICC(1)": ["-pc_type", "bjacobi", "-pd_mat_type", "sbaij", "-ksp_pc_side", "right", "-sub_pc_factor_levels", "1"],
           "secant preconditioner": ["-pd_pc_matrix", "secant"]}
# -log_view events reported, in this order: pdimplicit's own (include/pd_log.h) and PETSc's solver events
EVENTS = ["PDBondForce", "PDBondTangent", "PDAssembly", "PDTangentProduct", "PDLimiter", "PDHistory", "PDEnergy", "PDFieldsWrite", "KSPSolve", "PCSetUp",
          "PCApply", "MatMult", "MatSolve"]


def parse_log(path):
    """Seconds per event of the 'PD solve' stage (the last occurrence of each event line wins: the solve
    stage is printed after set-up) and the stages' times."""
    ev, stages = {}, {}
    for line in open(path):
        m = re.match(r"^\s*\d+:\s+(PD [a-z-]+):\s+(\S+)", line)
        if m:
            stages[m.group(1)] = float(m.group(2))
        p = line.split()
        if p and p[0] in EVENTS and len(p) > 4:
            ev[p[0]] = ev.get(p[0], 0) + float(p[3])
    return ev, stages


def run(label, extra, dx, timeout):
    out = tempfile.mkdtemp(prefix="pdprofile_")
    logf = os.path.join(out, "log_view.txt")
    cmd = [EXE, "-options_file", SCENE, "-pd_dx", str(dx), "-pd_output_dir", out, "-log_view", ":" + logf] + extra
    with open(os.path.join(out, "stdout.txt"), "w") as f:
        code, wall, cpu, timed_out = run_timed(cmd, timeout, f)
    s = json.load(open(os.path.join(out, "summary.json")))
    rows = list(csv.DictReader(open(os.path.join(out, "curve.csv"))))
    ev, stages = parse_log(logf)
    return {"label": label, "dx": dx, "command": " ".join(["build/pdimplicit"] + cmd[1:2] + [os.path.relpath(SCENE, ROOT)] + cmd[3:5] + extra),
            "exit": code, "wall_s": wall, "cpu_s": cpu, "status": s["status"], "steps": s["steps"], "newton_its": s["newton_its"],
            "ksp_its": s["ksp_its"], "bonds": s["bonds"], "peak_N": s["peak_load_N"],
            "peak_rss_MB": s["memory"]["peak_rss_bytes"] / 2**20, "matrix_nonzeros": s["memory"]["matrix_nonzeros"], "events_s": ev, "stages_s": stages,
            "curve": [[float(r["cmod_m"]), float(r["load_N"])] for r in rows]}


def report(res):
    lines = ["# Where the time goes: the default scene's implicit path", "",
             "Written by `benchmarks/solve_profile.py` from `solve_profile.json`. The Gregoire D = 50 mm half-notched beam",
             "(`options/gregoire_d50_hn.opts`) under displacement control to CMOD 0.2 mm, one rank. Configurations of one",
             "spacing ran one after the other in one invocation; ratios are taken within it. Event times are PETSc's",
             "`-log_view` for the solve stage (inclusive: KSPSolve contains PCApply and MatMult, PCApply contains MatSolve).",
             "Event times are wall-clock and grow when other work shares the two cores; the CPU time (the run's own, from",
             "wait4) does not, and the ratios are taken on it. From 2,000 nodes a softening 3D model is preconditioned by GAMG",
             "(FGMRES, the hierarchy rebuilt when stale); `block ICC(0)` is the preconditioner it replaced at dx = 5 mm, and",
             "`left preconditioned` the side GAMG had before at dx = 2.5 mm. `last defaults` is the default before FGMRES, the",
             "indexed diagonal, the tangent scalars from the residual's loop and the residual's rows after a limiter grant",
             "(docs/solvers.md); `GMRES`, `diagonal by search`, `tangent's own loop` (which turns off the rows too) and",
             "`whole residual after a grant` undo one each. Memory is the run's peak resident set and the non-zeros are",
             "the assembled (preconditioning) matrix's, both from `summary.json`; `whole preconditioning matrix` keeps every",
             "bond in that matrix, as before it kept those up to 2.25 grid spacings (docs/solvers.md).", ""]
    for dx in sorted({r["dx"] for r in res.values()}, reverse=True):
        order = list(CONFIGS)
        runs = sorted((r for r in res.values() if r["dx"] == dx), key=lambda r: order.index(r["label"]) if r["label"] in order else len(order))
        base = next((r for r in runs if r["label"] == "default"), runs[0])
        # the most resolved curve run: one event per iteration, else the earlier (smaller) default cap
        ref = next((r for label in (REFERENCE, EARLIER_CAP) for r in runs if r["label"] == label), base)
        lines += ["## dx = %g mm" % (1e3 * dx), "",
                  "Peaks and RMS load differences (over the CMOD range both reach, relative to the peak) are against `%s`%s." % (
                      ref["label"], ", the most resolved curve" if ref is not base else " (no more resolved run at this spacing)"), "",
                  "| configuration | CPU (s) | CPU over default's | wall (s) | steps | Newton | KSP | peak (N) | peak vs reference | RMS vs reference | "
                  "memory (MB) | matrix non-zeros | status |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in runs:
            lines.append("| %s | %.1f | %.2f | %.1f | %d | %d | %d | %.1f | %+.3f %% | %.3f %% | %s | %s | %s |" % (
                r["label"], r["cpu_s"], r["cpu_s"] / base["cpu_s"], r["wall_s"], r["steps"], r["newton_its"], r["ksp_its"], r["peak_N"],
                100 * (r["peak_N"] / ref["peak_N"] - 1), 100 * curve_difference(ref, r),
                "%.0f" % r["peak_rss_MB"] if "peak_rss_MB" in r else "-",
                format(r["matrix_nonzeros"], ",") if "matrix_nonzeros" in r else "-", r["status"]))
        lines += ["", "Time by event (s, solve stage) and its share of the solve stage:", "",
                  "| configuration | " + " | ".join(EVENTS) + " |", "|---|" + "---|" * len(EVENTS)]
        for r in runs:
            tot = r["stages_s"].get("PD solve", 1)
            lines.append("| %s | " % r["label"] + " | ".join("%.2f (%.0f %%)" % (r["events_s"].get(e, 0), 100 * r["events_s"].get(e, 0) / tot)
                                                            for e in EVENTS) + " |")
        lines += ["", "Commands:", ""] + ["    %s" % r["command"] for r in runs] + [""]
    open(os.path.join(OUT, "solve_profile.md"), "w").write("\n".join(lines))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dx", type=float, default=5e-3)
    ap.add_argument("--timeout", type=float, default=1800)
    ap.add_argument("--configs", help="comma-separated labels of CONFIGS (default: all)")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--report", action="store_true")
    a = ap.parse_args()
    if not a.report:
        res = load_results(RESULTS)
        for k in [k for k in res if k.endswith("/dx=%g" % a.dx) and k.split("/")[0] not in CONFIGS]:
            del res[k]  # a configuration no longer compared
        save_results(RESULTS, res)
        labels = a.configs.split(",") if a.configs else list(CONFIGS)
        unknown = [l for l in labels if l not in CONFIGS]
        if unknown:
            ap.error("unknown configurations: %s" % ", ".join(unknown))
        def options(label):
            """A configuration's options; those that depend on the bond count read it from this spacing's
            default run, which is run first if it has not been."""
            if not callable(CONFIGS[label]):
                return CONFIGS[label]
            key = "default/dx=%g" % a.dx
            if "bonds" not in load_results(RESULTS).get(key, {}):
                store_result(RESULTS, key, run("default", [], a.dx, a.timeout))
            return CONFIGS[label](load_results(RESULTS)[key]["bonds"])

        with ThreadPoolExecutor(a.jobs) as pool:
            for label, r in zip(labels, pool.map(lambda l: run(l, options(l), a.dx, a.timeout), labels)):
                store_result(RESULTS, "%s/dx=%g" % (label, a.dx), r)
    report(load_results(RESULTS))


if __name__ == "__main__":
    main()
