"""The shipped Gregoire D = 50 mm scenes at dx = 5 mm, non-linear law, traced to CMOD = 0.2 mm.
Usage: test_gregoire.py un|hn"""
import sys

from pdtest import check, experiment_peaks, peak, rel, run


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
    _, lo, hi = experiment_peaks("gregoire2013_d50_un_load_cmod.csv")
    check(lo <= p <= hi, "unnotched: peak %.0f N inside the experimental envelope %.0f to %.0f N (data/)" % (p, lo, hi))


def half_notched():
    r = run("gregoire_d50_hn")
    p = traced(r, "half-notched")
    # Within 35 % of the experimental mean, the target set against the thesis's explicit +31 %.
    # The scene uses the thesis's surface-correction convention (whole cells in the family volume), with
    # which pdimplicit reproduces the thesis's three D = 50 mm peaks to 3 % (docs/softening.md).
    mean = experiment_peaks("gregoire2013_d50_hn_load_cmod.csv")[0]
    check(p <= 1.35 * mean, "half-notched: peak %.1f N within 35 %% of the experimental mean %.0f N (+%.1f %%)" % (p, mean, 100 * (p / mean - 1)))
    # and the thesis's 1,280 N to 3 %: the spread of the three beams about the thesis's values
    check(rel(p, 1280) < 0.03, "half-notched: peak %.1f N within 3 %% of the thesis's 1,280 N (%+.1f %%)" % (p, 100 * (p / 1280 - 1)))


if __name__ == "__main__":
    {"un": unnotched, "hn": half_notched}[sys.argv[1]]()
