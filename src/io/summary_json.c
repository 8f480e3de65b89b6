/* summary.json: what ran, what it cost and how it ended. */
#include "pd_io.h"
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>

/* Peak resident set of this process, summed over ranks. VmHWM belongs to the process image; ru_maxrss
   also keeps the peak of the process that forked it across exec (a Python driver's 700 MB showed up
   as the memory of an 80-node run), so it is only the fallback. */
static PetscErrorCode PeakMemory(MPI_Comm comm, PetscReal *total) {
  struct rusage ru;
  PetscReal     mine = 0;
  FILE         *fp   = fopen("/proc/self/status", "r");

  PetscFunctionBeginUser;
  if (fp) {
    char   line[256];
    double kb;
    while (fgets(line, sizeof line, fp))
      if (sscanf(line, "VmHWM: %lf kB", &kb) == 1) mine = (PetscReal)kb * 1024.0;
    fclose(fp);
  }
  if (mine == 0) {
    getrusage(RUSAGE_SELF, &ru);
    mine = (PetscReal)ru.ru_maxrss * 1024.0; /* kilobytes on Linux */
  }
  PetscCall(MPIU_Allreduce(&mine, total, 1, MPIU_REAL, MPI_SUM, comm));
  PetscFunctionReturn(0);
}

/* Physical effects the scene calls for; discretisation corrections are listed apart. */
static PetscErrorCode WriteEffects(MPI_Comm comm, FILE *fp, const PDModel *m) {
  const PDScene *sc = m->scene;
  const char    *names[PD_MAX_EFFECTS];
  const PetscInt n = PDModelEffects(m, names);

  PetscFunctionBeginUser;
  PetscCall(PetscFPrintf(comm, fp, "  \"effects\": ["));
  for (PetscInt k = 0; k < n; k++) PetscCall(PetscFPrintf(comm, fp, "%s\"%s\"", k ? ", " : "", names[k]));
  PetscCall(PetscFPrintf(comm, fp, "],\n"));
  {
    const PDLaw *law = &m->law[0];
    PetscCall(PetscFPrintf(
        comm, fp,
        "  \"law\": {\"name\": \"%s\", \"s0\": %.6e, \"s1\": %.6e, \"sc\": %.6e, \"ft_Pa\": %.6e, \"Gf_N_per_m\": %.6e, "
        "\"lattice_fracture_ratio\": %.6f, \"gf_lattice\": %s, \"tangent\": \"%s\", \"limiter_max_bonds\": %" PetscInt_FMT "},\n",
        PDLawNames[law->kind], (double)(law->kind == PD_LAW_ELASTIC ? 0 : law->nominal.s0),
        (double)(law->kind == PD_LAW_ELASTIC ? 0 : law->nominal.s1), (double)(law->kind == PD_LAW_ELASTIC ? 0 : law->nominal.sc),
        (double)law->ft, (double)law->Gf, (double)PDLatticeFractureRatio(sc), sc->gf_lattice ? "true" : "false",
        PDTangentNames[sc->tangent], m->limiter_max));
  }
  {
    /* discretisation corrections in force; the critical-stretch one only where a law has a critical stretch */
    const char *name[6];
    PetscInt    n = 0;
    if (sc->partial_volume) name[n++] = "partial_volume";
    if (sc->calibration == PD_CALIBRATION_STENCIL) name[n++] = "stencil_calibration";
    if (sc->surface_correction) name[n++] = "surface_correction";
    if (sc->surface_correction && sc->notch_surface && sc->nnotches) name[n++] = "notch_faces_corrected";
    if (sc->surface_correction && sc->sc_whole_cells && sc->calibration == PD_CALIBRATION_CONTINUUM)
      name[n++] = "family_volume_whole_cells";
    if (sc->surface_correction && sc->sc_correction && m->softening) name[n++] = "critical_stretch";
    PetscCall(PetscFPrintf(comm, fp, "  \"corrections\": ["));
    for (PetscInt k = 0; k < n; k++) PetscCall(PetscFPrintf(comm, fp, "%s\"%s\"", k ? ", " : "", name[k]));
    PetscCall(PetscFPrintf(comm, fp, "],\n"));
  }
  PetscFunctionReturn(0);
}

