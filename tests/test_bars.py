"""Steel bars (-pd_barK_*): axial stiffness and yield force as built, a bar holding a cut prism, its yield
plateau traced by path following, MPI.
Usage: test_bars.py axial|diagonal|notch|plateau|mpi|restart|stuttgart|pullout|embedded"""
import math
import os
import sys
import tempfile

from pdtest import check, rel, run, scene

AREA = math.pi * 0.012 ** 2 / 4  # m^2, the 12 mm bar of options/bar_prism.opts
FY, ES = 500e6, 200e9


def expected(eps, h):
    """Force of a bar of AREA at axial strain eps, bilinear with hardening ratio h."""
    ey = FY / ES
    return ES * AREA * eps if eps <= ey else FY * AREA + h * ES * AREA * (eps - ey)


def prism(model, dx):
    """The prism of options/bar_prism.opts without its cut, concrete 2e8 times softer than the steel
    (E = 1e3 Pa), pulled by 2 mm; in plane stress 100 mm thick with the bar as two of half its area."""
    if model == "3d":
        geo = ["-pd_domain", "0,0,0,0.4,0.1,0.1", "-pd_bar0_line", "0,0.05,0.05,0.4,0.05,0.05", "-pd_bar0_diameter", "0.012",
               "-pd_region0_box", "0,0,0,0,0.1,0.1", "-pd_region0_dofs", "x,y,z", "-pd_region1_box", "0.4,0,0,0.4,0.1,0.1",
               "-pd_region1_dofs", "x,y,z", "-pd_region1_displacement", "0.002,0,0"]
    else:
        geo = ["-pd_model", model, "-pd_thickness", "0.1", "-pd_domain", "0,0,0.4,0.1", "-pd_bar0_line", "0,0.05,0.4,0.05",
               "-pd_bar0_count", "2", "-pd_bar0_diameter", repr(0.012 / math.sqrt(2)), "-pd_region0_box", "0,0,0,0.1",
               "-pd_region0_dofs", "x,y", "-pd_region1_box", "0.4,0,0.4,0.1", "-pd_region1_dofs", "x,y", "-pd_region1_displacement", "0.002,0"]
    return ["-pd_name", "prism", "-pd_dx", dx, "-pd_E", "1e3", "-pd_law", "elastic", "-pd_region0_kind", "support", "-pd_region1_kind",
            "displacement", "-pd_steps", "10", "-pd_bar0_hardening", "0.02", "-ksp_rtol", "1e-12"] + geo


def axial():
    # The bar alone carries the load (the concrete's share is below 1e-6 of it): the force against the end
    # displacement is the nominal bar's, elastic, at yield and hardening (2 %), at spacings that do and do
    # not divide the section, in 3D and plane stress. The bar's length is that between the first and the
    # last node on its line, 0.4 m - dx. Tolerance 1e-4: the linear solves' (measured: 6e-6).
    for model, dx in (("3d", 0.02), ("3d", 0.0125), ("plane_stress", 0.01)):
        r = run(None, *prism(model, dx))
        length = 0.4 - dx
        worst = max(rel(x["load_N"], expected(x["disp_m"] / length, 0.02)) for x in r.curve)
        check(worst < 1e-4, "%s, dx = %g m: force within %.1e of E A_s eps, then f_y A_s + h E A_s (eps - eps_y), over %d steps (1e-4)"
              % (model, dx, worst, len(r.curve)))
        s = r.summary["bars"]
        check(s["segments"] == round(length / dx), "%d segments on the bar's line" % s["segments"])
        check(s["yielded_segments"] == s["segments"], "every segment yielded (%d)" % s["yielded_segments"])


