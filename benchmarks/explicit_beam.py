#!/usr/bin/python3
"""Implicit against explicit on the 3D Gregoire beams: each beam's default path-following run (IMPL-EX with
damage error 0.03 per step, as in benchmarks/size_effect.py) and its explicit run, one after the other in
one invocation on the same number of ranks, traced to the same CMOD (where the implicit run reached 10 % of
its peak), so that the wall-time ratio is taken on one machine state.

The explicit run cannot afford the ramp search of benchmarks/explicit_ramp.py on a large beam (each trial
is one full run). Its ramp is the shortest ramp that search found on the D = 50 mm half-notched beam at the
same spacing (docs/benchmarks/explicit_ramp.json) scaled by geometric similarity: lengths and times times
D/50, the wave speed unchanged, so that the load point's velocity at equal load factor and the ramp's
length over the beam's first period are the D = 50 mm run's (the scenes' load-point displacements scale
with D too). Only fracture is not similar (the size effect moves the peak to a smaller load factor), so
the explicit curve is checked against the implicit one as in explicit_ramp.py (peak, and RMS load difference over the common CMOD range, over the implicit peak), so
that the table says whether the explicit run is of equal accuracy. Writes docs/benchmarks/explicit_beam.json
and explicit_beam.md.

With --control cmod the explicit run is under CMOD control (-pd_explicit_cmod, docs/explicit.md): its gauge
opens along the ramp to a twentieth past the CMOD the implicit run ended at, a servo drives the load factor,
and the ramp is the shortest found under CMOD control on the D = 50 mm unnotched beam (explicit_ramp.py
--beam un --control cmod) times D/50. Such rows are kept beside the load-point ones (key suffix
/control=cmod).

--ramp T takes the explicit ramp T (s) instead of the scaled search's (recorded in the row: column 'ramp (ms)'
and 'reference_ramp_s' in the JSON), where the scaled ramp's run would not fit in the time at hand.

Usage: benchmarks/explicit_beam.py [--sizes 200] [--kinds hn fn un] [--dx 5e-3] [--ranks 2] [--control load|cmod] [--ramp T]
       [--timeout 10800] [--report]
"""
import argparse
import csv
import json
import os
import tempfile

from common import EXE, OUT, RESULTS_DIR, ROOT, curve_difference, load_results, run_timed, store_result, pyplot, save_figure
import size_effect

JSON = os.path.join(RESULTS_DIR, "explicit_beam.json")
IMPLEX = 0.03


CMOD_PAST = 1.05  # under CMOD control the gauge's ramp ends this far past the implicit run's last CMOD
CONTROLS = {"load": "load point", "cmod": "CMOD"}


def reference_ramp(dx, control):
    """The shortest ramp (s) within 1 % on the D = 50 mm beams at this spacing: the half-notched beam's under
    load-point control, the unnotched beam's under CMOD control."""
    return load_results(os.path.join(RESULTS_DIR, "explicit_ramp.json"))["dx_%g" % dx if control == "load" else "un cmod dx_%g" % dx][
        "shortest_ramp_s"]


def run(cmd, timeout):
    out = tempfile.mkdtemp(prefix="explicit_beam_")
    cmd = cmd + ["-pd_output_dir", out]
    with open(os.path.join(out, "log.txt"), "w") as log:
        code, wall, _, timed_out = run_timed(cmd, timeout, log)
    s = json.load(open(os.path.join(out, "summary.json")))
    rows = list(csv.DictReader(open(os.path.join(out, "curve.csv"))))
    return {"command": " ".join(cmd[cmd.index(EXE) + 1:-2]).replace(ROOT + os.sep, ""), "exit": code, "wall_s": wall, "timed_out": timed_out,
            "status": s["status"], "peak_N": s.get("peak_load_N"), "steps": s.get("steps"), "newton_its": s.get("newton_its"),
            "ksp_its": s.get("ksp_its"), "nodes": s["nodes"], "bonds": s["bonds"], "memory_MB": s["memory"]["peak_rss_bytes"] / 2**20,
            "explicit": s.get("explicit"), "curve": [[float(r["cmod_m"]), float(r["load_N"])] for r in rows]}


def study(D, kind, dx, ranks, timeout, control, ramp_given=None):
    mpi = ["mpiexec", "-n", str(ranks)] if ranks > 1 else []
    implicit = run(mpi + [EXE] + size_effect.scene_args(D, kind, dx, IMPLEX), timeout)
    cmod_end = implicit["curve"][-1][0]
    scene = os.path.join(ROOT, "options", "gregoire_d%d_%s.opts" % (D, kind))
    ramp50 = reference_ramp(dx, control)
    ramp = ramp_given or ramp50 * D / 50
    servo = ["-pd_explicit_cmod", repr(CMOD_PAST * cmod_end)] if control == "cmod" else []
    explicit = run(mpi + [EXE, "-options_file", scene, "-pd_dx", repr(dx), "-pd_mode", "explicit", "-pd_ramp_time", repr(ramp),
                          "-pd_stop_cmod", repr(cmod_end)] + servo, timeout)
    peak = max(l for _, l in implicit["curve"])
    explicit["peak_diff"] = explicit["peak_N"] / peak - 1 if explicit["peak_N"] else None
    explicit["rms_diff"] = curve_difference(implicit, explicit)
    return {"D_mm": D, "kind": kind, "dx": dx, "ranks": ranks, "control": control, "ramp_s": ramp, "reference_ramp_s": ramp50, "cmod_end_m": cmod_end,
            "implicit": implicit, "explicit": explicit}


