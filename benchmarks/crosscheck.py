#!/usr/bin/python3
"""Cross-check: run one scene on the implicit path and on the explicit reference path, and compare.

Compares the peak load, the load-displacement (or load-CMOD) curves over their common range (RMS load
difference over the implicit peak), the energy dissipated at the end of the common range, and the cost
(wall time, Newton/KSP iterations against time steps). Exits 1 when the peak or the curve differ by
more than the tolerances, so it can guard a scene in a script.

Usage: benchmarks/crosscheck.py SCENE.opts [--ranks N] [--peak-tol 0.05] [--curve-tol 0.10]
           [--explicit "-pd_ramp_time 0.05"] [--out DIR] [--record NAME] [-- extra pdimplicit options for both runs]
       benchmarks/crosscheck.py --report
Writes DIR/crosscheck.json, DIR/crosscheck.md and DIR/crosscheck.png (DIR defaults to
output/crosscheck_<scene>) and prints the table. --record also keeps the comparison as case NAME in
docs/benchmarks/crosscheck.json; --report writes docs/benchmarks/crosscheck.md from that file.
"""
import argparse
import json
import math
import os
import shlex
import subprocess
import sys
import time

from common import curve_rows, ENV, EXE, RESULTS_DIR, ROOT, load_results, save_results, pyplot, write_lines

JSON = os.path.join(RESULTS_DIR, "crosscheck.json")
# the recorded cases, in the order of the report, with what each shows
CASES = {
    "hn_dx5": "Half-notched Gregoire beam, dx = 5 mm (the shipped scene), explicit ramp 50 ms",
    "hn_dx10": "Half-notched beam, dx = 10 mm, default explicit ramp",
    "cantilever_dx20": "Elastic cantilever, dx = 20 mm, explicit damped to rest. The curves differ while the explicit "
                       "path passes through dynamic states on the way; for a force-controlled elastic scene the last row, "
                       "the rest state, is the comparison that matters",
}


def run(scene, out, ranks, opts):
    cmd = [EXE, "-options_file", scene, "-pd_output_dir", out] + opts
    if ranks > 1:
        cmd = ["mpiexec", "-n", str(ranks)] + cmd
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
    wall = time.time() - t0
    try:
        s = json.load(open(os.path.join(out, "summary.json")))
        rows = curve_rows(out)
    except OSError:
        sys.exit("crosscheck: %s failed (%d): %s" % (" ".join(cmd), p.returncode, (p.stderr.strip().splitlines() or ["?"])[-1]))
    return {"wall": wall, "summary": s, "rows": rows, "returncode": p.returncode}


def interp(x, xs, ys):
    for k in range(1, len(xs)):
        if xs[k] >= x:
            t = (x - xs[k - 1]) / (xs[k] - xs[k - 1]) if xs[k] > xs[k - 1] else 0
            return ys[k - 1] + t * (ys[k] - ys[k - 1])
    return ys[-1]


def compare(imp, exp):
    """Curve abscissa: CMOD when the scene has a gauge, else the load-point displacement."""
    key = "cmod_m" if not math.isnan(imp["rows"][-1]["cmod_m"]) else "disp_m"
    xi = [0.0] + [r[key] for r in imp["rows"]]
    yi = [0.0] + [r["load_N"] for r in imp["rows"]]
    xmax = min(max(xi), max(r[key] for r in exp["rows"]))
    # explicit rows within the range the implicit curve covers; a monotone abscissa is assumed for the implicit curve
    pts = [r for r in exp["rows"] if r[key] <= xmax]
    pi, pe = imp["summary"]["peak_load_N"], exp["summary"]["peak_load_N"]
    rms = math.sqrt(sum((r["load_N"] - interp(r[key], xi, yi)) ** 2 for r in pts) / max(1, len(pts))) / pi
    di = interp(xmax, xi, [0.0] + [r["dissipated_J"] for r in imp["rows"]])
    de = [r["dissipated_J"] for r in pts][-1] if pts else float("nan")
    return {"abscissa": key, "range": xmax, "rows_compared": len(pts), "peak_implicit_N": pi, "peak_explicit_N": pe,
            "peak_difference": pe / pi - 1, "curve_rms_over_peak": rms, "dissipated_implicit_J": di, "dissipated_explicit_J": de,
            "final_disp_implicit_m": imp["rows"][-1]["disp_m"], "final_disp_explicit_m": exp["rows"][-1]["disp_m"],
            "wall_implicit_s": imp["wall"], "wall_explicit_s": exp["wall"], "newton_its": imp["summary"]["newton_its"],
            "ksp_its": imp["summary"]["ksp_its"], "time_steps": exp["summary"]["explicit"]["time_steps"],
            "explicit_step": {k: exp["summary"]["explicit"][k] for k in ("eigenvalue_estimate_per_s2", "dt_stable_s", "dt_safety", "dt_s")},
            "kinetic_over_internal_max": max((r["kinetic_J"] / (r["stored_J"] + r["dissipated_J"]) for r in exp["rows"]
                                              if r["stored_J"] + r["dissipated_J"] > 1e-3 * exp["rows"][-1]["external_J"]), default=0.0)}


