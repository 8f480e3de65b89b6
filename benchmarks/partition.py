#!/usr/bin/python3
"""What each rank exchanges under the x-slab partition pdimplicit uses and under a partition in 3D blocks,
worked out from the lattice and the bond stencil (no run): for 64 to 1,024 ranks on three lattices of 1.8 to
14 million nodes, the nodes a rank owns, the ghost nodes it needs (the nodes within one horizon of its own
that another rank owns: what a mat-vec's scatter and a ghost update move), the bytes of one ghost update
of the displacements, the ranks it exchanges with, and the bonds it shares with other ranks (held and
evaluated by both, design point 6). The counts are exact for a rank whose slab or block lies inside the
lattice (the worst case: a rank at a face has fewer ghosts); blocks are the factorisation px x py x pz of
the rank count with the fewest ghosts per rank.

Writes docs/benchmarks/partition.json and partition.md (a few seconds).

Usage: benchmarks/partition.py [--report]
"""
import math
import os
import sys

from common import OUT, RESULTS_DIR, load_results, save_results

JSON = os.path.join(RESULTS_DIR, "partition.json")
M = math.pi  # the shipped horizon ratio
BS = 3  # dofs per node in 3D
# name, lattice size (nodes along x, y, z), what it is
LATTICES = [
    ("d400_dx2.5", (560, 20, 160), "Gregoire D = 400 mm beam at dx = 2.5 mm (1,400 x 50 x 400 mm)"),
    ("cube_1.8M", (122, 122, 122), "a cube of 122^3 nodes"),
    ("d400_dx1.25", (1120, 40, 320), "Gregoire D = 400 mm beam at dx = 1.25 mm"),
]
RANKS = [64, 128, 256, 512, 1024]


def stencil(m):
    """Lattice offsets of a node's bond family (3D, the node itself excluded): |offset| <= m dx."""
    r = int(math.floor(m))
    return [(i, j, k) for i in range(-r, r + 1) for j in range(-r, r + 1) for k in range(-r, r + 1)
            if 0 < i * i + j * j + k * k <= m * m * (1 + 1e-12)]


