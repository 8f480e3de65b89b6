#!/usr/bin/python3
"""Growth of the implicit path's cost with the model, memory per bond and what it is made of, and strong
scaling from 1 to 2 ranks.

Every case is the first load increment of a 3D half-notched Gregoire beam (the shipped scenes, non-linear
law, default solver choice: block ICC(0) on SBAIJ below 10,000 nodes, GAMG on AIJ from there), a quarter
of a per cent of the prescribed deflection: Newton with Eisenstat-Walker tolerances from rest, on the
tangent of an undamaged model. A Newton iteration is then what it costs in any increment (one assembly, a
preconditioner set-up where due, one Krylov solve); only the Krylov iterations per Newton iteration
change once bonds soften, and those are reported beside. Sizes: D = 50, 100, 200 and 400 mm at dx = 5 mm
and D = 200 mm at dx = 2.5 mm (3,500 to 448,000 nodes), one rank, one after the other; D = 200 and 400 mm
at dx = 5 mm again on two ranks.

Memory: the peak resident set (summed over ranks) per bond, split into what the run's own counts give: the
stiffness matrix (its non-zeros: 8-byte values, and a 4-byte column index per value on AIJ, per 3 x 3 block on SBAIJ), the bond arrays (ends, constant,
material, surface-correction factor, incidence: 36 bytes per bond), the bond scalar of the tangent (8; small
kinematics)
and the bond history (summary.json's history_bytes), the Krylov basis (GMRES restart 60 plus the work
vectors, as allocated: 64 vectors of the dofs, an upper bound) and the rest (the preconditioner, PETSc's
and MPI's own).

A second growth series reaches the 1.8 million nodes the model must grow to: the elastic cantilever
(options/cantilever.opts) from dx = 13.5 mm (3,920 nodes) to dx = 1/550 m (1,796,850 nodes, 105 million
bonds), one linear solve each (the scene is linear: a Newton iteration is that solve), CG with point Jacobi
(-pc_type jacobi, the default for linear 3D models since it was measured here; a block ICC(0) factor would
double the matrix's memory and leave the largest case no room in 24 GB). Its times are CPU times (wait4) of
the whole run, set-up and assembly included, since the series shared the machine with other runs.

Writes docs/benchmarks/scaling.json and scaling.md (about two hours).

Usage: benchmarks/scaling.py [--report | CASE ...]   (CASE: run only these, keep the others' results)
"""
import json
import math
import os
import sys
import tempfile

from common import EXE, RESULTS_DIR, ROOT, load_results, run_timed, save_results, write_lines

JSON = os.path.join(RESULTS_DIR, "scaling.json")
FIRST_INCREMENT = ["-pd_steps", "1", "-pd_lambda_max", "0.0025"]
BOND_ARRAY_BYTES, TANGENT_SCALAR_BYTES, KRYLOV_VECTORS = 36, 8, 64


def scene(d):
    return os.path.join(ROOT, "options", "gregoire_d%d_hn.opts" % d)


# key, scene, extra options, ranks
CASES = [
    ("d50_dx5", scene(50), [], 1),
    ("d100_dx5", scene(100), [], 1),
    ("d200_dx5", scene(200), [], 1),
    ("d400_dx5", scene(400), [], 1),
    ("d200_dx2.5", scene(200), ["-pd_dx", "0.0025"], 1),
    ("d200_dx5_2ranks", scene(200), [], 2),
    ("d400_dx5_2ranks", scene(400), [], 2),
    # the preconditioning matrix of the near bonds (-pd_pc_reach, the default since these cases were run)
    # against every bond in it, one after the other: outside the growth fit and the tables above
    ("d400_dx5_near", scene(400), ["-pd_pc_reach", "2.25"], 1),
    ("d400_dx5_whole", scene(400), ["-pd_pc_reach", "0"], 1),
]
PC_REACH = ("d400_dx5_near", "d400_dx5_whole")
# the elastic growth series (key, dx)
CANTILEVER = [("cantilever_dx13.5", "0.0135"), ("cantilever_dx10", "0.01"), ("cantilever_dx5", "0.005"), ("cantilever_dx2.5", "0.0025"),
              ("cantilever_dx1.82", repr(1 / 550))]