def diagonal():
    # Bars along lattice directions other than the axes: a face diagonal (1, 0, 1) in 3D and a (2, 1) bar in
    # plane stress, in the soft prism (concrete E = 1e3 Pa), the far face moved along the bar: the force
    # against the elongation of the node chain is the nominal bar's, elastic, at yield and hardening (1e-4,
    # as for the axes).
    common = ["-pd_name", "diagonal", "-pd_dx", "0.02", "-pd_E", "1e3", "-pd_law", "elastic", "-pd_bar0_diameter", "0.012",
              "-pd_bar0_hardening", "0.02", "-pd_region0_kind", "support", "-pd_region1_kind", "displacement", "-pd_steps", "10",
              "-ksp_rtol", "1e-12"]
    cases = {"3d (1, 0, 1)": (["-pd_domain", "0,0,0,0.4,0.1,0.4", "-pd_bar0_line", "0.01,0.05,0.01,0.39,0.05,0.39",
                               "-pd_region0_box", "0,0,0,0,0.1,0.4", "-pd_region0_dofs", "x,y,z", "-pd_region1_box", "0.4,0,0,0.4,0.1,0.4",
                               "-pd_region1_dofs", "x,y,z", "-pd_region1_displacement", "0.002,0,0.002"], 19, math.sqrt(2) * 0.02),
             "plane stress (2, 1)": (["-pd_model", "plane_stress", "-pd_thickness", "0.1", "-pd_domain", "0,0,0.38,0.2",
                                      "-pd_bar0_line", "0.01,0.01,0.37,0.19", "-pd_region0_box", "0,0,0,0.2", "-pd_region0_dofs", "x,y",
                                      "-pd_region1_box", "0.38,0,0.38,0.2", "-pd_region1_dofs", "x,y", "-pd_region1_displacement",
                                      "0.004,0.002"], 9, math.sqrt(5) * 0.02)}
    for name, (geo, nseg, step) in cases.items():
        r = run(None, *(common + geo))
        length = nseg * step
        worst = max(rel(x["load_N"], expected(x["disp_m"] / length, 0.02)) for x in r.curve)
        s = r.summary["bars"]
        check(s["segments"] == nseg and s["yielded_segments"] == nseg, "%s: %d segments, all yielded" % (name, s["segments"]))
        check(worst < 1e-4, "%s: force within %.1e of the nominal bar's over %d steps (1e-4)" % (name, worst, len(r.curve)))
    # a bar between lattice directions is embedded, which the default bond (concrete) cannot be: refused, naming its option
    r = run("bar_prism", "-pd_bar0_line", "0,0.05,0.05,0.4,0.09,0.05", expect_ok=False)
    check(r.returncode == 2 and "-pd_bar0_line" in r.stderr and "lattice direction" in r.stderr, "a bar off the lattice directions is bad input")


def notch():
    # Cut through at mid-length, the prism hangs on its bar: the bar's segment across the cut is kept without
    # concrete, and once it yields the load stays at f_y A_s exactly, at any dx (1e-9: round-off).
    # (Newton converges linearly on the yielded segment, whose tangent slope has a floor, -pd_steel_tangent_floor:
    # -snes_rtol 1e-14 asks it for round-off)
    for dx in ("0.02", "0.01"):
        r = run("bar_prism", "-pd_dx", dx, "-ksp_rtol", "1e-12", "-snes_rtol", "1e-14")
        c, s = r.curve, r.summary
        check(s["effects"] == ["elasticity", "steel_plasticity"], "effects %s" % s["effects"])
        top = max(x["load_N"] for x in c)
        check(rel(top, FY * AREA) < 1e-9, "dx = %s m: largest load %.6f N, f_y A_s = %.6f N" % (dx, top, FY * AREA))
        check(rel(c[-1]["load_N"], FY * AREA) < 1e-9 and c[-1]["yielded_segments"] >= 1, "the last step holds at the yield force, %d segment(s) yielded"
              % c[-1]["yielded_segments"])
        check(abs(c[-1]["steel_stress_Pa"] - FY) < 1e-6 * FY, "largest steel stress %.6e Pa, f_y" % c[-1]["steel_stress_Pa"])
        # the system is linear but for the one segment, so at the end it stores F_y^2 / 2K (K the initial
        # stiffness) and the segment has dissipated F_y times its plastic elongation, u - F_y / K
        k = c[0]["load_N"] / c[0]["disp_m"]
        stored, dissipated = (FY * AREA) ** 2 / (2 * k), FY * AREA * (c[-1]["disp_m"] - FY * AREA / k)
        check(rel(c[-1]["stored_J"], stored) < 1e-6, "stored %.6f J, F_y^2 / 2K = %.6f J (1e-6)" % (c[-1]["stored_J"], stored))
        check(rel(c[-1]["dissipated_J"], dissipated) < 1e-6, "dissipated %.6f J, F_y (u - F_y / K) = %.6f J (1e-6)" % (
            c[-1]["dissipated_J"], dissipated))
        # the fields: the segment across the cut yields alone, so its two nodes have the largest stress, f_y, and
        # the only plastic strain, which is the plastic elongation over the segment's length
        sigma, plastic = r.field("steel_stress"), r.field("steel_plastic_strain")
        yielded = plastic > 0
        check(yielded.sum() == 2 and abs(sigma[yielded] - FY).max() < 1e-6 * FY and abs(sigma).max() < FY * (1 + 1e-9)
              and rel(plastic[yielded].max(), (c[-1]["disp_m"] - FY * AREA / k) / float(dx)) < 1e-6,
              "fields: 2 nodes yielded at f_y, plastic strain %.4e = (u - F_y / K) / dx (1e-6)" % plastic.max())
    # a cut through a plane of nodes keeps only the bonds within the plane there (the notch rule), so the
    # plane's 25 nodes have no stiffness across it and that dof is pinned, but for the bar's node, which
    # its segments hold: 24 pinned dofs, and the two halves still hang on the bar
    r = run("bar_prism", "-pd_notch0_box", "0.21,-0.01,-0.01,0.21,0.11,0.11", "-ksp_rtol", "1e-12", "-snes_rtol", "1e-14")
    s = r.summary
    check(s["zero_stiffness_dofs_pinned"] == 24 and s["constrained_dofs"] == 150 + 24, "cut through a node plane: %d dofs pinned (24), "
          "%d constrained (the two faces' 150 and those)" % (s["zero_stiffness_dofs_pinned"], s["constrained_dofs"]))
    check(rel(max(x["load_N"] for x in r.curve), FY * AREA) < 1e-9, "and the largest load is f_y A_s")
    plain = run("bar_prism", "-pd_bar0_fy", "1e12")
    check(plain.summary["bars"]["first_yield"] is None, "a bar that never yields reports no first yield")


