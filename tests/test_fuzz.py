"""Fuzz table of bad input, generated from the option schema (build/pdimplicit -pd_help_markdown): for
every -pd_ option a value of the wrong type, values just outside its range, and a misspelt name, each
given to a scene where the option applies, on 1 and 2 ranks. Every case must stop with exit status 2,
name the option in its message and leave no output directory; a crash, a hang (no exit within
HANG_S seconds), a silent acceptance or another option blamed is a failure. Prints the totals.

The generated set has over 400 cases; CTest runs every fourth of them (over 100, each on 1 and 2 ranks) to
keep the suite short, --all runs every one.

Usage: test_fuzz.py [--all] [--ranks 1 2] [--table FILE]   (FILE: a Markdown table of every run and its outcome)
"""
import argparse
import os
import re
import shutil
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor

from pdtest import ENV, EXE, MPIEXEC, check, scene

HANG_S = 60
# where each "applies to" text of the schema is true: a scene and the options that switch the option on
GREGOIRE = [scene("gregoire_d50_hn"), "-pd_dx", "0.01"]
CANTILEVER = [scene("cantilever")]
CONTEXTS = [
    ("2D models", [scene("bar_tension_2d")]),
    ("finite kinematics", CANTILEVER + ["-pd_kinematics", "finite"]),
    ("zaccariotto form", GREGOIRE + ["-pd_law", "bilinear", "-pd_bilinear_form", "zaccariotto"]),
    ("bilinear law", GREGOIRE + ["-pd_law", "bilinear"]),
    ("trilinear law", GREGOIRE + ["-pd_law", "trilinear"]),
    ("non-linear law", GREGOIRE + ["-pd_law", "nonlinear"]),
    ("cylinders", CANTILEVER + ["-pd_void0_cylinder", "0.5,0.05,0.05,0.03", "-pd_void0_axis", "y"]),
    ("displacement regions", GREGOIRE),
    ("force regions", CANTILEVER),
    ("with -pd_unload_at", GREGOIRE + ["-pd_control", "arclength", "-pd_unload_at", "0.5"]),
    ("cmod or dissipation", GREGOIRE + ["-pd_control", "arclength", "-pd_arclength_type", "cmod"]),
    ("path following", GREGOIRE + ["-pd_control", "arclength"]),
    ("load or displacement control", GREGOIRE),
    ("explicit path", CANTILEVER + ["-pd_mode", "explicit"]),
    ("failure search", [scene("gregoire_d50_hn_failure"), "-pd_dx", "0.01"]),
    ("", CANTILEVER),
]
# family members the base scenes have: the cantilever's load region is region 1, the beam's region 2
MEMBER = {"material": "1", "notch": "0", "region": "1", "void": "0"}
MEMBER_SCENE = {"material": ["-pd_material1_box", "0,0,0,0.5,0.1,0.1"], "notch": [], "region": [], "void": []}
# not fuzzed here: a prefix for PETSc's options, flags that end the run at once, paths (tests/test_options.py,
# tests/test_bad_input.py) and shapes, whose bad values tests/test_bad_input.py lists one by one
SKIP = {"-pd_augmented_*", "-pd_help_markdown", "-pd_output_dir", "-pd_restart", "-pd_materialK_box", "-pd_notchK_box",
        "-pd_regionK_box", "-pd_regionK_cylinder", "-pd_voidK_box", "-pd_voidK_cylinder"}


def schema():
    """(name, type, range, applies-to) of every option in -pd_help_markdown's table; a material option is
    listed as -pd_X, `-pd_materialK_X`: both forms are kept."""
    out = subprocess.run([EXE, "-pd_help_markdown"], capture_output=True, text=True, env=ENV).stdout
    rows = []
    for line in out.splitlines():
        cells = [c.strip() for c in line.split("|")]
        if len(cells) < 7 or not cells[1].startswith("`-pd_"):
            continue
        for name in re.findall(r"`(-pd_[^`]+)`", cells[1]):
            rows.append((name, cells[2], cells[4], cells[5]))
    return rows


def context(name, when):
    base = next(args for key, args in CONTEXTS if key in when)
    m = re.match(r"-pd_(material|notch|region|void)K(_.*)", name)
    if not m:
        return base, name
    fam, rest = m.groups()
    if fam == "region" and "displacement" in rest:
        return GREGOIRE, "-pd_region2" + rest
    return base + MEMBER_SCENE[fam], "-pd_%s%s%s" % (fam, MEMBER[fam], rest)


def bad_values(typ, rng):
    """Values of the wrong type, and the nearest ones outside a range [a, b] / (a, b)."""
    if typ.startswith("real ") or typ == "real":
        vals = ["abc", "nan", "1e999", "2x"]
    elif typ == "integer":
        vals = ["abc", "1.5", "99999999999999999999"]
    elif typ == "true/false":
        return ["maybe"]
    elif typ.startswith("reals"):
        return ["abc", "1,nan,0"]
    elif typ.startswith("integers"):
        return ["abc", "1,1.5", "1,-1"]
    elif typ.startswith("`"):
        return ["bogus"]
    else:
        return []
    m = re.match(r"([\[(])(-?[0-9.e+]+|-inf), (-?[0-9.e+]+|inf)([\])])", rng)
    if m:
        lo_b, lo, hi, hi_b = m.groups()
        if lo != "-inf":
            vals.append(lo if lo_b == "(" else repr(float(lo) - 1e-3 * max(1, abs(float(lo)))) if typ != "integer" else str(int(float(lo)) - 1))
        if hi != "inf":
            vals.append(hi if hi_b == ")" else repr(float(hi) + 1e-3 * max(1, abs(float(hi)))) if typ != "integer" else str(int(float(hi)) + 1))
        else:
            vals.append("inf")
    return vals


