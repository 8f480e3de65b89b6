#!/usr/bin/python3
"""Size effect: the Gregoire et al. (2013) beams D = 50, 100, 200, 400 mm (unnotched, notch 0.2 D, notch
0.5 D) in 3D under path following (CMOD control), traced past the peak to 10 % of it.

Each finished run is stored in docs/benchmarks/size_effect.json, so an interrupted study resumes where it
stopped; docs/benchmarks/size_effect_table.md (tables) and size_effect.png (load-CMOD curves, nominal
strength against size) are rewritten from that file after every run. Runs go two at a time (one rank each).

A run longer than --timeout is stopped with SIGTERM and keeps what it traced, with a checkpoint (written
every 25 steps too). Its output stays in $PDSIZE_WORK (default /tmp/pdsize_work); --resume goes on from
the checkpoints of the selected runs that were interrupted, one leg of at most --timeout each, and the
stored result then covers all legs (CPU and wall time summed). --ranks N runs each leg under mpiexec on
N ranks (a leg may go on from a checkpoint on another number of ranks; it retraces the path). The stored
IMPL-EX runs were made with IMPL-EX steps in equilibrium to 1e-7 (before design note 50) or 1e-5 (before
note 63); a leg resumed now goes on at today's 1e-4 (summary.json's equilibrium_rtol says which).

Usage: benchmarks/size_effect.py [--jobs 2] [--ranks 1] [--dx 5e-3,10e-3] [--sizes 50,100,200,400] [--timeout 7200]
       [--dim 3|2] [--implex TOL] [--resume] [--report]     (--report only rewrites the tables and plot)
"""
import argparse
import concurrent.futures
import csv
import json
import os
import re
import sys
import tempfile

from common import EXE, RESULTS_DIR, ROOT, load_results, run_timed, store_result, pyplot, save_figure, write_lines

sys.path.insert(0, os.path.join(ROOT, "scripts"))
import gregoire_scenes  # noqa: E402 (scripts/ is a folder of scripts, not a package)

RESULTS = os.path.join(RESULTS_DIR, "size_effect.json")
KINDS = {"un": "unnotched", "fn": "notch 0.2 D", "hn": "notch 0.5 D"}
THICKNESS = 0.05
# Hobbs thesis Sec. 6.4 (explicit dynamics, dx = 5 mm): unnotched peak over experiment
THESIS_UN_ERROR = {100: "+10 %", 200: "+20 %", 400: "+40 %"}
# experimental peaks of the D = 50 mm beams (N), shared/data/README.md
EXPERIMENT_D50 = {"un": 4650, "hn": 979}


def scene_args_2d(D, kind, dx):
    """2D plane-stress versions of the same beams (scripts/gregoire_scenes.py), written to a scratch folder;
    at D = 50 mm the 2.5 mm wide supports and load are widened to catch a node line at dx = 5 mm."""
    folder = tempfile.mkdtemp(prefix="pdsize_scenes_")
    name = gregoire_scenes.scene(D / 1e3, kind, 2, dx, folder)
    args = ["-options_file", os.path.join(folder, name + ".opts"), "-pd_control", "arclength", "-pd_stop_fraction", "0.1"]
    if D == 50:
        args += ["-pd_region0_box", "0.0215,0,0.0285,0", "-pd_region1_box", "0.1465,0,0.1535,0", "-pd_region2_box", "0.084,0.05,0.091,0.05"]
    return args