def plateau():
    # The cut prism pulled by a force on its far face (held across, free along the bar): at f_y A_s its bar's
    # segment across the cut yields and the prism is a mechanism, a limit load with no stiffness along the pull.
    # Path following goes along the plateau: the load stays at f_y A_s while the cut opens to 10 mm, 40 times
    # the opening at the first yield. The tangent's floor on the yielded segment's slope is what lets it
    # (-pd_steel_tangent_floor; with the consistent slope, 0, the bordering's solve is singular there and the
    # path stops at the limit load). The work is exact on the plateau and through the step that meets the yield
    # surface (each segment's work over a step is its law's, not the cubic of the end slopes)
    with open(scene("bar_prism")) as f:
        lines = [x for x in f if not x.startswith("-pd_region1_")]
    path = os.path.join(tempfile.mkdtemp(prefix="pdtest_scene_"), "bar_prism_force.opts")
    with open(path, "w") as f:
        f.writelines(lines + ["-pd_region1_box 0.4,0,0,0.4,0.1,0.1\n", "-pd_region1_kind force\n", "-pd_region1_force %r,0,0\n" % (2 * FY * AREA),
                              "-pd_region2_box 0.4,0,0,0.4,0.1,0.1\n", "-pd_region2_kind support\n", "-pd_region2_dofs y,z\n"])
    r = run(None, "-options_file", path, "-pd_control", "arclength", "-pd_cmod_points", "0.18,0.05,0.05,0.22,0.05,0.05", "-pd_stop_cmod", "0.01")
    c, s = r.curve, r.summary
    first = next(x for x in c if x["yielded_segments"] > 0)
    worst = max(rel(x["load_N"], FY * AREA) for x in c if x["step"] > first["step"])
    check(s["status"].startswith("completed: CMOD") and c[-1]["cmod_m"] > 40 * first["cmod_m"],
          "force control past the limit load: %s, opening %.2f mm, %.0f times the first yield's" % (s["status"], 1e3 * c[-1]["cmod_m"],
                                                                                                    c[-1]["cmod_m"] / first["cmod_m"]))
    check(worst < 1e-6, "on the plateau the load stays at f_y A_s (largest difference %.1e, 1e-6)" % worst)
    held = c[-1]["stored_J"] + c[-1]["dissipated_J"]
    check(rel(c[-1]["external_J"], held) < 1e-6, "work %.6f J against stored and dissipated %.6f J (1e-6)" % (c[-1]["external_J"], held))
    # the same exactness under displacement control in ten long steps to 33 mm: the first crosses the yield; and with
    # a rupture strain of 5 %, which the segment passes within a step
    for extra in ([], ["-pd_bar0_rupture", "0.05"]):
        r = run("bar_prism", "-pd_region1_displacement", "0.033,0,0", "-pd_steps", "10", *extra)
        e = r.curve[-1]
        held = e["stored_J"] + e["dissipated_J"]
        check(rel(e["external_J"], held) < 1e-6 and (not extra or r.summary["effects"][-1] == "steel_rupture"),
              "displacement control%s: work %.6f J against stored and dissipated %.6f J (1e-6)" % (" through rupture" if extra else "",
                                                                                               e["external_J"], held))


