"""The small reinforced beam (options/rc_beam_2d.opts) up to 7 kN, before the bar delaminates
(docs/reinforcement.md): it cracks in flexure under the load, and the implicit curve, steel stress and
broken bonds match the explicit path's. With `slip`, the same beam with the bar on its own nodes under the
bond-slip law: displacement control alone carries it through its first cracks, its end state matches the
explicit path's, and the bar nodes' mass scaling keeps the explicit step at the concrete's. With `mode`, the
failure mode summary.json reports, on the bond-slip beam traced through its bar's yield explicitly. With
`crush`, the crushing criterion (-pd_eps_cu) on an elastic prism and on that beam.
Usage: test_rc_beam.py [slip|mode|crush]"""
import bisect
import math
import os
import sys

import numpy as np

from pdtest import check, run, run_both

OPTS = ["-pd_lambda_max", "0.065"]  # 0.52 mm at the load point, about 6.1 kN


def at(curve, d, key):
    """Value of key at load-point displacement d, interpolated along an explicit curve."""
    xs = [r["disp_m"] for r in curve]
    i = min(max(1, bisect.bisect_left(xs, d)), len(xs) - 1)
    t = (d - xs[i - 1]) / (xs[i] - xs[i - 1])
    return curve[i - 1][key] * (1 - t) + curve[i][key] * t


def main():
    imp = run("rc_beam_2d", *OPTS, "-pd_steps", "26")
    exp = run("rc_beam_2d", *OPTS, "-pd_mode", "explicit")
    a, b = imp.curve, exp.curve
    check(imp.summary["converged"] and exp.summary["converged"], "both paths reach 0.52 mm (%s; %s)" % (imp.summary["status"], exp.summary["status"]))
    # it cracks in flexure: the damaged nodes lie in the middle of the span, the most damaged on the soffit
    # side under the load
    x, _, d = imp.fields()
    x, d = x.reshape(len(d), -1), d.ravel()
    hurt = d > 0.3
    check(hurt.any() and np.all(np.abs(x[hurt, 0] - 0.65) < 0.2), "%d nodes damaged over 0.3, all within 0.2 m of mid-span" % hurt.sum())
    k = int(np.nanargmax(d))
    check(abs(x[k, 0] - 0.65) < 0.05 and x[k, 1] < 0.075, "the most damaged node at x = %.3f m, y = %.3f m: below the load, in the tension half"
          % (x[k, 0], x[k, 1]))
    # implicit against explicit at equal load-point displacement. The explicit curve oscillates about the
    # static one where a crack forms (measured: up to 20 % at the first crack, one row), so the curves are
    # compared by their RMS difference, and the state at the end
    peak = max(r["load_N"] for r in a)
    rows = [r for r in a if b[0]["disp_m"] < r["disp_m"] < b[-1]["disp_m"]]
    rms = np.sqrt(np.mean([(r["load_N"] - at(b, r["disp_m"], "load_N")) ** 2 for r in rows])) / peak
    check(rms < 0.05, "load against displacement: RMS difference %.2f %% of the peak %.0f N over %d rows (5 %%)" % (100 * rms, peak, len(rows)))
    e = a[-1]
    s_exp = at(b, e["disp_m"], "steel_stress_Pa")
    check(abs(e["steel_stress_Pa"] - s_exp) < 0.03 * s_exp, "steel stress at the end %.1f MPa against %.1f MPa explicit (3 %%)" % (
        e["steel_stress_Pa"] / 1e6, s_exp / 1e6))
    bb = at(b, e["disp_m"], "broken_bonds")
    check(e["broken_bonds"] > 0 and abs(e["broken_bonds"] - bb) <= 0.2 * bb, "broken bonds at the end %d against %.0f explicit (20 %%)" % (
        e["broken_bonds"], bb))
    # the elastic start, at the last row before cracking (0.18 mm; earlier the explicit ramp's inertia
    # shows, 3 % at 0.02 mm): the two paths' secant stiffness within 1 %
    r = [x for x in a if x["disp_m"] <= 1.8e-4][-1]
    k0, k1 = r["load_N"] / r["disp_m"], at(b, r["disp_m"], "load_N") / r["disp_m"]
    check(abs(k0 / k1 - 1) < 0.01, "stiffness at %.2f mm %.4e N/m against %.4e N/m explicit (1 %%)" % (1e3 * r["disp_m"], k0, k1))