def main():
    argv = sys.argv[1:]
    if argv == ["--report"]:
        report()
        return
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[:argv.index("--")] if "--" in argv else argv
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--peak-tol", type=float, default=0.05)
    ap.add_argument("--curve-tol", type=float, default=0.10)
    ap.add_argument("--explicit", default="", help="options for the explicit run only (ramp, damping, ...)")
    ap.add_argument("--out")
    ap.add_argument("--record", choices=sorted(CASES), help="keep the comparison as this case in docs/benchmarks/crosscheck.json")
    a = ap.parse_args(argv)
    name = os.path.splitext(os.path.basename(a.scene))[0]
    out = a.out or os.path.join(ROOT, "output", "crosscheck_" + name)
    os.makedirs(out, exist_ok=True)
    imp = run(a.scene, os.path.join(out, "implicit"), a.ranks, extra)
    exp = run(a.scene, os.path.join(out, "explicit"), a.ranks, extra + ["-pd_mode", "explicit"] + shlex.split(a.explicit))
    c = compare(imp, exp)
    c.update(scene=a.scene, options=" ".join(extra), explicit_options=a.explicit, ranks=a.ranks,
             status_implicit=imp["summary"]["status"], status_explicit=exp["summary"]["status"])
    ok = abs(c["peak_difference"]) <= a.peak_tol and c["curve_rms_over_peak"] <= a.curve_tol
    c["verdict"] = "agree" if ok else "differ"
    c["peak_tol"], c["curve_tol"] = a.peak_tol, a.curve_tol
    json.dump(c, open(os.path.join(out, "crosscheck.json"), "w"), indent=1)
    if a.record:
        res = load_results(JSON)
        res.setdefault("cases", {})[a.record] = dict(c, command=shlex.join(["benchmarks/crosscheck.py"] + sys.argv[1:]))
        save_results(JSON, res)
    md = ["# Cross-check: %s %s" % (name, c["options"]), ""] + table(c)
    open(os.path.join(out, "crosscheck.md"), "w").write("\n".join(md) + "\n")
    print("\n".join(md))
    plot(name, imp, exp, c, out)
    sys.exit(0 if ok else 1)


def table(c):
    unit = "mm CMOD" if c["abscissa"] == "cmod_m" else "mm displacement"
    return ["| | implicit | explicit |", "|---|---|---|",
          "| peak load (N) | %.1f | %.1f (%+.2f %%) |" % (c["peak_implicit_N"], c["peak_explicit_N"], 100 * c["peak_difference"]),
          "| dissipated at %.3f %s (J) | %.4g | %.4g |" % (1e3 * c["range"], unit, c["dissipated_implicit_J"], c["dissipated_explicit_J"]),
          "| last row: load-point displacement (m) | %.6e | %.6e (%+.2g %%) |" % (
              c["final_disp_implicit_m"], c["final_disp_explicit_m"], 100 * (c["final_disp_explicit_m"] / c["final_disp_implicit_m"] - 1)),
          "| wall time (s) | %.1f | %.1f |" % (c["wall_implicit_s"], c["wall_explicit_s"]),
          "| work | %d Newton, %d KSP iterations | %d time steps of %.3g s (%g of the stable step) |" % (
              c["newton_its"], c["ksp_its"], c["time_steps"], c["explicit_step"]["dt_s"], c["explicit_step"]["dt_safety"]),
          "| status | %s | %s |" % (c["status_implicit"], c["status_explicit"]), "",
          "Curves: RMS load difference %.2f %% of the implicit peak over %d explicit rows up to %.3f %s; largest kinetic over"
          " internal energy in the explicit run %.2g. Verdict (peak within %g %%, curve within %g %%): **%s**." % (
              100 * c["curve_rms_over_peak"], c["rows_compared"], 1e3 * c["range"], unit, c["kinetic_over_internal_max"],
              100 * c["peak_tol"], 100 * c["curve_tol"], c["verdict"])]


def report():
    res = load_results(JSON)
    lines = ["# Cross-checks: implicit against explicit", "",
             "Written by `benchmarks/crosscheck.py --report` from `crosscheck.json`; each case was recorded by the command under "
             "its heading (`--record`), one rank per run on the 2-core machine. The script compares peak load, curves (RMS load "
             "difference over the implicit peak, on the explicit rows inside the implicit curve's range), dissipated energy, last "
             "displacement and cost, and exits 1 when the peak or the curve differs by more than its tolerance."]
    for key, what in CASES.items():
        if key not in res.get("cases", {}):
            continue
        c = res["cases"][key]
        lines += ["", "## %s" % what, "", "`%s`" % c["command"], ""] + table(c)
    write_lines("crosscheck.md", lines)


def plot(name, imp, exp, c, out):
    unit = "mm CMOD" if c["abscissa"] == "cmod_m" else "mm displacement"
    try:
        plt = pyplot()
        fig, ax = plt.subplots(figsize=(6, 4))
        for r, lab in ((imp, "implicit"), (exp, "explicit")):
            ax.plot([1e3 * x[c["abscissa"]] for x in r["rows"]], [x["load_N"] for x in r["rows"]], label=lab)
        ax.set_xlabel(unit)
        ax.set_ylabel("load (N)")
        ax.set_title(name, fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(out, "crosscheck.png"), dpi=110)
    except ImportError:
        pass


if __name__ == "__main__":
    main()
