"""The bond family (docs/design.md, point 28): exact counts, an independent solution of the same discrete
model, and a family that neither translation of the domain nor the rank count changes.
Usage: test_bonds.py CASE"""
import math
import sys

import numpy as np

from pdtest import check, run, translated

# The elastic bar of options/bar_tension.opts at dx = 10 mm with m = 3: pairs exactly one horizon apart
# (offsets (3,0,0) and its permutations) are on the horizon's edge and bonded with partial volume 1/2.
BAR = ["-pd_horizon_ratio", 3, "-pd_surface_correction", "false"]
BAR_N = (50, 10, 10)
# solved to round-off, so that what is compared is the discrete model, not the linear solver
TIGHT = ["-ksp_rtol", "1e-14"]
OFFSET = 0.1234567


def lattice_pairs(n, m):
    """Pairs with n2 = di^2 + dj^2 + dk^2 <= m^2 on a lattice of n nodes per axis, counted per offset."""
    R, total = int(m) + 1, 0
    for o in np.ndindex(*(2 * R + 1,) * len(n)):
        d = tuple(c - R for c in o)
        if d > (0,) * len(n) and sum(c * c for c in d) <= m * m:
            total += math.prod(max(0, k - abs(c)) for k, c in zip(n, d))
    return total


def bar_reference(m=3.0, dx=0.01, E=30e9, F=1e5):
    """The bar's discrete model assembled and solved with scipy, apart from pdimplicit's search: constant
    influence, c = 12 E / (pi delta^4), partial volumes by the PA-PDLAMMPS rule with 1/2 at r = delta,
    no surface correction, small kinematics; supports and load as options/bar_tension.opts selects them."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spl
    n = np.array(BAR_N)
    ijk = np.array(list(np.ndindex(*BAR_N)))  # global id order: x slowest
    N, V, c = len(ijk), dx ** 3, 12 * E / (math.pi * (m * dx) ** 4)
    gid = lambda q: (q[:, 0] * n[1] + q[:, 1]) * n[2] + q[:, 2]
    rows, cols, vals, nbonds = [], [], [], 0
    R = int(m) + 1
    for o in np.ndindex(2 * R + 1, 2 * R + 1, 2 * R + 1):
        d = np.array(o) - R
        n2 = int(d @ d)
        if tuple(d) <= (0, 0, 0) or n2 > m * m:
            continue
        q = ijk + d
        ok = np.all((q >= 0) & (q < n), axis=1)
        a, b = np.nonzero(ok)[0], gid(q[ok])
        nbonds += len(a)
        r = math.sqrt(n2)
        beta = 0.5 if n2 == m * m else (1.0 if r <= m - 0.5 else m + 0.5 - r)
        kb = c * beta * V * V / (r * dx) * np.outer(d / r, d / r)
        for p in range(3):
            for s in range(3):
                for x, y, sign in ((a, a, 1), (b, b, 1), (a, b, -1), (b, a, -1)):
                    rows.append(3 * x + p)
                    cols.append(3 * y + s)
                    vals.append(np.full(len(a), sign * kb[p, s]))
    K = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(3 * N, 3 * N))
    fixed = np.zeros(3 * N, bool)
    left = ijk[:, 0] == 0
    fixed[3 * np.nonzero(left)[0]] = True                           # x on the left end layer
    fixed[3 * np.nonzero(left & (ijk[:, 1] == 5))[0] + 1] = True    # y on the line y = 0.05 (upper layer)
    fixed[3 * np.nonzero(left & (ijk[:, 2] == 5))[0] + 2] = True    # z on the line z = 0.05
    f = np.zeros(3 * N)
    right = np.nonzero(ijk[:, 0] == n[0] - 1)[0]
    f[3 * right] = F / len(right)
    u = np.zeros(3 * N)
    free = ~fixed
    u[free] = spl.spsolve(K[free][:, free].tocsc(), f[free])
    return nbonds, u.reshape(N, 3)


def field_difference(u, ref):
    return np.abs(u - ref).max() / np.abs(ref).max()


def exact():
    # every pair within the horizon, counted independently per lattice offset
    for scene, n, extra in (("bar_tension", BAR_N, []), ("bar_tension_2d", (50, 10), []), ("cantilever", (108, 10, 10), []),
                            ("gregoire_d50_un", (35, 10, 10), ["-pd_dx", 5e-3])):
        for m in (3, math.pi):
            s = run(scene, *extra, "-pd_horizon_ratio", repr(float(m)), "-pd_dry_run").summary
            want = lattice_pairs(n, m)
            check(s["bonds"] == want, "%s m = %.6g: %d bonds, %d pairs with r <= delta on the lattice" % (scene, m, s["bonds"], want))
    check(lattice_pairs(BAR_N, 3) == 233104, "the bar at m = 3 has 233,104 pairs with r <= delta")
    # the field of pdimplicit against the same discrete model solved apart from it
    nb, ref = bar_reference()
    r = run("bar_tension", *BAR, *TIGHT)
    _, u, _ = r.fields()
    d = field_difference(u, ref)
    check(r.summary["bonds"] == nb == 233104, "bar m = 3: %d bonds, reference %d" % (r.summary["bonds"], nb))
    check(d < 1e-10, "bar m = 3: largest displacement difference to the reference solution %.2e of the largest displacement" % d)


def translation():
    # the same bar with the domain and every region moved by OFFSET along each axis
    one = run("bar_tension", *BAR, *TIGHT)
    moved = run("bar_tension", *BAR, *TIGHT, *translated("bar_tension", OFFSET))
    x0, u0, _ = one.fields()
    x1, u1, _ = moved.fields()
    check(np.abs(x1 - x0 - OFFSET).max() < 1e-12, "translated lattice: the same nodes, moved by %g m" % OFFSET)
    check(moved.summary["bonds"] == one.summary["bonds"] == 233104, "translated bar: %d bonds, %d in place" % (moved.summary["bonds"], one.summary["bonds"]))
    d = field_difference(u1, u0)
    check(d < 1e-12, "translated bar: largest displacement difference %.2e of the largest displacement" % d)
    # notch cuts too: the half-notched Gregoire beam at dx = 5 mm and m = pi (design point 9)
    for m in (math.pi, 3):
        a = run("gregoire_d50_hn", "-pd_horizon_ratio", repr(float(m)), "-pd_dry_run").summary
        b = run("gregoire_d50_hn", "-pd_horizon_ratio", repr(float(m)), "-pd_dry_run", *translated("gregoire_d50_hn", OFFSET)).summary
        check(a["bonds"] == b["bonds"] == 156882 and a["bonds_cut_by_notches"] == b["bonds_cut_by_notches"],
              "half-notched beam m = %.6g: %d bonds (%d cut) in place, %d (%d cut) translated" % (
                  m, a["bonds"], a["bonds_cut_by_notches"], b["bonds"], b["bonds_cut_by_notches"]))


def ranks():
    runs = {p: run("bar_tension", *BAR, *TIGHT, ranks=p) for p in (1, 2, 3)}
    _, u1, _ = runs[1].fields()
    for p in (2, 3):
        _, u, _ = runs[p].fields()
        d = field_difference(u, u1)
        check(runs[p].summary["bonds"] == runs[1].summary["bonds"] == 233104,
              "%d ranks: %d bonds, 1 rank %d" % (p, runs[p].summary["bonds"], runs[1].summary["bonds"]))
        check(d < 1e-12, "%d ranks: largest displacement difference to 1 rank %.2e of the largest displacement" % (p, d))
    # a slab boundary inside the notch's reach: the half-notched beam's counts on 3 ranks
    s = run("gregoire_d50_hn", "-pd_dry_run", ranks=3).summary
    check(s["bonds"] == 156882 and s["bonds_cut_by_notches"] == 4612, "half-notched beam on 3 ranks: %d bonds, %d cut" % (s["bonds"], s["bonds_cut_by_notches"]))


if __name__ == "__main__":
    {"exact": exact, "translation": translation, "ranks": ranks}[sys.argv[1]]()