def mpi():
    # Two ranks split the prism across the cut: the same curve as one rank.
    # With the yielded segment's consistent slope Newton converges quadratically, and both runs reach its answer to
    # round-off; under the tangent's floor they would stop at Newton's tolerance, each from its own preconditioner
    opts = ["-pd_dx", "0.01", "-ksp_rtol", "1e-12", "-pd_steel_tangent_floor", "0"]
    a, b = run("bar_prism", *opts).curve, run("bar_prism", *opts, ranks=2).curve
    worst = max(abs(x["load_N"] - y["load_N"]) / (FY * AREA) for x, y in zip(a, b))
    check(len(a) == len(b) and worst < 1e-9, "2 ranks reproduce one rank: largest load difference %.1e of f_y A_s" % worst)
    check([x["yielded_segments"] for x in a] == [x["yielded_segments"] for x in b], "and the same yielded segments per step")


def restart():
    # Path following on the cut prism stopped at load factor 0.5, after the segment across the cut has
    # yielded (a finished run with -pd_checkpoint_every leaves a checkpoint); going on from there on 1 and
    # 2 ranks retraces the uninterrupted run: the load, and the energy the steel dissipated, which needs
    # the plastic stretch and the dissipation carried over.
    opts = ["-pd_control", "arclength", "-pd_region1_displacement", "0.001,0,0", "-ksp_rtol", "1e-12"]
    a = run("bar_prism", *opts).curve
    half = run("bar_prism", *opts, "-pd_lambda_max", "0.5", "-pd_steps", "5", "-pd_checkpoint_every", "100")  # first step 0.1 as in the whole run
    n = len(half.curve)
    check(half.curve[-1]["yielded_segments"] >= 1 and 1 < n < len(a), "the checkpoint at step %d of %d has a yielded segment" % (n, len(a)))
    for ranks in (1, 2):
        b = run("bar_prism", *opts, "-pd_restart", os.path.join(half.dir, "checkpoint.h5"), ranks=ranks).curve
        worst = max(max(abs(x[k] - y[k]) / max(abs(z[k]) for z in a) for k in ("load_N", "disp_m", "dissipated_J", "stored_J"))
                    for x, y in zip(a, b))
        check(len(a) == len(b) and worst < 1e-8, "%d rank(s): the restart retraces the %d steps, largest difference %.1e (1e-8)" % (
            ranks, len(a), worst))


def stuttgart():
    # The Stuttgart beams (scripts/stuttgart_scenes.py) as built: two 26 mm bars of 1,062 mm^2 together at
    # d = 270 mm, one segment per pair of nodes along the beam, and steel effects; the smallest 3D beam and
    # every plane-stress version, dry runs.
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts"))
    import stuttgart_scenes
    import tempfile
    folder = tempfile.mkdtemp(prefix="pdtest_scene_")
    cases = [("stuttgart_beam1", None, 2)] + [(None, stuttgart_scenes.scene(n, 2, folder), 1) for n in stuttgart_scenes.BEAMS]
    for name, path, nbars in cases:
        r = run(name, *(["-options_file", path] if path else []), "-pd_dry_run")
        s = r.summary
        area = sum(b["area_m2"] for b in s["bars"]["list"])
        nx = round(s["options"]["-pd_domain"][3 if s["options"]["-pd_model"] == "3d" else 2] / stuttgart_scenes.DX)
        check(len(s["bars"]["list"]) == nbars and rel(area, 2 * math.pi * 0.026 ** 2 / 4) < 1e-9 and s["bars"]["segments"] == nbars * (nx - 1)
              and "steel_plasticity" in s["effects"], "%s: %d bar(s) of %.1f mm^2 together, %d segments" % (
                  s["options"]["-pd_name"], nbars, 1e6 * area, s["bars"]["segments"]))