def rank_exchange(n, p, offs):
    """Owned and ghost nodes, neighbour ranks and shared bonds of an interior rank of the partition p
    (ranks along each axis) of the lattice n: its block is ceil(n/p) nodes along each axis, padded by the
    stencil's reach where other ranks lie beyond (p > 1), clipped by the lattice where they do not."""
    import numpy as np
    r = max(abs(o[0]) for o in offs)
    a = [-(-n[d] // p[d]) for d in range(3)]
    pad = [r if p[d] > 1 else 0 for d in range(3)]
    if any(p[d] > 1 and a[d] < r for d in range(3)):
        return None  # a block thinner than the reach: ghosts come from ranks beyond the next
    shape = [a[d] + 2 * pad[d] for d in range(3)]
    block = np.zeros(shape, dtype=bool)
    block[pad[0]:pad[0] + a[0], pad[1]:pad[1] + a[1], pad[2]:pad[2] + a[2]] = True
    reached = np.zeros(shape, dtype=bool)
    shared = 0
    for o in offs:
        src = [slice(max(0, -o[d]), shape[d] - max(0, o[d])) for d in range(3)]
        dst = [slice(max(0, o[d]), shape[d] - max(0, -o[d])) for d in range(3)]
        moved = block[tuple(src)]
        reached[tuple(dst)] |= moved
        shared += int(np.count_nonzero(moved & ~block[tuple(dst)]))
    ghost = reached & ~block
    owned = a[0] * a[1] * a[2]
    bonds = 0  # bonds with at least one owned end: owned pairs counted once, shared ones once per rank
    for o in offs:
        src = [slice(max(0, -o[d]), shape[d] - max(0, o[d])) for d in range(3)]
        dst = [slice(max(0, o[d]), shape[d] - max(0, -o[d])) for d in range(3)]
        inside = block[tuple(src)] & block[tuple(dst)]
        bonds += int(np.count_nonzero(inside))
    bonds = bonds // 2 + shared
    # neighbour ranks: the blocks (offset by -1, 0, 1 along each partitioned axis) that hold a ghost
    neigh = 0
    for di in (-1, 0, 1):
        for dj in (-1, 0, 1):
            for dk in (-1, 0, 1):
                if (di, dj, dk) == (0, 0, 0) or any(dd and p[d] == 1 for d, dd in enumerate((di, dj, dk))):
                    continue
                sl = []
                for d, dd in enumerate((di, dj, dk)):
                    lo = pad[d] + (a[d] if dd > 0 else 0) + (-pad[d] if dd < 0 else 0)
                    hi = lo + (pad[d] if dd else a[d])
                    sl.append(slice(lo, hi))
                if ghost[tuple(sl)].any():
                    neigh += 1
    return {"owned": owned, "ghosts": int(ghost.sum()), "neighbours": neigh, "bonds": bonds, "shared_bonds": shared}


def factorisations(P, n):
    for px in range(1, P + 1):
        if P % px:
            continue
        for py in range(1, P // px + 1):
            if (P // px) % py:
                continue
            pz = P // px // py
            if px <= n[0] and py <= n[1] and pz <= n[2]:
                yield (px, py, pz)


def measure():
    offs = stencil(M)
    res = {"horizon_ratio": M, "stencil_offsets": len(offs), "reach": max(o[0] for o in offs), "lattices": {}}
    for name, n, what in LATTICES:
        rows = []
        for P in RANKS:
            slab = rank_exchange(n, (P, 1, 1), offs) if P <= n[0] else None
            best = None
            for p in factorisations(P, n):
                e = rank_exchange(n, p, offs)
                if e is not None and (best is None or e["ghosts"] < best[1]["ghosts"]):
                    best = (p, e)
            rows.append({"ranks": P, "slab": slab, "block": best[1] if best else None, "block_shape": list(best[0]) if best else None})
            print(name, P, rows[-1])
        res["lattices"][name] = {"n": list(n), "what": what, "nodes": n[0] * n[1] * n[2], "rows": rows}
    save_results(JSON, res)


def report():
    res = load_results(JSON)
    lines = ["# Communication per rank: x-slabs against 3D blocks", "",
             "Written by `benchmarks/partition.py` from `partition.json`, worked out from the lattice and the bond stencil "
             "(horizon ratio pi: %d offsets, reach %d nodes along an axis), not measured. For one rank inside the lattice "
             "(a rank at a face has fewer ghosts): the nodes it owns, its ghost nodes (nodes within one horizon of its own that "
             "other ranks own: what each mat-vec's scatter and each ghost update move, %d doubles per node), the megabytes of one "
             "such update, the ranks it exchanges with, and the share of its bonds that another rank holds and evaluates too "
             "(design point 6). Slabs: the x-layers pdimplicit deals out today; a slab thinner than the reach would need ghosts "
             "from ranks beyond its neighbours, and a lattice has no more slabs than layers ('-'). Blocks: the factorisation "
             "px x py x pz of the rank count with the fewest ghosts." % (res["stencil_offsets"], res["reach"], BS), ""]
    for name, _, _ in LATTICES:
        lat = res["lattices"][name]
        n = lat["n"]
        lines += ["## %s: %d x %d x %d = %s nodes" % (lat["what"], n[0], n[1], n[2], format(lat["nodes"], ",")), "",
                  "| ranks | slab: owned | ghosts | ghosts / owned | MB per update | neighbours | shared bonds | "
                  "blocks | block: owned | ghosts | ghosts / owned | MB per update | neighbours | shared bonds |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for row in lat["rows"]:
            cells = ["%d" % row["ranks"]]
            for kind in ("slab", "block"):
                e = row[kind]
                if kind == "block":
                    cells.append(" x ".join(str(v) for v in row["block_shape"]) if e else "-")
                if e is None:
                    cells += ["-"] * 6
                    continue
                cells += [format(e["owned"], ","), format(e["ghosts"], ","), "%.2f" % (e["ghosts"] / e["owned"]),
                          "%.2f" % (e["ghosts"] * BS * 8 / 1e6), "%d" % e["neighbours"], "%.0f %%" % (100 * e["shared_bonds"] / e["bonds"])]
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    open(os.path.join(OUT, "partition.md"), "w").write("\n".join(lines))


if __name__ == "__main__":
    if "--report" not in sys.argv[1:]:
        measure()
    report()