CASES += [(k, os.path.join(ROOT, "options", "cantilever.opts"), ["-pd_dx", dx, "-pc_type", "jacobi"], 1) for k, dx in CANTILEVER]
SERIES = tuple(k for k, _ in CANTILEVER)


def measure(only):
    res = load_results(JSON)
    res.setdefault("runs", {})
    for key, path, opts, ranks in CASES:
        if only and key not in only:
            continue
        out = tempfile.mkdtemp(prefix="pdscaling_")
        first = [] if key in SERIES else FIRST_INCREMENT  # the cantilever: its one linear step
        cmd = [EXE, "-options_file", path, "-pd_output_dir", out] + first + opts
        if ranks > 1:
            cmd = ["mpiexec", "-n", str(ranks)] + cmd
        with open(os.path.join(out, "log"), "w") as log:
            rc, wall, cpu, _ = run_timed(cmd, 7200, log)
        s = json.load(open(os.path.join(out, "summary.json")))
        res["runs"][key] = {
            "command": " ".join(["build/pdimplicit", "-options_file", os.path.relpath(path, ROOT)] + first + opts),
            "ranks": ranks, "returncode": rc, "wall_s": wall, "cpu_s": cpu, "nodes": s["nodes"], "bonds": s["bonds"], "dofs": s["dofs"],
            "solver": s["solver"], "newton_its": s["newton_its"], "ksp_its": s["ksp_its"], "timings": s["timings"],
            "memory": s["memory"], "status": s["status"], "key": key}
        rows = open(os.path.join(out, "curve.csv")).read().strip().splitlines() if key in SERIES else []
        if len(rows) > 1:  # a header and at least one step
            res["runs"][key]["tip_m"] = float(rows[-1].split(",")[3])
        print(key, res["runs"][key])
        save_results(JSON, res)


def fit(xs, ys):
    """Exponent and prefactor of y = c x^p by least squares on the logarithms."""
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    p = sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)
    return p, math.exp(my - p * mx)


def breakdown(r):
    """Bytes per bond of the peak resident set and of its parts."""
    b, mem = r["bonds"], r["memory"]
    # AIJ: an 8-byte value and a 4-byte column index per non-zero; SBAIJ (with block ICC(0)): one column index per 3x3 block
    nz = mem["matrix_nonzeros"]
    matrix = nz * 12 if "gamg" in r["solver"] else nz * 8 + nz / 9 * 4
    parts = {"matrix": matrix, "bond arrays": b * BOND_ARRAY_BYTES, "tangent scalars": b * TANGENT_SCALAR_BYTES,
             "history": mem["history_bytes"], "Krylov basis": KRYLOV_VECTORS * r["dofs"] * 8}
    parts["rest"] = mem["peak_rss_bytes"] - sum(parts.values())
    return mem["peak_rss_bytes"] / b, {k: v / b for k, v in parts.items()}