/* C's snprintf, not PETSc's: PETSc's printf appends '.' to whole numbers, which is not JSON. */
static void JsonReal(char *buf, size_t len, PetscReal v) {
  if (PetscIsInfOrNanReal(v))
    snprintf(buf, len, "null");
  else
    snprintf(buf, len, "%.10e", (double)v);
}

/* The -pd_ options the scene read, given or by default, with their values: numbers and lists as JSON
   numbers and arrays, names and paths as strings. Options without a value (not given, and a default the
   model works out or none) are left out. Then the names of those given (option names are plain ASCII). */
static PetscErrorCode WriteOptions(MPI_Comm comm, FILE *fp, const PDScene *sc) {
  PetscInt n = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscFPrintf(comm, fp, "  \"options\": {"));
  for (PetscInt i = 0; i < sc->noptions; i++) {
    const PDOptionValue *v      = &sc->options[i];
    const PetscBool      quoted = v->type == PD_OPTION_ENUM || v->type == PD_OPTION_STRING ? PETSC_TRUE : PETSC_FALSE;
    const PetscBool      list   = v->type == PD_OPTION_REALS || v->type == PD_OPTION_INTS ? PETSC_TRUE : PETSC_FALSE;
    char                *name, *value = NULL;
    if (!v->value) continue;
    PetscCall(PDEscapeJSON(v->name, &name));
    if (quoted) PetscCall(PDEscapeJSON(v->value, &value));
    PetscCall(
        PetscFPrintf(comm, fp, "%s\n    %s: %s%s%s", n++ ? "," : "", name, list ? "[" : "", quoted ? value : v->value, list ? "]" : ""));
    PetscCall(PetscFree(name));
    PetscCall(PetscFree(value));
  }
  PetscCall(PetscFPrintf(comm, fp, "\n  },\n  \"options_given\": ["));
  n = 0;
  for (PetscInt i = 0; i < sc->noptions; i++)
    if (sc->options[i].set) PetscCall(PetscFPrintf(comm, fp, "%s\"%s\"", n++ ? ", " : "", sc->options[i].name));
  PetscCall(PetscFPrintf(comm, fp, "],\n"));
  PetscFunctionReturn(0);
}

/* Failure mode of a reinforced member (docs/reinforcement.md, "Failure mode"): the member fails where the
   concrete crushes (the run stopped as crushed, -pd_eps_cu) or the curve ends PD_FAILURE_DROP or more
   below its peak, and none otherwise; flexure where a bar yielded before it failed (before the crushing,
   or before the load fell for good: the last row at or above 1 - PD_FAILURE_DROP of the peak, since an
   explicit curve oscillates about it and its largest spike does not date the failure); shear (or
   anchorage) where it failed with its bars elastic. */
#define PD_FAILURE_DROP 0.1
static const char *FailureMode(const PDRecord *rec, PetscInt first_yield) {
  PetscReal peak = PETSC_MIN_REAL;
  PetscInt  held = 0;
  if (rec->nrows && !strncmp(rec->status, "crushed", 7)) return first_yield >= 0 ? "flexure" : "shear";
  for (PetscInt r = 0; r < rec->nrows; r++) peak = PetscMax(peak, rec->rows[r].load);
  for (PetscInt r = 0; r < rec->nrows; r++)
    if (rec->rows[r].load >= (1 - PD_FAILURE_DROP) * peak) held = r;
  if (!rec->nrows || held == rec->nrows - 1) return "none";
  return first_yield >= 0 && first_yield <= held ? "flexure" : "shear";
}

/* Steel bars: each bar's area, axial stiffness and yield force as built, the segments, how many yielded,
   where the first one did (the first step with a yielded segment), the largest steel stress and the failure mode. */