def scene_args(D, kind, dx, implex=0):
    """The shipped scene with path following to 10 % of the peak; the D = 50 mm scenes stop at CMOD 0.2 mm
    under displacement control, so they are switched over, and the unnotched one gets the strength scatter
    the generated unnotched scenes carry. implex > 0: IMPL-EX steps with that damage error per step."""
    args = ["-options_file", os.path.join(ROOT, "options", "gregoire_d%d_%s.opts" % (D, kind)), "-pd_dx", str(dx), "-pd_control",
            "arclength", "-pd_stop_fraction", "0.1"]
    if implex > 0:
        # IMPL-EX has no kink for Newton to cycle on: none of the implicit path's remedies below are needed
        args += ["-pd_arclength_implex", str(implex)]
    elif D >= 200:
        # where damage localises in the large beams Newton cycles across bond kinks; cutting such steps early
        # and not growing the arc length right after a cut took the D = 200 mm half-notched beam over its
        # peak, where the defaults crept along (docs/arclength.md, "Where this is not enough"). Under CMOD
        # control single bonds reloading onto their envelope snap where the gauge does not hold them; the
        # dissipation constraint passed the load where CMOD control crept, and softening granted in 8 parts
        # the bonds that then snapped as they entered softening (docs/arclength.md, "Bonds at their kink").
        # The energy released per step starts tiny where the first bonds soften; capped at 4 times that, the
        # descending branch would take about a thousand steps, so it may grow to 50 times, and steps aim at
        # 10 Newton iterations (a step with 8 parts takes 2 to 3 limiter stages even when short). Past the peak
        # the tangent is indefinite and GAMG built on it broke GMRES down; built on the secant matrix it does not
        # (docs/solvers.md, "Indefinite tangents")
        args += ["-pd_arclength_halved_its", "8", "-pd_arclength_hold", "2", "-pd_arclength_type", "dissipation",
                 "-pd_limiter_sublevels", "8", "-pd_arclength_growth", "50", "-pd_arclength_target_its", "10",
                 "-pd_pc_matrix", "secant"]
    if D == 50:
        # the path may run past the scene's load factor 1; the first step (lambda_max / steps) stays the scene's
        args += ["-pd_stop_cmod", "0", "-pd_lambda_max", "4", "-pd_steps", "800"]
        if kind == "un":
            args += ["-pd_strength_scatter", "0.05"]
    return args


def key(D, kind, dx, dim=3, implex=0):
    return "D=%d/%s/dx=%g%s%s" % (D, kind, dx, "/2d" if dim == 2 else "", "/implex=%g" % implex if implex > 0 else "")


def parse_key(k):
    """The inverse of key(): (D in mm, kind, dx in m, dim, IMPL-EX error per step or 0)."""
    p = k.split("/")
    implex = [float(x[7:]) for x in p[3:] if x.startswith("implex=")]
    return int(p[0][2:]), p[1], float(p[2][3:]), 2 if "2d" in p[3:] else 3, implex[0] if implex else 0


def method(k):
    """How a run was made, for tables and legends: dimension, dx in mm, IMPL-EX."""
    D, kind, dx, d, implex = parse_key(k)
    return "%dD %g%s" % (d, 1e3 * dx, " IMPL-EX %g" % implex if implex else "")


def portable(command):
    """The command as a user's clone would run it: scene paths relative to the project, generated 2D scenes
    named by the script that writes them."""
    command = command.replace(ROOT + os.sep, "")
    return re.sub(r"\S*pdsize_scenes_[^/\s]*/", "<scripts/gregoire_scenes.py output>/", command)


WORK = os.environ.get("PDSIZE_WORK", "/tmp/pdsize_work")
PAST_PEAK_STEPS = 5
CHECKPOINT_EVERY = 25  # steps: at D = 200 mm in 3D about every 10 to 20 minutes, 100 MB each


def resumable(r):
    """A stored run that stopped on its time limit and left a checkpoint to go on from."""
    return r.get("status", "").startswith(("interrupted", "stopped after")) and os.path.exists(r.get("checkpoint", ""))


