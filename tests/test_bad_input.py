"""Bad input: each case exits with status 2 before any solve, names the offending option in its message,
and leaves no output behind."""
import os
import shutil
import tempfile

from pdtest import check, run

CASES = [
    # (scene, extra options, text the message must contain)
    ("cantilever", ["-pd_E", "-30e9"], "-pd_E"),
    ("cantilever", ["-pd_E", "0"], "-pd_E"),
    ("cantilever", ["-pd_dx", "-0.01"], "-pd_dx"),
    ("cantilever", ["-pd_dx", "0"], "-pd_dx"),
    ("cantilever", ["-pd_horizon_ratio", "0.8"], "-pd_horizon_ratio"),
    ("cantilever", ["-pd_horizon_ratio", "1e12"], "-pd_horizon_ratio"),  # a horizon past the whole body
    ("cantilever", ["-pd_region1_box", "2,0,0,2.1,0.1,0.1"], "-pd_region1_box"),
    ("cantilever", ["-pd_region0_box", "0.001,0.001,0.001,0.002,0.002,0.002"], "-pd_region0_box"),  # between nodes: empty
    ("cantilever", ["-pd_influence", "gaussian"], "-pd_influence"),
    # notches and voids that cut the body apart, found from the bond graph's connectivity
    ("cantilever", ["-pd_notch0_box", "0.5,0,0,0.5,0.1,0.1"], "-pd_notch0_box"),  # the whole section
    ("cantilever", ["-pd_notch0_box", "0.5,0,0,0.5,0.1,0.0999999"], "-pd_notch0_box"),  # a hair short of the top face
    ("cantilever", ["-pd_notch0_box", "0.5,0,0,0.5,0.1,0.06", "-pd_notch1_box", "0.5,0,0.05,0.5,0.1,0.1"], "-pd_notch1_box"),  # two that meet
    ("cantilever", ["-pd_notch0_box", "0.5,0,0,0.5,0.1,0.05", "-pd_void0_box", "0.49,0,0.04,0.6,0.1,0.1"], "-pd_void0_box"),  # notch + void
    ("cantilever", ["-pd_dx", "abc"], "-pd_dx"),
    # explicit step counts past any integer, found from the stable step before anything is written
    ("cantilever", ["-pd_mode", "explicit", "-pd_ramp_time", "1e6"], "-pd_ramp_time"),
    ("cantilever", ["-pd_mode", "explicit", "-pd_dt_safety", "1e-9"], "-pd_dt_safety"),  # the default ramp, in tiny steps
    # CMOD control of the explicit path needs a gauge, a positive opening and a servo slower than the body
    ("cantilever", ["-pd_mode", "explicit", "-pd_explicit_cmod", "1e-4"], "-pd_explicit_cmod"),
    ("gregoire_d50_hn", ["-pd_mode", "explicit", "-pd_explicit_cmod", "-1e-4"], "-pd_explicit_cmod"),
    ("gregoire_d50_hn", ["-pd_mode", "explicit", "-pd_explicit_cmod", "1e-4", "-pd_adr", "true"], "-pd_explicit_cmod"),
    ("gregoire_d50_hn", ["-pd_mode", "explicit", "-pd_explicit_cmod", "1e-4", "-pd_servo_bandwidth", "2"], "-pd_servo_bandwidth"),
    ("gregoire_d50_hn_failure", ["-pd_explicit_cmod", "1e-4"], "-pd_explicit_cmod"),
    ("cantilever", ["-pd_region1_force", "0,zero,-1e4"], "-pd_region1_force"),
    ("cantilever", ["-pd_region2_box", "-0.08,0,0,0,0.1,0.1", "-pd_region2_kind", "displacement", "-pd_region2_dofs", "z",
                    "-pd_region2_displacement", "0,0,1e-3"], "-pd_region2"),  # conflicts with the clamp
    ("cantilever", ["-pd_law", "plastic"], "-pd_law"),
    ("cantilever", ["-pd_steps", "0"], "-pd_steps"),
    ("cantilever", ["-pd_region1_kind", "pull"], "-pd_region1_kind"),
    ("cantilever", ["-pd_rho", "-1"], "-pd_rho"),
    ("cantilever", ["-pd_void0_box", "0.2,0,0,0.2,0.1,0.1"], "-pd_void0_box"),  # flat: a notch's job
    ("cantilever", ["-pd_void0_cylinder", "0.5,0.05,0,0.005", "-pd_void0_axis", "z"], "-pd_void0_cylinder"),  # between node centres
    ("cantilever", ["-pd_void0_box", "0.3,0,0,0.4,0.1,0.1", "-pd_void0_axis", "y"], "-pd_void0_axis"),  # a box has no axis
    ("cantilever", ["-pd_void0_box", "-1,-1,-1,2,2,2"], "-pd_void"),  # no material left
    ("cantilever", ["-pd_void0_box", "0.9,0,0,1.1,0.1,0.1"], "-pd_region1"),  # the load region lies in the void
    ("cantilever", ["-pd_void1_box", "0.3,0,0,0.4,0.1,0.1"], "-pd_void1_box"),  # numbering gap
    ("gregoire_d50_hn", ["-pd_cmod_points", "0.0775,0.025,0,0.3,0.025,0"], "-pd_cmod_points"),
    ("gregoire_d50_hn", ["-pd_data_file", "missing.csv"], "-pd_data_file"),
    ("gregoire_d50_hn", ["-pd_mode", "explicit", "-pd_dt_safety", "0"], "-pd_dt_safety"),
    ("gregoire_d50_hn", ["-pd_mode", "explicit", "-pd_damping", "-5"], "-pd_damping"),
    ("gregoire_d50_hn", ["-pd_mode", "dynamic"], "-pd_mode"),
    ("gregoire_d50_hn", ["-pd_control", "arclength", "-pd_unload_at", "1.5"], "-pd_unload_at"),
    ("gregoire_d50_hn", ["-pd_control", "arclength", "-pd_arclength_type", "dissipation", "-pd_unload_at", "0.5"], "-pd_unload_at"),
    ("gregoire_d50_hn", ["-pd_control", "arclength", "-pd_unload_at", "0.5", "-pd_reload_at", "0.6"], "-pd_reload_at"),
    ("gregoire_d50_hn", ["-pd_control", "arclength", "-pd_arclength_halved_its", "-3"], "-pd_arclength_halved_its"),
    ("gregoire_d50_hn", ["-pd_control", "arclength", "-pd_arclength_hold", "-1"], "-pd_arclength_hold"),
    ("gregoire_d50_hn", ["-pd_limiter_sublevels", "0"], "-pd_limiter_sublevels"),
    ("gregoire_d50_hn", ["-pd_fc", "10e6"], "-pd_fc"),  # below the lattice's own E s0 / nu = 15.6 MPa
    ("gregoire_d50_hn", ["-pd_fc", "-1"], "-pd_fc"),
    ("gregoire_d50_hn", ["-pd_pc_matrix", "definite"], "-pd_pc_matrix"),
    ("gregoire_d50_hn", ["-pd_mat_type", "baij", "-pc_type", "gamg"], "-pd_mat_type"),  # GAMG reads AIJ only
    ("gregoire_d50_hn", ["-pd_mat_type", "sbaij", "-pc_type", "lu"], "-pd_mat_type"),  # no LU of symmetric storage
    ("gregoire_d50_hn", ["-pd_mat_type", "sbaij", "-pc_type", "bjacobi", "-sub_pc_type", "ilu"], "-sub_pc_type ilu"),
    ("gregoire_d50_hn", ["-pd_mat_type", "baij", "-pc_type", "lu", "-pc_factor_mat_solver_type", "umfpack"], "umfpack"),  # AIJ only
    ("gregoire_d50_hn", ["-pd_pc_reach", "0.5"], "-pd_pc_reach"),  # shorter than the nearest neighbour
    ("gregoire_d50_hn", ["-pd_pc_reach", "2", "-pd_tangent_product", "matrix"], "-pd_pc_reach"),  # the matrix is the operator
    ("cantilever", ["-pd_pc_reach", "2"], "-pd_pc_reach"),  # linear: solved with the assembled matrix
    ("gregoire_d50_hn", ["-pd_control", "arclength", "-pd_arclength_implex", "1.5"], "-pd_arclength_implex"),
    ("gregoire_d50_hn", ["-pd_control", "arclength", "-pd_arclength_type", "dissipation", "-pd_arclength_implex", "0.01"],
     "-pd_arclength_implex"),
    # steel bars
    ("bar_prism", ["-pd_bar0_line", "0,0.05,0.05,0.4,0.09,0.05"], "-pd_bar0_line"),  # not along a lattice direction
    ("bar_prism", ["-pd_bar0_line", "0,0.05,0.05,0.5,0.05,0.05"], "-pd_bar0_line"),  # leaves the domain
    ("bar_prism", ["-pd_bar0_line", "0,0.05,0.05,0.4"], "-pd_bar0_line"),  # four numbers
    ("bar_prism", ["-pd_bar0_line", "0.1,0.05,0.05,0.11,0.05,0.05"], "-pd_bar0_line"),  # shorter than dx
    ("bar_prism", ["-pd_bar0_diameter", "-0.012"], "-pd_bar0_diameter"),
    ("bar_prism", ["-pd_bar0_hardening", "1"], "-pd_bar0_hardening"),
    ("bar_prism", ["-pd_bar0_rupture", "0.001"], "-pd_bar0_rupture"),  # below the yield strain 0.0025
    ("bar_prism", ["-pd_bar0_count", "0"], "-pd_bar0_count"),
    # bond slip
    ("pullout", ["-pd_bar0_fcm", "-38e6"], "-pd_bar0_fcm"),
    ("bar_prism", ["-pd_bar0_bond", "slip"], "-pd_bar0_fcm"),  # no f_cm and no -pd_fc to take it from
    ("pullout", ["-pd_bar0_slips", "3e-3,2e-3,7e-3"], "-pd_bar0_slips"),  # s1 above s2
    ("pullout", ["-pd_bar0_slips", "1e-3,2e-3"], "-pd_bar0_slips"),  # two numbers
    ("pullout", ["-pd_bar0_diameter", "0.003"], "-pd_bar0_slips"),  # the default s3 = 0.6 d below s2
    ("pullout", ["-pd_kinematics", "finite"], "-pd_bar0_bond"),
    ("bar_prism", ["-pd_region1_nodes", "bars"], "-pd_region1_nodes"),  # no bar with bond slip
    ("bar_prism", ["-pd_bar0_slips", "1e-3,2e-3,7e-3"], "-pd_bar0_slips"),  # given to a bar without bond slip
    ("bar_prism", ["-pd_bar1_line", "0.1,0.05,0.05,0.3,0.05,0.05", "-pd_bar1_diameter", "0.01"], "-pd_bar1_line"),  # overlaps bar 0
    ("bar_prism", ["-pd_bar2_line", "0,0.03,0.03,0.4,0.03,0.03", "-pd_bar2_diameter", "0.01"], "-pd_bar2"),  # numbering gap
    ("cantilever", ["-pd_bar0_line", "0,0.05,0.05,1,0.05,0.05"], "-pd_bar0_diameter"),  # diameter missing
    # a section cut inside the body along x, under small kinematics
    ("rc_beam_2d", ["-pd_section_x", "1.4"], "-pd_section_x"),
    ("rc_beam_2d", ["-pd_section_x", "0.001"], "-pd_section_x"),  # before the first node column's plane
    ("rc_beam_2d", ["-pd_section_x", "0.6", "-pd_kinematics", "finite"], "-pd_section_x"),
    # no-fail zones and plates
    ("cantilever", ["-pd_nofail0_box", "0.5005,0.0405,0.0405,0.5006,0.0406,0.0406"], "-pd_nofail0_box"),  # holds no node
    ("cantilever", ["-pd_nofail0_box", "5,5,5,6,6,6"], "-pd_nofail0_box"),  # outside the domain
    ("cantilever", ["-pd_plate0_box", "0.9,0,0.1,1,0.1,0.12", "-pd_plate0_E", "-1"], "-pd_plate0_E"),
    ("cantilever", ["-pd_plate1_box", "0.9,0,0.1,1,0.1,0.12"], "-pd_plate1_box"),  # numbering gap
    ("cantilever", ["-pd_plate0_box", "0.5005,0.0405,0.0405,0.5006,0.0406,0.0406"], "-pd_plate0_box"),  # holds no node
]


