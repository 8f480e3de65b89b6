#!/usr/bin/python3
"""The Stuttgart shear beams of Leonhardt and Walther (Hobbs thesis Ch. 7) against the experiments, Eurocode 2
and the thesis's peridynamic model (Table 7.3): pdimplicit's peak load, failure mode (summary.json, the
criterion of docs/reinforcement.md), load-point deflection at the peak, wall and CPU time, nodes and bonds
for each beam. The scenes are the plane-stress ones, options/stuttgart_beam{N}_2d.opts (scripts/stuttgart_scenes.py),
traced on the explicit path with a ramp slow enough that the kinetic energy stays a small part of the work
(it is reported). P is the total of both point loads: the curve's load where the scene lists both load regions
(-pd_load_region 2,3), twice the left one's where it listed that one only (the beams run before the list existed).
Writes docs/benchmarks/stuttgart.json, stuttgart.md and stuttgart.png.

The same scenes are traced by path following (`path [--direct] BEAM ...`): arc length with IMPL-EX steps and the
default linear solver (GAMG), or with --direct a MUMPS factor of every tangent (null pivots detected), stopped once the load has fallen below half its peak (a failure by the criterion above; a cracking beam loses more than 10 % of its load in single steps long before); these
runs go to the list `path_following` of the same file.

Usage: benchmarks/stuttgart.py [--report | implicit | BEAM ... | path [--direct] BEAM ...]   (BEAM: numbers to run, keeping the others'
results; by default every beam but 10; implicit: how far the default implicit path gets on beam 3 in ten minutes)
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

from common import system_blas, curve_rows, EXE, RESULTS_DIR, ROOT, run_timed, save_results, load_results, pyplot, save_figure, write_lines

sys.path.insert(0, os.path.join(ROOT, "scripts"))
from stuttgart_scenes import BEAMS  # noqa: E402

JSON = os.path.join(RESULTS_DIR, "stuttgart.json")
COMMIT = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
# Table 7.3: beam -> (experimental P (kN) of each test, mode, Eurocode 2 P, mode, thesis PD normal mesh P, mode)
TABLE = {1: ((777,), "shear", 287, "shear", 335, "shear"), 2: ((520,), "shear", 194, "shear", 253, "shear"),
         3: ((294,), "shear", 144, "shear", 170, "shear"), 4: ((161,), "shear", 144, "shear", 131, "shear"),
         5: ((118,), "shear", 144, "shear", 112, "shear"), 6: ((118,), "shear", 144, "shear", 85, "shear"),
         7: ((120, 131), "shear", 144, "shear", 87, "shear"), 8: ((126, 126), "shear", 125, "flexure", 76, "flexure"),
         10: ((94, 103), "flexure", 93, "flexure", 56, "flexure")}
AVD = {n: BEAMS[n][2] for n in TABLE}  # a_v/d, from the scenes' Table 7.1
# load-point displacement traced (m) and the ramp's rate (m/s): the rate keeps the kinetic energy small; a
# slender beam needs a longer travel to fail, so its ramp is longer in time
TRAVEL = {1: 0.012, 2: 0.012, 3: 0.006, 4: 0.008, 5: 0.010, 6: 0.015, 7: 0.020, 8: 0.025, 10: 0.060}
RATE = 0.003 / 0.57
# beam 10 fails in flexure after a travel ten times the short beams': hours at this speed, run only when named
NOT_BY_DEFAULT = (10,)


# path following: IMPL-EX's damage error per step, as on the 3D Gregoire beams, and the stop once the member has
# failed. The solver is the default (GAMG) unless --direct: PETSc's own Cholesky factor is faster per step, but on
# beam 3 it broke down before the peak, where a crack had left the tangent singular; MUMPS's null-pivot detection
# gets through there
PATH_OPTIONS = ["-pd_control", "arclength", "-pd_arclength_implex", "0.03", "-pd_stop_fraction", "0.5"]
# `path --direct`: a MUMPS factor of every tangent, its null pivots detected (ICNTL(24)), so that a fragment a
# crack has freed is held where it is instead of breaking the factorisation (docs/reinforcement.md)
DIRECT_OPTIONS = ["-ksp_type", "preonly", "-pc_type", "cholesky", "-pc_factor_mat_solver_type", "mumps", "-mat_mumps_icntl_24", "1"]
PATH_LIMIT = 3600  # s: the time budget per beam
BLAS_NAME = {"netlib": "reference BLAS", "openblas": "OpenBLAS"}  # MUMPS's dense work; rows without a record ran on the reference one


def load_factor(summary):
    """P over the curve's load: 1 where the curve sums both load points, 2 where it is the left one's."""
    return 1 if len(summary["options"]["-pd_load_region"]) == 2 else 2


P_FROM = {1: "both load points", 2: "twice the left load point's"}  # a run's record of where its P came from


def measure(beams, path=False, direct=False):
    for n in beams or [b for b in TABLE if b not in NOT_BY_DEFAULT]:
        out = tempfile.mkdtemp(prefix="pdbench_")
        if path:
            extra = ["-pd_lambda_max", "%g" % (TRAVEL[n] / 0.02), *PATH_OPTIONS, *(DIRECT_OPTIONS if direct else [])]
        else:
            extra = ["-pd_mode", "explicit", "-pd_lambda_max", "%g" % (TRAVEL[n] / 0.02), "-pd_ramp_time", "%g" % (TRAVEL[n] / RATE)]
        with open(os.path.join(out, "log"), "w") as log:
            code, wall, cpu, _ = run_timed([EXE, "-options_file", os.path.join(ROOT, "options", "stuttgart_beam%d_2d.opts" % n), "-pd_output_dir", out,
                                            *extra], PATH_LIMIT if path else 7200, log)
        rows = curve_rows(out) if os.path.exists(os.path.join(out, "curve.csv")) else []
        if not rows or not os.path.exists(os.path.join(out, "summary.json")):
            print(n, "no curve or summary (exit %d): see %s" % (code, out))
            continue
        s = json.load(open(os.path.join(out, "summary.json")))
        k = max(range(len(rows)), key=lambda i: rows[i]["load_N"])
        f = load_factor(s)
        run = {"beam": n, "peak_kN": f * rows[k]["load_N"] / 1e3, "steel_stress_at_peak_Pa": rows[k]["steel_stress_Pa"], "mode": s["bars"]["failure_mode"], "wall_s": round(wall, 1), "cpu_s": round(cpu, 1),
                   "nodes": s["nodes"], "bonds": s["bonds"], "disp_at_peak_m": rows[k]["disp_m"], "end_load_kN": f * rows[-1]["load_N"] / 1e3,
                   "first_yield_kN": f * s["bars"]["first_yield"]["load_N"] / 1e3 if s["bars"]["first_yield"] else None,
                   "P_from": P_FROM[f],
                   "kinetic_over_work_at_peak": rows[k]["kinetic_J"] / max(rows[k]["external_J"], 1e-30), "options": extra, "exit": code,
                   "status": s["status"], "commit": COMMIT, "eps_cu": float(s["options"].get("-pd_eps_cu", 0))}
        if path:
            run.update({"steps": s["steps"], "newton_its": s["newton_its"], "ksp_its": s["ksp_its"], "solver": s["solver"], "blas": system_blas()})
        print(n, run)
        # read again before writing: another instance may have saved other beams meanwhile
        res = load_results(JSON)
        key = "path_following" if path else "beams"
        runs = {b["beam"]: b for b in res.get(key, [])}
        runs[n] = run
        res[key] = [runs[b] for b in sorted(runs)]
        save_results(JSON, res)
        shutil.rmtree(out)


def probe_implicit(n=3, limit=600):
    """How far the default implicit path gets on beam n in limit seconds: the step, load factor, load-point
    displacement, load and iterations of its last accepted step, and how it ended."""
    out = tempfile.mkdtemp(prefix="pdbench_")
    with open(os.path.join(out, "log"), "w") as log:
        code, wall, cpu, timed_out = run_timed([EXE, "-options_file", os.path.join(ROOT, "options", "stuttgart_beam%d_2d.opts" % n),
                                                "-pd_output_dir", out], limit, log)
    rows = curve_rows(out)
    s = json.load(open(os.path.join(out, "summary.json")))
    probe = {"beam": n, "limit_s": limit, "cpu_s": round(cpu, 1), "wall_s": round(wall, 1), "exit": code, "status": s["status"],
             "solver": s["solver"], "steps": rows[-1]["step"], "newton_its": s["newton_its"], "ksp_its": s["ksp_its"],
             "disp_m": rows[-1]["disp_m"], "P_kN": load_factor(s) * rows[-1]["load_N"] / 1e3, "broken_bonds": rows[-1]["broken_bonds"], "commit": COMMIT,
             "P_from": P_FROM[load_factor(s)]}
    print("implicit", probe)
    res = load_results(JSON)
    res["implicit_probe"] = probe
    save_results(JSON, res)
    shutil.rmtree(out)


def report():
    res = load_results(JSON)
    done = {b["beam"]: b for b in res.get("beams", [])}
    lines = ["# The Stuttgart shear beams", "",
             "Written by `benchmarks/stuttgart.py` from `stuttgart.json`. Leonhardt and Walther's beams as the Hobbs thesis models them "
             "(Ch. 7, Tables 7.1 to 7.3): section 190 x 320 mm, d = 270 mm, two 26 mm bars, no stirrups, four-point bending, dx = 11.5 mm, "
             "the bilinear law with k_r = 25. pdimplicit: the plane-stress scenes `options/stuttgart_beam{N}_2d.opts` (190 mm thick, both bars "
             "on one line, fib Model Code 2010 bond slip, crushing at f_cm), traced on the explicit path at a load-point speed of %.1f mm/s. "
             "P is the total of both point loads, the sum of their reactions; rows marked * were run before the curve could sum two "
             "regions and took twice the left one's (the beam and its loads are symmetric, but where one shear span fails first the two "
             "reactions part after the peak). The experiment's P is the mean where the beam was tested twice. "
             "Mode, from the curve (the sum of both points, or in the rows marked * the left point's alone): shear where the beam lost its load with its bars elastic, flexure where they yielded "
             "first, none where the curve did not end 10 %% below its peak (docs/reinforcement.md); a run that did not complete says how "
             "it ended. Deflection: the load points' at the peak. "
             "KE / W: kinetic energy over the work done, at the peak. CPU: the run's own; wall: with the two cores shared by other runs." % (1e3 * RATE), "",
             "| beam | a_v/d | experiment P (kN), mode | Eurocode 2 P (kN), error, mode | thesis PD P (kN), error, mode | pdimplicit P (kN), error, mode "
             "| deflection (mm) | KE / W | CPU (s) | wall (s) | nodes | bonds | commit |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    err = lambda p, e: "%+.0f %%" % (100 * (p / e - 1))
    errs, modes = {"ec2": [], "thesis": [], "ours": []}, {"ec2": 0, "thesis": 0, "ours": 0}
    for n, (exps, mode, ec2, ec2m, pd, pdm) in TABLE.items():
        avd = AVD[n]
        e = sum(exps) / len(exps)
        errs["ec2"].append(abs(ec2 / e - 1))
        errs["thesis"].append(abs(pd / e - 1))
        modes["ec2"] += ec2m == mode
        modes["thesis"] += pdm == mode
        r = done.get(n)
        ours = "not run"
        if r:
            ours = "%.0f%s, %s, %s%s" % (r["peak_kN"], "" if r.get("P_from") == P_FROM[1] else "*", err(r["peak_kN"], e), r["mode"],
                                         "" if r["status"].startswith("completed") else " (%s)" % r["status"].split()[0].rstrip(":"))
            errs["ours"].append(abs(r["peak_kN"] / e - 1))
            modes["ours"] += r["mode"] == mode
        lines.append("| %d | %g | %.0f, %s | %d, %s, %s | %d, %s, %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            n, avd, e, mode, ec2, err(ec2, e), ec2m, pd, err(pd, e), pdm, ours, "%.2f" % (1e3 * r["disp_at_peak_m"]) if r else "-",
            "%.3f" % r["kinetic_over_work_at_peak"] if r else "-", r["cpu_s"] if r else "-", r["wall_s"] if r else "-", r["nodes"] if r else "-", r["bonds"] if r else "-",
            r["commit"] if r else "-"))
    mean = lambda v: "%.0f %%" % (100 * sum(v) / len(v)) if v else "-"
    pr = res.get("implicit_probe")
    if pr:
        r = done.get(pr["beam"])
        lines += ["", "The default implicit path on beam %d (`benchmarks/stuttgart.py implicit`: the scene's own options, stopped after %d s): "
                  "%d steps, %d Newton and %d Krylov iterations in %.0f s of CPU took it to %.2f mm at the load points and P = %.0f kN%s with %d "
                  "broken bonds (%s; solver %s)%s." % (
                      pr["beam"], pr["limit_s"], pr["steps"], pr["newton_its"], pr["ksp_its"], pr["cpu_s"], 1e3 * pr["disp_m"], pr["P_kN"],
                      "" if pr.get("P_from") == P_FROM[1] else " (twice the left point's)", pr["broken_bonds"], pr["status"].split()[0].rstrip(":"), pr["solver"],
                      ", where the explicit path peaks at %.2f mm and %.0f kN" % (1e3 * r["disp_at_peak_m"], r["peak_kN"]) if r else "")]
    path = {b["beam"]: b for b in res.get("path_following", [])}
    perr, pmodes = [], 0
    if path:
        lines += ["", "## Path following", "",
                  "The same scenes traced by arc length with IMPL-EX steps (`benchmarks/stuttgart.py path [--direct] BEAM`: damage error "
                  "0.03 per step, stopped once the load fell below half its peak or after %d s). Solver: the default linear solver "
                  "(GAMG), or with `--direct` a MUMPS factor of every tangent with its null pivots detected (`%s`), on the BLAS named (the rows "
                  "before pdimplicit's set-up installed OpenBLAS ran on the reference BLAS, several times slower in MUMPS's dense work: "
                  "docs/benchmarks/blas.md). Mode and deflection "
                  "as above; the path may turn back in deflection after the peak (snap-back). eps_cu: the ultimate compressive strain at which "
                  "the run stops as crushed (`-pd_eps_cu`, docs/reinforcement.md, \"Failure mode\"); - where the run predates it." % (PATH_LIMIT, " ".join(DIRECT_OPTIONS)), "",
                  "| beam | a_v/d | experiment P (kN), mode | pdimplicit P (kN), error, mode | explicit P (kN) | deflection (mm) | steel stress at the peak (MPa) "
                  "| solver | eps_cu | steps / Newton / Krylov | CPU (s) | wall (s) | end | commit |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for n, r in sorted(path.items()):
            exps, mode = TABLE[n][0], TABLE[n][1]
            e = sum(exps) / len(exps)
            perr.append(abs(r["peak_kN"] / e - 1))
            pmodes += r["mode"] == mode
            lines.append("| %d | %g | %.0f, %s | %.0f, %s, %s | %s | %.2f | %.0f | %s | %s | %d / %d / %d | %s | %s | %s | %s |" % (
                n, AVD[n], e, mode, r["peak_kN"], err(r["peak_kN"], e), r["mode"], "%.0f" % done[n]["peak_kN"] if n in done else "-",
                1e3 * r["disp_at_peak_m"], r["steel_stress_at_peak_Pa"] / 1e6,
                ("MUMPS, null pivots, %s" % BLAS_NAME[r.get("blas", "netlib")]) if "-mat_mumps_icntl_24" in r["options"] else "GAMG", "%g" % r["eps_cu"] if r.get("eps_cu") else "-", r["steps"], r["newton_its"], r["ksp_its"], r["cpu_s"], r["wall_s"],
                r["status"].split(":")[0], r["commit"]))
    lines += ["", "| | Eurocode 2 | thesis PD | pdimplicit, explicit | pdimplicit, path following |", "|---|---|---|---|---|",
              "| beams | %d | %d | %d | %d |" % (len(TABLE), len(TABLE), len(done), len(path)),
              "| mean absolute peak error | %s | %s | %s | %s |" % (mean(errs["ec2"]), mean(errs["thesis"]), mean(errs["ours"]), mean(perr)),
              "| right failure mode | %d | %d | %d | %d |" % (modes["ec2"], modes["thesis"], modes["ours"], pmodes), ""]
    lines += ["![peak load against a_v/d](stuttgart.png)", ""]
    lines += ["Command per beam: `build/pdimplicit -options_file options/stuttgart_beam{N}_2d.opts` with "
              "the options of `stuttgart.json` (for beam 3: `%s`)." % " ".join(done[3]["options"]) if 3 in done else "", ""]
    write_lines("stuttgart.md", lines)
    plot(done, path)


def plot(done, path):
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    avd = [AVD[n] for n in TABLE]
    ax.plot(avd, [sum(TABLE[n][0]) / len(TABLE[n][0]) for n in TABLE], "ko-", label="experiment")
    ax.plot(avd, [TABLE[n][2] for n in TABLE], "s--", color="0.5", label="Eurocode 2")
    ax.plot(avd, [TABLE[n][4] for n in TABLE], "^--", color="tab:blue", label="thesis PD (3D)")
    mine = [n for n in TABLE if n in done]
    ax.plot([AVD[n] for n in mine], [done[n]["peak_kN"] for n in mine], "D-", color="tab:red", label="pdimplicit (2D, explicit)")
    if path:
        ax.plot([AVD[n] for n in sorted(path)], [path[n]["peak_kN"] for n in sorted(path)], "o", mfc="none", ms=9, color="tab:green",
                label="pdimplicit (2D, path following)")
    ax.set_xlabel("a_v / d")
    ax.set_ylabel("P (kN), both point loads")
    ax.set_yscale("log")
    ax.legend()
    save_figure(fig, "stuttgart.png", dpi=100)


if __name__ == "__main__":
    if sys.argv[1:] == ["implicit"]:
        probe_implicit()
    elif sys.argv[1:2] == ["path"]:
        measure([int(a) for a in sys.argv[2:] if a != "--direct"], path=True, direct="--direct" in sys.argv[2:])
    elif "--report" not in sys.argv[1:]:
        measure([int(a) for a in sys.argv[1:]])
    report()
