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

from common import curve_rows, EXE, RESULTS_DIR, ROOT, last_fields, run_timed, save_results, load_results, write_lines

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
    ts, tc, cc, yt, yc = (row[k] for k in ("section_steel_N", "section_concrete_tension_N", "section_concrete_compression_N",
                                            "section_tension_y_m", "section_compression_y_m"))
    y_bar = H - bar_depth(extra)
    moment = -(ts * y_bar + tc * yt + cc * yc)
    nominal = row["load_N"] / 2 * (x - xs) - row["load_N"] * max(0, x - xl)
    return {"load_N": row["load_N"], "x_m": x, "support_x_m": xs, "moment_over_nominal": moment / nominal,
            "concrete_tension_share": tc / (ts + tc), "concrete_tension_y_m": yt, "lever_arm_m": yc - y_bar, "steel_N": ts}


def measure(names):
    res = load_results(JSON)
    res["section"] = section()
    res.setdefault("runs", {})
    for name, what, extra in CASES:
        if names and name not in names:
            continue
        out = tempfile.mkdtemp(prefix="pdbench_")
        with open(os.path.join(out, "log"), "w") as log:
            code, wall, cpu, _ = run_timed([EXE, "-options_file", SCENE, "-pd_output_dir", out, *extra], 3600, log)
        rows = curve_rows(out)
        k = max(range(len(rows)), key=lambda i: rows[i]["load_N"])
        first = next((r for r in rows if r["yielded_segments"] > 0), None)
        # the steel stress over the cracked section's at the same load, at the last row before the bar yields (or the last)
        before = [r for r in rows if r["yielded_segments"] == 0 and r["broken_bonds"] > 0]
        sec = section(bar_depth(extra))
        ratio = before[-1]["steel_stress_Pa"] / (before[-1]["load_N"] * SPAN / 4 / (AS * sec["lever_arm_m"])) if before else None
        status = open(os.path.join(out, "log")).read().strip().splitlines()[-1]
        cut = at_section(extra, before[-1]) if before and "-pd_section_x" in extra else None
        res["runs"][name] = {"what": what, "options": extra, "exit": code, "cpu_s": round(cpu, 1), "status": status,
                             "peak_N": rows[k]["load_N"], "disp_at_peak_m": rows[k]["disp_m"], "steel_stress_at_peak_Pa": rows[k]["steel_stress_Pa"],
                             "first_yield_N": first["load_N"] if first else None, "steel_over_section": ratio, "broken_bonds": int(rows[-1]["broken_bonds"]),
                             "delaminated_m": delaminated(out, H - bar_depth(extra), float(extra[extra.index("-pd_dx") + 1]) if "-pd_dx" in extra else 0.01), "final_disp_m": rows[-1]["disp_m"], "P_y_N": sec["P_y_N"], "commit": COMMIT,
                             "section_before_yield": cut}
        print(name, res["runs"][name])
    save_results(JSON, res)


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
                  "A section cut (`-pd_section_x`, docs/reinforcement.md \"Section forces\") through the mid-span crack, at the last row "
                  "before the bar yields: the moment of the forces crossing it over the nominal one, a simply supported beam's under a "
                  "point load at the load's centre; of the tension across it, the concrete's share and the height at which it acts; the lever "
                  "arm from the bar to the concrete's compression, against the cracked section's z = (1 - k/3) d = %.1f mm." % (
                      1e3 * s["lever_arm_m"]), "",
                  "| run | load (N) | moment / nominal | concrete's share of the tension | its height (mm) | lever arm (mm) |", "|---|---|---|---|---|---|"]
        for what, c in cuts:
            lines.append("| %s | %.0f | %.3f | %.2f | %.0f | %.1f |" % (what, c["load_N"], c["moment_over_nominal"], c["concrete_tension_share"],
                                                                 1e3 * c["concrete_tension_y_m"], 1e3 * c["lever_arm_m"]))
    lines += ["", "Commands: `build/pdimplicit -options_file options/rc_beam_2d.opts` with the options of each run:", ""]
    lines += ["    %s" % " ".join(c[2]) for c in CASES]
    write_lines("rc_beam.md", lines)


if __name__ == "__main__":
    if "--report" not in sys.argv[1:]:
        measure(sys.argv[1:])
    report()
