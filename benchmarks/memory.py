#!/usr/bin/python3
"""What a whole non-linear 3D run's peak memory is made of, and what the levers on it cost: the D = 200 mm
half-notched Gregoire beam (3D, dx = 5 mm, 56,000 nodes) under its default path following (IMPL-EX, damage
error 0.03 per step) traced to 10 % of its peak on two ranks, with the solver defaults and with one lever
changed at a time, and on one rank (what the second rank adds), one run after the other in one invocation. Records the peak resident set summed over the
ranks (summary.json) per bond, wall and CPU time, iterations, the peak load and the curve's RMS difference
to the default run. Writes docs/benchmarks/memory.json and memory.md.

Usage: benchmarks/memory.py [--configs "default,Krylov restart 30"] [--ranks 2] [--timeout 1800] [--report]
"""
import argparse
import os

from common import RESULTS_DIR, curve_difference, load_results, run_scene, store_result, write_lines

RESULTS = os.path.join(RESULTS_DIR, "memory.json")
SCENE = "gregoire_d200_hn"
PATH = ["-pd_control", "arclength", "-pd_stop_fraction", "0.1", "-pd_arclength_implex", "0.03"]
# label -> extra options. The Krylov bases of path following: the direction's solve and the augmented
# corrector's, both FGMRES(60), whose basis grows with the iterations a solve reaches; the preconditioning
# matrix's reach (docs/solvers.md), whose matrix and GAMG set-up scale with its bonds; GAMG's Galerkin
# products on two ranks, all at once by default when this was measured (src/solve/static.c; now from 100,000
# nodes), against the algorithm PETSc itself
# picks for this matrix, which keeps intermediate products for reuse; GAMG's prolongators without their smoothing
# (no product of the matrix with them, sparser coarse levels); checkpoints as the size-effect study
# writes them, whose per-bond datasets are written while the solver's structures are alive
CONFIGS = {"default": [],
           "checkpoints every 25 steps": ["-pd_checkpoint_every", "25"],
           "Krylov restart 30": ["-ksp_gmres_restart", "30", "-pd_augmented_ksp_gmres_restart", "30"],
           "preconditioning reach 1.75": ["-pd_pc_reach", "1.75"],
           "Galerkin products kept for reuse": ["-matptap_via", "nonscalable"],
           "GAMG unsmoothed aggregation": ["-pc_gamg_agg_nsmooths", "0"],
           "one rank": []}
RANKS = {"one rank": 1}  # the others run on --ranks


def measure(label, ranks, timeout):
    run = run_scene(SCENE, PATH + CONFIGS[label], timeout, prefix="pdmemory_", ranks=ranks)
    s = run["summary"]
    if not s:
        return {"label": label, "exit": run["code"], "status": "no summary (exit %s)" % run["code"]}
    return {"label": label, "ranks": ranks, "exit": run["code"], "status": s["status"], "nodes": s["nodes"], "bonds": s["bonds"],
            "peak_rss_bytes": s["memory"]["peak_rss_bytes"], "bytes_per_bond": s["memory"]["peak_rss_bytes"] / s["bonds"],
            "wall_s": run["wall"], "cpu_s": run["cpu"], "steps": s["steps"], "newton_its": s["newton_its"], "ksp_its": s["ksp_its"],
            "peak_N": s["peak_load_N"], "curve": [[r["cmod_m"], r["load_N"]] for r in run["rows"] or []],
            "command": " ".join(["pdimplicit", "-options_file", "options/%s.opts" % SCENE] + PATH + CONFIGS[label]) +
            (" (mpiexec -n %d)" % ranks if ranks > 1 else "")}


def report(res):
    ref = res.get("default")
    lines = ["# Peak memory of a whole non-linear 3D run, and its levers", "",
             "Written by `benchmarks/memory.py` from `memory.json`: the D = 200 mm half-notched Gregoire beam (3D, dx = 5 mm) "
             "under its default path following (IMPL-EX, damage error 0.03 per step), traced to 10 % of its peak, each "
             "configuration one run after the other in one invocation. Memory is the peak resident set summed over the "
             "ranks, over the bonds; the curve difference is the RMS load difference to the default run over its peak. "
             "Row `default` was measured when GAMG's Galerkin products ran all at once on several ranks at every size; since "
             "design point 68 (docs/design.md) a model of this size takes the row-merged product, the algorithm of row "
             "`Galerkin products kept for reuse`, and all at once is kept from 100,000 nodes.", "",
             "| configuration | ranks | nodes | bonds | peak memory (MB) | bytes per bond | wall (s) | CPU (s; - under mpiexec) | steps / Newton / Krylov | "
             "peak (N) | vs default: peak | curve | status |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for label in CONFIGS:
        r = res.get(label)
        if not r or "bonds" not in r:
            continue
        dp = "%+.2f %%" % (100 * (r["peak_N"] / ref["peak_N"] - 1)) if ref and "peak_N" in ref else "-"
        dc = "%.2f %%" % (100 * curve_difference(ref, r)) if ref and ref.get("curve") and r.get("curve") else "-"
        lines.append("| %s | %d | %d | %d | %.0f | %.0f | %.0f | %s | %d / %d / %d | %.0f | %s | %s | %s |" % (
            label, r["ranks"], r["nodes"], r["bonds"], r["peak_rss_bytes"] / 2 ** 20, r["bytes_per_bond"], r["wall_s"],
            "%.0f" % r["cpu_s"] if r.get("cpu_s") else "-",
            r["steps"], r["newton_its"], r["ksp_its"], r["peak_N"], dp, dc, r["status"]))
    if ref and "bonds" in ref:
        lines += ["", "Against the default run:"]
        for label in CONFIGS:
            r = res.get(label)
            if label == "default" or not r or "bonds" not in r:
                continue
            lines.append("- %s: %.0f bytes per bond against %.0f (%+.0f %%), %.2f times the wall time, %.2f times the Krylov iterations." % (
                label, r["bytes_per_bond"], ref["bytes_per_bond"], 100 * (r["bytes_per_bond"] / ref["bytes_per_bond"] - 1), r["wall_s"] / ref["wall_s"],
                r["ksp_its"] / ref["ksp_its"]))
    write_lines("memory.md", lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--configs", default=",".join(CONFIGS))
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=1800)
    ap.add_argument("--report", action="store_true")
    a = ap.parse_args()
    res = load_results(RESULTS)
    for label in ([] if a.report else a.configs.split(",")):
        print("running", label, flush=True)
        res = store_result(RESULTS, label, measure(label, RANKS.get(label, a.ranks), a.timeout))
        print("  %s: %.0f bytes per bond, %.0f s" % (res[label].get("status"), res[label].get("bytes_per_bond", 0), res[label].get("wall_s", 0)),
              flush=True)
        report(res)
    report(res)


if __name__ == "__main__":
    main()
