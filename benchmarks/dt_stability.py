#!/usr/bin/python3
"""The explicit path's time step on the half-notched Gregoire beam (options/gregoire_d50_hn.opts with
-pd_mode explicit -pd_ramp_time 0.05, traced to CMOD = 0.2 mm).

For each spacing: the largest eigenvalue of M^-1 K on the free dofs computed by numpy (dense, from the
stiffness an elastic implicit run writes with PETSc's binary viewer; where that is too large, 10,000 power
iterations of pdimplicit instead), against pdimplicit's power-iteration estimate (after 10 to 1,000
iterations), its Gershgorin bound and the estimate of THEORY.md Eq. 4.6; the
largest -pd_dt_safety at which the run stays stable, by bisection (an unstable run stops with status
`unstable`); the default run (0.9 of the stable step) against the former default (0.7 of Eq. 4.6).

Usage: benchmarks/dt_stability.py [--dx 1e-2 5e-3] [--bisect 7] [--numpy-max-dofs 12000]   (about 40 minutes)
Writes docs/benchmarks/dt_stability.json and docs/benchmarks/dt_stability.md.
"""
import argparse
import json
import os
import sys
import tempfile

from common import EXE, OUT, RESULTS_DIR, ROOT, load_results, run_timed, store_result

sys.path.insert(0, os.path.join(ROOT, "tests"))
from pdtest import mass_scaled_eigenvalue  # noqa: E402  (numpy's eigenvalue on the dumped stiffness, shared with the tests)

SCENE = os.path.join(ROOT, "options", "gregoire_d50_hn.opts")
EXPLICIT = ["-pd_mode", "explicit", "-pd_ramp_time", "0.05"]
JSON = os.path.join(RESULTS_DIR, "dt_stability.json")
ITS = (10, 30, 100, 300, 1000)
REF_ITS = 10000  # the reference where numpy's dense solver would take too long (the table compares both at dx = 10 mm)


def run(dx, opts, timeout=900):
    """One run; returns its summary with the exit code and CPU time added."""
    out = tempfile.mkdtemp(prefix="dt_stability_")
    cmd = [EXE, "-options_file", SCENE, "-pd_dx", repr(dx), "-pd_output_dir", out] + opts
    with open(os.path.join(out, "log.txt"), "w") as log:
        code, wall, cpu, _ = run_timed(cmd, timeout, log)
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    s.update(returncode=code, cpu_s=cpu, wall_run_s=wall)
    return s


def stable(s):
    return s["returncode"] == 0 and s["converged"] and s["status"].startswith("completed")


def study(dx, nbisect, max_dofs):
    lam_np, nfree = mass_scaled_eigenvalue("gregoire_d50_hn", dx, max_dofs=max_dofs)
    power = {}
    for n in ITS + (REF_ITS,):  # stopped at CMOD = 1 um: only the estimate is wanted
        power[n] = run(dx, EXPLICIT + ["-pd_dt_power_its", str(n), "-pd_stop_cmod", "1e-6"])["explicit"]["eigenvalue_estimate_per_s2"]
    lam = lam_np if lam_np else power[REF_ITS]
    print("dx %g: largest eigenvalue %.6e 1/s^2 (numpy %s, %d free dofs; %d power iterations %.6e)" % (
        dx, lam, lam_np, nfree, REF_ITS, power[REF_ITS]), flush=True)
    default = run(dx, EXPLICIT)
    e = default["explicit"]
    assert stable(default), default["status"]
    former = run(dx, EXPLICIT + ["-pd_dt_safety", repr(0.7 * e["dt_eq46_s"] / e["dt_stable_s"])])
    print("  default: %d steps of %.4g s, %.1f s CPU; former: %d steps of %.4g s, %.1f s CPU" % (
        e["time_steps"], e["dt_s"], default["cpu_s"], former["explicit"]["time_steps"], former["explicit"]["dt_s"], former["cpu_s"]), flush=True)
    lo, hi, trials = e["dt_safety"], 1.1, []
    s = run(dx, EXPLICIT + ["-pd_dt_safety", repr(hi)])
    trials.append({"safety": hi, "stable": stable(s), "time_steps": s["explicit"]["time_steps"], "status": s["status"]})
    assert not stable(s), "safety %g stable: raise the bracket" % hi
    for _ in range(nbisect):
        mid = 0.5 * (lo + hi)
        s = run(dx, EXPLICIT + ["-pd_dt_safety", repr(mid)])
        trials.append({"safety": mid, "stable": stable(s), "time_steps": s["explicit"]["time_steps"], "status": s["status"]})
        print("  safety %.5f: %s" % (mid, s["status"]), flush=True)
        if stable(s):
            lo = mid
        else:
            hi = mid
    keep = ("time_steps", "dt_s", "stretch_per_step_max", "kinetic_energy_max_J")
    return {
        "nodes": default["nodes"], "bonds": default["bonds"], "free_dofs": nfree,
        "eigenvalue_reference_per_s2": lam, "reference": "numpy" if lam_np else "%d power iterations" % REF_ITS,
        "eigenvalue_numpy_per_s2": lam_np, "eigenvalue_power_per_s2": {str(n): v for n, v in power.items()},
        "power_iterations": e["power_iterations"], "eigenvalue_estimate_per_s2": e["eigenvalue_estimate_per_s2"],
        "eigenvalue_gershgorin_per_s2": e["eigenvalue_gershgorin_per_s2"],
        "dt_eq46_s": e["dt_eq46_s"], "dt_gershgorin_s": e["dt_gershgorin_s"], "dt_stable_s": e["dt_stable_s"], "dt_exact_s": 2 / lam**0.5,
        "default": {"dt_safety": e["dt_safety"], "peak_load_N": default["peak_load_N"], "cpu_s": default["cpu_s"], **{k: e[k] for k in keep}},
        "former": {"dt_safety": 0.7, "of": "Eq. 4.6", "peak_load_N": former["peak_load_N"], "cpu_s": former["cpu_s"],
                   **{k: former["explicit"][k] for k in keep}},
        "safety_stable": lo, "safety_unstable": hi, "trials": trials,
    }


