"""The tables in docs/benchmarks agree with their committed data: every benchmark script's --report is run
into a scratch folder (PD_REPORT_DIR) from the committed JSON, and the tables it writes must equal the
committed ones byte for byte; elastic.md must hold elastic_table.md's rows (it quotes them)."""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOCS = os.path.join(ROOT, "docs", "benchmarks")
# script -> the tables its --report writes
REPORTS = {"accuracy_cost.py": ["accuracy_cost.md"], "gregoire.py": ["gregoire.md"], "size_effect.py": ["size_effect_table.md"],
           "elastic.py": ["elastic_table.md"], "solve_profile.py": ["solve_profile.md"], "dt_stability.py": ["dt_stability.md"],
           "explicit_ramp.py": ["explicit_ramp.md"], "explicit_beam.py": ["explicit_beam.md"], "hard_cases.py": ["hard_cases.md"], "blas.py": ["blas.md"],
           "rc_beam.py": ["rc_beam.md"], "pullout.py": ["pullout.md"], "calibration.py": ["calibration.md"],
           "halfnotched.py": ["halfnotched.md"], "pc_refresh.py": ["pc_refresh.md"],
           "compression.py": ["compression.md"], "crosscheck.py": ["crosscheck.md"],
           "partition.py": ["partition.md"], "scaling.py": ["scaling.md"], "stuttgart.py": ["stuttgart.md"],
           "softening_convergence.py": ["softening_convergence.md"], "targets.py": ["targets.md"], "memory.py": ["memory.md"],
           "build_profile.py": ["build_profile.md"], "implex_step.py": ["implex_step.md"]}


def main():
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, PD_REPORT_DIR=tmp, MPLBACKEND="Agg")
        for script, tables in REPORTS.items():
            r = subprocess.run([sys.executable, os.path.join(ROOT, "benchmarks", script), "--report"], env=env, capture_output=True, text=True)
            if r.returncode:
                failures.append("%s --report failed: %s" % (script, r.stderr.strip()[-300:]))
                continue
            for t in tables:
                new, old = open(os.path.join(tmp, t)).read(), open(os.path.join(DOCS, t)).read()
                if new != old:
                    diff = [l for l in new.splitlines() if l not in old.splitlines()][:3]
                    failures.append("%s differs from what %s writes from its data, e.g. %s" % (t, script, diff))
        quoted = open(os.path.join(DOCS, "elastic.md")).read().splitlines()
        missing = [l for l in open(os.path.join(DOCS, "elastic_table.md")).read().splitlines() if l.startswith("|") and l not in quoted]
        if missing:
            failures.append("elastic.md lacks %d rows of elastic_table.md, e.g. %s" % (len(missing), missing[0]))
    for f in failures:
        print("FAIL:", f)
    print("%d tables checked, %d failures" % (sum(map(len, REPORTS.values())) + 1, len(failures)))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