def cases():
    out = []
    for name, typ, rng, when in schema():
        if name in SKIP:
            continue
        base, opt = context(name, when)
        for v in bad_values(typ, rng):
            out.append((base, [opt, v], opt))
        if not re.search(r"K_|_\*", name):
            out.append((base, [opt + "x", "1"], opt + "x"))  # misspelt: unknown, with a suggestion
    # text values with a meaning to check
    out += [(CANTILEVER, ["-pd_name", "a/b"], "-pd_name"), (CANTILEVER, ["-pd_name", ".."], "-pd_name"),
            (CANTILEVER, ["-pd_name", ""], "-pd_name"), (CANTILEVER, ["-pd_region0_dofs", "w"], "-pd_region0_dofs"),
            (GREGOIRE, ["-pd_data_file", "/nonexistent.csv"], "-pd_data_file"),
            (GREGOIRE + ["-pd_control", "arclength"], ["-pd_restart", "/nonexistent.h5"], "-pd_restart"),
            (CANTILEVER, ["-pd_load_region", "7"], "-pd_load_region"), (CANTILEVER, ["-pd_disp_region", "-1"], "-pd_disp_region"),
            (CANTILEVER, ["-pd_load_region", "1,1"], "-pd_load_region"),
            # a force and a displacement region cannot add up to one load
            (CANTILEVER + ["-pd_region2_box", "0.5,0,0.1,0.5,0.1,0.1", "-pd_region2_kind", "displacement", "-pd_region2_dofs", "z",
                           "-pd_region2_displacement", "0,0,-1e-3"], ["-pd_load_region", "1,2"], "-pd_load_region"),
            (CANTILEVER, ["-pd_region17_box", "0,0,0,1,0.1,0.1"], "-pd_region17_box"),
            (CANTILEVER, ["-pd_materialx_E", "1e9"], "-pd_materialx_E")]
    return out


def run_case(case, ranks):
    base, args, needle = case
    out = os.path.join(tempfile.mkdtemp(prefix="pdfuzz_"), "out")
    cmd = [EXE, "-options_file"] + base[:1] + base[1:] + ["-pd_dry_run", "-pd_output_dir", out] + args
    if ranks > 1:
        cmd = [MPIEXEC, "-n", str(ranks)] + cmd
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=HANG_S)
        code, err = p.returncode, p.stderr
    except subprocess.TimeoutExpired:
        code, err = None, ""
    if code is None:
        outcome = "hang"
    elif code == 0:
        outcome = "accepted"
    elif code == 2 and needle in err and not os.path.exists(out):
        outcome = "clean"
    elif code == 2 and needle not in err:
        outcome = "other option blamed"
    elif code == 2:
        outcome = "output left"
    elif code < 0 or code > 128 or "Caught signal" in err or "SEGV" in err:
        outcome = "crash"
    else:
        outcome = "exit %d" % code
    shutil.rmtree(os.path.dirname(out), ignore_errors=True)
    line = next((l.strip() for l in err.splitlines() if "error" in l), err.strip().splitlines()[-1] if err.strip() else "")
    return {"ranks": ranks, "options": " ".join(args), "context": " ".join(a for a in base[1:]), "outcome": outcome, "message": line[:160]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--table")
    ap.add_argument("--all", action="store_true")
    a = ap.parse_args()
    table = cases()
    if not a.all:
        table = table[::4]
    # the scenes the cases start from are good input themselves: a case fails for its own option only
    for base in {tuple(c[0]) for c in table}:
        r = run_case((list(base), [], ""), 1)
        check(r["outcome"] == "accepted", "context accepted: %s" % (" ".join(base[1:]) or os.path.basename(base[0])))
    results = []
    for ranks in a.ranks:
        # mpiexec start-up is mostly waiting: several cases at once keep the two cores busy
        with ThreadPoolExecutor(max_workers=4 if ranks == 1 else 8) as pool:
            results += list(pool.map(lambda c: run_case(c, ranks), table))
    totals = {}
    for r in results:
        totals[r["outcome"]] = totals.get(r["outcome"], 0) + 1
    print("fuzz: %d cases x ranks %s = %d runs: %s" % (len(table), a.ranks, len(results),
                                                     ", ".join("%s %d" % kv for kv in sorted(totals.items()))))
    if a.table:
        with open(a.table, "w") as f:
            f.write("| ranks | options | scene options | outcome | message |\n|---|---|---|---|---|\n")
            for r in results:
                f.write("| %d | `%s` | %s | %s | %s |\n" % (r["ranks"], r["options"], r["context"], r["outcome"], r["message"].replace("|", "\\|")))
    bad = [r for r in results if r["outcome"] != "clean"]
    for r in bad[:40]:
        print("  %d rank(s) %-50s %-20s %s" % (r["ranks"], r["options"][:50], r["outcome"], r["message"][:100]))
    check(len(table) >= 100, "%d distinct bad inputs (at least 100) of the %d generated" % (len(table), len(cases())))
    check(not bad, "every case exits 2 naming its option, with no output left: %d of %d runs do not" % (len(bad), len(results)))


if __name__ == "__main__":
    main()