def report():
    runs = load_results(JSON)["runs"]
    one = [runs[k] for k, _, _, ranks in CASES if ranks == 1 and k in runs and k not in PC_REACH + SERIES]
    per_newton = lambda r: r["timings"]["solve"] / r["newton_its"]
    per_ksp = lambda r: r["timings"]["solve"] / max(1, r["ksp_its"])
    gamg = [r for r in one if "gamg" in r["solver"]]
    lines = ["# Growth, memory and strong scaling", "",
             "Written by `benchmarks/scaling.py` from `scaling.json`. Each case is the first load increment (0.25 % of the "
             "prescribed deflection) of a 3D half-notched Gregoire beam, non-linear law, default solvers: Newton with "
             "Eisenstat-Walker tolerances on the tangent of the undamaged model, so that a Newton iteration costs what it costs "
             "in any increment (an assembly, a preconditioner set-up where due, a Krylov solve). Once bonds soften only the Krylov "
             "iterations per Newton iteration change (docs/benchmarks/solve_profile.md). Solve: the solve stage of "
             "`summary.json` (assembly, preconditioner, Krylov), wall-clock; the one-rank cases ran one after the other.", "",
             "## Time per Newton iteration against the model's size (one rank)", "",
             "| case | nodes | bonds | solver | Newton | KSP | solve (s) | per Newton iteration (s) | per Krylov iteration (ms) | "
             "peak memory (MB) | bytes per bond |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for k, _, _, ranks in CASES:
        if ranks != 1 or k not in runs or k in PC_REACH + SERIES:
            continue
        r = runs[k]
        lines.append("| %s | %s | %s | %s | %d | %d | %.2f | %.3f | %.1f | %.0f | %.0f |" % (
            k, format(r["nodes"], ","), format(r["bonds"], ","), r["solver"], r["newton_its"], r["ksp_its"], r["timings"]["solve"],
            per_newton(r), 1e3 * per_ksp(r), r["memory"]["peak_rss_bytes"] / 2**20, r["memory"]["peak_rss_bytes"] / r["bonds"]))
    if len(gamg) >= 2:
        p, c = fit([r["nodes"] for r in gamg], [per_newton(r) for r in gamg])
        pk, _ = fit([r["nodes"] for r in gamg], [per_ksp(r) for r in gamg])
        big = 1.8e6
        lines += ["", "Fitted over the %d GAMG cases (%s to %s nodes): time per Newton iteration ~ N^%.2f, per Krylov "
                  "iteration ~ N^%.2f. Extrapolated to %s nodes (the D = 400 mm beam at dx = 2.5 mm): %.0f s per Newton iteration "
                  "on one rank, if it fitted in memory (below)." % (
                      len(gamg), format(min(r["nodes"] for r in gamg), ","), format(max(r["nodes"] for r in gamg), ","), p, pk,
                      format(int(big), ","), c * big**p)]
    series = [runs[k] for k in SERIES if k in runs and runs[k]["status"].startswith("completed")]
    if series:
        lines += ["", "## The elastic cantilever to 1.8 million nodes (one rank, CG with point Jacobi)", "",
                  "One linear solve per case (a linear scene's Newton iteration). CPU: the run's own (set-up, assembly, solve); "
                  "the solve's wall time is from `summary.json` and grew when other runs shared the cores.", "",
                  "| case | nodes | bonds | CG iterations | CPU (s) | solve, wall (s) | CPU over Krylov iterations (ms) | peak memory (MB) | bytes per bond | tip deflection (mm) |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for r in series:
            lines.append("| %s | %s | %s | %d | %.1f | %.1f | %.2f | %.0f | %.0f | %.4f |" % (
                r["key"], format(r["nodes"], ","), format(r["bonds"], ","), r["ksp_its"], r["cpu_s"], r["timings"]["solve"],
                1e3 * r["cpu_s"] / r["ksp_its"], r["memory"]["peak_rss_bytes"] / 2**20, r["memory"]["peak_rss_bytes"] / r["bonds"], 1e3 * r.get("tip_m", float("nan"))))
        if len(series) >= 3:
            p, _ = fit([r["nodes"] for r in series], [r["cpu_s"] for r in series])
            pk, _ = fit([r["nodes"] for r in series], [r["cpu_s"] / r["ksp_its"] for r in series])
            pi, _ = fit([r["nodes"] for r in series], [r["ksp_its"] for r in series])
            lines += ["", "Fitted over %s to %s nodes: CPU time per Newton iteration (the solve and what builds it) ~ N^%.2f, that "
                      "over the Krylov iterations ~ N^%.2f, Krylov iterations ~ N^%.2f (point Jacobi's grow with the lattice's size, as "
                      "1/dx for a fixed beam)." % (format(min(r["nodes"] for r in series), ","), format(max(r["nodes"] for r in series), ","), p, pk, pi)]
    lines += ["", "## What the memory is made of (bytes per bond, one rank)", "",
              "The matrix from its non-zeros (8-byte values; 4-byte column indices, one per value on AIJ, one per 3 x 3 block on SBAIJ); bond arrays 36 bytes per bond (ends, constant, "
              "material, surface-correction factor, incidence); the tangent's bond scalar 8 (small kinematics: its geometric part "
              "is zero and not stored); the bond history as `summary.json` "
              "counts it; the Krylov basis as an upper bound (64 vectors of the dofs: GMRES restart 60 and work vectors); the rest "
              "is the preconditioner (the GAMG hierarchy, or the ICC factor) and what PETSc and MPI hold.", "",
              "| case | peak | matrix | bond arrays | tangent scalars | history | Krylov basis | rest |", "|---|---|---|---|---|---|---|---|"]
    for k, _, _, ranks in CASES:
        if ranks != 1 or k not in runs or k in PC_REACH + SERIES:
            continue
        total, parts = breakdown(runs[k])
        lines.append("| %s | %.0f | %s |" % (k, total, " | ".join("%.0f" % parts[p] for p in
                                                                     ("matrix", "bond arrays", "tangent scalars", "history", "Krylov basis", "rest"))))
    lines += ["", "## Strong scaling: one and two ranks", "",
              "| beam | nodes | solve, 1 rank (s) | solve, 2 ranks (s) | speed-up | KSP, 1 and 2 ranks | peak memory, 1 and 2 ranks (MB) |",
              "|---|---|---|---|---|---|---|"]
    for k, _, _, ranks in CASES:
        if ranks != 2 or k not in runs or k.replace("_2ranks", "") not in runs:
            continue
        r2, r1 = runs[k], runs[k.replace("_2ranks", "")]
        lines.append("| %s | %s | %.2f | %.2f | %.2f | %d, %d | %.0f, %.0f |" % (
            k.replace("_2ranks", ""), format(r1["nodes"], ","), r1["timings"]["solve"], r2["timings"]["solve"],
            r1["timings"]["solve"] / r2["timings"]["solve"], r1["ksp_its"], r2["ksp_its"], r1["memory"]["peak_rss_bytes"] / 2**20,
            r2["memory"]["peak_rss_bytes"] / 2**20))
    if all(k in runs for k in PC_REACH):
        lines += ["", "## The preconditioning matrix of the near bonds", "",
                  "The D = 400 mm beam's first increment again, with the preconditioning matrix keeping the bonds up to 2.25 grid "
                  "spacings (`-pd_pc_reach 2.25`, the default in 3D since the cases above were run) and every bond "
                  "(`-pd_pc_reach 0`), one after the other with today's build. Its parts as above, the matrix's record of each "
                  "bond's scalar (8 bytes per bond) in the rest.", "",
                  "| case | solver | Newton | KSP | solve (s) | per Newton iteration (s) | matrix non-zeros | peak memory (MB) | "
                  "bytes per bond | matrix | rest |", "|---|---|---|---|---|---|---|---|---|---|---|"]
        for k in PC_REACH:
            r = runs[k]
            total, parts = breakdown(r)
            lines.append("| %s | %s | %d | %d | %.2f | %.3f | %s | %.0f | %.0f | %.0f | %.0f |" % (
                k, r["solver"], r["newton_its"], r["ksp_its"], r["timings"]["solve"], per_newton(r), format(r["memory"]["matrix_nonzeros"], ","),
                r["memory"]["peak_rss_bytes"] / 2**20, total, parts["matrix"], parts["rest"]))
    lines += ["", "Commands:", ""] + ["    %s%s" % ("mpiexec -n 2 " if runs[k]["ranks"] > 1 else "", runs[k]["command"])
                                       for k, _, _, _ in CASES if k in runs]
    write_lines("scaling.md", lines)


if __name__ == "__main__":
    if "--report" not in sys.argv[1:]:
        measure(sys.argv[1:])
    report()
