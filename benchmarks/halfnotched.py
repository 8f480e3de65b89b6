#!/usr/bin/python3
"""What drives the half-notched D = 50 mm beam's peak above the experiment.

Two parts, one data file (docs/benchmarks/halfnotched.json), one report (halfnotched.md):

- hinge: an independent cohesive-crack model of the same beams with the same material data, the hinge
  model of Olesen (J. Eng. Mech. 127(3), 2001): a band of length s = zeta h over the ligament h deforms
  with plane sections; its fibres are linear elastic until f_t, then open a cohesive crack w with
  sigma(w) from a softening law of fracture energy G_F, the band's elongation s eps = s sigma / E + w.
  The load is P = 4 M / L at the largest moment over the hinge's rotation. It shares nothing with the
  peridynamic model but E, f_t, G_F and the geometry, so where both miss the experiment by the same
  amount the cause lies in the data, not in the lattice.
- pd: pdimplicit on the shipped 3D scenes with one ingredient changed per run (law, tensile strength,
  horizon, notch faces, lattice fracture energy, spacing).

Usage: benchmarks/halfnotched.py [--report | --hinge | CASE ...]
  --hinge    recompute the hinge model (a few seconds) and keep the runs
  CASE ...   run only these pdimplicit cases (names below), keep the others' results
  (no argument: everything, about 15 minutes on one core)
"""
import json
import math
import os
import sys
import tempfile

import numpy as np

from common import EXE, RESULTS_DIR, ROOT, experiment_peaks, load_results, run_timed, save_results, write_lines

JSON = os.path.join(RESULTS_DIR, "halfnotched.json")

# data of the series (data/README.md): E, splitting strength, G_F from fib MC2010, f_cm
E, FT_SPLIT, GF, FCM = 37e9, 3.9e6, 143.2, 42.3
THICKNESS, SPAN, DEPTH = 0.05, 0.125, 0.05
LIGAMENTS = {"un": 0.05, "fn": 0.04, "hn": 0.025}
# tensile strengths one may read from the data: the splitting strength itself, the axial strength it
# implies by EN 1992-1-1 3.1.2(8) (f_ct = 0.9 f_ct,sp), and fib MC2010's mean from f_ck = f_cm - 8 MPa
STRENGTHS = [("splitting f_ct,sp", FT_SPLIT), ("axial 0.9 f_ct,sp (EN 1992-1-1)", 0.9 * FT_SPLIT),
             ("MC2010 0.3 (f_cm - 8)^(2/3)", 0.3e6 * (FCM - 8) ** (2.0 / 3.0))]
LAWS = ["linear", "bilinear", "exponential"]
ZETA = 0.5  # Olesen's hinge length over the ligament

# name, beam, what changes, options on top of the shipped scene
CASES = [
    ("hn", "hn", "shipped scene (non-linear law, continuum calibration, dx = 5 mm, m = pi)", []),
    ("un", "un", "shipped scene", []),
    ("hn_bilinear", "hn", "law: bilinear (k_r = 25)", ["-pd_law", "bilinear"]),
    ("hn_trilinear", "hn", "law: trilinear", ["-pd_law", "trilinear"]),
    ("hn_ft_axial", "hn", "tensile strength 0.9 f_ct,sp = 3.51 MPa", ["-pd_ft", "3.51e6"]),
    ("un_ft_axial", "un", "tensile strength 0.9 f_ct,sp = 3.51 MPa", ["-pd_ft", "3.51e6"]),
    ("hn_m3", "hn", "horizon 3 dx (15 mm, 0.60 of the ligament)", ["-pd_horizon_ratio", "3"]),
    ("hn_m4", "hn", "horizon 4 dx (20 mm, 0.80 of the ligament)", ["-pd_horizon_ratio", "4"]),
    ("hn_dx10", "hn", "dx = 10 mm (horizon 31 mm, 1.26 ligaments)", ["-pd_dx", "0.01"]),
    ("hn_notch_surface", "hn", "notch faces corrected as free surfaces", ["-pd_sc_notch_surface"]),
    ("hn_gf_lattice", "hn", "critical stretches calibrated to the lattice's fracture energy", ["-pd_gf_lattice"]),
    ("hn_stencil", "hn", "stencil calibration (bulk and faces as stiff as E)", ["-pd_calibration", "stencil"]),
]


