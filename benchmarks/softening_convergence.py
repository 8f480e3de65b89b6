#!/usr/bin/python3
"""Softening under refinement at a fixed horizon ratio: the Gregoire D = 50 mm beams (unnotched, fifth- and
half-notched; options/gregoire_d50_{un,fn,hn}.opts as shipped: non-linear law, E, f_t and G_F of the
material data, the same for all three, horizon pi dx) traced to CMOD = 0.2 mm at dx = 5, 2.5 and 1.25 mm
with today's solver defaults.

For each beam the table gives the peak at every spacing, its change between the two finest spacings,
whether the unnotched peak lies inside the experimental envelope (largest loads of the lower and upper
curves in data/), the RMS difference of the two finest curves over the finer one's peak, and what each run
cost (steps, Newton and Krylov iterations, CPU time, peak memory). The plot shows the curves by spacing
over the experimental envelopes, and the peaks against dx.

Results go to docs/benchmarks/softening_convergence.json, one entry per run, kept between invocations (an
interrupted study resumes where it stopped); softening_convergence.md and .png are written from it.

Usage: benchmarks/softening_convergence.py [--dx 0.005 0.0025 0.00125] [--beams un fn hn] [--timeout 7200]
       [--report]
"""
import argparse
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import (EXE, RESULTS_DIR, ROOT, curve_difference, curve_rows, experiment_peaks, plot_gregoire_experiment,  # noqa: E402
                    last_fields, load_results, pyplot, run_timed, save_figure, store_result, write_lines)

DATA = os.path.join(RESULTS_DIR, "softening_convergence.json")
BEAMS = {"un": "unnotched", "fn": "fifth-notched", "hn": "half-notched"}
SPACINGS = [0.01, 0.005, 0.0025, 0.00125]
DAMAGED = 0.1  # nodal damage above which a node counts in the damaged zone


def key(beam, dx):
    return "%s dx=%g" % (beam, dx)


def damaged_zone(outdir):
    """Length along the beam (m) of the damaged zone at the end of a run, layer by layer: in each layer of nodes,
    the span of the columns whose mean nodal damage exceeds DAMAGED, plus one spacing. Returned for the lowest
    damaged layer (the crack's root: the bottom face, or the notch tip) and as the median over the damaged
    layers. A localised crack is one band about a horizon either side of its plane; a zone that stays as
    long while the horizon shrinks has not localised."""
    import numpy as np
    x, _, dmg = last_fields(outdir)
    dx = np.min(np.diff(np.unique(x[:, 0])))
    spans = []
    for z in np.unique(x[:, 2]):
        layer = x[:, 2] == z
        cols = np.unique(x[layer, 0])
        mean = np.array([dmg[layer][x[layer, 0] == c].mean() for c in cols])
        hot = cols[mean > DAMAGED]
        if hot.size:
            spans.append(float(hot.max() - hot.min() + dx))
    return {"root": spans[0] if spans else 0.0, "median": float(np.median(spans)) if spans else 0.0}


def measure(beam, dx, timeout):
    out = tempfile.mkdtemp(prefix="pdconv_")
    cmd = [EXE, "-options_file", os.path.join(ROOT, "options", "gregoire_d50_%s.opts" % beam), "-pd_output_dir", out, "-pd_dx", repr(dx)]
    with open(os.path.join(out, "log.txt"), "w") as log:
        code, wall, cpu, timed_out = run_timed(cmd, timeout, log)
    s = json.load(open(os.path.join(out, "summary.json")))
    rows = curve_rows(out)
    curve = [[r["cmod_m"], abs(r["load_N"])] for r in rows]
    return {"status": s["status"], "converged": s["converged"], "timed_out": timed_out, "returncode": code, "peak_N": max(c[1] for c in curve),
            "final_cmod_m": curve[-1][0], "nodes": s["nodes"], "bonds": s["bonds"], "steps": s["steps"], "newton_its": s["newton_its"],
            "ksp_its": s["ksp_its"], "wall_s": wall, "cpu_s": cpu, "peak_rss_bytes": s["memory"]["peak_rss_bytes"], "solver": s["solver"],
            "damaged_zone_m": damaged_zone(out), "horizon_m": s["dx_m"] * s["horizon_ratio"], "curve": curve, "command": " ".join(["pdimplicit"] + cmd[1:3] + ["-pd_dx", repr(dx)])}


def spacings(res, beam):
    return sorted((float(k.split("dx=")[1]) for k in res if k.startswith(beam + " ")), reverse=True)


