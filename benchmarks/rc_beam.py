#!/usr/bin/python3
"""The small reinforced beam (options/rc_beam_2d.opts) against cracked-section analysis: cracking and
yield loads by hand, and pdimplicit's curves with the three bar bonds (concrete: the interface bonds follow
the concrete law; perfect: they never fail, the thesis' choice; slip: the bar on its own nodes under the
fib Model Code 2010 bond-slip law), on the implicit path and the explicit one. Records each run's peak, the steel stress there,
whether the bar yielded, and how far along the bar the concrete delaminated (bar-line nodes whose damage
exceeds 0.5). Writes docs/benchmarks/rc_beam.json and rc_beam.md (a few minutes).

Usage: benchmarks/rc_beam.py [--report | CASE ...]   (CASE: run only these, keep the others' results)
"""
import math
import os
import subprocess
import sys
import tempfile

from common import curve_rows, EXE, OUT, RESULTS_DIR, ROOT, last_fields, run_timed, save_results, load_results, write_lines

JSON = os.path.join(RESULTS_DIR, "rc_beam.json")
# the commit each run was measured at (runs can be measured apart: CASE arguments)
COMMIT = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
SCENE = os.path.join(ROOT, "options", "rc_beam_2d.opts")

# the scene's section and materials
B, H, D, SPAN = 0.1, 0.15, 0.115, 1.2
EC, ES, FT, FY, AS = 30e9, 200e9, 3e6, 500e6, math.pi * 0.008 ** 2 / 4

# name, what, extra options
CASES = [
    ("concrete_implicit", "bond concrete, implicit (secant tangent)", ["-pd_tangent", "secant", "-pd_lambda_max", "0.25"]),
    ("concrete_default", "bond concrete, implicit (default path)", ["-pd_lambda_max", "0.2"]),
    ("concrete_explicit", "bond concrete, explicit", ["-pd_mode", "explicit", "-pd_lambda_max", "0.25"]),
    ("perfect_implicit", "bond perfect, implicit (secant tangent)", ["-pd_bar0_bond", "perfect", "-pd_tangent", "secant", "-pd_lambda_max", "0.25"]),
    # bond slip (fib Model Code 2010 with f_cm = 38 MPa, the mean strength that goes with f_t = 3 MPa) on the default path
    # (displacement control, path following where it fails, IMPL-EX where that fails) with a direct solver (half the
    # time of the default GAMG on this 2D model), through the bar's yield
    ("slip_implicit", "bond slip, implicit (default path, Cholesky)", ["-pd_bar0_bond", "slip", "-pd_bar0_fcm", "38e6", "-pd_lambda_max", "0.6",
                                                                      "-pd_steps", "160", "-ksp_type", "preonly", "-pc_type", "cholesky"]),
    # the same with a concrete six times weaker in tension and brittle: does the steel's shortfall against the cracked
    # section follow the concrete's tensile strength?
    ("slip_weak", "bond slip, f_t = 0.5 MPa, G_f = 10 N/m, implicit", ["-pd_bar0_bond", "slip", "-pd_bar0_fcm", "38e6", "-pd_ft", "0.5e6", "-pd_Gf", "10",
                                                                     "-pd_lambda_max", "0.25", "-pd_steps", "70", "-ksp_type", "preonly", "-pc_type",
                                                                     "cholesky"]),
    # the bond-slip beam at half the spacing (the horizon half as deep against the section; the bar on the node line at
    # d = 112.5 mm, the nearest to 115 mm), on the default path with its default solver
    ("slip_dx5", "bond slip, dx = 5 mm, d = 112.5 mm, implicit (default path)", ["-pd_dx", "0.005", "-pd_bar0_line", "0,0.0375,1.3,0.0375", "-pd_bar0_bond",
                                                                               "slip", "-pd_bar0_fcm", "38e6", "-pd_lambda_max", "0.45", "-pd_steps", "120"]),
    # the bond-slip run with a section cut through the mid-span crack (-pd_section_x): what carries the moment there
    ("slip_section", "bond slip, implicit, section at mid-span", ["-pd_bar0_bond", "slip", "-pd_bar0_fcm", "38e6", "-pd_lambda_max", "0.6",
                                                                  "-pd_steps", "160", "-ksp_type", "preonly", "-pc_type", "cholesky",
                                                                  "-pd_section_x", "0.65"]),
    # the same with the supports and the load on one node column each (the scene's hold two, which resist the beam's
    # rotation there like clamped plates): a simply supported beam under a knife-edge load, as section analysis assumes
    ("slip_knife", "bond slip, implicit, supports and load on one node column", ["-pd_region0_box", "0.045,0,0.045,0", "-pd_region1_box",
                                                                                 "1.245,0,1.245,0", "-pd_region2_box", "0.645,0.15,0.645,0.15",
                                                                                 *["-pd_bar0_bond", "slip", "-pd_bar0_fcm", "38e6", "-pd_lambda_max",
                                                                                   "0.6", "-pd_steps", "160", "-ksp_type", "preonly", "-pc_type",
                                                                                   "cholesky", "-pd_section_x", "0.65"]]),
    # 20,000 time steps as the other explicit runs: the bar nodes' mass is scaled to the concrete's stable step
    ("slip_explicit", "bond slip, explicit", ["-pd_bar0_bond", "slip", "-pd_bar0_fcm", "38e6", "-pd_mode", "explicit", "-pd_lambda_max", "0.6"]),
]


