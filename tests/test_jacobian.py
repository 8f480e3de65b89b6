"""Hand-coded tangent against finite differences (-snes_test_jacobian) on a small deformed scene."""
import re

from pdtest import check, run

SMALL = ["-pd_domain", "-0.08,0,0,0.3,0.1,0.1", "-pd_dx", "0.02", "-pd_region1_box", "0.3,0,0,0.3,0.1,0.1",
         "-pd_region1_force", "0,0,-2e5", "-pd_mat_type", "aij"]


def main():
    # finite kinematics: the tangent has the geometric term; tested at u = 0 and at the deformed iterates
    r = run("cantilever", *SMALL, "-pd_kinematics", "finite", "-snes_test_jacobian")
    ratios = [float(x) for x in re.findall(r"\|\|J - Jfd\|\|_F/\|\|J\|\|_F = ([0-9.eE+-]+)", r.stdout)]
    check(len(ratios) >= 2, "%d Jacobian comparisons made" % len(ratios))
    check(max(ratios) < 1e-6, "finite kinematics: max ||J - Jfd||/||J|| = %.3e < 1e-6" % max(ratios))
    s = r.summary
    check(s["converged"], "Newton converged (%d iterations)" % s["newton_its"])
    # small kinematics: the linear stiffness (checked through SNES Newton with the linear model)
    r = run("cantilever", *SMALL, "-snes_type", "newtonls", "-snes_test_jacobian")
    ratios = [float(x) for x in re.findall(r"\|\|J - Jfd\|\|_F/\|\|J\|\|_F = ([0-9.eE+-]+)", r.stdout)]
    check(len(ratios) >= 1 and max(ratios) < 1e-6, "small kinematics: max ||J - Jfd||/||J|| = %.3e < 1e-6" % max(ratios))
    softening()
    slip()


def slip():
    # The bond-slip links (options/pullout.opts at dx = 30 mm), pulled 2 mm in four increments through the rise,
    # the plateau and into the fall of the bond law, with steel that stays elastic (its yield kink would
    # straddle the differencing step). Backtracking keeps the iterates near the path.
    r = run("pullout", "-pd_dx", "0.03", "-pd_steps", "4", "-pd_region1_displacement", "-0.002,0,0", "-pd_bar0_fy", "5e9",
            "-pd_mat_type", "aij", "-pd_pc_reach", "0", "-snes_test_jacobian", "-snes_test_err", "1e-11", "-snes_linesearch_type", "bt")
    ratios = [float(x) for x in re.findall(r"\|\|J - Jfd\|\|_F/\|\|J\|\|_F = ([0-9.eE+-]+)", r.stdout)]
    s = r.summary
    check(s["converged"] and abs(s["bars"]["max_slip_m"] - 0.002) < 1e-9, "bond slip: pulled to a slip of %.3f mm" % (1e3 * s["bars"]["max_slip_m"]))
    check(len(ratios) >= 5 and max(ratios) < 1e-6, "bond slip: %d comparisons, max ||J - Jfd||/||J|| = %.3e < 1e-6" % (len(ratios), max(ratios)))


def softening():
    # The half-notched beam at dx = 10 mm pushed to its peak in one increment, so that the history of
    # every bond is still zero and each Newton iterate is a softening state. The bond force has a kink
    # at s0; PETSc's default differencing step straddles it for bonds within ~1e-7 of s0 and the
    # difference then grows with the step (measured: 1.7e-3 with the default, 2e-2 with
    # -snes_test_err 1e-6, 4e-7 with 1e-10, 1.6e-7 with 1e-11; round-off stays below 1e-7), so the comparison uses 1e-11.
    # -snes_test_jacobian compares the preconditioning matrix too: it keeps every bond here (-pd_pc_reach 0),
    # so that it is the Jacobian (by default it keeps the near bonds only, and tests/test_tangent.c compares
    # the operator with a matrix of every bond)
    args = ["-pd_dx", "0.01", "-pd_region2_displacement", "0,0,-2.5e-5", "-pd_steps", "1", "-pd_limiter_max_bonds", "0", "-pd_mat_type", "aij",
            "-pd_pc_reach", "0", "-snes_test_jacobian", "-snes_test_err", "1e-11"]
    for kin in ("small", "finite"):
        r = run("gregoire_d50_hn", *args, "-pd_kinematics", kin)
        ratios = [float(x) for x in re.findall(r"\|\|J - Jfd\|\|_F/\|\|J\|\|_F = ([0-9.eE+-]+)", r.stdout)]
        s = r.summary
        check(s["softening_bonds"] > 50, "%s kinematics: %d bonds softening at the end" % (kin, s["softening_bonds"]))
        check(len(ratios) >= 5 and max(ratios) < 1e-6, "%s kinematics, softening: %d comparisons, max ||J - Jfd||/||J|| = %.3e < 1e-6" % (kin, len(ratios), max(ratios)))


if __name__ == "__main__":
    main()