def checkpoint_cases():
    """Restarts that must be refused: a missing file, a file that is not HDF5, a checkpoint of another scene
    (the same beam at another spacing, with another tensile strength, or with another constraint), and a
    restart outside path following."""
    good = run("gregoire_d200_hn_2d", "-pd_dx", "0.01", "-pd_control", "arclength", "-pd_stop_fraction", "0.9",
               "-pd_checkpoint_every", "5")
    ck = os.path.join(good.dir, "checkpoint.h5")
    check(os.path.exists(ck), "a checkpoint to restart from: %s" % ck)
    arc = ["-pd_control", "arclength"]
    # hostile copies of the good checkpoint: its values are input like any other
    import h5py
    import numpy as np
    hostile = []
    for what, edit in (("arc_length", lambda f: f.attrs.modify("arc_length", np.nan)),
                       ("kappa", lambda f: f["kappa"].__setitem__(Ellipsis, 1e300)),
                       ("level", lambda f: f["level"].__setitem__(Ellipsis, 0.5)),
                       ("kappa_length", lambda f: f.create_dataset("kappa", data=np.zeros(f.pop("kappa").shape[0] + 1))),
                       ("displacement", lambda f: f["displacement"].__setitem__(0, np.inf)),
                       ("steps", lambda f: f.attrs.modify("steps", np.int32(-3))),
                       ("curve", lambda f: f["curve"].__setitem__(5, np.nan))):
        bad = os.path.join(good.dir, "hostile_%s.h5" % what)
        shutil.copy(ck, bad)
        with h5py.File(bad, "r+") as f:
            edit(f)
        hostile.append(("gregoire_d200_hn_2d", arc + ["-pd_dx", "0.01", "-pd_restart", bad], "-pd_restart"))
    return hostile + [("gregoire_d200_hn_2d", arc + ["-pd_restart", ck + ".missing"], "-pd_restart"),
            ("gregoire_d200_hn_2d", arc + ["-pd_restart", os.path.join(good.dir, "curve.csv")], "-pd_restart"),
            ("gregoire_d200_hn_2d", arc + ["-pd_restart", ck], "-pd_restart"),  # dx 5 mm against the checkpoint's 10 mm
            ("gregoire_d200_hn_2d", arc + ["-pd_dx", "0.01", "-pd_ft", "3e6", "-pd_restart", ck], "-pd_restart"),  # other strength
            ("gregoire_d200_hn_2d", arc + ["-pd_dx", "0.01", "-pd_arclength_type", "dissipation", "-pd_restart", ck], "-pd_restart"),
            ("gregoire_d200_hn_2d", ["-pd_dx", "0.01", "-pd_restart", ck], "-pd_restart"),  # displacement control
            ("gregoire_d200_hn_2d", arc + ["-pd_checkpoint_every", "-1"], "-pd_checkpoint_every")]