static PetscErrorCode WriteBars(MPI_Comm comm, FILE *fp, const PDModel *m, const PDRecord *rec) {
  const PDScene *sc    = m->scene;
  PetscInt       first = -1;
  PetscReal      smax = 0, slip = 0;
  PetscInt       anchors = 0; /* nodes of embedded bars that are not the bar's own */

  PetscFunctionBeginUser;
  if (!sc->nbars) PetscFunctionReturn(0);
  for (PetscInt q = 0; q < m->lat->nbarnodes; q++) anchors += m->lat->bn_role[q] != PD_BAR_NODE;
  for (PetscInt r = 0; r < rec->nrows; r++) {
    if (first < 0 && rec->rows[r].yielded > 0) first = r;
    smax = PetscMax(smax, rec->rows[r].steel_stress);
    slip = PetscMax(slip, rec->rows[r].slip);
  }
  PetscCall(PetscFPrintf(comm, fp, "  \"bars\": {\n    \"list\": ["));
  for (PetscInt k = 0; k < sc->nbars; k++) {
    const PDBar    *b = &sc->bar[k];
    const PetscReal A = PDBarArea(b);
    PetscCall(PetscFPrintf(comm, fp,
                           "%s{\"bar\": %" PetscInt_FMT
                           ", \"bond\": \"%s\", \"embedded\": %s, \"area_m2\": %.10e, \"axial_stiffness_N\": %.10e, "
                           "\"yield_force_N\": %.10e",
                           k ? ", " : "", k, b->slip ? "slip" : (b->perfect ? "perfect" : "concrete"), b->embedded ? "true" : "false",
                           (double)A, (double)(b->E * A), (double)(b->fy * A)));
    if (b->slip) {
      PDSlipEnvelope env;
      PDSlipEnvelopeSetUp(b, &env);
      PetscCall(PetscFPrintf(comm, fp, ", \"tau_max_Pa\": %.10e, \"slips_m\": [%.10e, %.10e, %.10e]", (double)env.tau_max,
                             (double)b->slips[0], (double)b->slips[1], (double)b->slips[2]));
    }
    PetscCall(PetscFPrintf(comm, fp, "}"));
  }
  PetscCall(PetscFPrintf(comm, fp,
                         "],\n    \"segments\": %" PetscInt_FMT ",\n    \"yielded_segments\": %" PetscInt_FMT
                         ",\n    \"max_steel_stress_Pa\": %.10e,\n    \"bar_nodes\": %" PetscInt_FMT ",\n    \"max_slip_m\": %.10e,\n",
                         m->bonds->nseg_global, m->yielded, (double)smax, m->lat->nbarnodes - anchors, (double)slip));
  PetscCall(PetscFPrintf(comm, fp, "    \"anchor_nodes\": %" PetscInt_FMT ",\n", anchors));
  if (first >= 0)
    PetscCall(PetscFPrintf(comm, fp, "    \"first_yield\": {\"step\": %" PetscInt_FMT ", \"load_N\": %.10e, \"disp_m\": %.10e},\n",
                           rec->rows[first].step, (double)rec->rows[first].load, (double)rec->rows[first].disp));
  else
    PetscCall(PetscFPrintf(comm, fp, "    \"first_yield\": null,\n"));
  PetscCall(PetscFPrintf(comm, fp, "    \"failure_mode\": \"%s\"\n  },\n", FailureMode(rec, first)));
  PetscFunctionReturn(0);
}

