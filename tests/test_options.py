"""Strict options and output that survives: unknown and unused -pd_ options, gaps in the numbering of
regions and materials, -help, the options echo, hostile scene names, the output directory, and a run
stopped by a signal, killed, or failed. Run one case: test_options.py
misspelt|numbering|help|names|output_dir|interrupt|killed"""
import csv
import json
import re
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

from pdtest import ENV, EXE, check, run, scene

COLUMNS = 18  # curve.csv


def bad(name, args, *needles):
    """A run that must stop as bad input: exit status 2, every needle in its one-line message, no output."""
    out = os.path.join(tempfile.mkdtemp(prefix="pdopt_"), "out")
    r = run(name, *args, expect_ok=False, outdir=out)
    line = next((l for l in r.stderr.splitlines() if "error" in l), "")
    check(r.returncode == 2 and all(n in line for n in needles) and not os.path.exists(out),
          "%-32s exit %d, no output, says: %s" % (" ".join(args)[:32], r.returncode, line[:150]))
    shutil.rmtree(os.path.dirname(out))


# (scene, extra options, texts the message must hold)
MISSPELT = [
    ("cantilever", ["-pd_dxx", "0.02"], ["-pd_dxx", "did you mean -pd_dx?"]),
    ("cantilever", ["-pd_lawx", "linear"], ["-pd_lawx", "did you mean -pd_law?"]),
    ("cantilever", ["-pd_region1_forse", "0,0,-1"], ["-pd_region1_forse", "did you mean -pd_region1_force?"]),
    ("gregoire_d50_hn", ["-pd_arclenght_type", "cmod"], ["-pd_arclenght_type", "did you mean -pd_arclength_type?"]),
    # valid options where the scene does not use them
    ("cantilever", ["-pd_ramp_time", "0.05"], ["-pd_ramp_time", "explicit"]),
    ("gregoire_d50_hn", ["-pd_control_fallback", "false", "-pd_stop_fraction", "0.1"], ["-pd_stop_fraction", "path following"]),
    ("cantilever", ["-pd_stop_fraction", "0.1"], ["-pd_stop_fraction", "path following"]),  # no damage: no fallback
    ("cantilever", ["-pd_control_fallback", "false"], ["-pd_control_fallback", "a scene with damage"]),
    ("gregoire_d50_hn", ["-pd_mode", "explicit", "-pd_limiter_max_bonds", "3"], ["-pd_limiter_max_bonds", "implicit"]),
    ("gregoire_d50_hn", ["-pd_nonlinear_k", "20", "-pd_law", "trilinear"], ["-pd_nonlinear_k", "non-linear law"]),
    ("cantilever", ["-pd_thickness", "0.1"], ["-pd_thickness", "2D"]),
    ("cantilever", ["-pd_region1_displacement", "0,0,1e-3"], ["-pd_region1_displacement", "displacement regions"]),
    ("gregoire_d50_hn", ["-pd_control_fallback", "false", "-pd_augmented_ksp_monitor"], ["-pd_augmented_ksp_monitor", "augmented"]),
]
NUMBERING = [
    ("cantilever", ["-pd_region7_box", "0,0,0,0.1,0.1,0.1", "-pd_region7_kind", "monitor"], ["-pd_region7_", "no region 2"]),
    ("cantilever", ["-pd_region2_kind", "monitor"], ["-pd_region2_kind", "region 2 has no -pd_region2_box"]),
    ("cantilever", ["-pd_region16_box", "0,0,0,0.1,0.1,0.1"], ["-pd_region16_box", "0 to 15"]),
    ("cantilever", ["-pd_material2_box", "0.5,0,0,1,0.1,0.1"], ["-pd_material2_box", "no material 1"]),
    ("cantilever", ["-pd_material8_box", "0.5,0,0,1,0.1,0.1"], ["-pd_material8_box", "1 to 7"]),
    ("cantilever", ["-pd_material0_E", "1e9"], ["-pd_material0_E", "-pd_E"]),
    ("gregoire_d50_hn", ["-pd_notch8_box", "0.05,0,0,0.05,0.05,0.01"], ["-pd_notch8_box", "0 to 7"]),
    ("gregoire_d50_hn", ["-pd_notch2_box", "0.05,0,0,0.05,0.05,0.01"], ["-pd_notch2_box", "no notch 1", "notches are numbered"]),
]