SLIP = ["-pd_bar0_bond", "slip", "-pd_bar0_fcm", "38e6", "-pd_lambda_max", "0.1"]  # 0.8 mm at the load point


def slip():
    # displacement control alone (no hand-over to path following): Newton cycles as the first cracks open
    # across the bar's bond-slip links, and is settled by freezing the softened bonds' branches (static.c)
    imp = run("rc_beam_2d", *SLIP, "-pd_steps", "25", "-pd_control_fallback", "false")
    exp = run("rc_beam_2d", *SLIP, "-pd_mode", "explicit")
    check(imp.summary["converged"] and exp.summary["converged"], "both paths reach 0.8 mm (%s; %s)" % (imp.summary["status"], exp.summary["status"]))
    a, b = imp.curve, exp.curve
    check(a[-1]["broken_bonds"] > 0 and a[-1]["load_N"] > 4 * 3e6 * 0.1 * 0.15 ** 2 / 6 / 1.2,
          "cracked: %d broken bonds, load %.0f N above the cracking load" % (a[-1]["broken_bonds"], a[-1]["load_N"]))
    # the end state against the explicit path at the same displacement (measured: load 0.7 %, steel stress
    # 0.5 %, slip 0.9 %, broken bonds 2 of 100); between the first crack and the end the explicit curve
    # oscillates about the static one (a crack bursts dynamically), so the end is where they are compared
    e = a[-1]
    for key, tol in (("load_N", 0.03), ("steel_stress_Pa", 0.03), ("slip_m", 0.03), ("broken_bonds", 0.2)):
        ref = at(b, e["disp_m"], key)
        check(abs(e[key] / ref - 1) < tol, "%s at %.2f mm: %.4g implicit, %.4g explicit (%g %%)" % (key, 1e3 * e["disp_m"], e[key], ref, 100 * tol))
    # the bar nodes' mass is scaled to the concrete's stable step: with their steel mass alone the step is
    # about half (measured 0.57 of the scaled one); the mass added is a few per cent of the beam's 46.8 kg
    plain = run("rc_beam_2d", *SLIP, "-pd_mode", "explicit", "-pd_bar_mass_scaling", "false", "-pd_ramp_time", "1e-4", expect_ok=False)
    conc = run("rc_beam_2d", "-pd_lambda_max", "0.1", "-pd_mode", "explicit", "-pd_ramp_time", "1e-4", expect_ok=False)
    dt = {k: r.summary["explicit"]["dt_stable_s"] for k, r in (("scaled", exp), ("plain", plain), ("concrete", conc))}
    check(abs(dt["scaled"] / dt["concrete"] - 1) < 0.1 and dt["plain"] < 0.7 * dt["scaled"],
          "stable steps: %.3e s scaled, %.3e s steel mass only, %.3e s concrete bond (scaled within 10 %% of it)" % (
              dt["scaled"], dt["plain"], dt["concrete"]))
    added = exp.summary["explicit"]["bar_mass_added_kg"]
    check(0 < added < 0.05 * 1.3 * 0.15 * 0.1 * 2400, "mass added to the bar nodes %.3f kg, under 5 %% of the beam's" % added)