def softening(law, ft, gf):
    """sigma(w) (Pa, w in m) of a cohesive law with strength ft and fracture energy gf, and its w_c."""
    if law == "linear":
        wc = 2 * gf / ft
        return (lambda w: np.where(w < wc, ft * (1 - w / wc), 0.0)), wc
    if law == "bilinear":  # fib MC2010 Eq. 5.1-10: kink at w1 = G_F / f_t, 0.2 f_t, w_c = 5 w1
        w1 = gf / ft
        return (lambda w: np.where(w <= w1, ft * (1 - 0.8 * w / w1), np.where(w < 5 * w1, ft * (0.25 - 0.05 * w / w1), 0.0))), 5 * w1
    # Hordijk (1991): c1 = 3, c2 = 6.93, w_c = 5.136 G_F / f_t
    c1, c2, wc = 3.0, 6.93, 5.136 * gf / ft

    def f(w):
        x = np.minimum(w / wc, 1.0)
        return np.where(w < wc, ft * ((1 + (c1 * x) ** 3) * np.exp(-c2 * x) - x * (1 + c1 ** 3) * math.exp(-c2)), 0.0)
    return f, wc


def fracture_energy(law, ft, gf):
    f, wc = softening(law, ft, gf)
    w = np.linspace(0, wc, 200001)
    return float(np.trapz(f(w), w))


def hinge_peak(law, ft, gf, h, zeta=ZETA, n=801):
    """Largest load (N) of three-point bending whose ligament h carries the hinge of length zeta h."""
    f, wc = softening(law, ft, gf)
    s, y = zeta * h, np.linspace(0, h, n)  # y from the notch tip up
    wtab = np.linspace(0, 1.5 * wc, 20001)
    # the band's elongation of a cracked fibre, s sigma(w) / E + w; made monotone where the law is steeper
    # than E / s (a snap-back of the fibre, which the hinge passes at constant elongation)
    dtab = np.maximum.accumulate(wtab + s * f(wtab) / E)

    def stresses(theta, y0):
        d = theta * (y0 - y)  # elongation: opening below the neutral axis y0
        sig = E * d / s
        cracked = sig > ft
        sig[cracked] = f(np.interp(d[cracked], dtab, wtab))
        return sig

    def moment(theta):
        lo, hi = 0.0, h  # axial force: all compressed at y0 = 0, all stretched at y0 = h
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if np.trapz(stresses(theta, mid), y) < 0 else (lo, mid)
        y0 = 0.5 * (lo + hi)
        return -THICKNESS * np.trapz(stresses(theta, y0) * (y - y0), y)

    theta_cr = 2 * ft / E * s / h  # rotation at the first crack
    return max(4 * moment(t) / SPAN for t in np.geomspace(0.3 * theta_cr, 400 * theta_cr, 300))


def gf_matching(law, ft, beam, target):
    """The fracture energy (N/m) with which the hinge meets target (N) on beam, by bisection."""
    lo, hi = 5.0, 1000.0
    for _ in range(40):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if hinge_peak(law, ft, mid, LIGAMENTS[beam]) < target else (lo, mid)
    return math.sqrt(lo * hi)