def run_one(D, kind, dx, timeout, dim=3, prev=None, implex=0, ranks=1):
    """One leg of a run on `ranks` MPI ranks: from the start, or from prev's checkpoint (prev: the stored
    result of the legs so far; a leg may use another number of ranks)."""
    os.makedirs(WORK, exist_ok=True)
    out = tempfile.mkdtemp(prefix=key(D, kind, dx, dim, implex).replace("/", "_").replace("=", "") + "_", dir=WORK)
    scene = scene_args(D, kind, dx, implex) if dim == 3 else scene_args_2d(D, kind, dx)
    if dim == 2 and implex > 0:
        scene += ["-pd_arclength_implex", str(implex)]
    # the progress display (one entry per step, on stderr) goes to log.txt, to follow a long run
    cmd = (["mpiexec", "-n", str(ranks)] if ranks > 1 else []) + [EXE] + scene + ["-pd_checkpoint_every", str(CHECKPOINT_EVERY)]
    if prev:
        cmd += ["-pd_restart", prev["checkpoint"]]
    cmd += ["-pd_progress", "-pd_output_dir", out]
    with open(os.path.join(out, "log.txt"), "w") as log:
        code, wall, cpu, timed_out = run_timed(cmd, timeout, log)
    legs = prev.get("legs", 1) + 1 if prev else 1
    # CPU time is summed over legs only where every leg measured it (not under mpiexec)
    known = cpu is not None and (not prev or prev.get("cpu") is not None)
    r = {"wall": wall + (prev["wall"] if prev else 0), "cpu": cpu + (prev.get("cpu", 0) if prev else 0) if known else None, "returncode": code,
         "command": portable(" ".join(scene)) + (" (mpiexec -n %d)" % ranks if ranks > 1 else ""), "legs": legs}
    if os.path.exists(os.path.join(out, "checkpoint.h5")):
        r["checkpoint"] = os.path.join(out, "checkpoint.h5")
    if not os.path.exists(os.path.join(out, "summary.json")):
        r["status"] = "stopped after %d s" % r["wall"] if timed_out else "failed: " + open(os.path.join(out, "log.txt")).read()[-100:]
        return r
    r.update(parse_run(out))
    return r


def parse_run(out):
    """What the tables and plots need from a finished run's output directory."""
    s = json.load(open(os.path.join(out, "summary.json")))
    rows = list(csv.DictReader(open(os.path.join(out, "curve.csv"))))
    load = [float(x["load_N"]) for x in rows]
    disp = [float(x["disp_m"]) for x in rows]
    k = max(range(len(load)), key=lambda i: load[i])
    return dict(status=s["status"], converged=s["converged"], steps=s["steps"], newton=s["newton_its"], ksp=s["ksp_its"], peak=s["peak_load_N"],
                nodes=s["nodes"], bonds=s["bonds"], memory_MB=s["memory"]["peak_rss_bytes"] / 2**20, final_fraction=load[-1] / load[k],
                snapback_m=disp[k] - min(disp[k:]), dissipated=float(rows[-1]["dissipated_J"]), wall_s=s["wall_s"],
                cmod=[float(x["cmod_m"]) for x in rows], load=load)


def past_peak(r):
    """Whether a run's peak is its structure's peak: it fell after it to below 95 % of it, or (a run stopped
    for time) for at least PAST_PEAK_STEPS steps in a row to below 99.5 % of it. IMPL-EX steps are accepted
    in equilibrium with the real law, so a load that falls step after step is past the limit point."""
    if "load" not in r:
        return False
    load = r["load"]
    k = max(range(len(load)), key=lambda i: load[i])
    after = load[k:]
    falling = len(after) > PAST_PEAK_STEPS and all(b < a for a, b in zip(after, after[1:]))
    return r["final_fraction"] < 0.95 or (falling and r["final_fraction"] < 0.995)


def peak_step(r):
    """The step (counted from 1, the curve's first row) at which a run reached its largest load."""
    load = r["load"]
    return max(range(len(load)), key=lambda i: load[i]) + 1


def nominal_strength(D, P):
    """sigma_N = 3 P S / (2 b D^2), S = 2.5 D: the elastic bending stress of the unnotched section."""
    return 1.5 * P * 2.5 * (D / 1e3) / (THICKNESS * (D / 1e3) ** 2) / 1e6