def misspelt():
    for name, args, needles in MISSPELT:
        bad(name, args, *needles)


def numbering():
    for name, args, needles in NUMBERING:
        bad(name, args, *needles)


def schema_names():
    """Every option of the schema as -help shows it, from the generated Markdown table."""
    out = subprocess.run([EXE, "-pd_help_markdown"], capture_output=True, text=True, env=ENV, check=True).stdout
    names = []
    for line in out.splitlines():
        if line.startswith("| `-pd"):
            names.append(line.split("|")[1].strip().replace("`", ""))
    return names


def help_text(*args):
    out = os.path.join(tempfile.mkdtemp(prefix="pdopt_"), "out")
    t0 = time.time()
    p = subprocess.run([EXE, *args, "-pd_output_dir", out, "-help"], capture_output=True, text=True, env=ENV)
    wall = time.time() - t0
    created = os.path.exists(out)
    shutil.rmtree(os.path.dirname(out))
    return p, wall, created


def option_block(text, name):
    """The lines -help prints for one option, from its name to the next blank line."""
    lines = text.splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("  %s <" % name))
    end = next((i for i in range(start, len(lines)) if not lines[i].strip()), len(lines))
    return " ".join(l.strip() for l in lines[start:end])


def help_():
    names = schema_names()
    check(len(names) >= 85 and "-pd_dx" in names and "-pd_regionK_box" in names and "-pd_E, -pd_materialK_E" in names,
          "the schema lists %d options" % len(names))
    p, wall, created = help_text("-options_file", scene("gregoire_d50_hn"))
    check(p.returncode == 0 and wall < 10 and not created, "-help: exit %d in %.1f s, no output directory" % (p.returncode, wall))
    missing = [n for n in names if "  %s <" % n not in p.stdout]
    check(not missing, "-help lists every schema option (missing: %s)" % missing[:5])
    check("constrained dofs" not in p.stdout and "results in" not in p.stdout and "Scene read: gregoire_d50_hn" in p.stdout,
          "-help read the scene and built nothing")
    dx, ramp, region = option_block(p.stdout, "-pd_dx"), option_block(p.stdout, "-pd_ramp_time"), option_block(p.stdout, "-pd_regionK_kind")
    check("<real (m)>" in dx and "required" in dx and "(0, inf)" in dx and "This scene reads it: -pd_dx = 0.005" in dx, "-pd_dx: " + dx[:160])
    check("default: 0" in ramp and "This scene does not use it" in ramp, "-pd_ramp_time: " + ramp[-80:])
    check("-pd_region2_kind = displacement" in region, "-pd_regionK_kind: " + region[-100:])
    p, wall, created = help_text()
    check(p.returncode == 0 and not created and "No scene read" in p.stdout, "-help without a scene: exit %d, lists the options" % p.returncode)
    p, wall, created = help_text("-options_file", scene("cantilever"), "-pd_dxx", "1")
    check(p.returncode == 0 and not created and "did you mean -pd_dx?" in p.stdout, "-help with a misspelt option: exit 0, names it")


