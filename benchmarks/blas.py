#!/usr/bin/python3
"""Which BLAS the direct solvers run on. Debian's petsc-dev links the reference BLAS/LAPACK (netlib) unless an
optimised one is installed; MUMPS and CHOLMOD do their dense work (the supernodes of a 3D horizon's fill-in) in
it. Times the elastic solve of the half-notched D = 50 mm beam (one linear solve, one rank) with MUMPS and
CHOLMOD Cholesky on netlib and on OpenBLAS (libopenblas0-serial, which the set-up installs), each chosen per run by
LD_LIBRARY_PATH whichever the system's alternative is, and the
default CG + block Jacobi/ICC(0) for reference. Writes docs/benchmarks/blas.json and blas.md.

Usage: benchmarks/blas.py [--dx 5e-3 2.5e-3] [--report]   (needs libopenblas0-serial installed)
"""
import json
import os
import sys
import tempfile

from common import BLAS_DIRS, EXE, OUT, RESULTS_DIR, ROOT, run_timed, save_results

JSON = os.path.join(RESULTS_DIR, "blas.json")
SCENE = os.path.join(ROOT, "options", "gregoire_d50_hn.opts")
ELASTIC = ["-pd_law", "elastic", "-pd_region2_displacement", "0,0,-5e-5", "-pd_steps", "1", "-pd_stop_cmod", "0"]
SOLVERS = [
    ("CG + bjacobi/ICC(0), SBAIJ", ["-pc_type", "bjacobi"], ["netlib"]),
    ("MUMPS Cholesky, SBAIJ", ["-ksp_type", "preonly", "-pc_type", "cholesky", "-pc_factor_mat_solver_type", "mumps"], ["netlib", "openblas"]),
    ("CHOLMOD Cholesky, AIJ", ["-ksp_type", "preonly", "-pd_mat_type", "aij", "-pc_type", "cholesky", "-pc_factor_mat_solver_type", "cholmod"],
     ["netlib", "openblas"]),
]


def run(dx, opts, blas):
    out = tempfile.mkdtemp(prefix="pdbench_")
    cmd = ["env", "LD_LIBRARY_PATH=" + BLAS_DIRS[blas], EXE, "-options_file", SCENE, "-pd_dx", repr(dx), "-pd_output_dir", out] + ELASTIC + opts
    with open(os.path.join(out, "log.txt"), "w") as log:
        code, wall, cpu, _ = run_timed(cmd, 3600, log)
    s = json.load(open(os.path.join(out, "summary.json")))
    return {"exit": code, "cpu_s": cpu, "solve_s": s["timings"]["solve"], "peak_rss_bytes": s["memory"]["peak_rss_bytes"],
            "status": s["status"]}


def main():
    dxs = [5e-3, 2.5e-3]
    if "--dx" in sys.argv:
        dxs = [float(x) for x in sys.argv[sys.argv.index("--dx") + 1:] if not x.startswith("--")]
    if not all(os.path.exists(os.path.join(d.split(":")[0], "libblas.so.3")) for d in BLAS_DIRS.values()):
        sys.exit("blas.py: install libopenblas0-serial first")
    res = {"rows": []}
    for dx in dxs:
        for name, opts, blases in SOLVERS:
            for blas in blases:
                r = run(dx, opts, blas)
                r.update({"dx": dx, "solver": name, "blas": blas})
                res["rows"].append(r)
                print(dx, name, blas, "%.2f s" % r["solve_s"], flush=True)
    save_results(JSON, res)
    report(res)


def report(res):
    lines = ["# Direct solvers and the BLAS they run on", "",
             "Written by `benchmarks/blas.py` from `blas.json`: the elastic solve of the half-notched D = 50 mm beam (one linear "
             "solve, one rank), solve-stage time from `summary.json`. netlib is the reference BLAS/LAPACK Debian's petsc-dev "
             "pulls in; OpenBLAS is `libopenblas0-serial`, which pdimplicit's set-up installs; each is chosen per run through "
             "`LD_LIBRARY_PATH`.", "",
             "| dx (mm) | solver | BLAS | solve (s) | speed-up over netlib | peak memory (MB) |", "|---|---|---|---|---|---|"]
    by = {(r["dx"], r["solver"], r["blas"]): r for r in res["rows"]}
    for r in res["rows"]:
        base = by.get((r["dx"], r["solver"], "netlib"))
        up = "%.1f" % (base["solve_s"] / r["solve_s"]) if base and r["blas"] != "netlib" else "-"
        lines.append("| %g | %s | %s | %.2f | %s | %.0f |" % (1e3 * r["dx"], r["solver"], r["blas"], r["solve_s"], up,
                                                            r["peak_rss_bytes"] / 2**20))
    lines.append("")
    with open(os.path.join(OUT, "blas.md"), "w") as f:
        f.write("\n".join(lines))


if __name__ == "__main__":
    if "--report" in sys.argv:
        report(json.load(open(JSON)))
    else:
        main()