def bond_stress(s, fcm=38e6, d=0.012):
    """fib Model Code 2010 bond stress (Pa) at slip s (m): pull-out, good bond, s1 = 1 mm, s2 = 2 mm, s3 = 0.6 d."""
    tmax, s1, s2, s3 = 2.5 * math.sqrt(fcm / 1e6) * 1e6, 1e-3, 2e-3, 0.6 * d
    if s <= s1:
        return tmax * (s / s1) ** 0.4
    if s <= s2:
        return tmax
    return tmax - 0.6 * tmax * (min(s, s3) - s2) / (s3 - s2)


def follows_bond_law(r, name, L=0.06, d=0.012):
    """Checks a pull-out's force against tau(s) pi d L (the bar bonded over L): on the plateau (every node of the bar
    past s1, exact but for the solves: 1e-5 of the peak), on the fall (1 %), on the rise from 0.2 mm (at least 0.9 of it,
    the loaded end slipping more than the mean) and at the peak (1e-5). Returns tau_max pi d L."""
    top = bond_stress(1.5e-3) * math.pi * d * L
    for lo, hi, tol, what in ((1.1e-3, 1.9e-3, 1e-5, "plateau"), (2.5e-3, 6e-3, 0.01, "fall")):
        rows = [x for x in r.curve if lo <= x["slip_m"] <= hi]
        worst = max(abs(x["load_N"] - bond_stress(x["slip_m"]) * math.pi * d * L) / top for x in rows)
        check(len(rows) >= 5 and worst < tol, "%s%s: %d rows, force against tau(s) pi d L within %.2g of the peak (%.2g)" % (
            name, what, len(rows), worst, tol))
    rows = [x for x in r.curve if 2e-4 <= x["slip_m"] <= 1e-3]
    low = min(x["load_N"] / (bond_stress(x["slip_m"]) * math.pi * d * L) for x in rows)
    check(len(rows) >= 3 and 0.9 < low <= 1 + 1e-9, "%srise: force at least %.3f of tau(s) pi d L from 0.2 mm (0.9)" % (name, low))
    peak = max(x["load_N"] for x in r.curve)
    check(abs(peak - top) < 1e-5 * top, "%speak %.1f N = tau_max pi d L = %.1f N (1e-5)" % (name, peak, top))
    return top


def pullout():
    # options/pullout.opts: a 12 mm bar bonded over L = 60 mm in elastic concrete, pulled by 6 mm. The force
    # against the slip of the loaded end follows tau(s) pi d L where the bond stress is uniform: on the
    # plateau (every node of the bar past s1, f = tau_max pi d L, exact but for the solves) and on the fall,
    # where the inner nodes slip less than the loaded end by the bar's stretch and the concrete's (measured
    # +0.6 %; 1 %). On the rise, the loaded end's slip is not the mean: its force is below, by at most 10 %
    # past a slip of 0.2 mm (measured 5 %). A restart from a checkpoint. The same curve on two ranks, which split the bar, to 2.5 mm in
    # 100 increments (at 60 the first increment is cut on one rank count and not on the other, and the
    # curves then have different points); the solves' tolerance allows 1e-6 of the increment's load.
    r = run("pullout")
    s = r.summary
    check(s["converged"] and "bond_slip" in s["effects"] and s["bars"]["list"][0]["bond"] == "slip" and s["bars"]["bar_nodes"] == 6,
          "pulled out to %.1f mm, 6 bar nodes, effect bond_slip" % (1e3 * s["bars"]["max_slip_m"]))
    top = follows_bond_law(r, "")
    # path following stopped at load factor 0.5 and gone on from its checkpoint retraces the whole run, slips included
    arc = ["-pd_control", "arclength"]
    whole = run("pullout", *arc).curve
    half = run("pullout", *arc, "-pd_lambda_max", "0.5", "-pd_steps", "30", "-pd_checkpoint_every", "100")  # the same first step
    again = run("pullout", *arc, "-pd_restart", os.path.join(half.dir, "checkpoint.h5")).curve
    worst = max(max(abs(x[k] - y[k]) / max(abs(z[k]) for z in whole) for k in ("load_N", "slip_m")) for x, y in zip(whole, again))
    check(1 < len(half.curve) < len(whole) == len(again) and worst < 1e-8, "restart at step %d: the %d steps retraced, slips too, largest "
          "difference %.1e (1e-8)" % (len(half.curve), len(whole), worst))
    short = ["-pd_steps", "100", "-pd_region1_displacement", "-0.0025,0,0", "-pd_domain", "0,0,0,0.08,0.15,0.15"]  # 8 layers: split at 40 mm
    a, b = run("pullout", *short).curve, run("pullout", *short, ranks=2).curve
    worst = max(abs(x["load_N"] - y["load_N"]) / top for x, y in zip(a, b))
    check(len(a) == len(b) and worst < 1e-5, "2 ranks: the same %d steps, largest load difference %.1e of the peak (1e-5)" % (len(b), worst))


