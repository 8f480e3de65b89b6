"""What the benchmark scripts share: where things are, how pdimplicit is started and timed, how results
are kept between runs, and the digitised experimental curves."""
import csv
import json
import os
import subprocess
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# PDIMPLICIT lets a long study run a copy of the binary while the build tree is rebuilt
EXE = os.environ.get("PDIMPLICIT", os.path.join(ROOT, "build", "pdimplicit"))
# committed results (JSON) are read from RESULTS_DIR; tables and plots go to OUT, the same folder unless
# PD_REPORT_DIR names another (tests/test_docs_tables.py regenerates the tables there and compares)
RESULTS_DIR = os.path.join(ROOT, "docs", "benchmarks")
OUT = os.environ.get("PD_REPORT_DIR", RESULTS_DIR)
# Open MPI refuses to start as root without these (CI runs as root)
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
# the BLAS/LAPACK libraries of Debian's alternatives, as LD_LIBRARY_PATH chooses them for one run
BLAS_DIRS = {"netlib": "/usr/lib/x86_64-linux-gnu/blas:/usr/lib/x86_64-linux-gnu/lapack",
             "openblas": "/usr/lib/x86_64-linux-gnu/openblas-serial"}


def system_blas():
    """Which BLAS a run gets without LD_LIBRARY_PATH: where Debian's libblas.so.3 alternative points."""
    return "openblas" if "openblas" in os.path.realpath("/usr/lib/x86_64-linux-gnu/libblas.so.3") else "netlib"


def curve_rows(outdir):
    """The rows of a run's curve.csv, every column a float."""
    with open(os.path.join(outdir, "curve.csv")) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def last_fields(outdir):
    """Node coordinates, displacement and nodal damage of the last fields a run wrote to outdir/fields.h5,
    or None where it wrote none (an explicit run that stops unstable)."""
    import h5py
    import numpy as np
    path = os.path.join(outdir, "fields.h5")
    if not os.path.exists(path):
        return None
    with h5py.File(path, "r") as f:
        g = f["fields"]
        key = sorted(k for k in g if k.startswith("displacement_"))[-1]
        return np.array(g["coordinates"]), np.array(g[key]), np.array(g[key.replace("displacement", "damage")]).ravel()


def run_timed(cmd, timeout, stdout, stderr=subprocess.STDOUT, grace=600):
    """Runs cmd (output to the open files given), stopped after timeout seconds: SIGTERM, on which
    pdimplicit finishes the step under way and writes what it traced (status 'interrupted'), then SIGKILL
    grace seconds later. Under mpiexec the signal goes to the ranks, not to mpiexec, which kills its ranks
    a second after forwarding it. Returns (exit code, wall s, CPU s, timed out). The CPU time is the
    child's own (wait4), which a second run sharing the two cores does not inflate as it does the wall
    time; under mpiexec it is None (measured, wait4 on Open MPI's mpiexec counted about half of what its
    two busy ranks used)."""
    t0 = time.time()
    p = subprocess.Popen(cmd, stdout=stdout, stderr=stderr, env=ENV)
    under_mpiexec = os.path.basename(cmd[0]) == "mpiexec"
    stop = (lambda: subprocess.run(["pkill", "-TERM", "-P", str(p.pid)])) if under_mpiexec else p.terminate
    timers = [threading.Timer(timeout, stop), threading.Timer(timeout + grace, p.kill)]
    for t in timers:
        t.start()
    _, status, ru = os.wait4(p.pid, 0)
    for t in timers:
        t.cancel()
    wall = time.time() - t0
    cpu = None if under_mpiexec else ru.ru_utime + ru.ru_stime
    return os.waitstatus_to_exitcode(status), wall, cpu, wall >= timeout