def names():
    # a hostile scene name: valid JSON, XML and SVG, and the name read back unchanged
    for name in ['a"<&b', "b\u00e9ton 'x' > y \u2713"]:
        r = run("cantilever", "-pd_dx", "0.02", "-pd_name", name)
        s = r.summary
        check(s["scene"] == name and s["options"]["-pd_name"] == name, "summary.json parses, scene %r" % s["scene"])
        grid = ET.parse(os.path.join(r.dir, "fields.xmf")).getroot().find("Domain/Grid")
        check(grid.get("Name") == name, "fields.xmf parses, grid %r" % grid.get("Name"))
        svg = ET.parse(os.path.join(r.dir, "curve.svg")).getroot()
        titles = [t.text for t in svg.iter("{http://www.w3.org/2000/svg}text")]
        check(name in titles, "curve.svg parses, title %r" % titles[0])
        opts = s["options"]
        check(opts["-pd_dx"] == 0.02 and opts["-pd_horizon_ratio"] > 3.14 and opts["-pd_region1_force"] == [0, 0, -1e4]
              and opts["-pd_region0_kind"] == "support" and "-pd_ramp_time" not in opts
              and "-pd_name" in s["options_given"] and "-pd_horizon_ratio" not in s["options_given"],
              "summary.json echoes the options the scene read (%d of them, %d given)" % (len(opts), len(s["options_given"])))
    # a name that would leave the output root: refused, nothing written anywhere under the working directory
    for name in ["../../x", "a/b", "..", "x\ty"]:
        cwd = tempfile.mkdtemp(prefix="pdopt_")
        work = os.path.join(cwd, "a", "b")
        os.makedirs(work)
        p = subprocess.run([EXE, "-options_file", scene("cantilever"), "-pd_dx", "0.02", "-pd_name", name], cwd=work, capture_output=True,
                           text=True, env=ENV)
        left = sorted(os.path.join(d, f) for d, ds, fs in os.walk(cwd) for f in ds + fs)
        check(p.returncode == 2 and "-pd_name" in p.stderr and left == [os.path.join(cwd, "a"), work],
              "-pd_name %r: exit %d, nothing written: %s" % (name, p.returncode, p.stderr.strip()[:100]))
        shutil.rmtree(cwd)


def output_dir():
    tmp = tempfile.mkdtemp(prefix="pdopt_")
    afile = os.path.join(tmp, "afile")
    with open(afile, "w") as f:
        f.write("keep\n")
    for out in (afile, os.path.join(afile, "sub")):
        r = run("cantilever", "-pd_dx", "0.02", expect_ok=False, outdir=out)
        check(r.returncode == 2 and "-pd_output_dir" in r.stderr and "not a directory" in r.stderr and open(afile).read() == "keep\n",
              "-pd_output_dir %s: exit %d: %s" % (out.replace(tmp, "..."), r.returncode, r.stderr.strip()[:120]))
    shutil.rmtree(tmp)


def read_curve(path):
    with open(path) as f:
        text = f.read()
    rows = list(csv.reader(text.splitlines())) or [[]]  # the file may be created but not yet written
    return rows[0], rows[1:], text.endswith("\n")


def start_softening(rows):
    """Starts the half-notched beam at dx = 10 mm and waits until curve.csv holds rows steps (or the run ends)."""
    outdir = tempfile.mkdtemp(prefix="pdtest_")
    p = subprocess.Popen([EXE, "-options_file", scene("gregoire_d50_hn"), "-pd_dx", "1e-2", "-pd_output_dir", outdir],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=ENV)
    curve, seen, t_end = os.path.join(outdir, "curve.csv"), 0, time.time() + 120
    while p.poll() is None and time.time() < t_end and seen < rows:
        time.sleep(0.02)
        if os.path.exists(curve):
            seen = len(read_curve(curve)[1])
    return outdir, p, curve, seen