def given(r):
    """A note where the row's ramp is not the D = 50 mm search's scaled by D/50 (--ramp)."""
    scaled = r["reference_ramp_s"] * r["D_mm"] / 50
    return "" if abs(r["ramp_s"] / scaled - 1) < 1e-9 else " (ramp given: %.2g of the scaled search's)" % (r["ramp_s"] / scaled)


def report(res):
    plt = pyplot()
    lines = ["# Implicit against explicit on the 3D Gregoire beams", "",
             "Written by `benchmarks/explicit_beam.py` from `explicit_beam.json`. Each beam's default path-following run",
             "(IMPL-EX, damage error %g per step) and its explicit run, one after the other in one invocation, on the same ranks," % IMPLEX,
             "both to the CMOD at which the implicit run reached 10 % of its peak. The explicit ramp is the shortest ramp within",
             "1 % on the D = 50 mm half-notched beam at the same spacing (`explicit_ramp.md`) times D/50 (geometric similarity:",
             "the same load-point velocity at equal load factor, the same ramp over the beam's first period); its step is the default 0.9 of",
             "2/sqrt(lambda_max), lambda_max estimated by power iterations (docs/explicit.md). Peak and RMS differences are",
             "the explicit curve's against the implicit one, over the implicit peak; the ratio is of wall times.",
             "Column 'explicit control': the load point ramped (the scenes' control), or the CMOD gauge's opening ramped with a servo",
             "driving the load factor (`-pd_explicit_cmod`, docs/explicit.md), its ramp the shortest within 1 % under CMOD control on the",
             "D = 50 mm unnotched beam (`explicit_ramp.md`) times D/50.", "",
             "| D (mm) | beam | dx (mm) | ranks | nodes | bonds | implicit peak (N) | steps / Newton / KSP | implicit wall (s) | explicit control | "
             "ramp (ms) | dt (us) | time steps | explicit peak (N) | peak diff | RMS diff | explicit wall (s) | explicit / implicit |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    fig, ax = plt.subplots(figsize=(6, 4))
    for k in sorted(res):
        r = res[k]
        imp, exp = r["implicit"], r["explicit"]
        e = exp["explicit"] or {}
        control = r.get("control", "load")
        lines.append("| %d | %s | %g | %d | %d | %d | %.0f | %s / %s / %s | %.0f | %s | %.1f | %.3f | %s | %.0f | %+.2f %% | %.2f %% | %.0f | %.1f |" % (
            r["D_mm"], size_effect.KINDS[r["kind"]], 1e3 * r["dx"], r["ranks"], imp["nodes"], imp["bonds"], imp["peak_N"], imp["steps"],
            imp["newton_its"], imp["ksp_its"], imp["wall_s"], CONTROLS[control] + given(r), 1e3 * r["ramp_s"], 1e6 * e.get("dt_s", 0), e.get("time_steps"), exp["peak_N"] or 0,
            100 * (exp["peak_diff"] or 0), 100 * exp["rms_diff"], exp["wall_s"], exp["wall_s"] / imp["wall_s"]))
        for run, style in ((imp, "-"), (exp, "--" if control == "load" else ":")):
            c = list(zip(*run["curve"]))
            ax.plot([1e3 * x for x in c[0]], [1e-3 * y for y in c[1]], style,
                    label="D %d %s %s" % (r["D_mm"], r["kind"], "implicit" if run is imp else "explicit, %s" % CONTROLS[control]))
    lines += ["", "Statuses: " + "; ".join("%s implicit '%s', explicit '%s'" % (k, res[k]["implicit"]["status"], res[k]["explicit"]["status"])
                                            for k in sorted(res)) + ".", ""]
    ax.set_xlabel("CMOD (mm)")
    ax.set_ylabel("load (kN)")
    ax.legend(fontsize=7)
    save_figure(fig, "explicit_beam.png", dpi=100)
    lines += ["![load against CMOD](explicit_beam.png)", ""]
    open(os.path.join(OUT, "explicit_beam.md"), "w").write("\n".join(lines))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", type=int, nargs="+", default=[200])
    ap.add_argument("--kinds", nargs="+", default=["hn", "fn", "un"])
    ap.add_argument("--dx", type=float, default=5e-3)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--control", choices=list(CONTROLS), default="load", help="cmod: the explicit run under CMOD control")
    ap.add_argument("--ramp", type=float, help="explicit ramp (s) instead of the D = 50 mm search's scaled by D/50")
    ap.add_argument("--timeout", type=float, default=10800)
    ap.add_argument("--report", action="store_true")
    a = ap.parse_args()
    res = load_results(JSON)
    if not a.report:
        for D in a.sizes:
            for kind in a.kinds:
                key = "D=%d/%s/dx=%g/ranks=%d" % (D, kind, a.dx, a.ranks) + ("/control=cmod" if a.control == "cmod" else "")
                res = store_result(JSON, key, study(D, kind, a.dx, a.ranks, a.timeout, a.control, a.ramp))
                report(res)
    report(res)


if __name__ == "__main__":
    main()