def mode():
    # The failure mode in summary.json (docs/reinforcement.md, "Failure mode") on the bond-slip beam traced
    # explicitly to 4.8 mm, with three bars: the beam's own, which yields and holds its load (no failure
    # yet); one that ruptures at 1 % strain after yielding (flexure); and one that cannot yield, anchored by
    # a bond forty times weaker, which pulls out (failure with the bar elastic: shear or anchorage).
    # The crack bursts and the bar's yield make bonds gain stretch fast; the stability check lets them by
    # because the energy balance holds (docs/explicit.md).
    base = ["-pd_bar0_bond", "slip", "-pd_mode", "explicit", "-pd_lambda_max", "0.6"]
    cases = (("yields", ["-pd_bar0_fcm", "38e6"], "none"), ("ruptures", ["-pd_bar0_fcm", "38e6", "-pd_bar0_rupture", "0.01"], "flexure"),
             ("pulls out", ["-pd_bar0_fcm", "1e6", "-pd_bar0_fy", "5e9"], "shear"))
    for what, extra, want in cases:
        r = run("rc_beam_2d", *base, *extra)
        s, last = r.summary, r.curve[-1]
        peak = max(row["load_N"] for row in r.curve)
        check(s["converged"] and s["bars"]["failure_mode"] == want, "bar that %s: %s, failure mode %s (end %.0f N, peak %.0f N, first yield %s)" % (
            what, s["status"], s["bars"]["failure_mode"], last["load_N"], peak, s["bars"]["first_yield"]))
        if what == "yields":  # (a bar's rupture releases energy in one step: its balance is not asserted here)
            held = last["stored_J"] + last["dissipated_J"] + last["kinetic_J"] + last["damped_J"]
            check(abs(held / last["external_J"] - 1) < 0.01, "energy balance at the end: work %.3f J, held %.3f J (1 %%)" % (last["external_J"], held))


def crush():
    # The crushing criterion (-pd_eps_cu, docs/reinforcement.md "Failure mode"). First an elastic prism in
    # uniaxial compression: the layers held by the support and the load are left out, so the bond strain it
    # follows is the prism's own, about u / h between the first and last node rows (h = 0.195 m; the two
    # layers next to the held rows take a little more than their share of u, the body a little less: 2e-3
    # bounds that), in proportion to u at every step (linear), and the run stops at the first step beyond
    # -eps_cu.
    r = run("prism_compression_2d", "-pd_law", "elastic", "-pd_eps_cu", "0.002", "-pd_steps", "10", "-pd_lambda_max", "1")
    s, c = r.summary, r.curve
    check(s["status"].startswith("crushed") and s["converged"] and "crushing_strain" in s["effects"], "elastic prism: %s (effects %s)" % (
        s["status"], ", ".join(s["effects"])))
    ratios = [row["strain_min"] / (-row["disp_m"] / 0.195) for row in c]
    check(abs(ratios[0] - 1) < 2e-3 and max(abs(q / ratios[0] - 1) for q in ratios) < 1e-5,
          "strain followed: %.5f times the prism's u / h (within 2e-3), the same at every step (to 1e-5: of bonds whose compressions "
          "tie within 1e-6, the criterion follows the one of the smallest id)" % ratios[0])
    check(c[-1]["strain_min"] <= -0.002 < c[-2]["strain_min"], "stopped at the first step beyond -0.002: %.5f after %.5f" % (
        c[-1]["strain_min"], c[-2]["strain_min"]))
    # the prism is symmetric, so several bonds tie for the largest compression: two ranks name the same one
    r2 = run("prism_compression_2d", "-pd_law", "elastic", "-pd_eps_cu", "0.002", "-pd_steps", "10", "-pd_lambda_max", "1", ranks=2)
    check(r2.summary["status"] == s["status"], "two ranks: %s" % r2.summary["status"])
    # The bond-slip beam with a hardening bar (explicit, as `mode`): the compression at the top grows after
    # the bar yields (to about 0.0007), having stayed below about 0.0006 before, so eps_cu = 0.00065 crushes
    # it in flexure, in the compression zone at the top of the span's middle third.
    r = run("rc_beam_2d", "-pd_bar0_bond", "slip", "-pd_mode", "explicit", "-pd_lambda_max", "0.6", "-pd_bar0_fcm", "38e6",
            "-pd_bar0_hardening", "0.2", "-pd_eps_cu", "0.00065")
    s = r.summary
    fy = s["bars"]["first_yield"]
    x, y = [float(v) for v in s["status"].split(" at (")[1].split(")")[0].split(",")]
    check(s["status"].startswith("crushed") and s["bars"]["failure_mode"] == "flexure" and fy and fy["step"] < r.curve[-1]["step"],
          "hardening bar: %s, failure mode %s, first yield %s" % (s["status"], s["bars"]["failure_mode"], fy))
    check(y > 0.13 and 0.45 < x < 0.85, "crushed in the compression zone at (%.3f, %.3f) m: top 20 mm, middle third of the span" % (x, y))
    # a path-following run of the prism, stopped short of crushing with a checkpoint, goes on from it (the
    # linear model's stiffness is assembled anew for the restart's matrix) and keeps its strain column
    prism = ["-pd_law", "elastic", "-pd_control", "arclength", "-pd_steps", "10"]
    a = run("prism_compression_2d", *prism, "-pd_eps_cu", "0.004", "-pd_lambda_max", "0.4", "-pd_checkpoint_every", "2")
    b = run("prism_compression_2d", *prism, "-pd_eps_cu", "0.002", "-pd_lambda_max", "1", "-pd_restart",
            os.path.join(a.dir, "checkpoint.h5"))
    kept = [row["strain_min"] for row in b.curve[:len(a.curve)]]
    check(b.summary["status"].startswith("crushed") and kept == [row["strain_min"] for row in a.curve],
          "restart: %s; strain_min of the %d rows before it kept" % (b.summary["status"], len(a.curve)))
    # without the criterion nothing of it shows
    r = run("prism_compression_2d", "-pd_law", "elastic", "-pd_steps", "2", "-pd_lambda_max", "0.2")
    check("crushing_strain" not in r.summary["effects"] and all(row["strain_min"] == 0 for row in r.curve),
          "without -pd_eps_cu: no crushing_strain effect, strain_min 0 (%s)" % ", ".join(r.summary["effects"]))