# The same beam in four-point bending with knife-edge supports and loads (options/rc_flexure_2d.opts): loads a = 0.4 m
# from the supports, P the sum of both
FLEXURE_SCENE = os.path.join(ROOT, "options", "rc_flexure_2d.opts")
A = 0.4
PATH = ["-pd_control", "arclength", "-pd_arclength_implex", "0.01", "-pd_steps", "200", "-ksp_type", "preonly", "-pc_type", "cholesky"]
# at dx = 5 mm the node columns nearest the knife edges (those of dx = 10 mm lie halfway between two) and the bar's node line
DX5 = ["-pd_dx", "0.005", "-pd_bar0_line", "0,0.0375,1.3,0.0375", "-pd_region0_box", "0.0475,0,0.0475,0", "-pd_region1_box", "1.2475,0,1.2475,0",
       "-pd_region2_box", "0.4475,0.15,0.4475,0.15", "-pd_region3_box", "0.8475,0.15,0.8475,0.15"]
FLEXURE = [
    ("flexure_path", "path following, IMPL-EX 0.01, Cholesky (the scene's recommendation)", PATH + ["-pd_lambda_max", "0.5", "-pd_section_x", "0.65"]),
    ("flexure_default", "default path", ["-pd_lambda_max", "0.5", "-pd_section_x", "0.65"]),
    ("flexure_explicit", "explicit, ramp 0.24 s", ["-pd_lambda_max", "0.5", "-pd_mode", "explicit", "-pd_ramp_time", "0.24"]),
    ("flexure_dx5", "path following as the first, dx = 5 mm, d = 112.5 mm", PATH + DX5 + ["-pd_lambda_max", "0.5", "-pd_section_x", "0.65"]),
    # an embedded bar (on nodes of its own at its true places, docs/reinforcement.md): on the scene's node line, and at a
    # depth between two node lines, where a bar on its chain of nodes cannot lie
    ("flexure_embedded", "path following as the first, the bar embedded", PATH + ["-pd_bar0_embedded", "true", "-pd_lambda_max", "0.5",
                                                                                   "-pd_section_x", "0.65"]),
    ("flexure_embedded_d120", "path following as the first, the bar embedded at d = 120 mm, between two node lines",
     PATH + ["-pd_steps", "400", "-pd_bar0_embedded", "true", "-pd_bar0_line", "0,0.03,1.3,0.03", "-pd_lambda_max", "0.5", "-pd_section_x",
             "0.65"]),  # it takes more than 20 times 200 steps to its peak
]


