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


if __name__ == "__main__":
    main()