def hinge():
    rows = []
    for what, ft in STRENGTHS:
        for law in LAWS:
            peaks = {beam: hinge_peak(law, ft, GF, h) for beam, h in LIGAMENTS.items()}
            rows.append({"strength": what, "ft_Pa": ft, "law": law, "zeta": ZETA, "gf_check": fracture_energy(law, ft, GF),
                         "peaks_N": peaks})
    zeta = {str(z): {beam: hinge_peak("bilinear", FT_SPLIT, GF, h, zeta=z) for beam, h in LIGAMENTS.items()} for z in (0.25, 0.5, 1.0)}
    hn_mean = experiment_peaks("hn")[0]
    gf = gf_matching("bilinear", FT_SPLIT, "hn", hn_mean)
    fit = {"law": "bilinear", "ft_Pa": FT_SPLIT, "gf": gf, "peaks_N": {beam: hinge_peak("bilinear", FT_SPLIT, gf, h) for beam, h in LIGAMENTS.items()}}
    # every fracture energy: the strength with which the hinge meets the unnotched mean, and the
    # half-notched peak that pair gives
    pairs = []
    for gf in (25.0, 50.0, 100.0, GF, 200.0, 400.0):
        lo, hi = 1e6, 10e6
        for _ in range(30):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if hinge_peak("bilinear", mid, gf, LIGAMENTS["un"]) < experiment_peaks("un")[0] else (lo, mid)
        ft = 0.5 * (lo + hi)
        pairs.append({"gf": gf, "ft_Pa": ft, "hn_N": hinge_peak("bilinear", ft, gf, LIGAMENTS["hn"])})
    return {"rows": rows, "zeta_bilinear_splitting": zeta, "gf_matching_hn": fit, "pairs_matching_un": pairs}


def run(name):
    _, beam, _, extra = next(c for c in CASES if c[0] == name)
    out = tempfile.mkdtemp(prefix="pdbench_")
    scene = os.path.join(ROOT, "options", "gregoire_d50_%s.opts" % beam)
    with open(os.path.join(out, "log"), "w") as log:
        code, wall, cpu, _ = run_timed([EXE, "-options_file", scene, "-pd_output_dir", out, *extra], 3600, log)
    s = json.load(open(os.path.join(out, "summary.json")))
    return {"exit": code, "status": s["status"], "peak_N": s["peak_load_N"], "nodes": s["nodes"], "bonds": s["bonds"],
            "newton_its": s["newton_its"], "cpu_s": round(cpu, 1)}


def fmt(v):
    return "{:,.0f}".format(v)


def pct(v, ref):
    return "%+.1f %%" % (100 * (v / ref - 1))


