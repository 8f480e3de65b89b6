"""Voids (-pd_voidK_box, -pd_voidK_cylinder): material removed from the domain. Usage: test_voids.py CASE"""
import math
import sys

import numpy as np

from pdtest import check, rel, run

TIGHT = ["-ksp_rtol", "1e-13"]
# the bar of options/bar_tension.opts widened to y = 0.2 m, the added half made a void again
WIDENED = ["-pd_domain", "0,0,0,0.5,0.2,0.1", "-pd_void0_box", "0,0.1,0,0.5,0.2,0.1"]


def equivalence():
    # A void's faces are free surfaces exactly like the domain's: the widened bar with its added half void
    # has the plain bar's bonds and surface-correction factors, and the same answer, on 1 and 2 ranks (the
    # 2-rank runs also see the void on both slabs).
    plain = run("bar_tension", *TIGHT)
    p = plain.summary
    for ranks in (1, 2):
        r = run("bar_tension", *TIGHT, *WIDENED, ranks=ranks)
        s = r.summary
        check(s["void_nodes"] == 5000 and s["nodes"] == p["nodes"], "%d rank(s): %d nodes, %d in the void (5000)" % (ranks, s["nodes"], s["void_nodes"]))
        check(s["bonds"] == p["bonds"], "%d rank(s): %d bonds, the plain bar %d" % (ranks, s["bonds"], p["bonds"]))
        check(s["surface_correction_range"] == p["surface_correction_range"], "surface-correction range %s, the plain bar %s" % (
            s["surface_correction_range"], p["surface_correction_range"]))
        check(s["isolated_nodes"] == 0 and s["zero_stiffness_dofs_pinned"] == 0, "void nodes are neither isolated nor zero-stiffness dofs")
        d = rel(r.curve[-1]["disp_m"], plain.curve[-1]["disp_m"])
        check(d < 1e-9, "%d rank(s): end displacement %.12e m, the plain bar %.12e m (relative %.1e)" % (
            ranks, r.curve[-1]["disp_m"], plain.curve[-1]["disp_m"], d))


def family_count(dx, m, solid):
    """Bonds between solid nodes of the lattice, each pair once: offsets d with d.d <= m^2 (the horizon's
    edge included), counted here independently of pdimplicit's neighbour search."""
    n, R = solid.shape, int(math.floor(m)) + 1
    total = 0
    for d in np.ndindex(2 * R + 1, 2 * R + 1, 2 * R + 1):
        d = tuple(int(v) - R for v in d)
        if d <= (0, 0, 0) or sum(v * v for v in d) > m * m * (1 + 1e-12):
            continue  # each pair once: lexicographically positive offsets
        lo = tuple(slice(max(0, -v), k - max(0, v)) for v, k in zip(d, n))
        hi = tuple(slice(max(0, v), k - max(0, -v)) for v, k in zip(d, n))
        total += int(np.sum(solid[lo] & solid[hi]))
    return total


def hole():
    # A cylindrical hole through the bar along z (centre 0.25, 0.05; radius 30 mm): the nodes whose cell
    # centres lie in it, and the bonds among the others, counted here from the lattice; void nodes do not move.
    dx, m, rad = 0.01, math.pi, 0.03
    r = run("bar_tension", "-pd_void0_cylinder", "0.25,0.05,0,%g" % rad, "-pd_fields_every", 1)
    s = r.summary
    n = (50, 10, 10)
    c = [(np.arange(k) + 0.5) * dx for k in n]
    X, Y, Z = np.meshgrid(*c, indexing="ij")
    hollow = (X - 0.25) ** 2 + (Y - 0.05) ** 2 <= (rad + 1e-9 * dx) ** 2
    bonds = family_count(dx, m, ~hollow)
    check(s["void_nodes"] == int(hollow.sum()), "%d void nodes, %d cell centres in the cylinder" % (s["void_nodes"], hollow.sum()))
    check(s["bonds"] == bonds, "%d bonds, %d counted among the solid nodes" % (s["bonds"], bonds))
    x, u, dmg = r.fields()
    inside = (x[:, 0] - 0.25) ** 2 + (x[:, 1] - 0.05) ** 2 <= (rad + 1e-9 * dx) ** 2
    check(np.all(u[inside] == 0) and np.all(np.isnan(dmg[inside])) and not np.any(np.isnan(dmg[~inside])),
          "void nodes: displacement 0, damage NaN (%d of them); solid nodes' damage finite" % inside.sum())
    plain = run("bar_tension").curve[-1]["disp_m"]
    check(r.curve[-1]["disp_m"] > plain, "the hole makes the bar softer: %.6e m against %.6e m" % (r.curve[-1]["disp_m"], plain))


if __name__ == "__main__":
    {"equivalence": equivalence, "hole": hole}[sys.argv[1]]()