def flexure():
    # The beam in four-point bending with knife-edge supports and loads (options/rc_flexure_2d.opts), traced to 3.44 mm
    # at the load points by path following with IMPL-EX steps (the options its scene recommends) and, at the same
    # time, to 4 mm on the explicit path. Cracked-section analysis: the bar yields at P_y = 2 A_s f_y (1 - k/3) d / a.
    a_s, d, a, n = math.pi * 0.008 ** 2 / 4, 0.115, 0.4, 200 / 30
    rho = a_s / (0.1 * d)
    k = math.sqrt(2 * rho * n + (rho * n) ** 2) - rho * n
    p_y = 2 * a_s * 500e6 * (1 - k / 3) * d / a
    m_cr = 3e6 * 0.1 * 0.15 ** 2 / 6
    path = ["-pd_control", "arclength", "-pd_arclength_implex", "0.01", "-pd_steps", "200", "-ksp_type", "preonly", "-pc_type", "cholesky"]
    imp, exp = run_both(("rc_flexure_2d", *path, "-pd_lambda_max", "0.43", "-pd_section_x", "0.65"),
                        ("rc_flexure_2d", "-pd_lambda_max", "0.5", "-pd_mode", "explicit", "-pd_ramp_time", "0.24"))
    check(imp.summary["converged"] and exp.summary["converged"], "both paths reach their end (%s; %s)" % (imp.summary["status"], exp.summary["status"]))
    # flexural cracks: on the soffit, damage only where the moment passes the cracking moment (x from 0.045 + a M_cr / M_y,
    # M_y = P_y a / 2, to the mirror point), and at least two cracks between the loads
    x, _, dmg = imp.fields()
    x, dmg = x.reshape(len(dmg), -1), dmg.ravel()
    soffit = (np.abs(x[:, 1] - 0.005) < 1e-9) & (dmg > 0.5)
    lo = 0.045 + a * m_cr / (p_y * a / 2)
    cracks = np.unique(np.round(x[soffit, 0] / 0.02))  # columns two apart count as one crack
    check(soffit.any() and np.all((x[soffit, 0] > lo) & (x[soffit, 0] < 1.29 - lo)) and np.sum((cracks * 0.02 > 0.445) & (cracks * 0.02 < 0.845)) >= 2,
          "soffit damaged at x = %s m, all between %.3f and %.3f m where M > M_cr, at least 2 cracks between the loads" % (
              ", ".join("%.3f" % v for v in sorted(set(np.round(x[soffit, 0], 3)))), lo, 1.29 - lo))
    first = imp.summary["bars"]["first_yield"]
    check(first and abs(first["load_N"] / p_y - 1) < 0.05, "first yield at %s N against P_y = %.0f N by section analysis (5 %%)" % (
        "%.0f" % first["load_N"] if first else "none", p_y))
    # at the first yield the two loads are equal, as section analysis assumes: the moment across mid-span is P a / 2
    row = next(r for r in imp.curve if r["step"] == first["step"])
    m = section_forces(row)[1]
    check(abs(m / (row["load_N"] * a / 2) - 1) < 0.01, "moment at mid-span at the first yield %.1f N m, P a / 2 = %.1f N m (1 %%)" % (m, row["load_N"] * a / 2))
    # the explicit cross-check: the same elastic stiffness before the first crack (its ramp's inertia shows earlier),
    # and the same plateau once the bar has yielded (the crack phase between oscillates about the static curve)
    r = [q for q in imp.curve if q["disp_m"] <= 2e-4][-1]
    k0, k1 = r["load_N"] / r["disp_m"], at(exp.curve, r["disp_m"], "load_N") / r["disp_m"]
    check(abs(k0 / k1 - 1) < 0.01, "stiffness at %.2f mm %.4e N/m against %.4e N/m explicit (1 %%)" % (1e3 * r["disp_m"], k0, k1))
    held = [q["load_N"] for q in imp.curve if q["step"] >= first["step"]]
    late = [q["load_N"] for q in exp.curve if 3.5e-3 < q["disp_m"] <= 4e-3]
    pi, pe = np.mean(held), np.mean(late)
    check(len(held) > 1 and late and abs(pi / pe - 1) < 0.03, "plateau: %.0f N implicit once the bar yields (%d rows), %.0f N explicit from 3.5 "
          "to 4 mm (3 %%), P_y %.0f N" % (pi, len(held), pe, p_y))