PetscErrorCode PDSummaryWrite(MPI_Comm comm, const PDModel *m, const PDRecord *rec) {
  const PDScene *sc = m->scene;
  FILE          *fp;
  char           path[PETSC_MAX_PATH_LEN], peak[32], dpeak[32], fin[32], *text;
  PetscMPIInt    size;
  PetscReal      pk = PETSC_MIN_REAL, dpk = PD_NAN, last = PD_NAN, mem, wall;
  PetscLogDouble now;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  for (PetscInt k = 0; k < rec->nrows; k++)
    if (rec->rows[k].load > pk) {
      pk  = rec->rows[k].load;
      dpk = rec->rows[k].disp;
    }
  if (!rec->nrows)
    pk = PD_NAN;
  else
    last = rec->rows[rec->nrows - 1].load;
  JsonReal(peak, sizeof peak, pk);
  JsonReal(dpeak, sizeof dpeak, dpk);
  JsonReal(fin, sizeof fin, last);
  PetscCall(PeakMemory(comm, &mem));
  PetscCall(PetscTime(&now));
  wall = now - rec->t_start;
  PetscCall(PetscSNPrintf(path, sizeof path, "%s/summary.json.tmp", rec->dir));
  PetscCall(PetscFOpen(comm, path, "w", &fp));
  PetscCall(PDEscapeJSON(sc->name, &text));
  PetscCall(PetscFPrintf(comm, fp, "{\n  \"scene\": %s,\n  \"mode\": \"%s\",\n  \"ranks\": %d,\n", text,
                         sc->explicit_mode ? "explicit" : "implicit", size));
  PetscCall(PetscFree(text));
  if (sc->explicit_mode)
    PetscCall(PetscFPrintf(
        comm, fp,
        "  \"explicit\": {\"eigenvalue_estimate_per_s2\": %.10e, \"power_iterations\": %" PetscInt_FMT
        ", \"eigenvalue_gershgorin_per_s2\": %.10e, \"dt_stable_s\": %.10e, \"dt_gershgorin_s\": %.10e, \"dt_eq46_s\": %.10e, "
        "\"dt_safety\": %.10e, \"dt_s\": %.10e, \"time_steps\": %" PetscInt_FMT
        ", \"kinetic_energy_max_J\": %.6e, \"velocity_max_m_per_s\": %.6e, \"stretch_per_step_max\": %.6e, \"damping\": %.6e, "
        "\"bar_mass_added_kg\": %.6e, \"control\": \"%s\", \"cmod_target_m\": %.6e, \"servo_gain_m\": %.10e, "
        "\"servo_fundamental_per_s\": %.6e, \"servo_bandwidth\": %.6e, \"servo_cg_iterations\": %" PetscInt_FMT "},\n",
        (double)rec->eig_est, sc->dt_power_its, (double)rec->eig_bound, (double)rec->dt_stable, (double)(2 / PetscSqrtReal(rec->eig_bound)),
        (double)rec->dt_eq46, (double)sc->dt_safety, (double)rec->dt, rec->time_steps, (double)rec->ke_max, (double)rec->v_peak,
        (double)rec->ds_peak, (double)sc->damping, (double)rec->bar_mass_added, sc->explicit_cmod > 0 ? "cmod" : "load",
        (double)sc->explicit_cmod, (double)rec->servo_gain, (double)rec->servo_omega1, (double)sc->servo_bandwidth, rec->servo_its));
  if (sc->has_section) /* the plane the cut was moved to, halfway between two node columns */
    PetscCall(PetscFPrintf(comm, fp, "  \"section\": {\"x_m\": %.10e},\n", (double)sc->section_x));
  if (sc->failure_search) {
    PetscCall(PetscFPrintf(
        comm, fp, "  \"failure_search\": {\"criterion\": \"%s\", \"tolerance\": %.6e, \"lower_N\": %.6e, \"upper_N\": %.6e, \"trials\": [",
        PDFailureCriteria[sc->failure_criterion], (double)sc->failure_tol, (double)rec->fail_lower, (double)rec->fail_upper));
    for (PetscInt k = 0; k < rec->ntrials; k++) {
      PetscCall(PDEscapeJSON(rec->trial[k].why, &text));
      PetscCall(PetscFPrintf(comm, fp, "%s\n    {\"load_N\": %.6e, \"carried\": %s, \"time_steps\": %" PetscInt_FMT ", \"reason\": %s}",
                             k ? "," : "", (double)rec->trial[k].load, rec->trial[k].verdict > 0 ? "true" : "false", rec->trial[k].steps,
                             text));
      PetscCall(PetscFree(text));
    }
    PetscCall(PetscFPrintf(comm, fp, "]},\n"));
  }
  /* nodes hold material (bar nodes included); the lattice's void nodes and the bar-node slots no bar node takes
     (pinned, no bonds) are counted apart, and in the dofs */
  PetscCall(PetscFPrintf(comm, fp,
                         "  \"nodes\": %" PetscInt_FMT ",\n  \"void_nodes\": %" PetscInt_FMT ",\n  \"unused_slots\": %" PetscInt_FMT
                         ",\n  \"bonds\": %" PetscInt64_FMT ",\n  \"dofs\": %" PetscInt_FMT ",\n",
                         m->lat->nglobal - m->lat->nvoid - m->lat->nunused, m->lat->nvoid, m->lat->nunused, m->bonds->nbonds_global,
                         m->lat->nglobal * m->bs));
  PetscCall(WriteEffects(comm, fp, m));
  PetscCall(PetscFPrintf(comm, fp, "  \"dx_m\": %.10e,\n  \"horizon_ratio\": %.10e,\n  \"influence\": \"%s\",\n  \"kinematics\": \"%s\",\n",
                         (double)sc->dx, (double)sc->horizon_ratio, PDInfluences[sc->influence], PDKinematicsNames[sc->kinematics]));
  PetscCall(PetscFPrintf(comm, fp, "  \"bonds_cut_by_notches\": %" PetscInt_FMT ",\n  \"surface_correction_range\": [%.6e, %.6e],\n",
                         m->bonds->ncut, (double)m->bonds->lambda_min, (double)m->bonds->lambda_max));
  /* the lattice bulk's modulus along an axis over the continuum's, with the continuum micromodulus: what
     -pd_calibration stencil divides out, and what the continuum calibration's results converge to; and its
     Poisson ratio along an axis, which -pd_fc's rise is calibrated with */
  PetscCall(PetscFPrintf(comm, fp, "  \"calibration\": \"%s\",\n  \"lattice_stiffness_ratio\": %.6f,\n  \"lattice_poisson_ratio\": %.6f,\n",
                         PDCalibrationNames[sc->calibration], (double)PDLatticeStiffnessRatio(sc), (double)PDLatticePoissonRatio(sc)));
  PetscCall(PetscFPrintf(comm, fp,
                         "  \"constrained_dofs\": %" PetscInt_FMT ",\n  \"zero_stiffness_dofs_pinned\": %" PetscInt_FMT
                         ",\n  \"isolated_nodes\": %" PetscInt_FMT ",\n",
                         m->nconstrained, m->nzero_dofs, m->nisolated));
  {
    char      via[64] = "default";
    PetscBool set;
    PetscCall(PetscOptionsGetString(NULL, NULL, "-matptap_via", via, sizeof via, &set));
    PetscCall(PDEscapeJSON(via, &text));
    PetscCall(PetscFPrintf(comm, fp, "  \"galerkin_product\": %s,\n", text)); /* GAMG's on several ranks (static.c) */
    PetscCall(PetscFree(text));
  }
  PetscCall(PDEscapeJSON(rec->solver, &text));
  PetscCall(PetscFPrintf(comm, fp,
                         "  \"solver\": %s,\n  \"pc_reach\": %.4f,\n  \"linear\": %s,\n  \"jacobian_assemblies\": %" PetscInt_FMT
                         ",\n  \"residuals_by_rows\": %" PetscInt_FMT ",\n  \"forces_by_change\": %" PetscInt_FMT ",\n",
                         text, (double)m->pc_reach, m->linear ? "true" : "false", m->jacobian_assemblies, m->residuals_by_rows,
                         m->forces_by_change));
  PetscCall(PetscFree(text));
  PetscCall(PetscFPrintf(comm, fp,
                         "  \"steps\": %" PetscInt_FMT ",\n  \"newton_its\": %" PetscInt_FMT ",\n  \"ksp_its\": %" PetscInt_FMT ",\n",
                         rec->steps, rec->newton_its, rec->ksp_its));
  PetscCall(PetscFPrintf(comm, fp,
                         "  \"broken_bonds\": %" PetscInt64_FMT ",\n  \"softening_bonds\": %" PetscInt64_FMT
                         ",\n  \"max_bonds_per_iteration\": %" PetscInt_FMT ",\n  \"max_regularised_dofs\": %" PetscInt_FMT ",\n",
                         m->broken, m->softening_bonds, rec->max_events_per_its, m->max_regularised));
  PetscCall(WriteBars(comm, fp, m, rec));
  PetscCall(PetscFPrintf(comm, fp, "  \"peak_load_N\": %s,\n  \"disp_at_peak_m\": %s,\n  \"final_load_N\": %s,\n", peak, dpeak, fin));
  PetscCall(PetscFPrintf(comm, fp, "  \"wall_s\": %.4f,\n", (double)wall));
  if (rec->fallback_step > 0) {
    PetscCall(PDEscapeJSON(rec->fallback_why, &text));
    PetscCall(PetscFPrintf(comm, fp,
                           "  \"path_following_from\": {\"step\": %" PetscInt_FMT
                           ", \"load_factor\": %.10g, \"why\": %s, \"implex_from_step\": %" PetscInt_FMT "},\n",
                           rec->fallback_step, (double)rec->fallback_lambda, text, rec->fallback_implex_step));
    PetscCall(PetscFree(text));
  }
  if (rec->arc_rtol > 0)
    PetscCall(PetscFPrintf(
        comm, fp,
        "  \"equilibrium_rtol\": {\"implicit_steps\": %.3e, \"implex_steps\": %.3e},\n  \"implex_insensitive_steps\": %" PetscInt_FMT
        ",\n  \"implex_faces_steps\": %" PetscInt_FMT ",\n",
        (double)rec->arc_rtol, (double)rec->implex_rtol, rec->implex_insensitive, rec->implex_faces));
  if (rec->restart_from[0]) {
    PetscCall(PDEscapeJSON(rec->restart_from, &text));
    PetscCall(PetscFPrintf(comm, fp, "  \"restart\": {\"from\": %s, \"step\": %" PetscInt_FMT "},\n", text, rec->restart_step));
    PetscCall(PetscFree(text));
  }
  PetscCall(PetscFPrintf(comm, fp, "  \"timings\": {\"setup\": %.4f, \"assembly\": %.4f, \"solve\": %.4f, \"output\": %.4f},\n",
                         (double)rec->t_setup, (double)m->t_assembly, (double)rec->t_solve, (double)rec->t_output));
  {
    /* estimate for -pd_dry_run: bond arrays, history, the stiffness (block rows of 8-byte values and
       4-byte column indices; SBAIJ stores the upper half) and, on softening scenes, the 60-vector
       GMRES basis of the consistent tangent */
    const PetscReal nb = (PetscReal)m->bonds->nbonds_global, bs2 = (PetscReal)(m->bs * m->bs), ndof = (PetscReal)(m->bs * m->lat->nglobal);
    const PetscReal est = nb * (2 * sizeof(PetscInt) + 2 * sizeof(PetscReal) + 2 * sizeof(PetscInt)) + (PetscReal)m->history_bytes +
                          (nb + m->lat->nglobal) * (bs2 * 8 + 4) + (m->softening ? 61 * ndof * sizeof(PetscScalar) : 0);
    PetscCall(PetscFPrintf(comm, fp,
                           "  \"memory\": {\"history_bytes\": %" PetscInt64_FMT
                           ", \"matrix_nonzeros\": %.0f, \"estimated_bytes\": %.0f, \"peak_rss_bytes\": %.0f},\n",
                           m->history_bytes, (double)rec->matrix_nonzeros, (double)est, (double)mem));
  }
  PetscCall(WriteOptions(comm, fp, sc));
  PetscCall(PDEscapeJSON(rec->status, &text));
  PetscCall(PetscFPrintf(comm, fp, "  \"converged\": %s,\n  \"status\": %s\n}\n", rec->converged ? "true" : "false", text));
  PetscCall(PetscFree(text));
  PetscCall(PetscFClose(comm, fp));
  PetscCall(PDFileCommit(comm, rec->dir, "summary.json"));
  PetscFunctionReturn(0);
}