def report(res):
    lines = ["# Softening under refinement: the D = 50 mm beams at dx = 5, 2.5 and 1.25 mm", "",
             "Written by `benchmarks/softening_convergence.py` from `softening_convergence.json`. The shipped scenes",
             "(`options/gregoire_d50_{un,fn,hn}.opts`: non-linear law, E = 37 GPa, f_t = 3.9 MPa, G_F = 143.2 N/m for all",
             "three beams, horizon pi dx, so the horizon shrinks with dx) traced to CMOD = 0.2 mm with the solver",
             "defaults, one rank. Envelope: the largest loads of the experiment's lower and upper curves (data/).",
             "'Curves apart': RMS load difference of the two finest curves over the CMOD range both reach, over the finer",
             "one's peak. CPU: the run's own (wait4); other runs shared the two cores, so wall times are longer.", "",
             "Damaged zone: in each layer of nodes, the length along the beam of the columns whose mean damage exceeds %g" % DAMAGED,
             "at the end; at the crack's root (the lowest damaged layer: bottom face or notch tip) and the median over the",
             "damaged layers. A localised crack's zone is about two horizons long.", "",
             "| beam | dx (mm) | horizon (mm) | peak (N) | vs experimental mean | inside envelope | damaged zone, root / median (mm) | steps | Newton | Krylov | CPU (s) | peak memory (GB) | bonds | end |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    summary = []
    for beam, name in BEAMS.items():
        mean, low, high = experiment_peaks(beam)
        dxs = spacings(res, beam)
        for dx in dxs:
            r = res[key(beam, dx)]
            p = r["peak_N"]
            vs = "%+.1f %%" % (100 * (p / mean - 1)) if mean else "-"
            inside = ("yes" if low <= p <= high else "no") if mean else "-"
            end = "CMOD %.3f mm" % (1e3 * r["final_cmod_m"]) + ("" if r["final_cmod_m"] >= 2e-4 else " (" + r["status"][:60] + ")")
            zone = r["damaged_zone_m"]
            lines.append("| %s | %g | %.1f | %.0f | %s | %s | %.1f / %.1f | %d | %d | %d | %.0f | %.1f | %d | %s |" % (
                name, 1e3 * dx, 1e3 * r["horizon_m"], p, vs, inside, 1e3 * zone["root"], 1e3 * zone["median"], r["steps"], r["newton_its"], r["ksp_its"], r["cpu_s"], r["peak_rss_bytes"] / 1e9, r["bonds"], end))
        if len(dxs) >= 2:
            a, b = res[key(beam, dxs[-2])], res[key(beam, dxs[-1])]
            summary.append((name, 1e3 * dxs[-2], 1e3 * dxs[-1], 100 * (b["peak_N"] / a["peak_N"] - 1), 100 * curve_difference(b, a)))
    lines += ["", "Between the two finest spacings:", "", "| beam | spacings (mm) | peak change | curves apart |", "|---|---|---|---|"]
    lines += ["| %s | %g to %g | %+.1f %% | %.1f %% |" % s for s in summary]
    lines.append("")
    write_lines("softening_convergence.md", lines)
    plot(res)


def plot(res):
    plt = pyplot()
    fig, axes = plt.subplots(1, 4, figsize=(19, 4.5))
    styles = {0.005: ":", 0.0025: "--", 0.00125: "-"}
    for ax, (beam, name) in zip(axes, BEAMS.items()):
        plot_gregoire_experiment(ax, beam, mean=False)
        for dx in spacings(res, beam):
            c = res[key(beam, dx)]["curve"]
            ax.plot([1e3 * x[0] for x in c], [x[1] for x in c], ls=styles.get(dx, "-"), color="k", lw=1.1, label="dx = %g mm" % (1e3 * dx))
        ax.set_title(name)
        ax.set_xlabel("CMOD (mm)")
        ax.set_ylabel("load (N)")
        ax.set_xlim(0, 0.21)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    ax = axes[3]
    for beam, name in BEAMS.items():
        dxs = spacings(res, beam)
        ax.plot([1e3 * dx for dx in dxs], [res[key(beam, dx)]["peak_N"] for dx in dxs], "o-", label=name)
        mean, low, high = experiment_peaks(beam)
        if mean:
            ax.axhspan(low, high, alpha=0.15)
    ax.set_xscale("log")
    ax.set_xlabel("dx (mm)")
    ax.set_ylabel("peak load (N)")
    ax.set_title("peaks by spacing (bands: experimental envelopes)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    save_figure(fig, "softening_convergence.png", dpi=100)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, nargs="+", default=SPACINGS)
    ap.add_argument("--beams", nargs="+", default=list(BEAMS), choices=list(BEAMS))
    ap.add_argument("--timeout", type=int, default=7200, help="seconds before a run is stopped (SIGTERM keeps its curve)")
    ap.add_argument("--report", action="store_true")
    a = ap.parse_args()
    if not a.report:
        for dx in a.dx:
            for beam in a.beams:
                r = measure(beam, dx, a.timeout)
                print(key(beam, dx), {k: v for k, v in r.items() if k != "curve"}, flush=True)
                store_result(DATA, key(beam, dx), r)
    report(load_results(DATA))


if __name__ == "__main__":
    main()