SECTION = ["-pd_law", "elastic", "-pd_steps", "2", "-pd_lambda_max", "0.05", "-ksp_rtol", "1e-10"]
COLUMNS = ("section_steel_N", "section_concrete_tension_N", "section_concrete_compression_N", "section_steel_height_m", "section_tension_height_m",
           "section_compression_height_m", "section_shear_N")


def section_forces(row):
    """The section's columns of a curve row: the forces along x, their moment about the soffit (height 0) and the shear."""
    ts, tc, cc, ys, yt, yc, v = (row[k] for k in COLUMNS)
    return ts + tc + cc, -(ts * ys + tc * yt + cc * yc), v


def section():
    # The section cut (-pd_section_x) on the elastic beam: by equilibrium of the part before the plane, the forces
    # the crossing bonds carry sum to its reactions. The beam has no horizontal load, so the forces along x cancel;
    # the shear is the left support's reaction, half the load by symmetry (the supports differ in x only); and
    # the moment about the soffit grows along the span by that reaction times the distance (the support's
    # own couple, its two node columns held, drops out of the difference).
    runs = {x: run("rc_beam_2d", *SECTION, "-pd_section_x", x) for x in (0.2, 0.6)}
    moved = run("rc_beam_2d", *SECTION, "-pd_steps", "1", "-pd_section_x", 0.6032).summary["section"]["x_m"]
    check(abs(moved - 0.6) < 1e-12, "-pd_section_x 0.6032 cuts at x = %.6f m, halfway between the node columns at 0.595 and 0.605 m" % moved)
    for x, r in runs.items():
        for row in r.curve[1:]:
            n, m, v = section_forces(row)
            check(abs(row["section_steel_height_m"] - 0.035) < 1e-12, "x = %g m, step %d: the bar's force acts at %.4f m, its line" % (
                x, row["step"], row["section_steel_height_m"]))
            check(abs(n) < 1e-8 * row["section_concrete_tension_N"], "x = %g m, step %d: forces along x sum to %.3g N (tension %.4g N)" % (
                x, row["step"], n, row["section_concrete_tension_N"]))
            check(abs(-v / (row["load_N"] / 2) - 1) < 1e-4, "x = %g m, step %d: shear %.6g N against half the load %.6g N (1e-4)" % (
                x, row["step"], -v, row["load_N"] / 2))
    for a, b in zip(runs[0.2].curve[1:], runs[0.6].curve[1:]):
        dm = section_forces(b)[1] - section_forces(a)[1]
        check(abs(dm / (b["load_N"] / 2 * 0.4) - 1) < 1e-5, "step %d: moment from x = 0.2 to 0.6 m grows by %.6g N m, the reaction times "
              "0.4 m %.6g N m (1e-5)" % (b["step"], dm, b["load_N"] / 2 * 0.4))
    # in 3D the heights and the shear are along z, the vertical of the scenes' beams: the elastic cantilever
    # (options/cantilever.opts, 10 kN down at its free end) cut at x = 0.3 and 0.7 m carries the load as shear at
    # both, no net force along x, and a moment that changes by the load times 0.4 m between them (hogging: the
    # tension at the top)
    cut = {}
    for x in (0.3, 0.7):
        row = run("cantilever", "-pd_section_x", x, "-ksp_rtol", "1e-10").curve[-1]
        n, cut[x], v = section_forces(row)
        tc = row["section_concrete_tension_N"]
        check(abs(n) < 1e-6 * tc and abs(v / -1e4 - 1) < 1e-6, "cantilever cut at x = %g m: forces along x sum to %.2g N (tension "
              "%.4g N), shear %.6g N against the load -1e4 N (1e-6)" % (x, n, tc, v))
    check(abs(abs(cut[0.3] - cut[0.7]) / (1e4 * 0.4) - 1) < 1e-6, "cantilever: moment from x = 0.3 to 0.7 m changes by %.6g N m, the "
          "load times 0.4 m (1e-6)" % (cut[0.7] - cut[0.3]))
    # two ranks sum the same forces: the plane at mid-span is where the two ranks' slabs meet, so that every bond
    # crossing it has a ghost end and is held by both ranks (each counts it once)
    one, two = run("rc_beam_2d", *SECTION, "-pd_section_x", 0.65), run("rc_beam_2d", *SECTION, "-pd_section_x", 0.65, ranks=2)
    diff = max(abs(b[k] - a[k]) / abs(a["section_concrete_tension_N"]) for a, b in zip(one.curve, two.curve) for k in COLUMNS)
    check(len(two.curve) == len(one.curve) and diff < 1e-8, "two ranks: the section's columns within %.1e of one rank's (1e-8 of the tension)" % diff)
    # a path-following run's restart from a checkpoint keeps the section's columns of the rows before it
    arc = ["-pd_law", "elastic", "-pd_control", "arclength", "-pd_section_x", 0.6]
    a = run("rc_beam_2d", *arc, "-pd_steps", "4", "-pd_lambda_max", "0.02", "-pd_checkpoint_every", "2")
    b = run("rc_beam_2d", *arc, "-pd_steps", "8", "-pd_lambda_max", "0.04", "-pd_restart", os.path.join(a.dir, "checkpoint.h5"))
    kept = [[row[k] for k in COLUMNS] for row in b.curve[:len(a.curve)]]
    check(kept == [[row[k] for k in COLUMNS] for row in a.curve] and len(b.curve) > len(a.curve),
          "restart: the section's columns of the %d rows before it kept, %d rows in all" % (len(a.curve), len(b.curve)))


if __name__ == "__main__":
    {"slip": slip, "mode": mode, "crush": crush, "section": section, "flexure": flexure}.get(sys.argv[1] if sys.argv[1:] else "", main)()