def section(d=D):
    """Cracked-section analysis of three-point bending with the bar at depth d: cracking load from f_t W, yield
    load from the elastic cracked section (n = E_s/E_c, neutral axis k d, lever arm (1 - k/3) d)."""
    D = d
    rho, n = AS / (B * D), ES / EC
    k = math.sqrt(2 * rho * n + (rho * n) ** 2) - rho * n
    my = AS * FY * (1 - k / 3) * D
    mcr = FT * B * H * H / 6
    return {"P_cr_N": 4 * mcr / SPAN, "P_y_N": 4 * my / SPAN, "k": k, "lever_arm_m": (1 - k / 3) * D}


def bar_depth(extra):
    """The bar's depth below the top face: the scene's, or that of a -pd_bar0_line among the run's options."""
    return H - float(extra[extra.index("-pd_bar0_line") + 1].split(",")[1]) if "-pd_bar0_line" in extra else D


def delaminated(outdir, y, dx):
    """Length (m) of the bar's node line (at height y, nodes dx apart) whose nodal damage exceeds 0.5 at the last
    fields written."""
    import numpy as np
    fields = last_fields(outdir)
    if fields is None:  # a run stopped at its step cap writes no fields
        return None
    x, _, d = fields
    on = np.abs(x[:, 1] - y) < 1e-9  # a bar node (bond slip) has damage 0: only the concrete counts
    return float(np.sum(d[on] > 0.5)) * dx


def section_moment(row):
    """The bending moment the section cut's forces along x carry, about height 0: minus each times its height."""
    return -sum(row["section_%s" % f] * row["section_%s_height_m" % h] for f, h in (("steel_N", "steel"), ("concrete_tension_N", "tension"),
                                                                                     ("concrete_compression_N", "compression")))


def at_section(extra, row):
    """What the section cut (-pd_section_x) reports at a curve row: the moment of the forces crossing it over the nominal
    one, that of a simply supported beam under a point load, P/2 (x - x_support) - P max(0, x - x_load) with the
    centres of the left support's and the load's boxes; the concrete's share of the tension; the lever arm from the
    bar to the concrete's compression."""
    def centre(region, default):
        opt = "-pd_region%d_box" % region
        box = (extra[extra.index(opt) + 1] if opt in extra else default).split(",")
        return 0.5 * (float(box[0]) + float(box[2]))
    x = float(extra[extra.index("-pd_section_x") + 1])
    xs, xl = centre(0, "0.045,0,0.055,0"), centre(2, "0.64,0.15,0.66,0.15")
    ts, tc, yt, yc = (row[k] for k in ("section_steel_N", "section_concrete_tension_N", "section_tension_height_m", "section_compression_height_m"))
    y_bar = row["section_steel_height_m"]
    moment = section_moment(row)
    nominal = row["load_N"] / 2 * (x - xs) - row["load_N"] * max(0, x - xl)
    return {"load_N": row["load_N"], "x_m": x, "support_x_m": xs, "moment_over_nominal": moment / nominal,
            "concrete_tension_share": tc / (ts + tc), "concrete_tension_y_m": yt, "lever_arm_m": yc - y_bar, "steel_N": ts}


def flexure_yield(d):
    """Cracked-section yield load of the four-point beam with the bar at depth d."""
    return 2 * AS * FY * section(d)["lever_arm_m"] / A