def main():
    # an output directory whose path HDF5's parallel I/O cannot take (it aborted the process after the solve)
    long_dir = os.path.join(tempfile.gettempdir(), "d" * 240)
    for name, args, needle in CASES + checkpoint_cases() + [("cantilever", ["-pd_output_dir", long_dir], "-pd_output_dir")]:
        out = os.path.join(tempfile.mkdtemp(prefix="pdbad_"), "out")
        r = run(name, *args, expect_ok=False, outdir=out)
        msg = (r.stdout + r.stderr).strip().splitlines()
        first = next((l for l in msg if needle in l), msg[-1] if msg else "")
        check(r.returncode == 2 and needle in r.stderr and not os.path.exists(out),
              "%-14s %-45s exit %d, no output, says: %s" % (name, " ".join(args)[:45], r.returncode, first.strip()[:110]))
        shutil.rmtree(os.path.dirname(out))
    # a missing options file is reported by PETSc with the file name
    out = os.path.join(tempfile.mkdtemp(prefix="pdbad_"), "out")
    r = run(None, "-options_file", "no_such_scene.opts", expect_ok=False, outdir=out)
    check(r.returncode == 2 and "no_such_scene.opts" in r.stderr and not os.path.exists(out), "missing options file: exit %d" % r.returncode)


if __name__ == "__main__":
    main()
