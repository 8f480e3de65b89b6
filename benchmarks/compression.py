#!/usr/bin/python3
"""Concrete in compression: the plane-stress prism of options/prism_compression_2d.opts (100 x 200 mm,
f_t = 3.9 MPa, f_c = 42.3 MPa) without and with -pd_fc, and the same with a 5 % bond strength scatter.
Records the peak stress, where it stands against the lattice's own strength E s0 / nu and against f_c,
the mean damage of the prism's middle half at the end, and how each run ended. Then the half-notched
D = 50 mm beam at dx = 10 mm without and with -pd_fc: a flexural crack, whose curve -pd_fc must not move.
Writes docs/benchmarks/compression.json and compression.md (about a minute).

Usage: benchmarks/compression.py [--report | CASE ...]   (CASE: run only these, keep the others' results)
"""
import os
import sys
import tempfile

from common import EXE, OUT, RESULTS_DIR, ROOT, load_results, run_timed, save_results

JSON = os.path.join(RESULTS_DIR, "compression.json")
PRISM = os.path.join(ROOT, "options", "prism_compression_2d.opts")
BEAM = os.path.join(ROOT, "options", "gregoire_d50_hn.opts")
AREA, FC, FT, NU = 0.1 * 0.1, 42.3e6, 3.9e6, 1.0 / 3  # section (m^2), strengths (Pa), the plane lattice's Poisson ratio

# name, what, scene, extra options
CASES = [
    ("prism_off", "prism, no -pd_fc (the thesis' bond)", PRISM, ["-pd_fc", "0"]),
    ("prism_on", "prism, -pd_fc 42.3e6", PRISM, []),
    ("prism_off_scatter", "prism, no -pd_fc, 5 % strength scatter", PRISM, ["-pd_fc", "0", "-pd_strength_scatter", "0.05"]),
    ("prism_on_scatter", "prism, -pd_fc 42.3e6, 5 % strength scatter", PRISM, ["-pd_strength_scatter", "0.05"]),
    ("prism_off_explicit", "prism, no -pd_fc, explicit path", PRISM, ["-pd_fc", "0", "-pd_mode", "explicit"]),
    ("prism_on_explicit", "prism, -pd_fc 42.3e6, explicit path", PRISM, ["-pd_mode", "explicit"]),
    ("beam_off", "half-notched D = 50 mm beam, dx = 10 mm, no -pd_fc", BEAM, ["-pd_dx", "0.01"]),
    ("beam_on", "half-notched D = 50 mm beam, dx = 10 mm, -pd_fc 42.3e6", BEAM, ["-pd_dx", "0.01", "-pd_fc", "42.3e6"]),
]


def middle_damage(outdir):
    """Mean nodal damage of the prism's middle half (50 < y < 150 mm) at the last fields written."""
    import h5py
    import numpy as np
    if not os.path.exists(os.path.join(outdir, "fields.h5")):
        return None  # an explicit run that stops unstable writes no fields
    with h5py.File(os.path.join(outdir, "fields.h5"), "r") as f:
        g = f["fields"]
        key = sorted(k for k in g if k.startswith("damage_"))[-1]
        x, d = np.array(g["coordinates"]), np.array(g[key]).ravel()
    mid = (x[:, 1] > 0.05) & (x[:, 1] < 0.15)
    return float(d[mid].mean())


def measure(names):
    import json
    for name, what, path, extra in CASES:
        if names and name not in names:
            continue
        out = tempfile.mkdtemp(prefix="pdbench_")
        with open(os.path.join(out, "log"), "w") as log:
            code, wall, cpu, _ = run_timed([EXE, "-options_file", path, "-pd_output_dir", out, *extra], 3600, log)
        s = json.load(open(os.path.join(out, "summary.json")))
        r = {"what": what, "options": extra, "exit": code, "cpu_s": round(cpu, 1), "status": s["status"].replace("|", "/"),
             "peak_N": s["peak_load_N"], "steps": s["steps"], "newton_its": s["newton_its"], "effects": s["effects"], "s0": s["law"]["s0"],
             "steps_kind": "time steps" if "-pd_mode" in extra else "load steps"}
        if path == PRISM:
            r["middle_damage"] = middle_damage(out)
        res = load_results(JSON)  # other runs may have written meanwhile
        res.setdefault("runs", {})[name] = r
        save_results(JSON, res)
        print(name, r)


def report():
    res = load_results(JSON)
    runs = res["runs"]
    E = 37e9
    own = E * runs["prism_off"]["s0"] / NU
    lines = ["# Concrete in compression: the lattice's own strength and -pd_fc", "",
             "Written by `benchmarks/compression.py` from `compression.json`. `options/prism_compression_2d.opts`: a plane-stress prism "
             "100 x 200 mm (dx = 5 mm), E = 37 GPa, f_t = 3.9 MPa, f_c = 42.3 MPa, non-linear law, bottom face on rollers, top face "
             "pushed down. Without `-pd_fc` the bonds across the load soften in tension once nu |eps| = s0, at E s0 / nu = %.1f MPa "
             "(nu = 1/3 in the plane). Stress: peak load over the prism's section. Middle damage: mean nodal damage of the middle half "
             "(50 < y < 150 mm) at the end." % (own / 1e6), "",
             "| run | peak stress (MPa) | over E s0 / nu | over f_c | middle damage | steps | Newton | CPU (s) | end |",
             "|---|---|---|---|---|---|---|---|---|"]
    for name, _, path, _ in CASES:
        if path != PRISM:
            continue
        r = runs[name]
        sig = r["peak_N"] / AREA
        md = "-" if r["middle_damage"] is None else "%.3f" % r["middle_damage"]
        lines.append("| %s | %.1f | %.2f | %.2f | %s | %d %s | %d | %.1f | %s |" % (
            r["what"], sig / 1e6, sig / own, sig / FC, md, r["steps"], r["steps_kind"], r["newton_its"], r["cpu_s"], r["status"]))
    b0, b1 = runs["beam_off"], runs["beam_on"]
    lines += ["", "A flexural crack with and without `-pd_fc` (`options/gregoire_d50_hn.opts -pd_dx 0.01`): peak %.1f N without, "
              "%.1f N with (relative change %.1e); %d and %d steps, %d and %d Newton iterations." % (
                  b0["peak_N"], b1["peak_N"], abs(b1["peak_N"] / b0["peak_N"] - 1), b0["steps"], b1["steps"], b0["newton_its"], b1["newton_its"]),
              "", "Commands:", ""]
    lines += ["    build/pdimplicit -options_file %s %s" % (os.path.relpath(c[2], ROOT), " ".join(c[3])) for c in CASES]
    open(os.path.join(OUT, "compression.md"), "w").write("\n".join(lines) + "\n")


if __name__ == "__main__":
    if "--report" not in sys.argv[1:]:
        measure(sys.argv[1:])
    report()
