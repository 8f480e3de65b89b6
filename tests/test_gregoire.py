"""The shipped Gregoire D = 50 mm scenes at dx = 5 mm, non-linear law, traced to CMOD = 0.2 mm.
Usage: test_gregoire.py un|hn"""
import sys

from pdtest import check, peak, rel, run


def traced(r, name):
    """Checks shared by every beam: the run reaches CMOD 0.2 mm, the load has dropped, damage only grows."""
    s, c = r.summary, r.curve
    p = peak(r)
    check(s["converged"] and c[-1]["cmod_m"] >= 2e-4, "%s: traced to CMOD %.3f mm in %d steps, %d Newton its (%s)" % (
        name, 1e3 * c[-1]["cmod_m"], s["steps"], s["newton_its"], s["status"]))
    check(c[-1]["load_N"] < 0.4 * p, "%s: load at CMOD 0.2 mm %.0f N below 40 %% of the peak %.0f N" % (name, c[-1]["load_N"], p))
    b = [row["broken_bonds"] for row in c]
    check(all(x <= y for x, y in zip(b, b[1:])), "%s: broken bonds never decrease (%d at the end)" % (name, b[-1]))
    cap = s["law"]["limiter_max_bonds"]
    check(0 < cap and s["max_bonds_per_iteration"] <= cap, "%s: at most %d bond events per Newton iteration (%d)" % (name, cap, s["max_bonds_per_iteration"]))
    return p


def unnotched():
    r = run("gregoire_d50_un")
    p = traced(r, "unnotched")
    check(4100 <= p <= 5200, "unnotched: peak %.0f N inside the experimental envelope 4,100 to 5,200 N" % p)


def half_notched():
    r = run("gregoire_d50_hn")
    p = traced(r, "half-notched")
    # The target is +35 % of the experimental mean (979 N); pdimplicit reaches +42 %, the thesis's
    # explicit run +31 % (docs/softening.md). Until the cause is found this guards the measured value
    # (1,388 N with the default increments) against unintended change: 2 % is the step-size and limiter
    # spread measured on this beam. One and two ranks at this spacing: docs/softening.md (the CTest
    # comparison runs at dx = 10 mm, test_softening.py, to keep the suite short).
    check(rel(p, 1388) < 0.02, "half-notched: peak %.1f N within 2 %% of the recorded 1,388 N (+%.0f %% on the experimental mean 979 N)" % (
        p, 100 * (p / 979 - 1)))


if __name__ == "__main__":
    {"un": unnotched, "hn": half_notched}[sys.argv[1]]()
