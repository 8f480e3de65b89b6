#!/usr/bin/python3
"""Gregoire et al. (2013) D = 50 mm beams traced to CMOD = 0.2 mm: laws, spacings, limiter and tangent.

Runs the three shipped scenes (unnotched, fifth-, half-notched) with each softening law at dx = 5 and
2.5 mm, and the half-notched beam at dx = 5 mm with limiter caps N = 1, 10, 100, none and with the
secant tangent. Each finished run is stored in docs/benchmarks/gregoire.json, so an interrupted study
resumes where it stopped; docs/benchmarks/gregoire.md (tables) and gregoire.png (load-CMOD curves
with the experimental envelopes) are rewritten from that file after every run.

Usage: benchmarks/gregoire.py [--dx 5e-3] [--beams hn,un] [--laws nonlinear] [--studies] [--ranks 1]
       [--timeout 3600] [--results FILE] [--report]     (--report only rewrites the tables and plot)
"""
import argparse
import os

from common import RESULTS_DIR, experiment_peaks, load_results, plot_gregoire_experiment, run_scene, store_result, pyplot, save_figure, write_lines

RESULTS = os.path.join(RESULTS_DIR, "gregoire.json")

BEAMS = {"un": "unnotched", "fn": "fifth-notched", "hn": "half-notched"}
LAWS = ["linear", "bilinear", "trilinear", "nonlinear"]
SPACINGS = [5e-3, 2.5e-3]
# experimental mean peak and min-max (N), Gregoire et al. (2013) as digitised in data/ (FN: thesis Fig. 5.9)
EXPERIMENT = {beam: experiment_peaks(beam) for beam in BEAMS}
# Hobbs thesis, non-linear law, dx = 5 mm, explicit: with / without the critical-stretch correction (Sec. 5.5.5)
THESIS = {"un": (4748, 5336), "fn": (3097, 3320), "hn": (1280, 1362)}


def key(beam, law, dx, extra):
    return "%s/%s/dx=%g/%s" % (beam, law, dx, " ".join(extra) or "default")


def run_one(beam, law, dx, extra, ranks, timeout):
    run = run_scene("gregoire_d50_%s" % beam, ["-pd_law", law, "-pd_dx", str(dx)] + extra, timeout, "pdgregoire_", ranks)
    if run["timed_out"]:
        return {"status": "stopped after %d s" % timeout, "wall": timeout}
    r = {"wall": run["wall"], "cpu": run["cpu"], "returncode": run["code"]}
    s, rows = run["summary"], run["rows"]
    if s is None or rows is None:
        r["status"] = "failed: " + (open(os.path.join(run["out"], "log.txt")).read().strip().splitlines() or ["?"])[-1][:100]
        return r
    r.update(status=s["status"], converged=s["converged"], steps=s["steps"], newton=s["newton_its"], ksp=s["ksp_its"],
             peak=s["peak_load_N"], final_load=rows[-1]["load_N"], final_cmod=rows[-1]["cmod_m"],
             broken=s["broken_bonds"], max_events=s["max_bonds_per_iteration"], solver=s["solver"], nodes=s["nodes"],
             bonds=s["bonds"], timings=s["timings"], law=s["law"],
             curve=[[x["cmod_m"], x["load_N"]] for x in rows])
    return r


def load_all():
    """Every results file (gregoire*.json): runs on different spacings can go to different files, in parallel."""
    res = {}
    for name in sorted(os.listdir(RESULTS_DIR)):
        if name.startswith("gregoire") and name.endswith(".json"):
            res.update(load_results(os.path.join(RESULTS_DIR, name)))
    return res


def fmt(v, f="%.0f"):
    return "-" if v is None else f % v


def row(k, r, beam):
    peak = r.get("peak")
    mean = EXPERIMENT[beam][0]
    err = "%+.0f %%" % (100 * (peak / mean - 1)) if peak and mean else "-"
    thesis = "%+.1f %%" % (100 * (peak / THESIS[beam][0] - 1)) if peak else "-"
    ratio = "%.0f %%" % abs(100 * r["final_load"] / peak) if peak and r.get("final_cmod", 0) >= 2e-4 else "-"
    return "| %s | %s | %s | %s | %s | %s | %s / %s | %s | %s | %s |" % (
        k, fmt(peak), err, thesis, ratio, r["status"][:40], fmt(r.get("steps"), "%d"), fmt(r.get("newton"), "%d"), fmt(r.get("ksp"), "%d"),
        fmt(r.get("max_events"), "%d"), fmt(r.get("wall"), "%.0f s"))


