/* How a scene is solved: control, path following, the explicit path, the failure search, the damage
   limiter, fields and checkpoints. Options outside the chosen path are left at their defaults (the
   schema says where each applies) and, if given, reported as unused. */
#include "scene_read.h"
#include "option_values.h"

/* Whether a preconditioner named on the command line can read the block storage mat ("sbaij" or "baij") in
   PETSc 3.18; where it cannot, the option (and its value) that named it. GAMG builds its graph from AIJ
   only; symmetric storage has no LU or ILU factorisation and no SOR for blocks; of the factorisation
   packages only PETSc's own and MUMPS read block storage, and MUMPS factors BAIJ by LU only. (Measured with
   every preconditioner and package of Debian's PETSc.) */
typedef struct {
  char pc[64], sub_pc[64], solver[64], sub_solver[64];
} PDPCChoice;

static PetscBool BlockStorageReadable(const char *mat, const PDPCChoice *c, const char **option, const char **value) {
  const PetscBool sym       = strcmp(mat, "sbaij") ? PETSC_FALSE : PETSC_TRUE;
  const char     *factor[2] = {c->pc, c->sub_pc}, *package[2] = {c->solver, c->sub_solver};
  const char     *fname[2] = {"-pc_type", "-sub_pc_type"};
  const char     *pname[2] = {"-pc_factor_mat_solver_type", "-sub_pc_factor_mat_solver_type"};

  *option = fname[0];
  *value  = c->pc;
  if (!strcmp(c->pc, "gamg")) return PETSC_FALSE;
  for (int k = 0; k < 2; k++) {
    const PetscBool lu = !strcmp(factor[k], "lu") || !strcmp(factor[k], "ilu") ? PETSC_TRUE : PETSC_FALSE;
    *option            = fname[k];
    *value             = factor[k];
    if (sym && (lu || !strcmp(factor[k], "sor"))) return PETSC_FALSE;
    *option = pname[k];
    *value  = package[k];
    if (package[k][0] && strcmp(package[k], "petsc") && strcmp(package[k], "mumps")) return PETSC_FALSE;
    if (!sym && !strcmp(package[k], "mumps") && !strcmp(factor[k], "cholesky")) return PETSC_FALSE;
  }
  return PETSC_TRUE;
}

/* -pc_type read once, with the scene (matrix.c and static.c ask whether the user chose one, and which), and
   the stiffness storage it needs: a preconditioner or factorisation package that cannot read the default
   symmetric block storage gets AIJ, and one that cannot read the storage chosen with -pd_mat_type is bad
   input, rather than a failure inside the first solve. */
