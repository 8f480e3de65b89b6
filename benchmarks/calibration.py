#!/usr/bin/env python3
"""Elastic convergence at a fixed horizon ratio under the two bond calibrations (-pd_calibration continuum,
the thesis' convention, and stencil): the elastic bar in tension (options/bar_tension.opts, axial strain
of its middle third against F / (E A)) and the cantilever (options/cantilever.opts, tip deflection against
Timoshenko with nu = 1/4), at dx = 20, 10, 5 and 2.5 mm for m = 3, pi and 4, and the lattice's bulk
stiffness ratio (summary.json) that the stencil calibration divides out.

With --softening, the Gregoire D = 50 mm beams (options/gregoire_d50_{un,fn,hn}.opts, non-linear law,
the same E, f_t and G_F for all three) traced to CMOD = 0.2 mm at dx = 5 and 2.5 mm: their peaks under
each calibration against the experimental envelopes, and the change between the two spacings. The
continuum calibration's dx = 2.5 mm peaks are those of docs/benchmarks/gregoire_dx2.5.json (the shipped
scenes, `benchmarks/gregoire.py`), not run again.

With --fe, the cantilever's elastic finite-element reference (benchmarks/fe_cantilever.py, CalculiX): the
beam of the scene on three meshes, and for each spacing the beam as the lattice loads it. The scene's
force region is the layer of nodes nearest to x = 1 m, at x = 1 - dx/2, and the deflection is that
layer's, so the lattice's beam is loaded and measured dx/2 short of its end (-1.5 dx/L in beam theory).
The cantilever's errors are also given against that beam: the clamp and the load point of the scene,
not of beam theory.

Results go to docs/benchmarks/calibration.json, one entry per run, kept between invocations; the table
docs/benchmarks/calibration.md and the plot calibration.png are written from it.

Usage: benchmarks/calibration.py [--dx 0.02 0.01 0.005 0.0025] [--calibration continuum stencil] [--ratios 3 pi 4] [--ranks 2]
       [--softening --beams un fn hn] [--fe] [--report]
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import GREGOIRE_DATA, OUT, RESULTS_DIR, experiment_peaks, last_fields, load_results, run_scene, store_result, pyplot, save_figure  # noqa: E402

DATA = os.path.join(RESULTS_DIR, "calibration.json")
RATIOS = {"3": 3.0, "pi": math.pi, "4": 4.0}
SCENES = ("bar_tension", "cantilever")
FE_MESHES = ("50x5x5", "100x10x10", "200x20x20")
FE_LOADED = "100x10x10"  # the mesh of the per-spacing references: within 0.04 % of the finest at L = 1 m
SPACINGS = (0.02, 0.01, 0.005, 0.0025)
BEAMS = {"un": "unnotched", "fn": "fifth-notched", "hn": "half-notched"}


def timoshenko(P=1e4, L=1.0, E=30e9, b=0.1, h=0.1, nu=0.25, k=5.0 / 6.0):
    I = b * h ** 3 / 12
    G = E / (2 * (1 + nu))
    return P * L ** 3 / (3 * E * I) + P * L / (k * G * b * h)


def bar_strain(outdir):
    """Axial strain in the middle third of the bar: slope of the layer-mean u_x against x."""
    x, u, _ = last_fields(outdir)
    sel = (x[:, 0] > 0.5 / 3) & (x[:, 0] < 1.0 / 3)
    layers = np.unique(np.round(x[sel, 0], 9))
    return np.polyfit(layers, [u[sel & (np.abs(x[:, 0] - xl) < 1e-9), 0].mean() for xl in layers], 1)[0]


def measure(scene, dx, m, calibration, ranks):
    run = run_scene(scene, ["-pd_dx", repr(dx), "-pd_horizon_ratio", repr(RATIOS[m]), "-pd_calibration", calibration], 7200, "pdcal_", ranks)
    if run["code"]:
        return {"status": "failed (%d)" % run["code"], "wall_s": run["wall"]}
    s = run["summary"]
    if scene == "bar_tension":
        exact = 1e5 / (30e9 * 0.1 * 0.1)
        value = bar_strain(run["out"])
    else:
        exact = timoshenko()
        value = abs(run["rows"][-1]["disp_m"])
    return {"status": "ok", "value": value, "reference": exact, "error": value / exact - 1, "nodes": s["nodes"], "bonds": s["bonds"],
            "wall_s": run["wall"], "ranks": ranks, "stiffness_ratio": s.get("lattice_stiffness_ratio")}


def measure_softening(beam, dx, calibration):
    run = run_scene("gregoire_d50_%s" % beam, ["-pd_dx", repr(dx), "-pd_calibration", calibration], 7200, "pdcal_")
    s = run["summary"]
    return {"status": s["status"], "peak_N": max(abs(r["load_N"]) for r in run["rows"]), "nodes": s["nodes"], "bonds": s["bonds"],
            "newton_its": s["newton_its"], "wall_s": run["wall"], "cpu_s": run["cpu"], "stiffness_ratio": s.get("lattice_stiffness_ratio")}


def softening_rows(res):
    """Peaks by beam, calibration and spacing: the runs in res, and the continuum calibration's dx = 2.5 mm
    peaks from gregoire_dx2.5.json."""
    peaks = {}
    for k, r in res.items():
        if k.startswith("gregoire "):
            _, beam, dx, cal = k.split(" ")
            peaks[(beam[5:], cal, float(dx[3:]))] = r
    fine = load_results(os.path.join(RESULTS_DIR, "gregoire_dx2.5.json"))
    for beam in BEAMS:
        r = fine.get("%s/nonlinear/dx=0.0025/default" % beam)
        if r and (beam, "continuum", 0.0025) not in peaks:
            peaks[(beam, "continuum", 0.0025)] = {"status": r["status"], "peak_N": r["peak"], "source": "gregoire_dx2.5.json"}
    return peaks


def softening_report(res, lines):
    peaks = softening_rows(res)
    if not peaks:
        return
    lines += ["## Softening: the D = 50 mm beams under each calibration", "",
              "Peak load (N) at dx = 5 and 2.5 mm, its change between them, and the experimental envelope (largest loads of",
              "the lower and upper curves in data/). `*`: from `gregoire_dx2.5.json` (`benchmarks/gregoire.py`). `†`: stopped",
              "(SIGTERM) before CMOD = 0.2 mm, past the peak. Wall times with other runs sharing the two cores.", "",
              "| beam | calibration | peak at 5 mm | peak at 2.5 mm | change | experiment (min - max) | Newton at 2.5 mm | wall at 2.5 mm (s) |",
              "|---|---|---|---|---|---|---|---|"]
    for beam in BEAMS:
        env = experiment_peaks(beam) if beam in GREGOIRE_DATA else None
        for cal in ("continuum", "stencil"):
            a, b = peaks.get((beam, cal, 0.005)), peaks.get((beam, cal, 0.0025))
            if not a and not b:
                continue
            fa = "%.0f" % a["peak_N"] if a else "-"
            fb = ("%.0f" % b["peak_N"] + ("*" if b.get("source") else "") + ("†" if b["status"].startswith("interrupted") else "")) if b else "-"
            ch = "%+.1f %%" % (100 * (b["peak_N"] / a["peak_N"] - 1)) if a and b else "-"
            ex = "%.0f - %.0f" % (env[1], env[2]) if env else "-"
            nb = str(b["newton_its"]) if b and "newton_its" in b else "-"
            wb = "%.0f" % b["wall_s"] if b and "wall_s" in b else "-"
            lines.append("| %s | %s | %s | %s | %s | %s | %s | %s |" % (BEAMS[beam], cal, fa, fb, ch, ex, nb, wb))
    lines.append("")


def key(scene, dx, m, calibration):
    return "%s dx=%g m=%s %s" % (scene, dx, m, calibration)


def report(res):
    rows = []
    for k, r in res.items():
        if k.startswith(("gregoire ", "fe ")):
            continue
        scene, dx, m, cal = k.split(" ")
        rows.append((SCENES.index(scene), -float(dx[3:]), list(RATIOS).index(m[2:]), cal, scene, float(dx[3:]), m[2:], r))
    rows.sort()
    fe = [res.get("fe cantilever mesh=" + mesh) for mesh in FE_MESHES]
    fe_loaded = {dx: res.get("fe cantilever dx=%g mesh=%s" % (dx, FE_LOADED)) for dx in SPACINGS}
    lines = ["# Elastic convergence under the two bond calibrations", "",
             "Written by `benchmarks/calibration.py` from `calibration.json`. Bar: axial strain of the middle third against",
             "F / (E A); cantilever: tip deflection against Timoshenko (nu = 1/4, k = 5/6). A negative error is a stiff",
             "model. `continuum` is the thesis' convention (continuum micromodulus, volume-method surface correction",
             "with the horizon's analytic volume); `stencil` divides the micromodulus by the lattice's bulk stiffness",
             "ratio and corrects surfaces by the directional energy method (docs/calibration.md). One rank up to",
             "dx = 5 mm, two below (wall time on the 2-core machine). 'vs FE': the cantilever's deflection against",
             "the finite-element beam loaded and measured where the lattice's is, at x = 1 m - dx/2, clamped at x = 0",
             "(below).", "",
             "| scene | dx (mm) | m | calibration | nodes | bonds | error | vs FE | bulk stiffness ratio | wall (s) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for _, _, _, cal, scene, dx, m, r in rows:
        if r["status"] != "ok":
            lines.append("| %s | %g | %s | %s | | | %s | | | %.0f |" % (scene, 1e3 * dx, m, cal, r["status"], r["wall_s"]))
            continue
        ratio = "%.4f" % r["stiffness_ratio"] if r.get("stiffness_ratio") else "-"
        ref = fe_loaded.get(dx)
        vs_fe = "%+.2f %%" % (100 * (r["value"] / ref["value"] - 1)) if scene == "cantilever" and ref else "-"
        lines.append("| %s | %g | %s | %s | %d | %d | %+.2f %% | %s | %s | %.1f |" % (scene, 1e3 * dx, m, cal, r["nodes"], r["bonds"],
                                                                                   100 * r["error"], vs_fe, ratio, r["wall_s"]))
    if any(fe):
        lines += ["", "Finite-element reference (`benchmarks/fe_cantilever.py`, CalculiX, C3D8I bricks): mean deflection of the end face.", "",
                  "| mesh | deflection (m) | against Timoshenko | wall (s) |", "|---|---|---|---|"]
        lines += ["| %s | %.7e | %+.2f %% | %.1f |" % (mesh, r["value"], 100 * (r["value"] / timoshenko() - 1), r["wall_s"])
                  for mesh, r in zip(FE_MESHES, fe) if r]
        lines += ["", "Loaded and measured at x = 1 m - dx/2 (mesh %s, over the shortened beam):" % FE_LOADED, "",
                  "| dx (mm) | load point (m) | deflection (m) | against Timoshenko at 1 m |", "|---|---|---|---|"]
        lines += ["| %g | %.5f | %.7e | %+.2f %% |" % (1e3 * dx, 1 - dx / 2, r["value"], 100 * (r["value"] / timoshenko() - 1))
                  for dx, r in fe_loaded.items() if r]
    lines += ["", "![error against spacing](calibration.png)", ""]
    softening_report(res, lines)
    with open(os.path.join(OUT, "calibration.md"), "w") as f:
        f.write("\n".join(lines))
    try:
        plt = pyplot()
    except ImportError:
        return
    def error(scene, dx, r):
        """The bar's against F / (E A), the cantilever's against the finite-element beam loaded where the lattice's is."""
        ref = fe_loaded.get(dx) if scene == "cantilever" else None
        return r["value"] / ref["value"] - 1 if ref else r["error"]

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, scene in zip(axes, SCENES):
        for m in RATIOS:
            for cal, style in (("continuum", "--"), ("stencil", "-")):
                pts = sorted((float(k.split(" ")[1][3:]), error(scene, float(k.split(" ")[1][3:]), r)) for k, r in res.items()
                             if k.startswith(scene + " ") and k.endswith(" m=%s %s" % (m, cal)) and r["status"] == "ok")
                if pts:
                    ax.plot([1e3 * p[0] for p in pts], [100 * abs(p[1]) for p in pts], style, marker="o", label="m = %s, %s" % (m, cal))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("dx (mm)")
        ax.set_title(scene + (" (against the finite-element beam)" if scene == "cantilever" else " (against F / (E A))"))
        ax.axhline(1.5, color="grey", lw=0.5)
        ax.grid(True, which="both", lw=0.3)
    axes[0].set_ylabel("|error| (%)")
    axes[1].legend(fontsize=7)
    save_figure(fig, "calibration.png", dpi=100)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dx", type=float, nargs="+", default=[0.02, 0.01, 0.005, 0.0025])
    ap.add_argument("--calibration", nargs="+", default=["continuum", "stencil"])
    ap.add_argument("--scenes", nargs="+", default=list(SCENES))
    ap.add_argument("--ratios", nargs="+", default=list(RATIOS), choices=list(RATIOS), help="horizon ratios of the elastic scenes")
    ap.add_argument("--ranks", type=int, default=2, help="ranks for dx below 5 mm")
    ap.add_argument("--softening", action="store_true", help="the D = 50 mm beams instead of the elastic scenes")
    ap.add_argument("--beams", nargs="+", default=list(BEAMS))
    ap.add_argument("--results", default=DATA, help="where the runs are stored (merged by hand into calibration.json afterwards)")
    ap.add_argument("--fe", action="store_true", help="the cantilever's finite-element reference (CalculiX)")
    ap.add_argument("--report", action="store_true")
    a = ap.parse_args()
    if a.fe and not a.report:
        import time
        from fe_cantilever import deflection
        runs = [("fe cantilever mesh=" + mesh, mesh, 1.0) for mesh in FE_MESHES]
        runs += [("fe cantilever dx=%g mesh=%s" % (dx, FE_LOADED), FE_LOADED, 1 - dx / 2) for dx in SPACINGS]
        for k, mesh, length in runs:
            if k in load_results(a.results):
                continue
            t0 = time.time()
            w = deflection(*map(int, mesh.split("x")), L=length)
            r = {"value": w, "wall_s": time.time() - t0, "length_m": length}
            print(k, r, flush=True)
            store_result(a.results, k, r)
    elif a.softening and not a.report:
        for beam in a.beams:
            for dx in a.dx:
                for cal in a.calibration:
                    k = "gregoire beam=%s dx=%g %s" % (beam, dx, cal)
                    r = measure_softening(beam, dx, cal)
                    print(k, r, flush=True)
                    store_result(a.results, k, r)
    elif not a.report:
        for scene in a.scenes:
            for dx in a.dx:
                for m in a.ratios:
                    for cal in a.calibration:
                        r = measure(scene, dx, m, cal, a.ranks if dx < 0.005 else 1)
                        print(key(scene, dx, m, cal), r, flush=True)
                        store_result(DATA, key(scene, dx, m, cal), r)
    report(load_results(DATA))


if __name__ == "__main__":
    main()