def report(res):
    plt = pyplot()
    import matplotlib.ticker
    keys = sorted(res, key=lambda k: (-parse_key(k)[3], parse_key(k)[2], parse_key(k)[0], list(KINDS).index(parse_key(k)[1])))
    lines = ["# Size effect: Gregoire beams D = 50 to 400 mm under path following", "",
             "Written by `benchmarks/size_effect.py` from `size_effect.json`. 3D and 2D plane stress (thickness 50 mm), non-linear",
             "law (f_t = 3.9 MPa, G_F = 143.2 N/m), surface and critical-stretch corrections, CMOD-controlled arc length",
             "(`-pd_control arclength`) from the start to 10 % of the peak; unnotched beams with 5 % bond-strength scatter",
             "(`-pd_strength_scatter 0.05`). CPU is the run's own on one rank (wall time grows when runs share the 2 cores); it is",
             "empty where a leg ran on 2 ranks under mpiexec, whose wall time is then the measure (size_effect.md says which).",
             "sigma_N = 3 P S / (2 b D^2) with span S = 2.5 D and b = 50 mm. 'load point back': how far the load point moves",
             "back after the peak (snap-back).", "",
             "| D (mm) | beam | model, dx (mm) | nodes | bonds | peak (N) | sigma_N (MPa) | end (of peak) | load point back (mm) | steps | Newton | KSP | "
             "wall (s) | CPU (s) | memory (MB) | status |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for k in keys:
        D, kind = parse_key(k)[:2]
        r = res[k]
        if "peak" not in r:
            lines.append("| %d | %s | %s | | | | | | | | | | %.0f | | | %s |" % (D, KINDS[kind], method(k), r.get("wall", 0), r["status"]))
            continue
        lines.append("| %d | %s | %s | %d | %d | %.0f | %.2f | %.3f | %.4f | %d | %d | %d | %.0f | %s | %s | %s |" % (
            D, KINDS[kind], method(k), r["nodes"], r["bonds"], r["peak"], nominal_strength(D, r["peak"]), r["final_fraction"],
            1e3 * r["snapback_m"], r["steps"], r["newton"], r["ksp"], r["wall"], "%.0f" % r["cpu"] if r.get("cpu") is not None else "",
            "%.0f" % r["memory_MB"] if r.get("memory_MB") else "",
            r["status"][:60] + (" (%d legs)" % r["legs"] if r.get("legs", 1) > 1 else "")))
    # Bazant's size effect law for notched beams, sigma_N = B f_t / sqrt(1 + D / D0): 1 / sigma_N^2 is linear
    # in D, so a least-squares line gives D0 = intercept / slope and B f_t = intercept^-1/2
    lines += ["", "Size effect law fitted to each series with three or more sizes (sigma_N in MPa, D0 in mm):", "",
              "| series | sizes | B f_t (MPa) | D0 (mm) | sigma_N ratio per doubling of D |", "|---|---|---|---|---|"]
    series = {}
    for k in keys:
        if past_peak(res[k]):
            D, kind = parse_key(k)[:2]
            series.setdefault((kind, method(k)), []).append((D, nominal_strength(D, res[k]["peak"])))
    for pts in series.values():
        pts.sort()
    for (kind, how), pts in sorted(series.items()):
        if len(pts) < 3:
            continue
        xs, ys = [p[0] for p in pts], [1 / p[1] ** 2 for p in pts]
        mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
        b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
        a = my - b * mx
        fit = "%.2f | %.0f" % (a ** -0.5, a / b) if a > 0 and b > 0 else "- | -"
        ratios = ", ".join("%.2f" % (q[1] / p[1]) for p, q in zip(pts, pts[1:]) if q[0] == 2 * p[0])
        lines.append("| %s, %s | %s | %s | %s |" % (KINDS[kind], how, ", ".join(str(p[0]) for p in pts), fit, ratios))
    # IMPL-EX against the implicit path on the same beam (size, notch, model and dx), where both runs are past the
    # structure's peak (past_peak): the peak's error and how many steps each took to reach it
    pairs = []
    for k in keys:
        D, kind, dx, dim, implex = parse_key(k)
        ref = key(D, kind, dx, dim)
        if implex > 0 and ref in res and past_peak(res[k]) and past_peak(res[ref]):
            pairs.append(((-dim, dx, D, list(KINDS).index(kind), implex), ref, k))
    if pairs:
        lines += ["", "IMPL-EX against the implicit path on the same beam (size, notch, model and dx), where both runs went past the peak;",
                  "steps to the peak count the curve's steps up to its largest load:", "",
                  "| D (mm) | beam | model, dx (mm) | IMPL-EX error per step | implicit peak (N) | IMPL-EX peak (N) | IMPL-EX against implicit | "
                  "steps to the peak, implicit / IMPL-EX |", "|---|---|---|---|---|---|---|---|"]
        for (_, dx, D, _, implex), ref, k in sorted(pairs):
            a, b = res[ref], res[k]
            lines.append("| %d | %s | %s | %g | %.0f | %.0f | %+.1f %% | %d / %d |" % (
                D, KINDS[parse_key(k)[1]], method(ref), implex, a["peak"], b["peak"], 100 * (b["peak"] / a["peak"] - 1),
                peak_step(a), peak_step(b)))
    write_lines("size_effect_table.md", lines)
    # one colour per size (curves) or notch ratio (strengths), one line style per way of computing
    size_colour = {50: "C0", 100: "C1", 200: "C2", 400: "C3"}
    kind_colour = {"un": "C0", "fn": "C1", "hn": "C2"}
    style = lambda how: ":" if how.startswith("2D") else "--" if "IMPL-EX 0.03" in how else "-." if "IMPL-EX" in how else "-"
    fig, ax = plt.subplots(1, 4, figsize=(22, 5))
    for i, kind in enumerate(KINDS):
        for k in keys:
            r, (D, kd) = res[k], parse_key(k)[:2]
            if kd != kind or "load" not in r:
                continue
            ax[i].plot([1e3 * c for c in r["cmod"]], [l / 1e3 for l in r["load"]], style(method(k)), color=size_colour.get(D, "k"),
                       lw=1.2, label="D = %d, %s" % (D, method(k)))
        ax[i].set(title=KINDS[kind], xlabel="CMOD (mm)", ylabel="load (kN)")
        ax[i].legend(fontsize=6.5, ncol=2, loc="upper right")
    marker = dict(zip(KINDS, "o^s"))
    for (kind, how), pts in sorted(series.items(), key=lambda s: (list(KINDS).index(s[0][0]), s[0][1])):
        ax[3].loglog([p[0] for p in pts], [p[1] for p in pts], style(how), marker=marker[kind], color=kind_colour[kind],
                     label="%s, %s" % (KINDS[kind], how))
    ax[3].set(title="nominal strength at the peak", xlabel="D (mm)", ylabel="sigma_N (MPa)")
    for axis in (ax[3].xaxis, ax[3].yaxis):
        axis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
        axis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax[3].set_xticks([50, 100, 200, 400])
    ax[3].set_yticks([1, 2, 3, 4, 6, 8])
    ax[3].legend(fontsize=6.5, loc="upper left", bbox_to_anchor=(1.02, 1))
    save_figure(fig, "size_effect.png", dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--ranks", type=int, default=1, help="MPI ranks per run (runs at once times ranks should not exceed the cores)")
    ap.add_argument("--dx", default="5e-3,10e-3")
    ap.add_argument("--sizes", default="50,100,200,400")
    ap.add_argument("--kinds", default="un,fn,hn")
    ap.add_argument("--timeout", type=float, default=7200)
    ap.add_argument("--dim", type=int, default=3, help="3, or 2 for plane-stress versions of the beams")
    ap.add_argument("--implex", type=float, default=0, help="IMPL-EX steps with this damage error per step (0: implicit)")
    ap.add_argument("--redo", default="", help="comma-separated result keys to run again")
    ap.add_argument("--resume", action="store_true", help="go on with the selected runs that stopped on their time limit")
    ap.add_argument("--report", action="store_true")
    a = ap.parse_args()
    res = load_results(RESULTS)
    # an old result stays in the file until its rerun finishes
    done = set(res) - set(a.redo.split(","))
    if not a.report:
        todo = [(D, kind, float(dx)) for dx in a.dx.split(",") for D in map(int, a.sizes.split(",")) for kind in a.kinds.split(",")
                if key(D, kind, float(dx), a.dim, a.implex) not in done or (a.resume and resumable(res[key(D, kind, float(dx), a.dim, a.implex)]))]
        with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
            futs = {pool.submit(run_one, D, kind, dx, a.timeout, a.dim, res[key(D, kind, dx, a.dim, a.implex)] if key(D, kind, dx, a.dim, a.implex) in done else None, a.implex, a.ranks):
                    (D, kind, dx) for D, kind, dx in todo}
            for f in concurrent.futures.as_completed(futs):
                D, kind, dx = futs[f]
                k = key(D, kind, dx, a.dim, a.implex)
                res = store_result(RESULTS, k, f.result())
                print(k, res[k].get("status"), "%.0f s" % res[k].get("wall", 0), flush=True)
                report(res)
    report(res)


if __name__ == "__main__":
    main()