def report():
    res = load_results(JSON)
    exp = {beam: experiment_peaks(beam) for beam in LIGAMENTS}
    h = res["hinge"]
    lines = ["# What drives the half-notched beam's peak", "",
             "Written by `benchmarks/halfnotched.py` from `halfnotched.json`. Gregoire et al. (2013), D = 50 mm, span 125 mm, "
             "50 mm thick; material data of `data/README.md`: E = 37 GPa, f_ct,sp = 3.9 MPa (splitting), G_F = 143.2 N/m "
             "(fib MC2010 estimate, not measured). Experiment (peak of the mean curve, envelopes): unnotched %s N (%s to %s), "
             "half-notched %s N (%s to %s); no fifth-notched curve." % tuple(fmt(v) for v in exp["un"] + exp["hn"]), "",
             "## An independent cohesive-crack model with the same data", "",
             "The hinge model of Olesen (2001): a band of length s = %.1f h over the ligament h, plane sections, fibres linear "
             "elastic up to f_t and then a cohesive crack with the softening law given (fracture energy G_F; the column 'G_F "
             "integrated' checks the law's area). Peak load P = 4 M / L. Nothing in it is peridynamic." % ZETA, "",
             "| tensile strength | f_t (MPa) | law | G_F integrated (N/m) | unnotched (N) | fifth-notched (N) | half-notched (N) | "
             "unnotched vs experiment | half-notched vs experiment |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in h["rows"]:
        p = r["peaks_N"]
        lines.append("| %s | %.2f | %s | %.1f | %s | %s | %s | %s | %s |" % (
            r["strength"], r["ft_Pa"] / 1e6, r["law"], r["gf_check"], fmt(p["un"]), fmt(p["fn"]), fmt(p["hn"]),
            pct(p["un"], exp["un"][0]), pct(p["hn"], exp["hn"][0])))
    lines += ["", "Hinge length (bilinear law, splitting strength): the peaks for s / h = "
              + ", ".join("%s: unnotched %s N, half-notched %s N" % (z, fmt(v["un"]), fmt(v["hn"]))
                          for z, v in sorted(h["zeta_bilinear_splitting"].items(), key=lambda kv: float(kv[0]))) + ".", ""]
    # the hinge as long as half the beam's depth in both beams (Ulfkjaer's choice): half the unnotched
    # ligament, the whole half-notched one
    zu, zh = h["zeta_bilinear_splitting"]["0.5"]["un"], h["zeta_bilinear_splitting"]["1.0"]["hn"]
    lines += ["With the hinge half the beam's depth long in both beams (25 mm): unnotched %s N (%s), half-notched %s N (%s), "
              "ratio %.3f." % (fmt(zu), pct(zu, exp["un"][0]), fmt(zh), pct(zh, exp["hn"][0]), zh / zu), ""]
    fit = h["gf_matching_hn"]
    lines += ["The fracture energy with which the hinge (bilinear, f_t = %.2f MPa) meets the half-notched mean: G_F = %.1f N/m "
              "(%.0f %% of the data's); with it the unnotched beam peaks at %s N (%s on its experiment)." % (
                  fit["ft_Pa"] / 1e6, fit["gf"], 100 * fit["gf"] / GF, fmt(fit["peaks_N"]["un"]), pct(fit["peaks_N"]["un"], exp["un"][0])), ""]
    lines += ["Pairs of strength and fracture energy with which the hinge (bilinear) meets the unnotched mean, and the "
              "half-notched peak each pair gives:", "", "| G_F (N/m) | f_t (MPa) | half-notched (N) | vs experiment |", "|---|---|---|---|"]
    lines += ["| %.1f | %.2f | %s | %s |" % (p["gf"], p["ft_Pa"] / 1e6, fmt(p["hn_N"]), pct(p["hn_N"], exp["hn"][0])) for p in h["pairs_matching_un"]]
    lines += ["", "## pdimplicit, one ingredient at a time", "",
              "3D, one rank; each run is the shipped scene `options/gregoire_d50_<beam>.opts` with the options given.", "",
              "| run | beam | what changes | peak (N) | vs shipped scene | vs experiment | nodes | bonds | Newton | CPU (s) | status |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    runs = res.get("runs", {})
    for name, beam, what, extra in CASES:
        if name not in runs:
            continue
        r, ref = runs[name], runs[beam]
        lines.append("| %s | %s | %s | %s | %s | %s | %d | %d | %d | %.1f | %s |" % (
            name, beam, what, fmt(r["peak_N"]), pct(r["peak_N"], ref["peak_N"]) if name != beam else "-", pct(r["peak_N"], exp[beam][0]),
            r["nodes"], r["bonds"], r["newton_its"], r["cpu_s"], r["status"]))
    # the notch sensitivity, half-notched over unnotched peak, which no pair of material constants moves much
    ratios = [r["peaks_N"]["hn"] / r["peaks_N"]["un"] for r in h["rows"]]
    pd = [runs[a]["peak_N"] / runs[b]["peak_N"] for a, b in (("hn", "un"), ("hn_ft_axial", "un_ft_axial")) if a in runs and b in runs]
    lines += ["", "Half-notched over unnotched peak: experiment %.3f; hinge %.3f to %.3f over the laws and strengths above; "
              "pdimplicit %s (shipped strength, then 0.9 f_ct,sp)." % (
                  exp["hn"][0] / exp["un"][0], min(ratios), max(ratios), " and ".join("%.3f" % v for v in pd) or "-")]
    lines += ["", "Commands (`benchmarks/halfnotched.py NAME` reruns one):", ""]
    lines += [("    build/pdimplicit -options_file options/gregoire_d50_%s.opts %s" % (beam, " ".join(extra))).rstrip() for _, beam, _, extra in CASES]
    write_lines("halfnotched.md", lines)


if __name__ == "__main__":
    args = sys.argv[1:]
    if "--report" not in args:
        if "--hinge" in args or not args or "hinge" not in load_results(JSON):
            h = hinge()  # read the file again afterwards: runs of another invocation may have landed meanwhile
            res = load_results(JSON)
            res["hinge"] = h
            save_results(JSON, res)
        for name in [c[0] for c in CASES if not args or c[0] in args]:
            r = run(name)
            res = load_results(JSON)
            res.setdefault("runs", {})[name] = r
            print(name, res["runs"][name], flush=True)
            save_results(JSON, res)
    report()