def report(res):
    lines = ["# Gregoire D = 50 mm beams: softening laws, spacing, limiter and tangent", "",
             "Written by `benchmarks/gregoire.py` from `gregoire.json` (one entry per finished run). Each run traces",
             "load against CMOD under load-point displacement control until CMOD = 0.2 mm (shipped scenes: surface",
             "and critical-stretch correction on, consistent tangent, full Newton steps, limiter cap by bond count:",
             "10 or 11 at dx = 5 mm, 99 at 2.5 mm; one rank unless stated).",
             "Experiment (data/, peak of the mean curve and of its envelopes): UN %s N (%s to %s), HN %s N (%s to %s). Thesis: Hobbs, explicit," % tuple(
                 "{:,.0f}".format(v) for v in EXPERIMENT["un"] + EXPERIMENT["hn"]),
             "non-linear law, dx = 5 mm, with critical-stretch correction UN 4,748, FN 3,097, HN 1,280 N.", "",
             "Columns: peak load; error against the experimental mean; difference from the thesis's corrected",
             "non-linear result; load at CMOD 0.2 mm over peak; status; steps / Newton its; KSP its; largest number",
             "of bond events in one Newton iteration; wall time (2-core machine, runs may share it).", ""]
    for beam in BEAMS:
        ks = sorted(k for k in res if k.startswith(beam + "/"))
        if not ks:
            continue
        lines += ["## %s" % BEAMS[beam], "", "| run | peak (N) | vs exp. | vs thesis | end/peak | status | steps / Newton | KSP | max events | wall |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        lines += [row(k[len(beam) + 1:], res[k], beam) for k in ks]
        lines.append("")
    write_lines("gregoire.md", lines)
    plot(res)


def plot(res):
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for ax, beam in zip(axes, BEAMS):
        plot_gregoire_experiment(ax, beam)
        for k in sorted(res):
            r = res[k]
            if not k.startswith(beam + "/") or "curve" not in r or not k.endswith("/default"):
                continue
            c = r["curve"]
            ax.plot([1e3 * x[0] for x in c], [x[1] for x in c], lw=1.2, ls="-" if "dx=0.005" in k else "--",
                    label=k[len(beam) + 1:].replace("/default", ""))
        ax.set_title("%s (dashed: dx = 2.5 mm)" % BEAMS[beam])
        ax.set_xlabel("CMOD (mm)")
        ax.set_ylabel("load (N)")
        ax.set_xlim(0, 0.21)
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    save_figure(fig, "gregoire.png", dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", default=",".join("%g" % d for d in SPACINGS))
    ap.add_argument("--beams", default="un,fn,hn")
    ap.add_argument("--laws", default=",".join(LAWS))
    ap.add_argument("--studies", action="store_true", help="also the limiter and tangent study (half-notched, dx = 5 mm)")
    ap.add_argument("--only-studies", action="store_true")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--timeout", type=int, default=3600)
    ap.add_argument("--report", action="store_true")
    ap.add_argument("--results", default=RESULTS, help="results file (docs/benchmarks/gregoire*.json are merged in the report)")
    a = ap.parse_args()
    res = load_results(a.results)
    jobs = []
    if not a.only_studies:
        for dx in [float(x) for x in a.dx.split(",")]:
            for beam in a.beams.split(","):
                for law in a.laws.split(","):
                    jobs.append((beam, law, dx, []))
    if a.studies or a.only_studies:
        for n in ("1", "100", "0"):
            jobs.append(("hn", "nonlinear", 5e-3, ["-pd_limiter_max_bonds", n]))
        jobs.append(("hn", "nonlinear", 5e-3, ["-pd_tangent", "secant"]))
        jobs.append(("hn", "nonlinear", 5e-3, ["-pd_sc_notch_surface"]))
    for beam, law, dx, extra in ([] if a.report else jobs):
        k = key(beam, law, dx, extra + (["ranks=%d" % a.ranks] if a.ranks > 1 else []))
        if k in res:
            continue
        print("running", k, flush=True)
        res = store_result(a.results, k, run_one(beam, law, dx, extra, a.ranks, a.timeout))
        print("  ", res[k]["status"], "peak", res[k].get("peak"), "wall %.0f s" % res[k].get("wall", 0), flush=True)
        report(load_all())
    report(load_all())


if __name__ == "__main__":
    main()
