#!/usr/bin/python3
"""Writes the geometrically similar Gregoire et al. (2013) beam scenes for D = 100, 200, 400 mm (3D) and
the 2D plane-stress scenes used by the path-following tests. D = 50 mm scenes are written by hand.

Geometry scales with D: length 3.5 D, span 2.5 D (supports at 0.5 D and 3 D), load at mid-span, CMOD
gauge on the bottom face at mid-span +- 0.2 D, notch 0.2 D (fn) or 0.5 D (hn); thickness 50 mm for
every size, as in the experiments. Supports and load act on a width of 0.05 D so that a large beam is
not loaded through a single line of nodes. Usage: scripts/gregoire_scenes.py (from the repository root).
"""
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NOTCH = {"un": (0.0, "unnotched"), "fn": (0.2, "notch 0.2 D"), "hn": (0.5, "notch 0.5 D")}


def scene(D, kind, dim, dx, outdir=os.path.join(ROOT, "options")):
    a, what = NOTCH[kind]
    L, t, x0, x1, xm, w = 3.5 * D, 0.05, 0.5 * D, 3.0 * D, 1.75 * D, 0.025 * D
    name = "gregoire_d%d_%s%s" % (round(1e3 * D), kind, "_2d" if dim == 2 else "")
    g = lambda v: "%.6g" % v
    if dim == 3:
        box = lambda xa, xb, za, zb: ",".join(g(v) for v in (xa, 0, za, xb, t, zb))
        pt = lambda x, z: ",".join(g(v) for v in (x, t / 2, z))
    else:
        box = lambda xa, xb, za, zb: ",".join(g(v) for v in (xa, za, xb, zb))
        pt = lambda x, z: ",".join(g(v) for v in (x, z))
    lines = ["# Gregoire et al. (2013) three-point bending, D = %g mm, %s; geometrically similar to the D = 50 mm"
             % (1e3 * D, what),
             "# beams (written by scripts/gregoire_scenes.py). %s" % (
                 "3D, thickness 50 mm." if dim == 3 else "2D plane stress, thickness 50 mm: a fast stand-in for tests."),
             "-pd_name " + name]
    if dim == 2:
        lines += ["-pd_model plane_stress", "-pd_thickness 0.05", "-pd_domain " + ",".join(g(v) for v in (0, 0, L, D))]
    else:
        lines += ["-pd_domain " + ",".join(g(v) for v in (0, 0, 0, L, t, D))]
    lines += ["-pd_dx %g" % dx, "-pd_E 37e9", "-pd_rho 2346", "-pd_law nonlinear", "-pd_ft 3.9e6", "-pd_Gf 143.2"]
    if dim == 3:
        # the surface-correction convention of the thesis's code, as in the D = 50 mm scenes (docs/softening.md)
        lines += ["-pd_sc_whole_cells"]
    if a > 0:
        lines += ["-pd_notch0_box " + box(xm, xm, 0, a * D)]
    else:
        # a homogeneous unnotched beam has no preferred crack site: past the peak, diffuse damage must pick
        # one (a bifurcation that path following cannot cross, docs/arclength.md); a 5 % scatter of the
        # bond strength, as in concrete, picks it
        lines += ["-pd_strength_scatter 0.05"]
    lines += ["# supports on the bottom face (left pinned, right a roller), load on the top face, each 0.05 D wide",
              "-pd_region0_box " + box(x0 - w, x0 + w, 0, 0), "-pd_region0_kind support",
              "-pd_region0_dofs " + ("x,y,z" if dim == 3 else "x,y"),
              "-pd_region1_box " + box(x1 - w, x1 + w, 0, 0), "-pd_region1_kind support",
              "-pd_region1_dofs " + ("z" if dim == 3 else "y"),
              "-pd_region2_box " + box(xm - w, xm + w, D, D), "-pd_region2_kind displacement",
              "-pd_region2_dofs " + ("z" if dim == 3 else "y"),
              # deflection scale: about 10 times the D = 50 mm beam's per unit depth
              "-pd_region2_displacement " + (",".join(g(v) for v in (0, 0, -0.01 * D)) if dim == 3 else ",".join(g(v) for v in (0, -0.01 * D))),
              "-pd_load_region 2", "-pd_steps 400",
              "-pd_cmod_points " + pt(xm - 0.2 * D, 0) + "," + pt(xm + 0.2 * D, 0)]
    with open(os.path.join(outdir, name + ".opts"), "w") as f:
        f.write("\n".join(lines) + "\n")
    return name


if __name__ == "__main__":
    for D in (0.1, 0.2, 0.4):
        for kind in NOTCH:
            print(scene(D, kind, 3, 5e-3))
    print(scene(0.4, "un", 2, 10e-3))
    print(scene(0.2, "hn", 2, 5e-3))
