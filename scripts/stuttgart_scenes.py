#!/usr/bin/python3
"""Writes the Stuttgart shear beams of Leonhardt and Walther as the Hobbs thesis models them (Ch. 7,
Tables 7.1 and 7.2): options/stuttgart_beam{1,2,3,4,5,6,7,8,10}.opts in 3D, and with --dim 2 the plane-stress
versions options/stuttgart_beam{...}_2d.opts (thickness 190 mm, the two bars lumped on one line).

Section 190 x 320 mm, d = 270 mm, two 26 mm bars (A_s = 1,062 mm^2, E_s = 208 GPa, f_y = 465 MPa,
perfectly plastic); four-point bending, span L, shear span L_1 (Table 7.1). Concrete: E_c and G_F from
Table 7.1, f_t = 0.3 (f_cm - 8)^(2/3) MPa (fib Model Code 2010, f_cm the cylinder strength), the bilinear
law with k_r = 25 as the thesis, dx = 11.5 mm. Not in the tables, and chosen here: the beam runs 150 mm past
each support; supports and loads sit on 100 x 20 mm steel bearing plates across the width, each held or
pushed along one line of nodes at its middle (a roller or a hinge), so that the plate can turn. Each load
point moves down by the same amount; the curve's load is one load point's reaction, half the thesis's P
(Table 7.3 gives the total of both point loads: Eurocode 2's flexural P = 2 M_u / L_1 for beams 8 and 10).
The concrete's compressive strength is f_cm (-pd_fc: crushing, docs/softening.md; without it the lattice's
struts and compression zones fail at a fraction of it), its ultimate compressive strain Eurocode 2's eps_cu2 =
0.0035 (-pd_eps_cu: a run stops where the concrete crushes, and the failure mode follows; docs/reinforcement.md),
and the bars are bonded by the fib Model Code 2010 bond-slip law with the same f_cm (docs/reinforcement.md).

Usage: scripts/stuttgart_scenes.py [--dim 2] [--out FOLDER]   (from the repository root; FOLDER by default options/)
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# beam: span L (m), shear span L_1 (m), a_v/d, f_cm,cyl (MPa), G_F (N/m), E_c (MPa)   (Table 7.1)
BEAMS = {1: (0.90, 0.27, 1.0, 28.6, 133, 30500), 2: (1.15, 0.40, 1.5, 28.6, 133, 30500), 3: (1.45, 0.54, 2.0, 28.6, 133, 30500),
         4: (1.70, 0.67, 2.5, 28.6, 133, 30500), 5: (1.95, 0.81, 3.0, 28.6, 133, 30500), 6: (2.55, 1.10, 4.0, 28.6, 133, 30500),
         7: (3.10, 1.35, 5.0, 29.6, 134, 30900), 8: (3.60, 1.62, 6.0, 29.7, 134, 30900), 10: (4.70, 2.16, 8.0, 28.9, 134, 30600)}
B, H, D, OVER, PLATE, PT, DX = 0.19, 0.32, 0.27, 0.15, 0.10, 0.02, 0.0115


def scene(n, dim, outdir):
    L, L1, avd, fcm, gf, ec = BEAMS[n]
    total, x0 = L + 2 * OVER, OVER
    loads = (x0 + L1, x0 + L - L1)
    ft = 0.3 * (fcm - 8) ** (2.0 / 3.0) * 1e6
    g = lambda v: "%.6g" % v
    name = "stuttgart_beam%d%s" % (n, "_2d" if dim == 2 else "")
    if dim == 3:  # x along the beam, y across (190 mm), z up
        box = lambda xa, za, xb, zb: ",".join(g(v) for v in (xa, 0, za, xb, B, zb))
        lines = ["-pd_domain " + ",".join(g(v) for v in (0, 0, 0, total, B, H))]
        bars = [("0,%s,%s,%s,%s,%s" % (g(y), g(H - D), g(total), g(y), g(H - D)), 1) for y in (0.05, B - 0.05)]
        line = lambda x, z: ",".join(g(v) for v in (x, 0, z, x, B, z))
    else:
        box = lambda xa, za, xb, zb: ",".join(g(v) for v in (xa, za, xb, zb))
        lines = ["-pd_model plane_stress", "-pd_thickness %g" % B, "-pd_domain " + ",".join(g(v) for v in (0, 0, total, H))]
        bars = [("0,%s,%s,%s" % (g(H - D), g(total), g(H - D)), 2)]
        line = lambda x, z: ",".join(g(v) for v in (x, z, x, z))
    head = ["# Stuttgart shear beam %d (Leonhardt and Walther; Hobbs thesis Tables 7.1 and 7.2): span %g m, shear span %g m"
            " (a_v/d = %g)," % (n, L, L1, avd),
            "# four-point bending, two 26 mm bars at d = 270 mm, bearing plates (written by scripts/stuttgart_scenes.py). %s"
            % ("3D." if dim == 3 else "2D plane stress, 190 mm thick."),
            "-pd_name " + name]
    lines = head + lines + ["-pd_dx %g" % DX, "-pd_E %g" % (ec * 1e6), "-pd_rho 2400", "-pd_law bilinear", "-pd_bilinear_kr 25",
                            "-pd_ft %.6g" % ft, "-pd_Gf %g" % gf, "-pd_fc %g" % (fcm * 1e6), "-pd_eps_cu 0.0035"]
    for k, (where, count) in enumerate(bars):
        lines += ["-pd_bar%d_line %s" % (k, where), "-pd_bar%d_diameter 0.026" % k, "-pd_bar%d_count %d" % (k, count),
                  "-pd_bar%d_E 208e9" % k, "-pd_bar%d_fy 465e6" % k, "-pd_bar%d_bond slip" % k]
    plates = [(x0, 0, PT), (x0 + L, 0, PT), (loads[0], H - PT, H), (loads[1], H - PT, H)]
    for k, (x, za, zb) in enumerate(plates):
        lines += ["-pd_plate%d_box %s" % (k, box(x - PLATE / 2, za, x + PLATE / 2, zb))]
    # supports: a hinge on the left, a roller on the right, each on the line of nodes under its plate's middle
    dofs = "x,y,z" if dim == 3 else "x,y"
    up = "z" if dim == 3 else "y"
    lines += ["-pd_region0_box " + line(x0, 0), "-pd_region0_kind support", "-pd_region0_dofs " + dofs,
              "-pd_region1_box " + line(x0 + L, 0), "-pd_region1_kind support", "-pd_region1_dofs " + up]
    down = "0,0,-0.02" if dim == 3 else "0,-0.02"
    for k, x in enumerate(loads, start=2):
        lines += ["-pd_region%d_box %s" % (k, line(x, H)), "-pd_region%d_kind displacement" % k, "-pd_region%d_dofs %s" % (k, up),
                  "-pd_region%d_displacement %s" % (k, down)]
    # the curve's load is the thesis's P, both point loads; its displacement the left load point's
    lines += ["-pd_load_region 2,3", "-pd_steps 400"]
    path = os.path.join(outdir, name + ".opts")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


if __name__ == "__main__":
    dim = int(sys.argv[sys.argv.index("--dim") + 1]) if "--dim" in sys.argv else 3
    out = sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else os.path.join(ROOT, "options")
    for n in BEAMS:
        print(scene(n, dim, out))
