"""Helpers shared by the scene regression tests: run pdimplicit, read its outputs, assert with context."""
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXE = os.environ.get("PDIMPLICIT", os.path.join(ROOT, "build", "pdimplicit"))
MPIEXEC = os.environ.get("MPIEXEC", "mpiexec")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")


def scene(name):
    return os.path.join(ROOT, "options", name + ".opts")


class Run:
    def __init__(self, outdir, proc):
        self.dir = outdir
        self.proc = proc
        self.returncode = proc.returncode
        self.stdout = proc.stdout
        self.stderr = proc.stderr

    @property
    def summary(self):
        with open(os.path.join(self.dir, "summary.json")) as f:
            return json.load(f)

    @property
    def curve(self):
        with open(os.path.join(self.dir, "curve.csv")) as f:
            return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]

    def fields(self, step=None):
        import h5py
        import numpy as np
        with h5py.File(os.path.join(self.dir, "fields.h5"), "r") as f:
            g = f["fields"]
            steps = sorted(k for k in g if k.startswith("displacement_"))
            key = steps[-1] if step is None else "displacement_%06d" % step
            return np.array(g["coordinates"]), np.array(g[key]), np.array(g[key.replace("displacement", "damage")])

    def field(self, name, step=None):
        """A scalar field of fields.h5 (damage, steel_stress, ...) at a step (the last written by default)."""
        import h5py
        import numpy as np
        with h5py.File(os.path.join(self.dir, "fields.h5"), "r") as f:
            g = f["fields"]
            key = sorted(k for k in g if k.startswith(name + "_"))[-1] if step is None else "%s_%06d" % (name, step)
            return np.array(g[key])


def run(scene_name, *args, ranks=1, expect_ok=True, outdir=None):
    """Runs a scene with extra options; returns a Run. Output goes to a fresh directory."""
    outdir = outdir or tempfile.mkdtemp(prefix="pdtest_")
    cmd = [EXE]
    if scene_name:
        cmd += ["-options_file", scene(scene_name)]
    cmd += ["-pd_output_dir", outdir] + [str(a) for a in args]
    if ranks > 1:
        cmd = [MPIEXEC, "-n", str(ranks)] + cmd
    start = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
    if os.environ.get("PDTEST_TIMES"):  # where a test's time goes: each run's wall time and options
        print("[%.1f s] %s" % (time.monotonic() - start, " ".join(str(a) for a in args)), file=sys.stderr)
    r = Run(outdir, proc)
    if expect_ok and proc.returncode != 0:
        fail("run failed (%d): %s\n%s\n%s" % (proc.returncode, " ".join(cmd), proc.stdout[-3000:], proc.stderr[-3000:]))
    return r


def run_both(first, second):
    """Runs two scenes at once, each given as (scene name, options...): a test comparing two long runs takes the time
    of the longer (its CTest entry claims two processors). Returns both Runs."""
    from concurrent.futures import ThreadPoolExecutor
    with ThreadPoolExecutor(2) as pool:
        return tuple(pool.map(lambda c: run(c[0], *c[1:]), (first, second)))


def translated(scene_name, offset):
    """Options that move a scene's domain and every box, gauge point and cylinder centre of it by offset
    (m) along each axis."""
    args = []
    with open(scene(scene_name)) as f:
        for line in f:
            t = line.split()
            if len(t) != 2 or not (t[0] in ("-pd_domain", "-pd_cmod_points") or t[0].endswith(("_box", "_cylinder"))):
                continue
            v = [float(x) for x in t[1].split(",")]
            moved = len(v) - 1 if t[0].endswith("_cylinder") else len(v)  # a cylinder's radius stays
            args += [t[0], ",".join(repr(x + offset if k < moved else x) for k, x in enumerate(v))]
    return args


def mass_scaled_eigenvalue(scene_name, dx, *args, max_dofs=None):
    """Largest eigenvalue of M^-1 K on the free dofs of a 3D scene at spacing dx, by numpy's dense symmetric
    solver: the stiffness written by an elastic implicit run with PETSc's binary viewer after its solve (-ksp_view_mat) (AIJ, 32-bit indices,
    big-endian; the bond constants do not depend on the law), free dofs the rows with a non-zero
    off-diagonal entry (constrained rows hold bc_scale alone), M = rho dx^3 with the scene's -pd_rho.
    Returns (eigenvalue, free dofs); the eigenvalue is None above max_dofs free dofs (the dense solver is
    O(n^3): 13 minutes for 11,000 dofs with the reference BLAS)."""
    import numpy as np
    path = os.path.join(tempfile.mkdtemp(prefix="pdtest_"), "K.bin")
    run(scene_name, "-pd_dx", dx, *args, "-pd_law", "elastic", "-pd_steps", 1, "-pd_stop_cmod", 0, "-pd_mat_type", "aij",
        "-ksp_view_mat", "binary:" + path)
    with open(path, "rb") as f:
        classid, nrows, ncols, nnz = np.fromfile(f, ">i4", 4)
        if classid != 1211216:
            fail("%s is not a PETSc binary matrix" % path)
        rows = np.repeat(np.arange(nrows), np.fromfile(f, ">i4", nrows))
        cols = np.fromfile(f, ">i4", nnz)
        vals = np.fromfile(f, ">f8", nnz)
    free = np.zeros(nrows, bool)
    free[rows[(rows != cols) & (vals != 0)]] = True
    if max_dofs is not None and free.sum() > max_dofs:
        return None, int(free.sum())
    k = np.zeros((nrows, ncols))
    k[rows, cols] = vals
    rho = float([l.split()[1] for l in open(scene(scene_name)) if l.startswith("-pd_rho ")][0])
    return float(np.linalg.eigvalsh(k[np.ix_(free, free)])[-1] / (rho * float(dx) ** 3)), int(free.sum())


def peak(r):
    """Largest load on the run's curve (N)."""
    return max(row["load_N"] for row in r.curve)


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def check(cond, msg):
    print(("ok   " if cond else "FAIL ") + msg)
    if not cond:
        sys.exit(1)


def rel(a, b):
    return abs(a - b) / abs(b)


def experiment_peaks(name):
    """Largest loads (N) of the experimental mean, lower and upper curves in data/NAME (rows of CMOD in mm,
    then mean, min and max load in kN), as benchmarks/common.py reads them."""
    rows = [l for l in open(os.path.join(ROOT, "data", name)) if not l.startswith("#")][1:]
    rows = [[float(x) for x in l.split(",")] for l in rows]
    return tuple(1e3 * max(r[c] for r in rows) for c in (1, 2, 3))