def run_case(scene, extra):
    """Runs one case into a fresh folder: the folder, exit code, wall and CPU time, the curve's rows, the log's last line,
    the first row with a yielded segment (or None) and the rows with broken bonds before it."""
    out = tempfile.mkdtemp(prefix="pdbench_")
    with open(os.path.join(out, "log"), "w") as log:
        code, wall, cpu, _ = run_timed([EXE, "-options_file", scene, "-pd_output_dir", out, *extra], 3600, log)
    rows = curve_rows(out)
    return {"out": out, "code": code, "wall": wall, "cpu": cpu, "rows": rows, "status": open(os.path.join(out, "log")).read().strip().splitlines()[-1],
            "first": next((r for r in rows if r["yielded_segments"] > 0), None),
            "before": [r for r in rows if r["yielded_segments"] == 0 and r["broken_bonds"] > 0]}


def store(group, name, entry, section_values=None):
    """Merges one run into the results file as it ends (another invocation may have stored runs meanwhile)."""
    merged = load_results(JSON)
    if section_values:
        merged["section"] = section_values
    merged.setdefault(group, {})[name] = entry
    save_results(JSON, merged)


def measure_flexure(res, names):
    """The four-point beam's runs: first yield against section analysis, the steel's stress against the cracked
    section's under the constant moment P a / 2, the plateau after the first yield, the section cut."""
    res.setdefault("flexure", {})
    for name, what, extra in FLEXURE:
        if name not in names:
            continue
        r = run_case(FLEXURE_SCENE, extra)
        rows, first, before = r["rows"], r["first"], r["before"]
        d = bar_depth(extra)
        z = section(d)["lever_arm_m"]
        held = [r["load_N"] for r in rows if first and r["step"] >= first["step"]]
        moment = section_moment(first) / (first["load_N"] * A / 2) if first and "-pd_section_x" in extra else None
        res["flexure"][name] = {"what": what, "options": extra, "exit": r["code"], "cpu_s": round(r["cpu"], 1), "wall_s": round(r["wall"], 1),
                                "commit": COMMIT, "status": r["status"], "P_y_N": flexure_yield(d),
                                "first_yield_N": first["load_N"] if first else None, "first_yield_disp_m": first["disp_m"] if first else None,
                                "steel_over_section": before[-1]["steel_stress_Pa"] / (before[-1]["load_N"] * A / 2 / (AS * z)) if before else None,
                                "plateau_N": sum(held) / len(held) if held else None, "moment_over_Pa2_at_first_yield": moment,
                                "peak_N": max(r["load_N"] for r in rows), "final_disp_m": rows[-1]["disp_m"], "steps": int(rows[-1]["step"]),
                                "curve": [[r["disp_m"], r["load_N"]] for r in rows[::max(1, len(rows) // 400)]]}
        print(name, {k: v for k, v in res["flexure"][name].items() if k != "curve"})
        store("flexure", name, res["flexure"][name])


def measure(names):
    res = load_results(JSON)
    res["section"] = section()
    res.setdefault("runs", {})
    measure_flexure(res, [n for n, _, _ in FLEXURE] if not names else names)
    for name, what, extra in CASES:
        if names and name not in names:
            continue
        r = run_case(SCENE, extra)
        rows, first, before = r["rows"], r["first"], r["before"]
        k = max(range(len(rows)), key=lambda i: rows[i]["load_N"])
        # the steel stress over the cracked section's at the same load, at the last row before the bar yields
        sec = section(bar_depth(extra))
        ratio = before[-1]["steel_stress_Pa"] / (before[-1]["load_N"] * SPAN / 4 / (AS * sec["lever_arm_m"])) if before else None
        cut = at_section(extra, before[-1]) if before and "-pd_section_x" in extra else None
        res["runs"][name] = {"what": what, "options": extra, "exit": r["code"], "cpu_s": round(r["cpu"], 1), "status": r["status"],
                             "peak_N": rows[k]["load_N"], "disp_at_peak_m": rows[k]["disp_m"], "steel_stress_at_peak_Pa": rows[k]["steel_stress_Pa"],
                             "first_yield_N": first["load_N"] if first else None, "steel_over_section": ratio, "broken_bonds": int(rows[-1]["broken_bonds"]),
                             "delaminated_m": delaminated(r["out"], H - bar_depth(extra), float(extra[extra.index("-pd_dx") + 1]) if "-pd_dx" in extra else 0.01), "final_disp_m": rows[-1]["disp_m"], "P_y_N": sec["P_y_N"], "commit": COMMIT,
                             "section_before_yield": cut}
        print(name, res["runs"][name])
        store("runs", name, res["runs"][name], res["section"])


def status(line):
    """The run's last log line without the output folder, which differs between runs."""
    line = line.strip().replace("pdimplicit: run stopped early: ", "stopped: ").replace("|", "/")
    return line.split("; results in")[0].split(": results in")[0]


def report():
    res = load_results(JSON)
    s = res["section"]
    lines = ["# The small reinforced beam against cracked-section analysis", "",
             "Written by `benchmarks/rc_beam.py` from `rc_beam.json`. `options/rc_beam_2d.opts`: 1300 x 150 mm, 100 mm thick "
             "(plane stress), span 1200 mm, one 8 mm bar (f_y = 500 MPa) at d = 115 mm, three-point bending, dx = 10 mm, no-fail "
             "zones at the supports and under the load. By hand: cracking at P_cr = 4 f_t W / L = %.0f N, yield of the bar at "
             "P_y = 4 A_s f_y (1 - k/3) d / L = %.0f N (k = %.3f). Delaminated: length of the bar's node line whose nodes' damage "
             "exceeds 0.5 at the end." % (s["P_cr_N"], s["P_y_N"], s["k"]), "",
             "Steel / section: the bar's largest stress over the cracked section's at the same load, M / (A_s z), at the last row "
             "with broken bonds before the bar yields (or the last row).", "",
             "| run | peak (N) | peak / P_y | steel stress at the peak (MPa) | first yield (N) | first yield / P_y | steel / section | broken bonds | delaminated (m) | CPU (s) | commit | end |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, _, _ in CASES:
        if name not in res["runs"]:
            continue
        r = res["runs"][name]
        ratio = r.get("steel_over_section")
        lines.append("| %s | %.0f | %.2f | %.0f | %s | %s | %s | %d | %s | %.1f | %s | %s |" % (
            r["what"], r["peak_N"], r["peak_N"] / r.get("P_y_N", s["P_y_N"]), r["steel_stress_at_peak_Pa"] / 1e6,
            "%.0f" % r["first_yield_N"] if r["first_yield_N"] else "none", "%.2f" % (r["first_yield_N"] / r.get("P_y_N", s["P_y_N"])) if r["first_yield_N"] else "-",
            "%.2f" % ratio if ratio else "-", r["broken_bonds"], "%.2f" % r["delaminated_m"] if r["delaminated_m"] is not None else "-", r["cpu_s"], r.get("commit", "before 4e4abbb"),
            status(r["status"])))
    cuts = [(res["runs"][n]["what"], res["runs"][n]["section_before_yield"]) for n, _, _ in CASES if res["runs"].get(n, {}).get("section_before_yield")]
    if cuts:
        lines += ["", "## At the section", "",
                  "A section cut at mid-span (`-pd_section_x 0.65`, docs/reinforcement.md \"Section forces\"), at the last row "
                  "before the bar yields (the scene's beam cracks there; on knife edges its widest crack formed a few centimetres "
                  "beside the load, so that the cut crosses a narrower one): the moment of the forces crossing it over the nominal one, a simply supported beam's under a "
                  "point load at the load's centre; of the tension across it, the concrete's share and the height at which it acts; the lever "
                  "arm from the bar to the concrete's compression, against the cracked section's z = (1 - k/3) d = %.1f mm." % (
                      1e3 * s["lever_arm_m"]), "",
                  "| run | load (N) | moment / nominal | concrete's share of the tension | its height (mm) | lever arm (mm) |", "|---|---|---|---|---|---|"]
        for what, c in cuts:
            lines.append("| %s | %.0f | %.3f | %.2f | %.0f | %.1f |" % (what, c["load_N"], c["moment_over_nominal"], c["concrete_tension_share"],
                                                                 1e3 * c["concrete_tension_y_m"], 1e3 * c["lever_arm_m"]))
    lines += ["", "Commands: `build/pdimplicit -options_file options/rc_beam_2d.opts` with the options of each run:", ""]
    lines += ["    %s" % " ".join(c[2]) for c in CASES]
    lines += flexure_report(res)
    write_lines("rc_beam.md", lines)


def flexure_report(res):
    """The four-point beam's table and plot (rc_flexure.png)."""
    runs = [(n, res.get("flexure", {}).get(n)) for n, _, _ in FLEXURE]
    runs = [(n, r) for n, r in runs if r]
    if not runs:
        return []
    lines = ["", "## Four-point bending with knife edges", "",
             "`options/rc_flexure_2d.opts`: the same beam, section and bar (bond slip), its supports and its two loads each on one "
             "node column, the loads a = 400 mm from the supports, so that the middle 400 mm carry P a / 2 (P the sum of both loads) "
             "wherever their cracks form. By cracked-section analysis the bar yields at P_y = 2 A_s f_y (1 - k/3) d / a. "
             "Steel / section: the bar's largest stress over M / (A_s z) with M = P a / 2, at the last row with broken bonds before "
             "the bar yields. The explicit curve oscillates about the static one while the beam cracks (its first yield and "
             "steel / section are read on an oscillation) and settles on the plateau. Plateau: the mean load from the first yield to the end. Moment at mid-span: the section cut's "
             "(`-pd_section_x 0.65`) over P a / 2 at the first yield (the two loads are applied as equal displacements, so they "
             "share P equally only as long as the beam cracks symmetrically).", "",
             "| run | P_y (N) | first yield (N) | first yield / P_y | at (mm) | steel / section | plateau / P_y | moment at mid-span / (P a/2) | steps | CPU (s) | commit | end |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for _, r in runs:
        fy = r["first_yield_N"]
        lines.append("| %s | %.0f | %s | %s | %s | %s | %s | %s | %d | %.1f | %s | %s |" % (
            r["what"], r["P_y_N"], "%.0f" % fy if fy else "none", "%.3f" % (fy / r["P_y_N"]) if fy else "-",
            "%.2f" % (1e3 * r["first_yield_disp_m"]) if fy else "-", "%.3f" % r["steel_over_section"] if r["steel_over_section"] else "-",
            "%.3f" % (r["plateau_N"] / r["P_y_N"]) if r["plateau_N"] else "-",
            "%.4f" % r["moment_over_Pa2_at_first_yield"] if r["moment_over_Pa2_at_first_yield"] else "-", r["steps"], r["cpu_s"], r["commit"],
            status(r["status"])))
    lines += ["", "![load against the load points' displacement](rc_flexure.png)", "",
              "Commands: `build/pdimplicit -options_file options/rc_flexure_2d.opts` with the options of each run:", ""]
    lines += ["    %s" % " ".join(r["options"]) for _, r in runs]
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    for _, r in runs:
        ax.plot([1e3 * c[0] for c in r["curve"]], [c[1] / 1e3 for c in r["curve"]], lw=0.8, label=r["what"])
    for p_y in sorted(set(round(r["P_y_N"]) for _, r in runs)):
        ax.axhline(p_y / 1e3, color="k", ls="--", lw=0.6)
    ax.set_xlabel("load points' displacement (mm)")
    ax.set_ylabel("P (kN)")
    ax.set_title("four-point bending; dashed: P_y by cracked-section analysis")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "rc_flexure.png"), dpi=110)
    return lines


if __name__ == "__main__":
    if "--report" not in sys.argv[1:]:
        measure(sys.argv[1:])
    report()