def interrupt():
    # a softening run stopped by a signal after a few steps: curve.csv was written row by row while it ran,
    # and holds exactly the steps done; summary.json parses and says interrupted; exit status 1
    for sig in (signal.SIGINT, signal.SIGHUP):
        outdir, p, curve, seen = start_softening(4)
        check(p.poll() is None and seen >= 4, "%s: %d rows in curve.csv while the run goes on" % (sig.name, seen))
        p.send_signal(sig)
        err = p.communicate(timeout=300)[1].decode()
        check(p.returncode == 1, "%s: exit status %d (1: stopped early)" % (sig.name, p.returncode))
        with open(os.path.join(outdir, "summary.json")) as f:
            s = json.load(f)
        # between steps, or inside the next one (Newton and Krylov iterations look for the signal too)
        check(re.match(r"interrupted by %s (after step %d|during step %d \(the curve ends at step %d\))$" % (
            sig.name, s["steps"], s["steps"] + 1, s["steps"]), s["status"]) and not s["converged"], "status: %s" % s["status"])
        header, rows, whole = read_curve(curve)
        steps = [int(r[0]) for r in rows]
        check(len(header) == COLUMNS and whole and all(len(r) == COLUMNS for r in rows) and steps == list(range(1, s["steps"] + 1))
              and s["steps"] >= seen, "curve.csv: %d complete rows, steps 1 to %d" % (len(rows), s["steps"]))
        tmp = [f for f in os.listdir(outdir) if f.endswith(".tmp")]
        check(not tmp and os.path.exists(os.path.join(outdir, "fields.h5")), "fields written, no temporary file left (%s)" % tmp)
        check("interrupted" in err, "stderr says so: %s" % err.strip().splitlines()[-1])
        shutil.rmtree(outdir)


def interrupt_step():
    # SIGTERM inside a long step ends the run within seconds, not at the step's end; the curve holds no row,
    # the summary says where. The step: the half-notched beam loaded in one increment, with the limiter
    # granting two bond events per Newton iteration (a fixed cap, so that the step stays long whatever the
    # default cap)
    outdir = tempfile.mkdtemp(prefix="pdtest_")
    p = subprocess.Popen([EXE, "-options_file", scene("gregoire_d50_hn"), "-pd_steps", "1", "-pd_dlambda_max", "1", "-pd_limiter_max_bonds", "2",
                          "-pd_output_dir", outdir],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=ENV)
    time.sleep(3)
    check(p.poll() is None, "the step is under way after 3 s")
    t0 = time.time()
    p.send_signal(signal.SIGTERM)
    p.communicate(timeout=300)
    waited = time.time() - t0
    s = json.load(open(os.path.join(outdir, "summary.json")))
    check(p.returncode == 1 and s["status"] == "interrupted by SIGTERM during step 1 (the curve ends at step 0)" and s["steps"] == 0,
          "exit %d, status %r" % (p.returncode, s["status"]))
    header, rows, whole = read_curve(os.path.join(outdir, "curve.csv"))
    check(len(header) == COLUMNS and not rows and whole, "curve.csv: the header, no row")
    check(waited < 5, "stopped %.2f s after the signal (within 5 s; the step alone takes over 10 s)" % waited)
    shutil.rmtree(outdir)


def killed():
    # SIGKILL cannot be caught: the rows flushed so far are all that is left, and they are whole
    outdir, p, curve, seen = start_softening(3)
    p.kill()
    p.communicate()
    header, rows, whole = read_curve(curve)
    check(p.returncode == -signal.SIGKILL and len(rows) >= 3 and whole and all(len(r) == COLUMNS for r in rows),
          "SIGKILL after %d steps: curve.csv keeps %d whole rows" % (seen, len(rows)))
    shutil.rmtree(outdir)
    # an error during the solve (here an unknown Krylov method): one line, exit status 1, and a summary
    r = run("cantilever", "-pd_dx", "0.02", "-ksp_type", "no_such_method", expect_ok=False)
    s = r.summary
    check(r.returncode == 1 and s["status"].startswith("failed: ") and "no_such_method" in s["status"] and not s["converged"],
          "a failed solve: exit %d, summary status %r" % (r.returncode, s["status"]))


CASES = {"misspelt": misspelt, "numbering": numbering, "help": help_, "names": names, "output_dir": output_dir, "interrupt": interrupt,
         "interrupt_step": interrupt_step, "killed": killed}

if __name__ == "__main__":
    for case in sys.argv[1:] or list(CASES):
        CASES[case]()