def run_scene(scene, args, timeout, prefix="pdbench_", ranks=1):
    """Runs pdimplicit on options/<scene>.opts with the further args, into a fresh output folder (its output in
    log.txt there), stopped after timeout seconds as run_timed says. Returns a dict: out (the folder), code, wall,
    cpu, timed_out, summary (summary.json, or None where the run wrote none) and rows (curve.csv's rows as
    floats, or None)."""
    out = tempfile.mkdtemp(prefix=prefix)
    cmd = [EXE, "-options_file", os.path.join(ROOT, "options", scene + ".opts"), "-pd_output_dir", out, *args]
    if ranks > 1:
        cmd = ["mpiexec", "-n", str(ranks)] + cmd
    with open(os.path.join(out, "log.txt"), "w") as log:
        code, wall, cpu, timed_out = run_timed(cmd, timeout, log)
    run = {"out": out, "code": code, "wall": wall, "cpu": cpu, "timed_out": timed_out, "summary": None, "rows": None}
    try:
        run["summary"] = json.load(open(os.path.join(out, "summary.json")))
        run["rows"] = curve_rows(out)
    except (OSError, ValueError):
        pass
    return run


def load_results(path):
    return json.load(open(path)) if os.path.exists(path) else {}


def save_results(path, res):
    """Writes a results file whole (temporary name, then rename): never left half written."""
    with open(path + ".tmp", "w") as f:
        json.dump(res, f, indent=1, sort_keys=True)
    os.replace(path + ".tmp", path)


def store_result(path, key, value):
    """Adds one run to a results file, merged into what is on disk, so that several studies can write the
    same file side by side. Returns the merged results."""
    res = load_results(path)
    res[key] = value
    save_results(path, res)
    return res


def experiment(name):
    """A digitised experimental curve in data/: rows of [CMOD (mm), mean, min, max load (kN)]."""
    rows = [l for l in open(os.path.join(ROOT, "data", name)) if not l.startswith("#")][1:]
    return [[float(x) for x in l.split(",")] for l in rows]


# the Gregoire D = 50 mm series' curves in data/, by beam
GREGOIRE_DATA = {"un": "gregoire2013_d50_un_load_cmod.csv", "hn": "gregoire2013_d50_hn_load_cmod.csv"}


def experiment_peaks(beam):
    """Largest loads (N) of a Gregoire beam's experimental mean, lower and upper curves, or Nones without data."""
    if beam not in GREGOIRE_DATA:
        return (None, None, None)
    rows = experiment(GREGOIRE_DATA[beam])
    return tuple(1e3 * max(r[c] for r in rows) for c in (1, 2, 3))


def plot_gregoire_experiment(ax, beam, mean=True):
    """Draws a Gregoire beam's experimental envelope (and its mean curve) on ax, in mm and N, where data/ has it."""
    if beam not in GREGOIRE_DATA:
        return
    d = experiment(GREGOIRE_DATA[beam])
    ax.fill_between([x[0] for x in d], [1e3 * x[2] for x in d], [1e3 * x[3] for x in d], color="0.85", label="experiment min-max")
    if mean:
        ax.plot([x[0] for x in d], [1e3 * x[1] for x in d], color="0.5", lw=1, label="experiment mean")


def curve_difference(a, b):
    """RMS load difference of run b against run a (dicts with a 'curve' of [CMOD, load] rows) over the CMOD
    range both reach, over a's peak."""
    import numpy as np
    ca, la = np.array(a["curve"]).T
    cb, lb = np.array(b["curve"]).T
    c = np.linspace(0, min(ca.max(), cb.max()), 400)
    return float(np.sqrt(np.mean((np.interp(c, ca, la) - np.interp(c, cb, lb)) ** 2)) / la.max())


def pyplot():
    """matplotlib's pyplot on its file-only backend: the reports write PNG files and open no window."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def save_figure(fig, name, dpi=100):
    """Lays the figure out, writes it beside the report (OUT) and closes it (a study rewrites its figures
    after every run)."""
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, name), dpi=dpi)
    pyplot().close(fig)


def write_lines(name, lines):
    """Writes a report's lines beside the others (OUT)."""
    with open(os.path.join(OUT, name), "w") as f:
        f.write("\n".join(lines) + "\n")