static PetscErrorCode ReadPreconditionerStorage(MPI_Comm comm, PDScene *sc, PetscBool mat_set) {
  PDPCChoice  c = {"", "", "", ""};
  const char *option, *value;
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-pc_type", c.pc, sizeof c.pc, &sc->pc_chosen));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-sub_pc_type", c.sub_pc, sizeof c.sub_pc, NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-pc_factor_mat_solver_type", c.solver, sizeof c.solver, NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-sub_pc_factor_mat_solver_type", c.sub_solver, sizeof c.sub_solver, NULL));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCheck(size == 1 || (strcmp(c.pc, "ilu") && strcmp(c.pc, "icc")), comm, PETSC_ERR_USER_INPUT,
             "Option -pc_type: %s has no parallel form in PETSc; on %d ranks use -pc_type bjacobi -sub_pc_type %s", c.pc, size, c.pc);
  sc->pc_aij = BlockStorageReadable("sbaij", &c, &option, &value) ? PETSC_FALSE : PETSC_TRUE;
  PetscCheck(!mat_set || !strcmp(sc->mat_type, "aij") || BlockStorageReadable(sc->mat_type, &c, &option, &value), comm,
             PETSC_ERR_USER_INPUT, "Option -pd_mat_type: %s storage cannot be read by %s %s in this PETSc (use aij)", sc->mat_type, option,
             value);
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadPathFollowing(PetscOptionItems *PetscOptionsObject, MPI_Comm comm, PDScene *sc) {
  PetscInt at = sc->has_cmod ? PD_ARC_CMOD : PD_ARC_CYLINDRICAL, solve = 1;

  PetscFunctionBeginUser;
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_arclength_type", &at, NULL));
  sc->arc_type = (PDArcType)at;
  PetscCheck(sc->arc_type != PD_ARC_CMOD || sc->has_cmod, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_arclength_type: cmod needs a CMOD gauge (-pd_cmod_points)");
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_arclength_solve", &solve, NULL));
  sc->arc_augmented = solve == 1 ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_arclength_initial", &sc->arc_initial, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_arclength_growth", &sc->arc_growth, NULL));
  PetscCall(PDOptionInt(PetscOptionsObject, sc, "-pd_arclength_target_its", &sc->arc_target_its, NULL));
  PetscCall(PDOptionInt(PetscOptionsObject, sc, "-pd_arclength_halved_its", &sc->arc_halved_its, NULL));
  PetscCall(PDOptionInt(PetscOptionsObject, sc, "-pd_arclength_hold", &sc->arc_hold, NULL));
  sc->arc_rtol = 0; /* worked out by the path: PD_ARC_RTOL, or PD_IMPLEX_RTOL for IMPL-EX steps */
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_arclength_rtol", &sc->arc_rtol, NULL));
  {
    PetscInt predictor = 1;
    PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_arclength_predictor", &predictor, NULL));
    sc->arc_secant = predictor == 1 ? PETSC_TRUE : PETSC_FALSE;
  }
  sc->arc_guess = PETSC_TRUE;
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_arclength_guess", &sc->arc_guess, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_arclength_implex", &sc->arc_implex, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_stop_fraction", &sc->stop_fraction, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_unload_at", &sc->unload_at, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_reload_at", &sc->reload_at, NULL));
  PetscCheck(sc->unload_at == 0 || sc->reload_at < sc->unload_at, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_reload_at: must lie in [0, -pd_unload_at), got %g", (double)sc->reload_at);
  if (sc->arc_type != PD_ARC_DISSIPATION) PetscFunctionReturn(0);
  PetscCheck(sc->arc_implex == 0, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_arclength_implex: a secant step dissipates nothing the dissipation constraint can measure; use cmod, "
             "cylindrical or spherical");
  PetscCheck(sc->unload_at == 0, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_unload_at: unloading dissipates nothing, so the dissipation constraint cannot follow it; use cmod, cylindrical "
             "or spherical");
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadImplicit(PetscOptionItems *PetscOptionsObject, MPI_Comm comm, PDScene *sc) {
  const PDRegion *load = &sc->region[sc->load_regions[0]]; /* the first sets the control */
  PetscInt        v = load->kind == PD_REGION_FORCE ? PD_CONTROL_FORCE : PD_CONTROL_DISPLACEMENT, t = 0;
  PetscBool       set;

  PetscFunctionBeginUser;
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_control", &v, NULL));
  sc->control = (PDControl)v;
  PetscCheck(sc->control >= PD_CONTROL_ARCLENGTH || (sc->control == PD_CONTROL_FORCE) == (load->kind == PD_REGION_FORCE), comm,
             PETSC_ERR_USER_INPUT, "Option -pd_control: '%s' does not match the load region %s, which is a %s region",
             PDControlNames[sc->control], load->option, PDRegionKinds[load->kind]);
  /* read first: whether the path-following options apply depends on it */
  sc->control_fallback = PETSC_TRUE;
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_control_fallback", &sc->control_fallback, NULL));
  PetscCall(ReadPathFollowing(PetscOptionsObject, comm, sc));
  sc->predictor = PETSC_TRUE;
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_predictor", &sc->predictor, NULL));
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_tangent", &t, NULL));
  sc->tangent             = (PDTangent)t;
  sc->steel_tangent_floor = 1e-3;
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_steel_tangent_floor", &sc->steel_tangent_floor, NULL));
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_pc_matrix", &t, NULL));
  sc->pc_matrix = (PDPCMatrix)t;
  t             = 0;
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_mat_type", &t, &set));
  if (set) PetscCall(PetscStrncpy(sc->mat_type, PDMatTypes[t], sizeof sc->mat_type));
  PetscCall(ReadPreconditionerStorage(comm, sc, set));
  sc->dlambda_max = sc->lambda_max / sc->steps;
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_dlambda_max", &sc->dlambda_max, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_dlambda_min", &sc->dlambda_min, NULL));
  PetscCheck(sc->explicit_mode || sc->dlambda_min <= sc->dlambda_max, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_dlambda_min: must be at most -pd_dlambda_max (%g), got %g", (double)sc->dlambda_max, (double)sc->dlambda_min);
  sc->assembly_changed_rows = PETSC_TRUE;
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_assembly_changed_rows", &sc->assembly_changed_rows, NULL));
  t = PD_TANGENT_PRODUCT_BONDS;
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_tangent_product", &t, NULL));
  sc->tangent_product = (PDTangentProduct)t;
  sc->stencil_product = PETSC_TRUE;
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_stencil_product", &sc->stencil_product, NULL));
  sc->pc_reach = -1;
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_pc_reach", &sc->pc_reach, &set));
  PetscCheck(!set || sc->pc_reach == 0 || sc->pc_reach >= 1, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_pc_reach: 0 (every bond) or a length of at least 1 grid spacing (the nearest neighbours), got %g",
             (double)sc->pc_reach);
  PetscCheck(!set || sc->pc_reach == 0 ||
                 (sc->kinematics == PD_KINEMATICS_SMALL && sc->pc_matrix == PD_PC_MATRIX_TANGENT &&
                  sc->tangent_product == PD_TANGENT_PRODUCT_BONDS),
             comm, PETSC_ERR_USER_INPUT,
             "Option -pd_pc_reach: a reduced preconditioning matrix needs small kinematics, -pd_pc_matrix tangent and "
             "-pd_tangent_product bonds (the Krylov operator is then the tangent from the bond scalars), got %g",
             (double)sc->pc_reach);
  sc->tangent_with_residual = PETSC_TRUE;
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_tangent_with_residual", &sc->tangent_with_residual, NULL));
  sc->residual_rows = PETSC_TRUE;
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_residual_rows", &sc->residual_rows, NULL));
  sc->diagonal_index = PETSC_TRUE;
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_diagonal_index", &sc->diagonal_index, NULL));
  sc->limiter_max = -1; /* by bond count, PDModelLimiterCap */
  PetscCall(PDOptionInt(PetscOptionsObject, sc, "-pd_limiter_max_bonds", &sc->limiter_max, NULL));
  PetscCall(PDOptionInt(PetscOptionsObject, sc, "-pd_limiter_stage_its", &sc->limiter_stage_its, NULL));
  PetscCall(PDOptionInt(PetscOptionsObject, sc, "-pd_limiter_sublevels", &sc->limiter_sublevels, NULL));
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_limiter_settle_first", &sc->limiter_settle_first, NULL));
  PetscCall(PDOptionInt(PetscOptionsObject, sc, "-pd_fields_every", &sc->fields_every, NULL));
  PetscCall(PDOptionInt(PetscOptionsObject, sc, "-pd_checkpoint_every", &sc->checkpoint_every, NULL));
  PetscCall(PDOptionString(PetscOptionsObject, sc, "-pd_restart", sc->restart, sizeof sc->restart, NULL));
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadExplicit(PetscOptionItems *PetscOptionsObject, MPI_Comm comm, PDScene *sc) {
  PetscFunctionBeginUser;
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_ramp_time", &sc->ramp_time, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_hold_time", &sc->hold_time, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_explicit_cmod", &sc->explicit_cmod, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_servo_bandwidth", &sc->servo_bandwidth, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_dt_safety", &sc->dt_safety, NULL));
  PetscCall(PDOptionInt(PetscOptionsObject, sc, "-pd_dt_power_its", &sc->dt_power_its, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_damping", &sc->damping, NULL));
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_adr", &sc->adr, NULL));
  sc->bar_mass_scaling = PETSC_TRUE;
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_bar_mass_scaling", &sc->bar_mass_scaling, NULL));
  PetscCheck(!(sc->adr && sc->damping > 0), comm, PETSC_ERR_USER_INPUT, "Option -pd_adr: sets its own damping; drop -pd_damping %g",
             (double)sc->damping);
  PetscCheck(sc->explicit_cmod == 0 || sc->has_cmod, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_explicit_cmod: the scene has no CMOD gauge (-pd_cmod_points)");
  PetscCheck(!(sc->adr && sc->explicit_cmod > 0), comm, PETSC_ERR_USER_INPUT,
             "Option -pd_explicit_cmod: dynamic relaxation (-pd_adr) counts time in steps and has no servo; drop one of them");
  PetscCall(PDOptionInt(PetscOptionsObject, sc, "-pd_output_stride", &sc->out_stride, NULL));
  PetscFunctionReturn(0);
}

/* Failure search options (Ness 2019 Sec. 3.5, 4.3). Tolerances are relative where the seed's are absolute
   (its velocity tolerance is in m/s), so that one default serves beams of any size and load. */
static PetscErrorCode ReadFailureSearch(PetscOptionItems *PetscOptionsObject, MPI_Comm comm, PDScene *sc) {
  const PDRegion *load = &sc->region[sc->load_regions[0]]; /* the first sets the control */
  PetscInt        crit = PD_FAILURE_DAMAGE, n = 2;
  PetscBool       set;

  PetscFunctionBeginUser;
  if (sc->failure_search) {
    PetscCheck(load->kind == PD_REGION_FORCE, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_failure_search: needs a load-controlled scene; the load region %s is of kind %s, not force", load->option,
               PDRegionKinds[load->kind]);
    PetscCheck(sc->damping > 0, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_failure_search: needs -pd_damping > 0 (a trial that survives must come to rest), got %g", (double)sc->damping);
    PetscCheck(sc->explicit_cmod == 0, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_explicit_cmod: the failure search holds loads of its own; drop -pd_explicit_cmod %g", (double)sc->explicit_cmod);
  }
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_failure_criterion", &crit, NULL));
  sc->failure_criterion = (PDFailureCriterion)crit;
  PetscCall(PDOptionRealArray(PetscOptionsObject, sc, "-pd_failure_bracket", sc->failure_bracket, &n, &set));
  PetscCheck(!set || (n == 2 && sc->failure_bracket[0] > 0 && sc->failure_bracket[1] > sc->failure_bracket[0]), comm, PETSC_ERR_USER_INPUT,
             "Option -pd_failure_bracket: needs two loads 0 < lower < upper, got %" PetscInt_FMT " value(s) %g,%g", n,
             (double)sc->failure_bracket[0], (double)(n > 1 ? sc->failure_bracket[1] : 0));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_failure_tol", &sc->failure_tol, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_failure_velocity_tol", &sc->failure_vtol, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_failure_force_tol", &sc->failure_ftol, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_failure_damage_tol", &sc->failure_dtol, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_failure_window", &sc->failure_window, NULL));
  PetscFunctionReturn(0);
}

PetscErrorCode PDSceneReadSolution(PetscOptionItems *PetscOptionsObject, MPI_Comm comm, PDScene *sc) {
  PetscFunctionBeginUser;
  PetscCall(ReadImplicit(PetscOptionsObject, comm, sc));
  PetscCall(ReadExplicit(PetscOptionsObject, comm, sc));
  PetscCall(ReadFailureSearch(PetscOptionsObject, comm, sc));
  PetscFunctionReturn(0);
}