def table(res):
    keys = sorted(res, key=lambda k: -float(k.split("_")[1]))
    col = lambda f: " | ".join(f(res[k]) for k in keys)
    rows = [
        ("nodes, bonds, free dofs", lambda r: "%d, %d, %d" % (r["nodes"], r["bonds"], r["free_dofs"])),
        ("largest eigenvalue of M^-1 K (1/s^2)", lambda r: "%.5e (%s)" % (r["eigenvalue_reference_per_s2"], r["reference"])),
        ("power iteration, %s iterations: below it by" % ", ".join(str(n) for n in ITS),
         lambda r: ", ".join("%.2g %%" % (100 * (1 - r["eigenvalue_power_per_s2"][str(n)] / r["eigenvalue_reference_per_s2"])) for n in ITS)),
        ("%d power iterations against numpy" % REF_ITS, lambda r: "%.1e" % abs(r["eigenvalue_power_per_s2"][str(REF_ITS)] / r["eigenvalue_numpy_per_s2"] - 1)
         if r["eigenvalue_numpy_per_s2"] else "(numpy not run)"),
        ("Gershgorin bound / largest eigenvalue", lambda r: "%.2f" % (r["eigenvalue_gershgorin_per_s2"] / r["eigenvalue_reference_per_s2"])),
        ("Eq. 4.6 step (former estimate)", lambda r: "%.4g s" % r["dt_eq46_s"]),
        ("Gershgorin step 2/sqrt(bound)", lambda r: "%.4g s (%.2f x Eq. 4.6)" % (r["dt_gershgorin_s"], r["dt_gershgorin_s"] / r["dt_eq46_s"])),
        ("exact stable step 2/sqrt(largest eigenvalue)", lambda r: "%.4g s (%.2f x Eq. 4.6)" % (r["dt_exact_s"], r["dt_exact_s"] / r["dt_eq46_s"])),
        ("stable step 2/sqrt(estimate), %d iterations" % res[keys[0]]["power_iterations"],
         lambda r: "%.4g s (%.2f %% above the exact one)" % (r["dt_stable_s"], 100 * (r["dt_stable_s"] / r["dt_exact_s"] - 1))),
        ("largest stable -pd_dt_safety (bisection)", lambda r: "%.4f (unstable at %.4f)" % (r["safety_stable"], r["safety_unstable"])),
        ("largest stable step", lambda r: "%.4g s = %.3f x Eq. 4.6 = %.4f x exact" % (
            r["safety_stable"] * r["dt_stable_s"], r["safety_stable"] * r["dt_stable_s"] / r["dt_eq46_s"],
            r["safety_stable"] * r["dt_stable_s"] / r["dt_exact_s"])),
        ("default step (0.9 of the stable step)", lambda r: "%.4g s = %.2f x the former default (0.7 x Eq. 4.6, %.4g s)" % (
            r["default"]["dt_s"], r["default"]["dt_s"] / r["former"]["dt_s"], r["former"]["dt_s"])),
        ("time steps to CMOD 0.2 mm, default / former", lambda r: "%d / %d" % (r["default"]["time_steps"], r["former"]["time_steps"])),
        ("CPU time, default / former", lambda r: "%.1f / %.1f s" % (r["default"]["cpu_s"], r["former"]["cpu_s"])),
        ("peak load, default / former", lambda r: "%.1f / %.1f N" % (r["default"]["peak_load_N"], r["former"]["peak_load_N"])),
    ]
    lines = ["| half-notched D = 50 mm, ramp 50 ms | " + " | ".join("dx = %g mm" % (1e3 * float(k.split("_")[1])) for k in keys) + " |",
             "|---|" + "---|" * len(keys)]
    lines += ["| %s | %s |" % (name, col(f)) for name, f in rows]
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dx", type=float, nargs="+", default=[1e-2, 5e-3])
    ap.add_argument("--bisect", type=int, default=7, help="bisection steps on the safety between the default and 1.1")
    ap.add_argument("--numpy-max-dofs", type=int, default=12000, help="largest free dof count for numpy's dense eigenvalues (dx = 5 mm: 10,400, about 15 minutes)")
    ap.add_argument("--report", action="store_true", help="only rewrite the table from dt_stability.json")
    a = ap.parse_args()
    res = load_results(JSON)
    if not a.report:
        if not os.path.exists(EXE):
            sys.exit("build pdimplicit first: %s" % EXE)
        for dx in a.dx:
            res = store_result(JSON, "dx_%g" % dx, study(dx, a.bisect, a.numpy_max_dofs))
    md = ("# Explicit time step: largest eigenvalue of M^-1 K and the stability limit\n\n"
          "Written by `benchmarks/dt_stability.py` from `dt_stability.json` (`options/gregoire_d50_hn.opts`, "
          "`-pd_mode explicit -pd_ramp_time 0.05`, one rank; CPU times with the two cores shared).\n\n" + table(res))
    with open(os.path.join(OUT, "dt_stability.md"), "w") as f:
        f.write(md)
    if not a.report:
        print(md)


if __name__ == "__main__":
    main()
