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

With --variants, the unnotched beam at dx = 10, 5 and 2.5 mm with one ingredient of its scene changed at a
time (the surface correction, its critical-stretch part, its family volume, a scatter of bond strength): which
of them drives its peak's rise under refinement.

With --fixed-horizon, the beams at dx = 5 and 2.5 mm with the horizon of the spacing twice as coarse (m = 2 pi),
under both bond calibrations.

With --implex [ERROR ...], the beams traced by path following with IMPL-EX steps from the first step (the 3D
D = 200 mm beams' path, docs/arclength.md) at each damage error per step given (0.03 without a value) instead of the
scenes' displacement control: each spacing's peak and curve against the default path's at the same spacing, and
what each path cost. With --increments N, the default path with N displacement increments over the scene's ramp
instead of its 200 (finer increments through the peak), reported beside them.

Usage: benchmarks/softening_convergence.py [--dx 0.01 0.005 0.0025 0.00125] [--beams un fn hn] [--variants]
       [--fixed-horizon [--coarse 0.01 0.005]] [--implex [0.03 0.01]] [--increments 800]
       [--timeout 7200] [--force] [--report]
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import (RESULTS_DIR, ROOT, curve_difference, experiment_peaks, plot_gregoire_experiment,  # noqa: E402
                    last_fields, load_results, pyplot, run_scene, save_figure, store_result, write_lines)

DATA = os.path.join(RESULTS_DIR, "softening_convergence.json")
BEAMS = {"un": "unnotched", "fn": "fifth-notched", "hn": "half-notched"}
SPACINGS = [0.01, 0.005, 0.0025, 0.00125]
# one ingredient of the unnotched beam's scene changed at a time (run with --variants, up to dx = 2.5 mm)
VARIANTS = {"critical-stretch correction off": ["-pd_sc_correction", "false"], "surface correction off": ["-pd_surface_correction", "false"],
            "partial volumes in the surface correction": ["-pd_sc_whole_cells", "false"], "5 % bond-strength scatter": ["-pd_strength_scatter", "0.05"]}
VARIANT_SPACINGS = [0.01, 0.005, 0.0025]
# the horizon held while dx halves (m-refinement instead of delta-refinement): the coarse spacing's horizon pi dx is
# 2 pi times the fine one's
FIXED_HORIZON = ["-pd_horizon_ratio", repr(2 * math.pi)]
FIXED_PAIRS = [(0.01, 0.005), (0.005, 0.0025)]
# the two bond calibrations (docs/calibration.md): the lattice's bulk stiffness depends on m under the first only
CALIBRATIONS = {"continuum": [], "stencil": ["-pd_calibration", "stencil"]}
# path following with IMPL-EX steps; 0.03 is the damage error per step the 3D D = 200 mm beams take (benchmarks/size_effect.py)
IMPLEX_ERRORS = [0.03, 0.01, 0.003]
# displacement increments over the scene's ramp for --increments (the scenes take 200)
INCREMENTS = [800]


def implex(error):
    return ["-pd_control", "arclength", "-pd_arclength_implex", "%g" % error]


DAMAGED = 0.1  # nodal damage above which a node counts in the damaged zone


def key(beam, dx, extra=()):
    return " ".join(["%s dx=%g" % (beam, dx)] + list(extra))


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


def measure(beam, dx, timeout, extra=()):
    args = ["-pd_dx", repr(dx), *extra]
    run = run_scene("gregoire_d50_%s" % beam, args, timeout, "pdconv_")
    s, rows = run["summary"], run["rows"]
    if s is None or not rows:  # a run that failed to start or was killed
        return {"status": "failed (exit %d)%s" % (run["code"], "; " + s["status"] if s else ""), "wall_s": run["wall"], "cpu_s": run["cpu"]}
    curve = [[r["cmod_m"], abs(r["load_N"])] for r in rows]
    return {"status": s["status"], "converged": s["converged"], "timed_out": run["timed_out"], "returncode": run["code"],
            "peak_N": max(c[1] for c in curve), "final_cmod_m": curve[-1][0], "nodes": s["nodes"], "bonds": s["bonds"], "steps": s["steps"],
            "newton_its": s["newton_its"], "ksp_its": s["ksp_its"], "wall_s": run["wall"], "cpu_s": run["cpu"],
            "peak_rss_bytes": s["memory"]["peak_rss_bytes"], "solver": s["solver"], "damaged_zone_m": damaged_zone(run["out"]),
            "stiffness_ratio": s.get("lattice_stiffness_ratio"), "horizon_m": s["dx_m"] * s["horizon_ratio"], "curve": curve,
            "command": " ".join(["pdimplicit", "-options_file", "options/gregoire_d50_%s.opts" % beam] + args)}


def passed_peak(r):
    """A run whose peak its table may quote: it has a curve, and the curve ends below its peak (a run stopped on the
    rising branch, or one that failed, does not know its peak)."""
    return r is not None and "peak_N" in r and r["curve"][-1][1] < 0.95 * r["peak_N"]


def spacings(res, beam, extra=()):
    """The spacings at which the beam (with the extra options) has a run whose peak is known, coarse first."""
    return [dx for dx in SPACINGS if passed_peak(res.get(key(beam, dx, extra)))]


def scene_value(beam, option):
    """A material value as the shipped scene gives it."""
    for line in open(os.path.join(ROOT, "options", "gregoire_d50_%s.opts" % beam)):
        if line.split()[:1] == [option]:
            return float(line.split()[1])
    return None


def report(res):
    run = sorted({dx for b in BEAMS for dx in spacings(res, b)}, reverse=True)
    lines = ["# Softening under refinement: the D = 50 mm beams at dx = %s mm" % ", ".join("%g" % (1e3 * dx) for dx in run), "",
             "Written by `benchmarks/softening_convergence.py` from `softening_convergence.json`. The shipped scenes",
             "(`options/gregoire_d50_{un,fn,hn}.opts`: non-linear law, E = %g GPa, f_t = %g MPa, G_F = %g N/m for all" % (
                 scene_value("un", "-pd_E") / 1e9, scene_value("un", "-pd_ft") / 1e6, scene_value("un", "-pd_Gf")),
             "three beams, horizon pi dx, so the horizon shrinks with dx) traced to CMOD = 0.2 mm with the solver",
             "defaults, one rank; a run stopped by its time limit past its peak says so in 'end'. Envelope: the largest",
             "loads of the experiment's lower and upper curves (data/).",
             "'Curves apart': RMS load difference of the two finest curves over the CMOD range both reach, over the finer",
             "one's peak. CPU: the run's own (wait4); other runs shared the two cores, so wall times are longer.", "",
             "Damaged zone: in each layer of nodes, the length along the beam of the columns whose mean damage exceeds %g" % DAMAGED,
             "at the end; at the crack's root (the lowest damaged layer: bottom face or notch tip) and the median over the",
             "damaged layers.", "",
             "| beam | dx (mm) | horizon (mm) | peak (N) | vs experimental mean | inside envelope | damaged zone, root / median (mm) | steps | Newton | Krylov | CPU (s) | peak memory (GB) | bytes per bond | bonds | end |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    summary = []
    for beam, name in BEAMS.items():
        mean, low, high = experiment_peaks(beam)
        dxs = spacings(res, beam)
        for dx in dxs:
            r = res[key(beam, dx)]
            p = r["peak_N"]
            vs = "%+.1f %%" % (100 * (p / mean - 1)) if mean else "-"
            inside = ("yes" if low <= p <= high else "no") if mean else "-"
            stop = "stopped by its time limit" if r.get("timed_out") else r["status"]
            end = "CMOD %.3f mm" % (1e3 * r["final_cmod_m"]) + ("" if r["status"].startswith("completed") else " (%s)" % stop)
            zone = r["damaged_zone_m"]
            lines.append("| %s | %g | %.1f | %.0f | %s | %s | %.1f / %.1f | %d | %d | %d | %.0f | %.1f | %.0f | %d | %s |" % (
                name, 1e3 * dx, 1e3 * r["horizon_m"], p, vs, inside, 1e3 * zone["root"], 1e3 * zone["median"], r["steps"], r["newton_its"], r["ksp_its"], r["cpu_s"], r["peak_rss_bytes"] / 1e9, r["peak_rss_bytes"] / r["bonds"], r["bonds"], end))
        if len(dxs) >= 2:
            a, b = res[key(beam, dxs[-2])], res[key(beam, dxs[-1])]
            summary.append((name, 1e3 * dxs[-2], 1e3 * dxs[-1], 100 * (b["peak_N"] / a["peak_N"] - 1), 100 * curve_difference(b, a)))
    lines += ["", "Between the two finest spacings:", "", "| beam | spacings (mm) | peak change | curves apart |", "|---|---|---|---|"]
    lines += ["| %s | %g to %g | %+.1f %% | %.1f %% |" % s for s in summary]
    lines.append("")
    findings(res, summary, lines)
    variants_report(res, lines)
    fixed_horizon_report(res, lines)
    implex_report(res, lines)
    write_lines("softening_convergence.md", lines)
    plot(res)


def findings(res, summary, lines):
    """What the table says, in words written from the data."""
    aim = 3.0
    met = [s[0] for s in summary if abs(s[3]) < aim]
    missed = [s[0] for s in summary if abs(s[3]) >= aim]
    lines += ["Findings:", ""]
    if summary:
        lines.append("- Between the two finest spacings the peak moves by less than %g %% on %s, and by more on %s." % (
            aim, " and ".join(met) or "no beam", " and ".join(missed) or "no beam"))
    dxs = spacings(res, "un")
    if dxs:
        mean, low, high = experiment_peaks("un")
        inside = ["%g" % (1e3 * dx) for dx in dxs if low <= res[key("un", dx)]["peak_N"] <= high]
        outside = ["%g" % (1e3 * dx) for dx in dxs if not low <= res[key("un", dx)]["peak_N"] <= high]
        lines.append("- The unnotched peak lies inside the experimental envelope at dx = %s mm and outside it at dx = %s mm." % (
            ", ".join(inside) or "no spacing", ", ".join(outside) or "no spacing"))
        ratios = [res[key("un", dx)]["damaged_zone_m"]["root"] / res[key("un", dx)]["horizon_m"] for dx in dxs]
        zones = ", ".join("%.1f at %g mm" % (r, 1e3 * dx) for r, dx in zip(ratios, dxs))
        notched = [res[key(b, dx)]["damaged_zone_m"]["root"] / res[key(b, dx)]["horizon_m"] for b in ("fn", "hn") for dx in spacings(res, b)]
        if len(ratios) >= 2 and all(b > a for a, b in zip(ratios, ratios[1:])) and notched:
            lines.append("- At the end of each unnotched run the damaged zone on the bottom face is %s horizons long: it grows in" % zones)
            lines.append("  horizons as they shrink, so the damage along the tension face spreads instead of localising in one band.")
            lines.append("  At the notch tips it is %.1f to %.1f horizons long." % (min(notched), max(notched)))
        else:
            lines.append("- At the end of each unnotched run the damaged zone on the bottom face is %s horizons long." % zones)
    lines.append("")


def variants_report(res, lines):
    """What moves the unnotched beam's peak under refinement: its scene with one ingredient changed."""
    rows = [(name, extra) for name, extra in [("shipped scene", [])] + list(VARIANTS.items()) if spacings(res, "un", extra)]
    if len(rows) < 2:
        return
    lines += ["## The unnotched beam with one ingredient changed", "",
              "Peak (N) by spacing, and its change between the two finest spacings run.", "",
              "| scene | " + " | ".join("dx = %g mm" % (1e3 * dx) for dx in VARIANT_SPACINGS) + " | change |",
              "|---|" + "---|" * (len(VARIANT_SPACINGS) + 1)]
    for name, extra in rows:
        peaks = [res[key("un", dx, extra)]["peak_N"] if dx in spacings(res, "un", extra) else None for dx in VARIANT_SPACINGS]
        done = [p for p in peaks if p]
        change = "%+.1f %%" % (100 * (done[-1] / done[-2] - 1)) if len(done) >= 2 else "-"
        lines.append("| %s | %s | %s |" % (name, " | ".join("%.0f" % p if p else "-" for p in peaks), change))
    lines.append("")


def fixed_horizon_report(res, lines):
    """The horizon held while the spacing halves, under both calibrations."""
    fixed = [(b, cal, coarse, res[key(b, coarse, extra)], res[key(b, fine, FIXED_HORIZON + extra)]) for b in BEAMS for cal, extra in CALIBRATIONS.items()
             for coarse, fine in FIXED_PAIRS if passed_peak(res.get(key(b, fine, FIXED_HORIZON + extra))) and passed_peak(res.get(key(b, coarse, extra)))]
    if fixed:
        lines += ["## The horizon held while the spacing halves", "",
                  "A scene at the coarse spacing (horizon pi dx) against half that spacing with the same horizon (m = 2 pi): the",
                  "horizon as a length of the material, the lattice refined inside it. Under the continuum calibration (the shipped",
                  "scenes') the lattice's bulk stiffness depends on m; under the stencil calibration it is E at every m.", "",
                  "| beam | calibration | dx (mm) | horizon (mm) | peak at dx, m = pi (N) | peak at dx / 2, m = 2 pi (N) | change | bonds at dx / 2 | CPU (s) | peak memory (GB) |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        lines += ["| %s | %s | %g | %.1f | %.0f | %.0f | %+.1f %% | %d | %.0f | %.1f |" % (
            BEAMS[b], cal, 1e3 * coarse, 1e3 * a["horizon_m"], a["peak_N"], c["peak_N"], 100 * (c["peak_N"] / a["peak_N"] - 1), c["bonds"], c["cpu_s"], c["peak_rss_bytes"] / 1e9)
            for b, cal, coarse, a, c in fixed]
        lines.append("")


def implex_report(res, lines):
    """The beams by path following with IMPL-EX steps against the default path, spacing by spacing."""
    rows = [(b, dx, e) for b in BEAMS for dx in SPACINGS for e in IMPLEX_ERRORS if passed_peak(res.get(key(b, dx, implex(e))))]
    if not rows:
        return
    lines += ["## Path following with IMPL-EX steps", "",
              "The same scenes traced by path following with IMPL-EX steps from the first step (`%s ERROR`, ERROR the" % " ".join(implex(0)[:-1]),
              "damage error per step; the 3D D = 200 mm beams take 0.03), against the default path (displacement control, handing over where it finds no equilibrium;",
              "docs/arclength.md, \"The default path\") at the same spacing. 'Curves apart': RMS load difference over the CMOD",
              "range both reach, over the default path's peak. CPU: each run's own; runs shared the two cores.", "",
              "| beam | dx (mm) | damage error per step | peak, default path (N) | peak, IMPL-EX (N) | change | curves apart | steps | Newton | Krylov | CPU (s) | CPU, default path (s) | bytes per bond | end |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for b, dx, e in rows:
        r, d = res[key(b, dx, implex(e))], res.get(key(b, dx))
        known = passed_peak(d)
        end = "CMOD %.3f mm" % (1e3 * r["final_cmod_m"]) + ("" if r["status"].startswith("completed") else " (%s)" % (
            "stopped by its time limit" if r.get("timed_out") else r["status"]))
        lines.append("| %s | %g | %g | %s | %.0f | %s | %s | %d | %d | %d | %.0f | %s | %.0f | %s |" % (
            BEAMS[b], 1e3 * dx, e, "%.0f" % d["peak_N"] if known else "-", r["peak_N"], "%+.1f %%" % (100 * (r["peak_N"] / d["peak_N"] - 1)) if known else "-",
            "%.1f %%" % (100 * curve_difference(d, r)) if known else "-", r["steps"], r["newton_its"], r["ksp_its"], r["cpu_s"],
            "%.0f%s" % (d["cpu_s"], " (stopped by its time limit)" if d.get("timed_out") else "") if d else "-", r["peak_rss_bytes"] / r["bonds"], end))
    pairs = []
    for b in BEAMS:
        for e in IMPLEX_ERRORS:
            dxs = [dx for dx in SPACINGS if passed_peak(res.get(key(b, dx, implex(e))))]
            if len(dxs) >= 2:
                fine, coarse = res[key(b, dxs[-1], implex(e))], res[key(b, dxs[-2], implex(e))]
                pairs.append("%s at %g, %+.1f %% (%g to %g mm)" % (BEAMS[b], e, 100 * (fine["peak_N"] / coarse["peak_N"] - 1), 1e3 * dxs[-2], 1e3 * dxs[-1]))
    if pairs:
        lines += ["", "Peak change between the two finest spacings under IMPL-EX: %s." % "; ".join(pairs)]
    findings = []
    # the default path with finer displacement increments (--increments)
    for b in BEAMS:
        for dx in SPACINGS:
            d = res.get(key(b, dx))
            for n in INCREMENTS:
                f = res.get(key(b, dx, ["-pd_steps", str(n)]))
                if passed_peak(f) and passed_peak(d):
                    findings.append("- %s at dx = %g mm, the default path with %d displacement increments instead of the scene's: peak %.0f N "
                                    "(%+.1f %% against its own), %d Newton iterations, %.0f s." % (
                                        BEAMS[b].capitalize(), 1e3 * dx, n, f["peak_N"], 100 * (f["peak_N"] / d["peak_N"] - 1), f["newton_its"],
                                        f["cpu_s"]))
    # the explicit path's peak of the same scene, where the accuracy-cost study has one (benchmarks/accuracy_cost.py)
    explicit = load_results(os.path.join(RESULTS_DIR, "accuracy_cost.json"))
    for b in BEAMS:
        for dx in SPACINGS:
            e_run = explicit.get("gregoire_d50_%s/dx=%g/m=%.3f/explicit" % (b, dx, math.pi))
            errs = [e for e in IMPLEX_ERRORS if passed_peak(res.get(key(b, dx, implex(e))))]
            d = res.get(key(b, dx))
            if e_run and errs and passed_peak(d):
                pe, fine = e_run["peak"], res[key(b, dx, implex(min(errs)))]["peak_N"]
                findings.append("- %s at dx = %g mm against the explicit path's peak, %.0f N (`accuracy_cost.json`, a load ramp of %s s): the "
                                "default path %+.1f %%, IMPL-EX at %g %+.1f %%." % (
                                    BEAMS[b].capitalize(), 1e3 * dx, pe, e_run["options"][e_run["options"].index("-pd_ramp_time") + 1],
                                    100 * (d["peak_N"] / pe - 1), min(errs), 100 * (fine / pe - 1)))
    # where the default path did not finish: how far IMPL-EX got, and in what time
    for b, dx, e in rows:
        r, d = res[key(b, dx, implex(e))], res.get(key(b, dx))
        if d and d.get("timed_out"):
            findings.append("- %s at dx = %g mm: the default path stopped by its time limit at CMOD %.3f mm after %.0f s of CPU; IMPL-EX at %g "
                            "reached CMOD %.3f mm in %.0f s (%d steps, %d Newton iterations%s)." % (
                                BEAMS[b].capitalize(), 1e3 * dx, 1e3 * d["final_cmod_m"], d["cpu_s"], e, 1e3 * r["final_cmod_m"], r["cpu_s"],
                                r["steps"], r["newton_its"], "" if r["status"].startswith("completed") else "; stopped by its time limit"))
    # how the peak approaches the default path's as the damage error per step falls
    for b in BEAMS:
        for dx in SPACINGS:
            errs = [e for e in IMPLEX_ERRORS if passed_peak(res.get(key(b, dx, implex(e))))]
            d = res.get(key(b, dx))
            if len(errs) >= 2 and passed_peak(d):
                findings.append("- %s at dx = %g mm, peak against the default path's by damage error per step: %s." % (
                    BEAMS[b].capitalize(), 1e3 * dx, ", ".join("%+.1f %% at %g (%.0f s)" % (
                        100 * (res[key(b, dx, implex(e))]["peak_N"] / d["peak_N"] - 1), e, res[key(b, dx, implex(e))]["cpu_s"]) for e in errs)))
    if findings:
        lines += ["", "Findings:", ""] + findings
    lines.append("")


def plot(res):
    plt = pyplot()
    fig, axes = plt.subplots(1, 4, figsize=(19, 4.5))
    styles = {0.01: (0, (1, 3)), 0.005: ":", 0.0025: "--", 0.00125: "-"}
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
        line, = ax.plot([1e3 * dx for dx in dxs], [res[key(beam, dx)]["peak_N"] for dx in dxs], "o-", label=name)
        mean, low, high = experiment_peaks(beam)
        if mean:
            ax.axhspan(low, high, alpha=0.15, color=line.get_color())
    ax.set_xscale("log")
    ax.set_xlabel("dx (mm)")
    ax.set_ylabel("peak load (N)")
    ax.set_title("peaks by spacing (bands: experimental envelopes)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    save_figure(fig, "softening_convergence.png", dpi=100)


def run_missing(a, extra):
    """Runs each beam of --beams at each spacing of --dx with the extra options, unless stored (or --force)."""
    for dx in a.dx:
        for beam in a.beams:
            if key(beam, dx, extra) in load_results(DATA) and not a.force:
                continue
            r = measure(beam, dx, a.timeout, extra)
            print(key(beam, dx, extra), {k: v for k, v in r.items() if k != "curve"}, flush=True)
            store_result(DATA, key(beam, dx, extra), r)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, nargs="+", default=SPACINGS)
    ap.add_argument("--beams", nargs="+", default=list(BEAMS), choices=list(BEAMS))
    ap.add_argument("--variants", action="store_true", help="the unnotched beam with one ingredient changed (VARIANTS), dx = 10 to 2.5 mm")
    ap.add_argument("--fixed-horizon", action="store_true", help="the beams at half a spacing with its horizon (m = 2 pi), both calibrations")
    ap.add_argument("--coarse", type=float, nargs="+", default=[c for c, _ in FIXED_PAIRS], help="with --fixed-horizon: the coarse spacings of the pairs run")
    ap.add_argument("--implex", type=float, nargs="*", help="the beams by path following with IMPL-EX steps at these damage errors per step "
                    "(0.03 without a value) and the spacings of --dx")
    ap.add_argument("--increments", type=int, choices=INCREMENTS, help="the default path with this many displacement increments, at the "
                    "spacings of --dx")
    ap.add_argument("--timeout", type=int, default=7200, help="seconds before a run is stopped (SIGTERM keeps its curve)")
    ap.add_argument("--force", action="store_true", help="run again what is already stored")
    ap.add_argument("--report", action="store_true")
    a = ap.parse_args()
    a.pairs = [p for p in FIXED_PAIRS if p[0] in a.coarse]
    if a.implex == []:
        a.implex = [0.03]
    if a.fixed_horizon and not a.report:
        for beam in a.beams:
            for extra in CALIBRATIONS.values():
                for dx, more in [(c, []) for c, _ in a.pairs] + [(f, FIXED_HORIZON) for _, f in a.pairs]:
                    if key(beam, dx, more + extra) not in load_results(DATA):
                        store_result(DATA, key(beam, dx, more + extra), measure(beam, dx, a.timeout, more + extra))
    elif a.increments and not a.report:
        run_missing(a, ["-pd_steps", str(a.increments)])
    elif a.implex and not a.report:
        for error in a.implex:
            run_missing(a, implex(error))
    elif a.variants and not a.report:
        for extra in VARIANTS.values():
            for dx in VARIANT_SPACINGS:
                if key("un", dx, extra) not in load_results(DATA):
                    store_result(DATA, key("un", dx, extra), measure("un", dx, a.timeout, extra))
    elif not a.report:
        run_missing(a, [])
    report(load_results(DATA))


if __name__ == "__main__":
    main()
