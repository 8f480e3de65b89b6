#!/usr/bin/python3
"""What accuracy costs in time: implicit and explicit paths on the same points.

Points: the elastic cantilever against Timoshenko (tip deflection) and the Gregoire D = 50 mm beams
against experiment (peak load and load-CMOD curve, unnotched and half-notched) at dx = 20, 10, 5, 2.5 mm
with horizon ratio pi, and horizon ratios 2, 3, 4 at the spacings where both paths fit the time budget.
Each run records error, CPU and wall time, peak memory (largest resident set), nodes, bonds, and
Newton/KSP iterations or time steps, and an explicit run how its time step was chosen. Both paths run
with today's defaults; the explicit one is the tuned one (EXPLICIT, tuned_ramp below).

Every finished run is kept in docs/benchmarks/accuracy_cost.json (an interrupted study resumes);
docs/benchmarks/accuracy_cost.md and accuracy_cost.png are rewritten from it after each run.

Usage: benchmarks/accuracy_cost.py [--only implicit|explicit] [--timeout 3600] [--keys PREFIXES] [--force] [--report]
       PDIMPLICIT=/path/to/binary to time a copy while the build directory changes.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import tempfile

from common import EXE, RESULTS_DIR, ROOT, experiment as experiment_rows, load_results, run_timed, store_result, pyplot, save_figure, write_lines

RESULTS = os.path.join(RESULTS_DIR, "accuracy_cost.json")
PI = "3.141592653589793"

# The tuned explicit path: its default step (a safety factor on the stable step from the largest eigenvalue
# of M^-1 K, docs/explicit.md) and, on the Gregoire beams, the shortest load ramp whose half-notched curve
# stays within 1 % of the implicit one (benchmarks/explicit_ramp.py, explicit_ramp.json) at that spacing; the
# unnotched beam has the same geometry and bending periods and takes the same ramp. Where explicit_ramp.py
# did not run (dx = 20 mm) the ramp is the coarsest spacing's it found. The cantilever is loaded over
# 20,000 steps and held 50 ms with damping near critical for its first mode until at rest.
RAMP_STUDY = os.path.join(RESULTS_DIR, "explicit_ramp.json")
EXPLICIT = {"cantilever": ["-pd_mode", "explicit", "-pd_hold_time", "0.05", "-pd_damping", "1e6"]}
DATA = {"gregoire_d50_hn": "gregoire2013_d50_hn_load_cmod.csv", "gregoire_d50_un": "gregoire2013_d50_un_load_cmod.csv"}


def tuned_ramp(dx):
    """The shortest passing ramp of explicit_ramp.json at dx (or at its coarsest spacing)."""
    study = load_results(RAMP_STUDY)
    spacings = sorted((v["dx"], v) for v in study.values())
    entry = next((v for d, v in spacings if abs(d - dx) < 1e-9), spacings[-1][1])
    return min(r["ramp_s"] for r in entry["explicit"].values() if r["passes"])


def explicit_options(scene, dx):
    if scene in EXPLICIT:
        return EXPLICIT[scene]
    return ["-pd_mode", "explicit", "-pd_ramp_time", "%.6g" % tuned_ramp(dx)]


# (scene, dx, horizon ratio, paths): cheapest first, so a partial study still covers every axis
POINTS = []
for sc in ("cantilever", "gregoire_d50_hn", "gregoire_d50_un"):
    for dx in (0.02, 0.01):
        for m in ("2", "3", PI, "4"):
            POINTS.append((sc, dx, m, ("implicit", "explicit")))
POINTS += [("gregoire_d50_hn", 0.005, m, ("implicit", "explicit")) for m in ("2", "3", PI, "4")]
POINTS += [("gregoire_d50_un", 0.005, PI, ("implicit", "explicit"))]
POINTS += [("cantilever", 0.005, m, ("implicit",)) for m in ("2", "3", PI, "4")]
POINTS += [("gregoire_d50_hn", 0.0025, PI, ("explicit", "implicit"))]
POINTS += [("cantilever", 0.0025, PI, ("implicit",)), ("gregoire_d50_un", 0.0025, PI, ("explicit", "implicit"))]


def key(scene, dx, m, path):
    return "%s/dx=%g/m=%.4g/%s" % (scene, dx, float(m), path)


def timoshenko(P=1e4, L=1.0, E=30e9, b=0.1, h=0.1, nu=0.25, k=5.0 / 6.0):
    I = b * h ** 3 / 12
    G = E / (2 * (1 + nu))
    return P * L ** 3 / (3 * E * I) + P * L / (k * G * b * h)


def experiment(scene):
    return [(1e-3 * r[0], 1e3 * r[1]) for r in experiment_rows(DATA[scene])]


def interp(x, xs, ys):
    if x <= xs[0]:
        return ys[0]
    for k in range(1, len(xs)):
        if xs[k] >= x:
            t = (x - xs[k - 1]) / (xs[k] - xs[k - 1])
            return ys[k - 1] + t * (ys[k] - ys[k - 1])
    return None


def curve_error(curve, ref, cmod_max=2e-4):
    """RMS over the reference points up to cmod_max (and the run's last CMOD) of the load difference,
    over the reference peak."""
    xs, ys = [c[0] for c in curve], [c[1] for c in curve]
    peak = max(p for _, p in ref)
    d = [interp(x, xs, ys) - p for x, p in ref if x <= cmod_max and x <= xs[-1]]
    d = [v for v in d if v is not None]
    return math.sqrt(sum(v * v for v in d) / len(d)) / peak if d else None


def run_one(scene, dx, m, path, timeout):
    out = tempfile.mkdtemp(prefix="pdcost_")
    opts = ["-pd_dx", str(dx), "-pd_horizon_ratio", m] + (explicit_options(scene, dx) if path == "explicit" else [])
    cmd = [EXE, "-options_file", os.path.join(ROOT, "options", scene + ".opts"), "-pd_output_dir", out] + opts
    errf = tempfile.TemporaryFile(mode="w+")
    code, wall, cpu, timed_out = run_timed(cmd, timeout, subprocess.DEVNULL, errf)
    errf.seek(0)
    err = errf.read()
    r = {"wall": wall, "cpu": cpu, "returncode": code, "options": opts}
    try:
        s = json.load(open(os.path.join(out, "summary.json")))
        rows = list(csv.DictReader(open(os.path.join(out, "curve.csv"))))
    except (OSError, ValueError):
        r["status"] = ("stopped after %d s" % timeout) if timed_out else "failed: " + (err.strip().splitlines() or ["?"])[-1][:100]
        return r
    # peak resident set as pdimplicit measures it (VmHWM, summed over ranks): the rusage of a child forked
    # from this Python process would also count the interpreter's pages
    r.update(rss_mb=s["memory"]["peak_rss_bytes"] / 2 ** 20, status=s["status"], converged=s["converged"], nodes=s["nodes"], bonds=s["bonds"], newton=s.get("newton_its"),
             ksp=s.get("ksp_its"), peak=s["peak_load_N"], timings=s.get("timings"),
             curve=[[float(x["cmod_m"]) if x["cmod_m"] != "nan" else 0.0, float(x["load_N"]), float(x["disp_m"])] for x in rows])
    if "explicit" in s:
        # how the time step was chosen: the eigenvalue estimate, the stable step from it, the safety factor
        r["time_steps"] = s["explicit"]["time_steps"]
        r["dt"] = {k: s["explicit"][k] for k in ("eigenvalue_estimate_per_s2", "power_iterations", "dt_stable_s", "dt_safety", "dt_s")}
    return r


def errors(k, r, res):
    """Error against the physical reference, and against the finest implicit run of the same scene."""
    scene = k.split("/")[0]
    if "curve" not in r:
        return None, None, None
    if scene == "cantilever":
        ref = timoshenko()
        return abs(r["curve"][-1][2] - ref) / ref, None, None
    exp = experiment(scene)
    pexp = max(p for _, p in exp)
    finest = sorted((float(kk.split("/")[1][3:]), kk) for kk in res if kk.startswith(scene + "/") and kk.endswith("m=3.142/implicit")
                    and "curve" in res[kk])
    self_err = None
    if finest and finest[0][1] != k:
        c = res[finest[0][1]]["curve"]
        self_err = curve_error(r["curve"], [(x[0], x[1]) for x in c if x[0] <= 2e-4])
    return abs(r["peak"] - pexp) / pexp, curve_error(r["curve"], exp), self_err


def fmt(v, f):
    return "-" if v is None else f % v


def dx_of(k):
    return float(k.split("/")[1][3:])


def paths_compared(res, scene, dx):
    """The implicit and explicit runs of one beam and spacing (horizon ratio pi), the explicit peak's
    relative difference and the RMS curve difference over the implicit peak; None where either is missing."""
    ki, ke = key(scene, dx, PI, "implicit"), key(scene, dx, PI, "explicit")
    if not all(kk in res and "curve" in res[kk] and res[kk].get("cpu") for kk in (ki, ke)):
        return None
    ri, re_ = res[ki], res[ke]
    return ri, re_, re_["peak"] / ri["peak"] - 1, curve_error(re_["curve"], [(x[0], x[1]) for x in ri["curve"] if x[0] <= 2e-4])


def headline(res, scene, dx):
    """Explicit over implicit CPU time on one beam and spacing, and how far apart their curves are."""
    c = paths_compared(res, scene, dx)
    if not c:
        return None
    ri, re_, dp, d = c
    # equal accuracy: peak within 1 % and curves within 1 % RMS of the peak, as the ramp was chosen on the
    # half-notched beam (explicit_ramp.py allows a little more where the explicit path's slowest ramp differs)
    equal = abs(dp) <= 0.01 and d <= 0.0125
    return ("- %s, dx = %g mm: explicit %.1f s of CPU (%d time steps), implicit %.1f s (%s Newton, %s Krylov iterations): "
            "the explicit run takes %.2f times the implicit one; peaks %.1f and %.1f N (%+.2f %%), curves %.2f %% RMS of the peak apart%s." % (
                scene.replace("gregoire_d50_", "Gregoire "), 1e3 * dx, re_["cpu"], re_["time_steps"], ri["cpu"], ri["newton"], ri["ksp"],
                re_["cpu"] / ri["cpu"], re_["peak"], ri["peak"], 100 * dp, 100 * d,
                "" if equal else " (not equal accuracy%s)" % ("; here the implicit reference is the one off, its displacement increments stepping over "
                                                              "the top of the peak: docs/softening.md, \"The finest spacing by path following with IMPL-EX "
                                                              "steps\"" if scene.endswith("_un") else "")))


def report(res):
    lines = ["# Accuracy against cost: implicit and explicit paths", "",
             "Written by `benchmarks/accuracy_cost.py` from `accuracy_cost.json`, with today's defaults (the shipped scenes,",
             "default solvers on both paths). One rank per run, one run after the other in one invocation, on the",
             "2-core machine; CPU time is each run's own (wait4), which work on the other core does not inflate as",
             "it does the wall time, and the ratios below are of CPU times. Errors: cantilever, tip deflection against",
             "Timoshenko (%.4e m); Gregoire beams, peak load against the experimental mean and RMS load difference" % timoshenko(),
             "over the experimental mean curve up to CMOD 0.2 mm (over the experimental peak); 'vs finest' is the RMS",
             "curve difference to the finest implicit run of the same beam (horizon ratio pi), the discretisation",
             "error the model itself can remove. Memory: peak resident set (VmHWM) from `summary.json`.", "",
             "The explicit path is the tuned one: its default step, a safety factor on the stable step from the",
             "largest eigenvalue of M^-1 K (docs/explicit.md), and on the Gregoire beams the shortest load ramp whose",
             "half-notched curve stays within 1 % of the implicit one (`docs/benchmarks/explicit_ramp.md`) at that",
             "spacing, the unnotched beam taking the same ramp (same geometry, same bending periods) and dx = 20 mm",
             "that of the coarsest spacing studied there. The elastic cantilever is loaded over 20,000 steps and held",
             "50 ms with damping near critical for its first mode.", "",
             "| scene | dx (mm) | m | path | nodes | bonds | error | curve error | vs finest | CPU (s) | wall (s) | memory (MB) | Newton / KSP or steps | status |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    order = sorted(res, key=lambda s: (s.split("/")[0], -dx_of(s), s.split("/")[2], s.split("/")[3]))
    for k in order:
        r = res[k]
        scene, dxs, ms, path = k.split("/")
        e, ce, se = errors(k, r, res)
        its = ("%d steps" % r["time_steps"]) if r.get("time_steps") else ("%s / %s" % (r.get("newton"), r.get("ksp")) if r.get("newton") is not None else "-")
        lines.append("| %s | %g | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            scene.replace("gregoire_d50_", "Gregoire "), 1e3 * dx_of(k), ms[2:], path, fmt(r.get("nodes"), "%d"), fmt(r.get("bonds"), "%d"),
            fmt(e and 100 * e, "%.2f %%"), fmt(ce and 100 * ce, "%.1f %%"), fmt(se and 100 * se, "%.2f %%"),
            fmt(r.get("cpu"), "%.1f"), fmt(r.get("wall"), "%.1f"), fmt(r.get("rss_mb"), "%.0f"), its, r["status"][:40]))
    lines += ["", "## How each explicit run chose its time step", "",
              "From `summary.json`: the largest eigenvalue of M^-1 K estimated by power iterations on the assembled",
              "operator, the stable step 2 / sqrt(lambda_max) it gives, the safety factor and the step taken.", "",
              "| scene | dx (mm) | m | lambda_max (1/s^2) | power iterations | stable step (s) | safety | step (s) | ramp (s) | time steps |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for k in order:
        r = res[k]
        if "dt" not in r:
            continue
        d = r["dt"]
        ramp = r["options"][r["options"].index("-pd_ramp_time") + 1] if "-pd_ramp_time" in r["options"] else "-"
        lines.append("| %s | %g | %s | %.4e | %d | %.4e | %.2f | %.4e | %s | %d |" % (
            k.split("/")[0].replace("gregoire_d50_", "Gregoire "), 1e3 * dx_of(k), k.split("/")[2][2:], d["eigenvalue_estimate_per_s2"],
            d["power_iterations"], d["dt_stable_s"], d["dt_safety"], d["dt_s"], ramp, r["time_steps"]))
    lines += ["", "## Explicit over implicit CPU time, to CMOD 0.2 mm (m = pi)", ""]
    heads = [h for sc in ("gregoire_d50_hn", "gregoire_d50_un") for dx in (0.01, 0.005, 0.0025) for h in [headline(res, sc, dx)] if h]
    lines += heads or ["- not measured yet"]
    lines += ["", "## Elastic cantilever under refinement", "",
              "Tip deflection error against Timoshenko by spacing (implicit path), per horizon ratio:", ""]
    for m in ("2", "3", "3.142", "4"):
        pts = sorted(((dx_of(k), errors(k, r, res)[0]) for k, r in res.items()
                      if k.startswith("cantilever/") and k.endswith("/m=%s/implicit" % m) and "curve" in r), reverse=True)
        if pts:
            lines.append("- m = %s: %s." % (m.replace("3.142", "pi"), ", ".join("%+.2f %% at %g mm" % (100 * e, 1e3 * dx) for dx, e in pts)))
    write_lines("accuracy_cost.md", lines)
    plot(res)


def plot(res):
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for ax, scene, what in zip(axes, ("cantilever", "gregoire_d50_hn", "gregoire_d50_un"),
                               ("cantilever: tip deflection error vs Timoshenko", "half-notched: curve difference to the finest implicit run",
                                "unnotched: curve difference to the finest implicit run")):
        for path, mk in (("implicit", "o"), ("explicit", "s")):
            for m, col in (("m=2", "C0"), ("m=3", "C1"), ("m=3.142", "C2"), ("m=4", "C3")):
                pts = []
                for k, r in res.items():
                    if k.startswith(scene + "/") and k.endswith("/%s/%s" % (m, path)) and "curve" in r and r.get("converged"):
                        e = errors(k, r, res)[0 if scene == "cantilever" else 2]
                        if e is None:
                            continue
                        pts.append((r.get("cpu") or r["wall"], max(e, 1e-5), 1e3 * float(k.split("/")[1][3:])))
                pts.sort()
                if pts:
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], marker=mk, color=col, ls="-" if path == "implicit" else "--",
                            label="%s %s" % (path, m.replace("3.142", "pi")))
                    for p in pts:
                        ax.annotate("%g" % p[2], (p[0], p[1]), fontsize=6)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("CPU time (s), labels: dx (mm)")
        ax.set_ylabel("relative error")
        ax.set_title(what, fontsize=9)
        ax.grid(alpha=0.3, which="both")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=6)
    save_figure(fig, "accuracy_cost.png", dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", choices=("implicit", "explicit"))
    ap.add_argument("--timeout", type=int, default=3600)
    ap.add_argument("--report", action="store_true")
    ap.add_argument("--keys", default="", help="only the points whose key starts with one of these comma-separated prefixes")
    ap.add_argument("--force", action="store_true", help="run the selected points again even where results are stored")
    a = ap.parse_args()
    res = load_results(RESULTS)
    for scene, dx, m, paths in ([] if a.report else POINTS):
        for path in paths:
            k = key(scene, dx, m, path)
            if (k in res and not a.force) or (a.only and path != a.only) or (a.keys and not k.startswith(tuple(a.keys.split(",")))):
                continue
            print("running", k, flush=True)
            res = store_result(RESULTS, k, run_one(scene, dx, m, path, a.timeout))
            print("  %s peak %s CPU %s s" % (res[k]["status"], res[k].get("peak"), res[k].get("cpu")), flush=True)
            report(res)
    report(res)


if __name__ == "__main__":
    main()