def embedded():
    # Embedded bars (on nodes of their own at their true places, tied to the concrete through anchor nodes), in
    # directions no lattice has. In soft concrete (E = 1e3 Pa) a bar held at one end and pulled along its line at the
    # other carries E A_s eps, then f_y A_s and the hardening branch, as the nominal bar at any dx: in plane stress at
    # 33.7 degrees (dx = 20 and 10 mm) and in 3D along (3, 1, 2) (1e-5: the soft concrete carries a few 1e-6; a
    # factor, as the contrast of steel and soft concrete defeats the iterative solves). Its segments are
    # ceil(L / dx), every one yielded.
    common = ["-pd_name", "embedded", "-pd_E", "1e3", "-pd_law", "elastic", "-pd_bar0_diameter", "0.012", "-pd_bar0_hardening", "0.02",
              "-pd_bar0_bond", "perfect", "-pd_region0_nodes", "bars", "-pd_region0_kind", "support", "-pd_region1_nodes", "bars",
              "-pd_region1_kind", "displacement", "-pd_steps", "10", "-ksp_type", "preonly", "-pc_type", "lu"]
    u = [c / math.sqrt(14) for c in (3, 1, 2)]
    far = [0.03 + 0.3 * u[0], 0.05 + 0.3 * u[1], 0.04 + 0.3 * u[2]]
    plane = ["-pd_model", "plane_stress", "-pd_thickness", "0.1", "-pd_domain", "0,0,0.4,0.3", "-pd_bar0_line", "0.05,0.05,0.35,0.25",
             "-pd_region0_box", "0.05,0.05,0.05,0.05", "-pd_region0_dofs", "x,y", "-pd_region1_box", "0.35,0.25,0.35,0.25",
             "-pd_region1_dofs", "x,y", "-pd_region1_displacement", "0.003,0.002"]
    space = ["-pd_domain", "0,0,0,0.4,0.2,0.3", "-pd_bar0_line", "0.03,0.05,0.04,%r,%r,%r" % tuple(far), "-pd_region0_box",
             "0.03,0.05,0.04,0.03,0.05,0.04", "-pd_region0_dofs", "x,y,z", "-pd_region1_box", "%r,%r,%r,%r,%r,%r" % tuple(far + far),
             "-pd_region1_dofs", "x,y,z", "-pd_region1_displacement", "%r,%r,%r" % tuple(0.003 * c for c in u)]
    for name, geo, length, dx in (("plane stress, 33.7 degrees", plane, math.hypot(0.3, 0.2), 0.02),
                                  ("plane stress, 33.7 degrees", plane, math.hypot(0.3, 0.2), 0.01), ("3d (3, 1, 2)", space, 0.3, 0.025)):
        r = run(None, *(common + geo + ["-pd_dx", repr(dx)]))
        worst = max(rel(x["load_N"], expected(x["disp_m"] / length, 0.02)) for x in r.curve)
        s = r.summary["bars"]
        nseg = math.ceil(length / dx)
        check(s["list"][0]["embedded"] and s["segments"] == nseg and s["yielded_segments"] == nseg and s["bar_nodes"] == nseg + 1,
              "%s, dx = %g m: embedded, %d segments (ceil(L / dx)), all yielded, %d anchors" % (name, dx, s["segments"], s["anchor_nodes"]))
        check(worst < 1e-5, "%s, dx = %g m: force within %.1e of the nominal bar's over %d steps (1e-5)" % (name, dx, worst, len(r.curve)))
    # Pulled out of elastic concrete, an embedded bar follows the bond law as the bar on its chain of nodes does
    # (follows_bond_law): along the axis (options/pullout.opts embedded) and along (0.8, 0.36, 0.48)
    # (options/pullout_inclined.opts); the inclined one in a shorter block on two ranks, which split it, gives the same
    # curve as on one (1e-5 of the peak, as for the chain)
    r = run("pullout", "-pd_bar0_embedded", "true")
    check(r.summary["bars"]["list"][0]["embedded"] and r.summary["bars"]["bar_nodes"] == 7, "along x, embedded: 7 bar nodes")
    follows_bond_law(r, "along x, embedded: ")
    r = run("pullout_inclined")
    s = r.summary
    check(s["converged"] and "bond_slip" in s["effects"] and s["bars"]["list"][0]["embedded"], "along (0.8, 0.36, 0.48): embedded, bond slip")
    # the fields: the largest slip is the summary's, at the loaded end; at the free end the bar's last segment carries
    # what the last node's bond carries, tau(slip) pi d times half a station (10 mm), by that node's equilibrium (1e-4:
    # Newton leaves the nodes out of balance by up to about 1e-6 of the load, which is 12 times this node's force)
    slip, sigma, x = r.field("slip"), r.field("steel_stress"), r.fields()[0]
    far = ((x - [0.048, 0.0716, 0.0788]) ** 2).sum(axis=1).argmin()
    bond = bond_stress(abs(slip[far])) * math.pi * 0.012 * 0.005
    check(rel(abs(slip).max(), s["bars"]["max_slip_m"]) < 1e-9 and rel(sigma[far] * AREA, bond) < 1e-4,
          "fields: largest slip %.4f mm (the summary's); at the free end the steel carries %.1f N, its bond %.1f N (1e-4)" % (
              1e3 * abs(slip).max(), sigma[far] * AREA, bond))
    top = follows_bond_law(r, "along (0.8, 0.36, 0.48): ")
    # 8 layers: two ranks split the bar and its anchors at x = 40 mm. On one rank, with the yielded segments' consistent
    # slope (0, no floor), block ICC(0) fails on this tangent with a zero pivot and the run goes on with GAMG, which
    # the failed state of the block Jacobi PC, kept until it was cleared, stopped at every solve
    short = ["-pd_domain", "0,0,0,0.08,0.15,0.15", "-pd_steel_tangent_floor", "0"]
    one, two = run("pullout_inclined", *short), run("pullout_inclined", *short, ranks=2)
    check("going on with GAMG" in one.stdout and one.summary["converged"], "one rank: block ICC(0) failed, the run went on with GAMG and completed")
    worst = max(abs(x["load_N"] - y["load_N"]) / top for x, y in zip(one.curve, two.curve))
    check(len(two.curve) == len(one.curve) and worst < 1e-5, "2 ranks split the bar: the same %d steps, largest load difference %.1e of the "
          "peak (1e-5)" % (len(two.curve), worst))
    # path following stopped at load factor 0.5 and gone on from its checkpoint retraces the run, slips included, as for
    # the chain (1e-8): the anchors are nodes of the checkpoint's layout like any other
    arc = ["-pd_control", "arclength"]
    whole = run("pullout_inclined", *arc).curve
    half = run("pullout_inclined", *arc, "-pd_lambda_max", "0.5", "-pd_steps", "30", "-pd_checkpoint_every", "100")
    again = run("pullout_inclined", *arc, "-pd_restart", os.path.join(half.dir, "checkpoint.h5")).curve
    worst = max(max(abs(x[k] - y[k]) / max(abs(z[k]) for z in whole) for k in ("load_N", "slip_m")) for x, y in zip(whole, again))
    check(1 < len(half.curve) < len(whole) == len(again) and worst < 1e-8, "restart at step %d: the %d steps retraced, largest difference "
          "%.1e (1e-8)" % (len(half.curve), len(whole), worst))
    # bad input: an off-lattice bar without a bond it can be embedded with, one said not to be embedded, and one under
    # finite kinematics; each names its option
    for extra, opt, what in ((["-pd_bar0_bond", "concrete"], "-pd_bar0_line", "slip or perfect"),
                             (["-pd_bar0_embedded", "false"], "-pd_bar0_embedded", "only be embedded"),
                             (["-pd_kinematics", "finite"], "-pd_bar0", "kinematics")):
        bad = run("pullout_inclined", *extra, expect_ok=False)
        check(bad.returncode == 2 and opt in bad.stderr and what in bad.stderr, "bad input (exit %d): %s" % (bad.returncode, bad.stderr.strip()[:160]))


if __name__ == "__main__":
    {"axial": axial, "diagonal": diagonal, "notch": notch, "plateau": plateau, "mpi": mpi, "restart": restart, "stuttgart": stuttgart,
     "pullout": pullout, "embedded": embedded}[sys.argv[1]]()
