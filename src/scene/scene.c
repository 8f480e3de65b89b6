/* Reads a scene from the PETSc options database and validates it before anything is built. */
#include "pd_scene.h"
#include "option_values.h"
#include <petscviewer.h>
#include <string.h>

const char *const        PDModelKinds[]      = {"3d", "plane_stress", "plane_strain"};
const char *const        PDInfluences[]      = {"constant", "conical", "quartic"};
const char *const        PDKinematicsNames[] = {"small", "finite"};
const char *const        PDLawNames[]        = {"elastic", "linear", "bilinear", "trilinear", "nonlinear"};
const char *const        PDStretchNames[]    = {"exact", "modified"};
const char *const        PDControlNames[]    = {"displacement", "force", "arclength", "auto"};
const char *const        PDArcTypes[]        = {"spherical", "cylindrical", "cmod", "dissipation"};
const char *const        PDTangentNames[]    = {"consistent", "secant"};
const char *const        PDPCMatrixNames[]   = {"tangent", "secant"};
const char *const        PDShapes[]          = {"box", "cylinder"};
const char *const        PDRegionKinds[]     = {"support", "displacement", "force", "monitor"};
const char *const        PDFailureCriteria[] = {"damage", "velocity", "force"};
static const char *const PDModes[]           = {"implicit", "explicit"};

/* Failure search options (Ness 2019 Sec. 3.5, 4.3). Tolerances are relative where the seed's are absolute
   (its velocity tolerance is in m/s), so that one default serves beams of any size and load. */
static PetscErrorCode ReadFailureSearch(PetscOptionItems *PetscOptionsObject, MPI_Comm comm, PDScene *sc) {
  PetscInt  crit = PD_FAILURE_DAMAGE, n = 2;
  PetscBool set;

  PetscFunctionBeginUser;
  sc->failure_tol    = 0.02;
  sc->failure_vtol   = 1e-2;
  sc->failure_ftol   = 0.05;
  sc->failure_dtol   = 1e-5;
  sc->failure_window = 0;
  PetscCall(PDOptionEnum(PetscOptionsObject, "-pd_failure_criterion", "Failure search: when a trial has failed or converged",
                         PDFailureCriteria, 3, &crit, NULL));
  sc->failure_criterion = (PDFailureCriterion)crit;
  PetscCall(PDOptionRealArray(PetscOptionsObject, "-pd_failure_bracket", "Failure search: first lower,upper test loads (N)",
                              sc->failure_bracket, &n, &set));
  PetscCheck(!set || (n == 2 && sc->failure_bracket[0] > 0 && sc->failure_bracket[1] > sc->failure_bracket[0]), comm, PETSC_ERR_USER_INPUT,
             "Option -pd_failure_bracket: needs two loads 0 < lower < upper, got %" PetscInt_FMT " value(s) %g,%g", n,
             (double)sc->failure_bracket[0], (double)(n > 1 ? sc->failure_bracket[1] : 0));
  PetscCall(PDOptionReal(PetscOptionsObject, "-pd_failure_tol", "Failure search: relative bracket width (upper - lower)/lower to stop at",
                         &sc->failure_tol, NULL));
  PetscCheck(sc->failure_tol > 0 && sc->failure_tol < 1, comm, PETSC_ERR_USER_INPUT, "Option -pd_failure_tol: must lie in (0, 1), got %g",
             (double)sc->failure_tol);
  PetscCall(PDOptionReal(PetscOptionsObject, "-pd_failure_velocity_tol",
                         "Failure search: converged when the mean loaded-node speed falls below this fraction of its largest value",
                         &sc->failure_vtol, NULL));
  PetscCheck(sc->failure_vtol > 0 && sc->failure_vtol < 1, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_failure_velocity_tol: must lie in (0, 1), got %g", (double)sc->failure_vtol);
  PetscCall(PDOptionReal(PetscOptionsObject, "-pd_failure_force_tol",
                         "Failure search (force decay): converged when out-of-balance over applied force at the loaded nodes is below this",
                         &sc->failure_ftol, NULL));
  PetscCheck(sc->failure_ftol > 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_failure_force_tol: must be positive, got %g",
             (double)sc->failure_ftol);
  PetscCall(PDOptionReal(PetscOptionsObject, "-pd_failure_damage_tol",
                         "Failure search (bond damage): fraction of bonds broken per time step below which damage counts as still",
                         &sc->failure_dtol, NULL));
  PetscCheck(sc->failure_dtol > 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_failure_damage_tol: must be positive, got %g",
             (double)sc->failure_dtol);
  PetscCall(PDOptionReal(
      PetscOptionsObject, "-pd_failure_window",
      "Failure search (bond damage): time (s) damage must stay still, or load and velocity stay aligned; 0: a quarter of the ramp",
      &sc->failure_window, NULL));
  PetscCheck(sc->failure_window >= 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_failure_window: must be non-negative, got %g",
             (double)sc->failure_window);
  PetscFunctionReturn(0);
}

/* 2D scenes give boxes as x0,y0,x1,y1 and points as x,y; store them in 3D form with z = 0. */
static PetscErrorCode ReadBox(PetscOptionItems *PetscOptionsObject, const PDScene *sc, const char *opt, const char *help, PetscReal box[6],
                              PetscBool *set) {
  PetscReal v[6];
  PetscInt  n = 2 * sc->dim;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < 6; i++) v[i] = 0;
  for (PetscInt a = 0; a < sc->dim; a++) {
    v[a]           = box[a];
    v[sc->dim + a] = box[3 + a];
  }
  PetscCall(PDOptionRealArray(PetscOptionsObject, opt, help, v, &n, set));
  if (*set) {
    PetscCheck(n == 2 * sc->dim, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s: expected %" PetscInt_FMT " numbers (lower corner, upper corner), got %" PetscInt_FMT, opt, 2 * sc->dim, n);
    for (PetscInt a = 0; a < 3; a++) {
      box[a]     = a < sc->dim ? PetscMin(v[a], v[sc->dim + a]) : 0;
      box[3 + a] = a < sc->dim ? PetscMax(v[a], v[sc->dim + a]) : 0;
      PetscCheck(a >= sc->dim || v[a] <= v[sc->dim + a], PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                 "Option %s: lower corner exceeds upper corner along axis %c", opt, (char)('x' + a));
    }
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadDofs(PetscOptionItems *PetscOptionsObject, const PDScene *sc, const char *opt, PetscBool dof[3], PetscBool *set) {
  char buf[64] = "";

  PetscFunctionBeginUser;
  PetscCall(PDOptionString(PetscOptionsObject, opt, "Constrained components, e.g. x,z", buf, sizeof buf, set));
  if (!*set) PetscFunctionReturn(0);
  dof[0] = dof[1] = dof[2] = PETSC_FALSE;
  for (const char *p = buf; *p; p++) {
    if (*p == ',' || *p == ' ') continue;
    PetscInt a = (*p == 'x' || *p == 'X') ? 0 : (*p == 'y' || *p == 'Y') ? 1 : (*p == 'z' || *p == 'Z') ? 2 : -1;
    PetscCheck(a >= 0 && a < sc->dim, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: unknown component '%c' in '%s' (use %s)", opt, *p,
               buf, sc->dim == 3 ? "x, y, z" : "x, y");
    dof[a] = PETSC_TRUE;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadVector(PetscOptionItems *PetscOptionsObject, const PDScene *sc, const char *opt, const char *help,
                                 PetscReal vec[3], PetscBool *set) {
  PetscInt n = sc->dim;

  PetscFunctionBeginUser;
  PetscCall(PDOptionRealArray(PetscOptionsObject, opt, help, vec, &n, set));
  PetscCheck(!*set || n == sc->dim, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: expected %" PetscInt_FMT " components, got %" PetscInt_FMT, opt, sc->dim, n);
  if (sc->dim == 2) vec[2] = 0;
  PetscFunctionReturn(0);
}

static PetscBool BoxesOverlap(const PetscReal a[6], const PetscReal b[6], PetscInt dim, PetscReal tol) {
  for (PetscInt k = 0; k < dim; k++)
    if (a[k] > b[3 + k] + tol || b[k] > a[3 + k] + tol) return PETSC_FALSE;
  return PETSC_TRUE;
}

static PetscErrorCode ReadMaterial(PetscOptionItems *PetscOptionsObject, PDScene *sc, PetscInt k) {
  PDMaterial *m = &sc->material[k];
  char        opt[64];
  PetscBool   set;
  PetscInt    law = m->law;

  PetscFunctionBeginUser;
  if (k == 0) {
    PetscCall(PetscStrncpy(m->option, "-pd", sizeof m->option));
    m->where.shape = PD_SHAPE_BOX;
    PetscCall(PetscArraycpy(m->where.box, sc->domain, 6));
  } else {
    *m = sc->material[0]; /* a further material starts from the base one */
    PetscCall(PetscSNPrintf(m->option, sizeof m->option, "-pd_material%" PetscInt_FMT, k));
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_box", m->option));
    PetscCall(
        ReadBox(PetscOptionsObject, sc, opt, "Region of this material (later materials win where boxes overlap)", m->where.box, &set));
    PetscCheck(BoxesOverlap(m->where.box, sc->domain, sc->dim, 0), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s: box lies outside the domain -pd_domain", opt);
    law = m->law;
  }
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_E", m->option));
  PetscCall(PDOptionReal(PetscOptionsObject, opt, "Young's modulus (Pa)", &m->E, NULL));
  PetscCheck(m->E > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: Young's modulus must be positive, got %g", opt, (double)m->E);
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_rho", m->option));
  PetscCall(PDOptionReal(PetscOptionsObject, opt, "Density (kg/m^3)", &m->rho, NULL));
  PetscCheck(m->rho > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: density must be positive, got %g", opt, (double)m->rho);
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_law", m->option));
  PetscCall(PDOptionEnum(PetscOptionsObject, opt, "Bond law: elastic, linear (brittle), bilinear, trilinear, nonlinear", PDLawNames, 5,
                         &law, NULL));
  m->law = (PDLawKind)law;
  if (m->law == PD_LAW_ELASTIC) PetscFunctionReturn(0);
  {
    PetscReal fcm = 0;
    PetscBool set_fcm, set_gf;
    PetscInt  form = m->bobaru;
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_ft", m->option));
    PetscCall(PDOptionReal(PetscOptionsObject, opt, "Tensile strength (Pa)", &m->ft, NULL));
    PetscCheck(m->ft > 0 || m->law == PD_LAW_LINEAR || (m->law == PD_LAW_BILINEAR && !m->bobaru), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s: tensile strength must be positive, got %g", opt, (double)m->ft);
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_fcm", m->option));
    PetscCall(PDOptionReal(PetscOptionsObject, opt, "Mean compressive strength (MPa): G_F = 73 fcm^0.18 (fib MC2010) when no G_F is given",
                           &fcm, &set_fcm));
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_Gf", m->option));
    PetscCall(PDOptionReal(PetscOptionsObject, opt, "Fracture energy (N/m)", &m->Gf, &set_gf));
    if (!set_gf && set_fcm) m->Gf = 73 * PetscPowReal(fcm, 0.18);
    PetscCheck(m->Gf > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: fracture energy must be positive, got %g", opt, (double)m->Gf);
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_bilinear_form", m->option));
    PetscCall(PDOptionEnum(PetscOptionsObject, opt, "Bilinear law: zaccariotto (s_c = k_r s0) or bobaru (s0 = ft/E)",
                           (const char *const[]){"zaccariotto", "bobaru"}, 2, &form, NULL));
    m->bobaru = form ? PETSC_TRUE : PETSC_FALSE;
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_bilinear_kr", m->option));
    PetscCall(PDOptionReal(PetscOptionsObject, opt, "Bilinear law (Zaccariotto): k_r = s_c/s0", &m->kr, NULL));
    PetscCheck(m->kr > 1, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: must exceed 1, got %g", opt, (double)m->kr);
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_trilinear_beta", m->option));
    PetscCall(PDOptionReal(PetscOptionsObject, opt, "Trilinear law: force ratio at the kink", &m->beta, NULL));
    PetscCheck(m->beta > 0 && m->beta < 1, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: must lie in (0, 1), got %g", opt,
               (double)m->beta);
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_nonlinear_k", m->option));
    PetscCall(PDOptionReal(PetscOptionsObject, opt, "Non-linear law: exponent k", &m->k, NULL));
    PetscCheck(m->k > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: must be positive, got %g", opt, (double)m->k);
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_nonlinear_alpha", m->option));
    PetscCall(PDOptionReal(PetscOptionsObject, opt, "Non-linear law: alpha", &m->alpha, NULL));
    PetscCheck(m->alpha >= 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: must be non-negative, got %g", opt, (double)m->alpha);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadNotch(PetscOptionItems *PetscOptionsObject, PDScene *sc, PetscInt k) {
  PDNotch  *n = &sc->notch[k];
  char      opt[64];
  PetscBool set;
  PetscInt  nflat = 0;
  PetscReal tol   = 1e-9 * sc->dx;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(n->option, sizeof n->option, "-pd_notch%" PetscInt_FMT, k));
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_box", n->option));
  PetscCall(ReadBox(PetscOptionsObject, sc, opt, "Notch: a box flat along one axis; bonds crossing or touching it are cut", n->box, &set));
  for (PetscInt a = 0; a < sc->dim; a++)
    if (n->box[3 + a] - n->box[a] <= tol) {
      n->normal = a;
      nflat++;
    }
  PetscCheck(nflat == 1, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: a notch box must be flat (zero width) along exactly one axis, %" PetscInt_FMT " are flat", opt, nflat);
  PetscCheck(BoxesOverlap(n->box, sc->domain, sc->dim, tol), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: notch lies outside the domain -pd_domain", opt);
  {
    PetscBool covers = PETSC_TRUE;
    for (PetscInt a = 0; a < sc->dim; a++)
      if (a != n->normal && (n->box[a] > sc->domain[a] + tol || n->box[3 + a] < sc->domain[3 + a] - tol)) covers = PETSC_FALSE;
    PetscCheck(!covers, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s: the notch spans the whole cross-section and would split the body in two", opt);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadRegion(PetscOptionItems *PetscOptionsObject, PDScene *sc, PetscInt k) {
  PDRegion *r = &sc->region[k];
  char      opt[64], opt2[64];
  PetscBool set_box, set_cyl, set, set_vec;
  PetscInt  kind = PD_REGION_MONITOR, axis = 2, n = 4;
  PetscReal cyl[4] = {0, 0, 0, 0};

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(r->option, sizeof r->option, "-pd_region%" PetscInt_FMT, k));
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_box", r->option));
  PetscCall(
      ReadBox(PetscOptionsObject, sc, opt, "Node region: box (flat along an axis selects one layer of nodes)", r->where.box, &set_box));
  PetscCall(PetscSNPrintf(opt2, sizeof opt2, "%s_cylinder", r->option));
  PetscCall(
      PDOptionRealArray(PetscOptionsObject, opt2, "Node region: cylinder as centre x,y,z and radius (axis from _axis)", cyl, &n, &set_cyl));
  PetscCheck(set_box != set_cyl, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Options %s and %s: give exactly one of them", opt, opt2);
  if (set_box) {
    r->where.shape = PD_SHAPE_BOX;
    PetscCheck(BoxesOverlap(r->where.box, sc->domain, sc->dim, 0.5 * sc->dx), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s: region lies outside the domain -pd_domain", opt);
  } else {
    PetscCheck(n == 4, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: expected 4 numbers (x,y,z,radius), got %" PetscInt_FMT, opt2, n);
    PetscCheck(cyl[3] > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: radius must be positive, got %g", opt2, (double)cyl[3]);
    r->where.shape = PD_SHAPE_CYLINDER;
    PetscCall(PetscArraycpy(r->where.center, cyl, 3));
    r->where.radius = cyl[3];
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_axis", r->option));
    PetscCall(PDOptionEnum(PetscOptionsObject, opt, "Cylinder axis", (const char *const[]){"x", "y", "z"}, 3, &axis, NULL));
    PetscCheck(sc->dim == 3 || axis == 2, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: a 2D scene's cylinder (a disc) has axis z",
               opt);
    r->where.axis = axis;
    for (PetscInt a = 0; a < sc->dim; a++)
      if (a != axis)
        PetscCheck(cyl[a] + cyl[3] >= sc->domain[a] && cyl[a] - cyl[3] <= sc->domain[3 + a], PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                   "Option %s: region lies outside the domain -pd_domain", opt2);
  }
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_kind", r->option));
  PetscCall(PDOptionEnum(PetscOptionsObject, opt, "What the region does", PDRegionKinds, 4, &kind, &set));
  PetscCheck(set, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s is required (support, displacement, force or monitor)", opt);
  r->kind = (PDRegionKind)kind;
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_dofs", r->option));
  PetscCall(ReadDofs(PetscOptionsObject, sc, opt, r->dof, &set));
  if (r->kind == PD_REGION_SUPPORT || r->kind == PD_REGION_DISPLACEMENT)
    PetscCheck(set && (r->dof[0] || r->dof[1] || r->dof[2]), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s is required for a %s region",
               opt, PDRegionKinds[r->kind]);
  else
    PetscCheck(!set, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: a %s region constrains no components", opt, PDRegionKinds[r->kind]);
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_%s", r->option, r->kind == PD_REGION_FORCE ? "force" : "displacement"));
  if (r->kind == PD_REGION_FORCE || r->kind == PD_REGION_DISPLACEMENT) {
    PetscCall(ReadVector(PetscOptionsObject, sc, opt,
                         r->kind == PD_REGION_FORCE ? "Total force (N) at load factor 1, spread evenly over the nodes"
                                                    : "Prescribed displacement (m) at load factor 1",
                         r->vector, &set_vec));
    PetscCheck(set_vec, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s is required for a %s region", opt, PDRegionKinds[r->kind]);
    PetscCheck(r->vector[0] != 0 || r->vector[1] != 0 || r->vector[2] != 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s: the vector is zero", opt);
    for (PetscInt a = 0; a < 3 && r->kind == PD_REGION_DISPLACEMENT; a++)
      PetscCheck(r->dof[a] || r->vector[a] == 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                 "Option %s: component %c is non-zero but not listed in %s_dofs", opt, (char)('x' + a), r->option);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode HasOption(const char *fmt, PetscInt k, PetscBool *has) {
  char opt[64];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(opt, sizeof opt, fmt, k));
  PetscCall(PetscOptionsHasName(NULL, NULL, opt, has));
  PetscFunctionReturn(0);
}

/* A relative data path in a scene is taken relative to the directory of the options file, so that a
   scene runs from any working directory. */
static PetscErrorCode ResolveNextToOptionsFile(char *path, size_t len) {
  int    argc;
  char **argv;
  char   dir[PETSC_MAX_PATH_LEN] = "", joined[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  if (path[0] == '/') PetscFunctionReturn(0);
  PetscCall(PetscGetArgs(&argc, &argv));
  for (int i = 1; i + 1 < argc; i++) {
    PetscBool is;
    PetscCall(PetscStrcmp(argv[i], "-options_file", &is));
    if (is) PetscCall(PetscStrncpy(dir, argv[i + 1], sizeof dir));
  }
  {
    char *slash = strrchr(dir, '/');
    if (!slash) PetscFunctionReturn(0);
    slash[1] = '\0';
  }
  PetscCall(PetscSNPrintf(joined, sizeof joined, "%s%s", dir, path));
  PetscCall(PetscStrncpy(path, joined, len));
  PetscFunctionReturn(0);
}

PetscErrorCode PDSceneCreateFromOptions(MPI_Comm comm, PDScene *sc) {
  PetscBool set, has;
  PetscInt  model = PD_MODEL_3D, influence = PD_INFLUENCE_CONSTANT, kin = PD_KINEMATICS_SMALL, mode = 0, n;
  PetscReal dom[6];

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(sc, sizeof *sc));
  PetscCall(PetscStrncpy(sc->name, "scene", sizeof sc->name));
  sc->horizon_ratio      = PETSC_PI;
  sc->partial_volume     = PETSC_TRUE;
  sc->surface_correction = PETSC_TRUE;
  sc->notch_surface      = PETSC_FALSE;
  sc->thickness          = 1.0;
  sc->steps              = 1;
  sc->fields_every       = 0;
  sc->load_region        = -1;
  sc->disp_region        = -1;
  sc->material[0].E      = 30e9;
  sc->material[0].rho    = 2400;
  sc->material[0].law    = PD_LAW_ELASTIC;
  sc->material[0].kr     = 25;
  sc->material[0].beta   = 0.25;
  sc->material[0].k      = 25;
  sc->material[0].alpha  = 0.25;
  sc->sc_correction      = PETSC_TRUE;
  sc->limiter_max        = -1; /* by bond count, PDModelLimiterCap */
  sc->limiter_stage_its  = 1;
  sc->limiter_sublevels  = 1;
  sc->lambda_max         = 1;
  sc->dlambda_min        = 1e-6;
  sc->dt_safety          = 0.9;
  sc->dt_power_its       = 100;

  PetscOptionsBegin(comm, NULL, "pdimplicit scene", NULL);
  PetscCall(
      PDOptionString(PetscOptionsObject, "-pd_name", "Scene name (names the default output directory)", sc->name, sizeof sc->name, NULL));
  PetscCall(PDOptionEnum(PetscOptionsObject, "-pd_mode", "Solution path: implicit (static) or explicit (dynamic relaxation)", PDModes, 2,
                         &mode, NULL));
  sc->explicit_mode = mode == 1 ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PDOptionBool(
      PetscOptionsObject, "-pd_failure_search",
      "Failure load of a load-controlled scene: explicit trials at constant loads, geometric bisection (implies explicit mode)",
      &sc->failure_search, NULL));
  if (sc->failure_search) sc->explicit_mode = PETSC_TRUE;
  PetscCall(PDOptionEnum(PetscOptionsObject, "-pd_model", "Spatial model", PDModelKinds, 3, &model, NULL));
  sc->model = (PDModelKind)model;
  sc->dim   = sc->model == PD_MODEL_3D ? 3 : 2;
  PetscCall(PDOptionReal(PetscOptionsObject, "-pd_thickness", "Thickness of a 2D model (m)", &sc->thickness, NULL));
  PetscCheck(sc->thickness > 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_thickness: must be positive, got %g", (double)sc->thickness);
  n = 2 * sc->dim;
  PetscCall(PetscArrayzero(dom, 6));
  PetscCall(PDOptionRealArray(PetscOptionsObject, "-pd_domain", "Body box: lower corner then upper corner (m)", dom, &n, &set));
  PetscCheck(set, comm, PETSC_ERR_USER_INPUT, "Option -pd_domain is required: give a scene with -options_file scene.opts");
  PetscCheck(n == 2 * sc->dim, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_domain: expected %" PetscInt_FMT " numbers for a %" PetscInt_FMT "D model, got %" PetscInt_FMT, 2 * sc->dim,
             sc->dim, n);
  for (PetscInt a = 0; a < 3; a++) {
    sc->domain[a]     = a < sc->dim ? dom[a] : 0;
    sc->domain[3 + a] = a < sc->dim ? dom[sc->dim + a] : 0;
    PetscCheck(a >= sc->dim || sc->domain[3 + a] > sc->domain[a], comm, PETSC_ERR_USER_INPUT,
               "Option -pd_domain: upper corner must exceed lower corner along %c", (char)('x' + a));
  }
  PetscCall(PDOptionReal(PetscOptionsObject, "-pd_dx", "Grid spacing (m)", &sc->dx, &set));
  PetscCheck(set, comm, PETSC_ERR_USER_INPUT, "Option -pd_dx is required");
  PetscCheck(sc->dx > 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_dx: grid spacing must be positive, got %g", (double)sc->dx);
  for (PetscInt a = 0; a < sc->dim; a++)
    PetscCheck(sc->dx <= sc->domain[3 + a] - sc->domain[a] + 1e-12, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_dx: %g exceeds the domain size along %c", (double)sc->dx, (char)('x' + a));
  PetscCall(PDOptionReal(PetscOptionsObject, "-pd_horizon_ratio", "Horizon over grid spacing, m = delta/dx", &sc->horizon_ratio, NULL));
  PetscCheck(sc->horizon_ratio >= 1, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_horizon_ratio: must be at least 1 (horizon no smaller than the grid spacing), got %g", (double)sc->horizon_ratio);
  PetscCall(PDOptionEnum(PetscOptionsObject, "-pd_influence", "Influence function", PDInfluences, 3, &influence, NULL));
  sc->influence = (PDInfluence)influence;
  PetscCall(
      PDOptionBool(PetscOptionsObject, "-pd_partial_volume", "PA-PDLAMMPS partial volumes at the horizon edge", &sc->partial_volume, NULL));
  PetscCall(PDOptionBool(PetscOptionsObject, "-pd_surface_correction", "Volume-method surface correction", &sc->surface_correction, NULL));
  PetscCall(PDOptionBool(
      PetscOptionsObject, "-pd_sc_notch_surface",
      "Treat notch faces as free surfaces in the surface correction (default: a notch is a cut, its bonds count in the family volume)",
      &sc->notch_surface, NULL));
  PetscCall(PDOptionBool(PetscOptionsObject, "-pd_sc_whole_cells",
                         "Surface correction family volume V_i = sum V_j with neighbour cells counted whole, as PeriPy computes it "
                         "(Hobbs thesis); default sum beta_ij V_j with the partial volumes of the horizon edge",
                         &sc->sc_whole_cells, NULL));
  PetscCall(PDOptionEnum(PetscOptionsObject, "-pd_kinematics", "Bond stretch: small (linearised) or finite (exact)", PDKinematicsNames, 2,
                         &kin, NULL));
  sc->kinematics = (PDKinematics)kin;
  {
    PetscInt v = sc->stretch;
    PetscCall(PDOptionEnum(PetscOptionsObject, "-pd_stretch",
                           "Finite-kinematics stretch: exact or modified (Miranda et al. 2018, no square root)", PDStretchNames, 2, &v,
                           NULL));
    sc->stretch = (PDStretch)v;
  }
  PetscCall(
      PDOptionFraction(PetscOptionsObject, "-pd_strength_scatter",
                       "Relative scatter r of the tensile strength per bond, f_t (1 + r xi) with xi in [-1, 1] from the bond's global id "
                       "(the same on any rank count); the fracture energy is kept. Heterogeneity that lets diffuse damage localise",
                       &sc->strength_scatter));
  PetscCall(PDOptionBool(PetscOptionsObject, "-pd_sc_correction",
                         "Per-bond critical stretch from lambda_ij c when surface correction is on (Eq. 5.32)", &sc->sc_correction, NULL));
  PetscCall(
      PDOptionBool(PetscOptionsObject, "-pd_gf_lattice",
                   "Critical stretches such that a crack plane of the lattice releases G_F (default: the continuum integral of the thesis, "
                   "which the lattice, cut at the horizon, reaches only in part)",
                   &sc->gf_lattice, NULL));

  sc->nmaterials = 1;
  PetscCall(ReadMaterial(PetscOptionsObject, sc, 0));
  for (PetscInt k = 1; k < PD_MAX_MATERIALS; k++) {
    PetscCall(HasOption("-pd_material%" PetscInt_FMT "_box", k, &has));
    if (!has) break;
    PetscCall(ReadMaterial(PetscOptionsObject, sc, k));
    sc->nmaterials++;
  }
  for (PetscInt k = 0; k < PD_MAX_NOTCHES; k++) {
    PetscCall(HasOption("-pd_notch%" PetscInt_FMT "_box", k, &has));
    if (!has) break;
    PetscCall(ReadNotch(PetscOptionsObject, sc, k));
    sc->nnotches++;
  }
  for (PetscInt k = 0; k < PD_MAX_REGIONS; k++) {
    PetscBool hb, hc;
    PetscCall(HasOption("-pd_region%" PetscInt_FMT "_box", k, &hb));
    PetscCall(HasOption("-pd_region%" PetscInt_FMT "_cylinder", k, &hc));
    if (!hb && !hc) break;
    PetscCall(ReadRegion(PetscOptionsObject, sc, k));
    sc->nregions++;
  }
  PetscCheck(sc->nregions > 0, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_region0_box: the scene defines no node regions (supports and loads)");
  for (PetscInt k = 0; k < sc->nregions && sc->load_region < 0; k++)
    if (sc->region[k].kind == PD_REGION_FORCE || sc->region[k].kind == PD_REGION_DISPLACEMENT) sc->load_region = k;
  PetscCall(PDOptionInt(PetscOptionsObject, "-pd_load_region", "Region whose applied force or reaction is the curve's load",
                        &sc->load_region, NULL));
  PetscCheck(sc->load_region >= 0 && sc->load_region < sc->nregions &&
                 (sc->region[sc->load_region].kind == PD_REGION_FORCE || sc->region[sc->load_region].kind == PD_REGION_DISPLACEMENT),
             comm, PETSC_ERR_USER_INPUT, "Option -pd_load_region: %" PetscInt_FMT " is not a force or displacement region",
             sc->load_region);
  sc->disp_region = sc->load_region;
  PetscCall(PDOptionInt(PetscOptionsObject, "-pd_disp_region",
                        "Region whose mean displacement along the load direction is the curve's displacement", &sc->disp_region, NULL));
  PetscCheck(sc->disp_region >= 0 && sc->disp_region < sc->nregions, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_disp_region: %" PetscInt_FMT " is not a region", sc->disp_region);
  {
    PetscReal pts[6] = {0, 0, 0, 0, 0, 0};
    n                = 2 * sc->dim;
    PetscCall(PDOptionRealArray(PetscOptionsObject, "-pd_cmod_points",
                                "CMOD gauge: two points; opening along their line, displacements interpolated from the lattice", pts, &n,
                                &sc->has_cmod));
    if (sc->has_cmod) {
      PetscCheck(n == 2 * sc->dim, comm, PETSC_ERR_USER_INPUT,
                 "Option -pd_cmod_points: expected %" PetscInt_FMT " numbers, got %" PetscInt_FMT, 2 * sc->dim, n);
      for (PetscInt p = 0; p < 2; p++)
        for (PetscInt a = 0; a < 3; a++) {
          sc->cmod[3 * p + a] = a < sc->dim ? pts[sc->dim * p + a] : 0;
          PetscCheck(a >= sc->dim || (sc->cmod[3 * p + a] >= sc->domain[a] && sc->cmod[3 * p + a] <= sc->domain[3 + a]), comm,
                     PETSC_ERR_USER_INPUT, "Option -pd_cmod_points: point %" PetscInt_FMT " lies outside the domain", p + 1);
        }
    }
  }
  PetscCall(
      PDOptionInt(PetscOptionsObject, "-pd_steps", "Load steps to lambda_max (the initial increment when adaptive)", &sc->steps, NULL));
  PetscCheck(sc->steps >= 1, comm, PETSC_ERR_USER_INPUT, "Option -pd_steps: must be at least 1, got %" PetscInt_FMT, sc->steps);
  {
    PetscInt  v = sc->region[sc->load_region].kind == PD_REGION_FORCE ? PD_CONTROL_FORCE : PD_CONTROL_DISPLACEMENT, t = sc->tangent;
    PetscBool set;
    PetscCall(PDOptionEnum(PetscOptionsObject, "-pd_control",
                           "Path control: displacement or force (must match the load region's kind), arclength (path following), auto "
                           "(the region's control until bonds soften, then path following)",
                           PDControlNames, 4, &v, &set));
    sc->control = (PDControl)v;
    PetscCheck(sc->control >= PD_CONTROL_ARCLENGTH ||
                   (sc->control == PD_CONTROL_FORCE) == (sc->region[sc->load_region].kind == PD_REGION_FORCE),
               comm, PETSC_ERR_USER_INPUT, "Option -pd_control: '%s' does not match the load region %s, which is a %s region",
               PDControlNames[sc->control], sc->region[sc->load_region].option, PDRegionKinds[sc->region[sc->load_region].kind]);
    if (sc->control >= PD_CONTROL_ARCLENGTH) {
      PetscInt at = sc->has_cmod ? PD_ARC_CMOD : PD_ARC_CYLINDRICAL;
      PetscCall(PDOptionEnum(PetscOptionsObject, "-pd_arclength_type",
                             "Path-following constraint: spherical, cylindrical (displacement norm), cmod (gauge opening), dissipation "
                             "(energy released); default cmod when the scene has a gauge",
                             PDArcTypes, 4, &at, NULL));
      sc->arc_type = (PDArcType)at;
      PetscCheck(sc->arc_type != PD_ARC_CMOD || sc->has_cmod, comm, PETSC_ERR_USER_INPUT,
                 "Option -pd_arclength_type: cmod needs a CMOD gauge (-pd_cmod_points)");
      {
        static const char *const solves[] = {"bordering", "augmented"};
        PetscInt                 solve    = 1;
        PetscCall(
            PDOptionEnum(PetscOptionsObject, "-pd_arclength_solve",
                         "Linear systems of a Newton iteration under a linear constraint (cmod, dissipation): augmented (one solve of "
                         "the tangent bordered by the constraint) or bordering (two solves with the tangent)",
                         solves, 2, &solve, NULL));
        sc->arc_augmented = solve == 1 ? PETSC_TRUE : PETSC_FALSE;
      }
      sc->arc_growth     = 4;
      sc->arc_target_its = 6;
      sc->stop_fraction  = 0.02;
      sc->arc_rtol       = 1e-7;
      PetscCall(
          PDOptionReal(PetscOptionsObject, "-pd_arclength_rtol",
                       "Path following: a step is in equilibrium when |residual| is below this fraction of |f_int| (applied forces and "
                       "reactions)",
                       &sc->arc_rtol, NULL));
      PetscCheck(sc->arc_rtol > 0 && sc->arc_rtol < 1, comm, PETSC_ERR_USER_INPUT, "Option -pd_arclength_rtol: must lie in (0, 1), got %g",
                 (double)sc->arc_rtol);
      PetscCall(PDOptionInt(PetscOptionsObject, "-pd_arclength_halved_its",
                            "Path following: halved Newton updates (after Newton cycles on frozen branches) allowed before the step is "
                            "cut; 0: the whole budget",
                            &sc->arc_halved_its, NULL));
      PetscCheck(sc->arc_halved_its >= 0, comm, PETSC_ERR_USER_INPUT,
                 "Option -pd_arclength_halved_its: must be non-negative, got %" PetscInt_FMT, sc->arc_halved_its);
      PetscCall(PDOptionInt(PetscOptionsObject, "-pd_arclength_hold",
                            "Path following: accepted steps after a cut during which the arc length does not grow", &sc->arc_hold, NULL));
      PetscCheck(sc->arc_hold >= 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_arclength_hold: must be non-negative, got %" PetscInt_FMT,
                 sc->arc_hold);
      PetscCall(PDOptionReal(PetscOptionsObject, "-pd_arclength_implex",
                             "Path following with IMPL-EX: each step uses bond damage extrapolated from the last two steps and "
                             "solves a secant problem (no softening kink, a definite matrix); the value is the largest difference in "
                             "bond damage between real and extrapolated history per step, which the arc length adapts to; 0: implicit",
                             &sc->arc_implex, NULL));
      PetscCheck(sc->arc_implex >= 0 && sc->arc_implex < 1, comm, PETSC_ERR_USER_INPUT,
                 "Option -pd_arclength_implex: must lie in [0, 1), got %g", (double)sc->arc_implex);
      PetscCheck(sc->arc_implex == 0 || sc->arc_type != PD_ARC_DISSIPATION, comm, PETSC_ERR_USER_INPUT,
                 "Option -pd_arclength_implex: a secant step dissipates nothing the dissipation constraint can measure; use cmod, "
                 "cylindrical or spherical");
      PetscCall(PDOptionReal(PetscOptionsObject, "-pd_arclength_initial",
                             "First arc length in the constraint's units (m, or J for dissipation); 0: what the first load step gives",
                             &sc->arc_initial, NULL));
      PetscCheck(sc->arc_initial >= 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_arclength_initial: must be non-negative, got %g",
                 (double)sc->arc_initial);
      PetscCall(
          PDOptionReal(PetscOptionsObject, "-pd_arclength_growth", "Largest arc length as a multiple of the first", &sc->arc_growth, NULL));
      PetscCheck(sc->arc_growth >= 1, comm, PETSC_ERR_USER_INPUT, "Option -pd_arclength_growth: must be at least 1, got %g",
                 (double)sc->arc_growth);
      PetscCall(PDOptionInt(PetscOptionsObject, "-pd_arclength_target_its", "Newton iterations per step the adaptive arc length aims at",
                            &sc->arc_target_its, NULL));
      PetscCheck(sc->arc_target_its >= 1, comm, PETSC_ERR_USER_INPUT,
                 "Option -pd_arclength_target_its: must be at least 1, got %" PetscInt_FMT, sc->arc_target_its);
      PetscCall(PDOptionFraction(PetscOptionsObject, "-pd_stop_fraction",
                                 "After the peak, stop with status separated once the load falls below this fraction of it; 0: off",
                                 &sc->stop_fraction));
      PetscCall(PDOptionFraction(PetscOptionsObject, "-pd_unload_at",
                                 "After the peak, unload once the load falls to this fraction of the peak, then load again; 0: off",
                                 &sc->unload_at));
      PetscCheck(
          sc->unload_at == 0 || sc->arc_type != PD_ARC_DISSIPATION, comm, PETSC_ERR_USER_INPUT,
          "Option -pd_unload_at: unloading dissipates nothing, so the dissipation constraint cannot follow it; use cmod, cylindrical "
          "or spherical");
      sc->reload_at = 0.02;
      PetscCall(PDOptionReal(PetscOptionsObject, "-pd_reload_at",
                             "With -pd_unload_at: load again once the load falls to this fraction of the peak", &sc->reload_at, NULL));
      PetscCheck(sc->reload_at >= 0 && (sc->unload_at == 0 || sc->reload_at < sc->unload_at), comm, PETSC_ERR_USER_INPUT,
                 "Option -pd_reload_at: must lie in [0, -pd_unload_at), got %g", (double)sc->reload_at);
    }
    PetscCall(PDOptionEnum(PetscOptionsObject, "-pd_tangent",
                           "Tangent of softening bonds: consistent (quadratic Newton, indefinite) or secant (positive)", PDTangentNames, 2,
                           &t, NULL));
    sc->tangent = (PDTangent)t;
    t           = sc->pc_matrix;
    PetscCall(PDOptionEnum(PetscOptionsObject, "-pd_pc_matrix",
                           "Matrix the preconditioner is built from: tangent (the Newton matrix) or secant (softening bonds at their "
                           "secant slope: definite where the tangent is not, after localisation)",
                           PDPCMatrixNames, 2, &t, NULL));
    sc->pc_matrix = (PDPCMatrix)t;
  }
  PetscCall(PDOptionReal(PetscOptionsObject, "-pd_lambda_max", "Load factor at which the path ends", &sc->lambda_max, NULL));
  PetscCheck(sc->lambda_max > 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_lambda_max: must be positive, got %g", (double)sc->lambda_max);
  sc->dlambda_max = sc->lambda_max / sc->steps;
  PetscCall(PDOptionReal(PetscOptionsObject, "-pd_dlambda_max", "Largest load-factor increment", &sc->dlambda_max, NULL));
  PetscCall(
      PDOptionReal(PetscOptionsObject, "-pd_dlambda_min", "Smallest load-factor increment before the run stops", &sc->dlambda_min, NULL));
  PetscCheck(sc->dlambda_min > 0 && sc->dlambda_min <= sc->dlambda_max, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_dlambda_min: must be positive and at most -pd_dlambda_max, got %g", (double)sc->dlambda_min);
  PetscCall(
      PDOptionReal(PetscOptionsObject, "-pd_stop_cmod", "Stop once the CMOD gauge opens this much (m); 0: off", &sc->stop_cmod, NULL));
  if (sc->explicit_mode) {
    PetscCall(PDOptionReal(PetscOptionsObject, "-pd_ramp_time",
                           "Explicit: duration of the fifth-order smoothstep ramp of the load factor (s); 0: 20,000 time steps",
                           &sc->ramp_time, NULL));
    PetscCheck(sc->ramp_time >= 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_ramp_time: must be non-negative, got %g", (double)sc->ramp_time);
    PetscCall(PDOptionReal(PetscOptionsObject, "-pd_hold_time", "Explicit: time held at the end of the ramp (s)", &sc->hold_time, NULL));
    PetscCheck(sc->hold_time >= 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_hold_time: must be non-negative, got %g", (double)sc->hold_time);
    PetscCall(PDOptionReal(PetscOptionsObject, "-pd_dt_safety",
                           "Explicit: time step as a fraction of the stable step 2/sqrt(lambda_max(M^-1 K)) (docs/explicit.md)",
                           &sc->dt_safety, NULL));
    PetscCheck(sc->dt_safety > 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_dt_safety: must be positive, got %g", (double)sc->dt_safety);
    PetscCall(PDOptionInt(PetscOptionsObject, "-pd_dt_power_its",
                          "Explicit: power iterations estimating the largest eigenvalue of the mass-scaled stiffness", &sc->dt_power_its,
                          NULL));
    PetscCheck(sc->dt_power_its > 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_dt_power_its: must be positive, got %" PetscInt_FMT,
               sc->dt_power_its);
    PetscCall(
        PDOptionReal(PetscOptionsObject, "-pd_damping", "Explicit: local damping C (kg/(m^3 s)), force density -C v", &sc->damping, NULL));
    PetscCheck(sc->damping >= 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_damping: must be non-negative, got %g", (double)sc->damping);
    PetscCall(
        PDOptionBool(PetscOptionsObject, "-pd_adr",
                     "Explicit: adaptive dynamic relaxation (fictitious masses, unit time steps, damping from the Rayleigh quotient); "
                     "times are then counted in steps",
                     &sc->adr, NULL));
    PetscCheck(!(sc->adr && sc->damping > 0), comm, PETSC_ERR_USER_INPUT, "Option -pd_adr: sets its own damping; drop -pd_damping %g",
               (double)sc->damping);
    PetscCall(PDOptionInt(PetscOptionsObject, "-pd_output_stride", "Explicit: time steps between curve rows; 0: about 400 rows",
                          &sc->out_stride, NULL));
    PetscCheck(sc->out_stride >= 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_output_stride: must be non-negative, got %" PetscInt_FMT,
               sc->out_stride);
  }
  if (sc->failure_search) {
    PetscCheck(sc->region[sc->load_region].kind == PD_REGION_FORCE, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_failure_search: needs a load-controlled scene; the load region %s is of kind %s, not force",
               sc->region[sc->load_region].option, PDRegionKinds[sc->region[sc->load_region].kind]);
    PetscCheck(sc->damping > 0, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_failure_search: needs -pd_damping > 0 (a trial that survives must come to rest), got %g", (double)sc->damping);
    PetscCall(ReadFailureSearch(PetscOptionsObject, comm, sc));
  }
  PetscCheck(sc->stop_cmod >= 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_stop_cmod: must be non-negative, got %g", (double)sc->stop_cmod);
  PetscCheck(sc->stop_cmod == 0 || sc->has_cmod, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_stop_cmod: the scene has no CMOD gauge (-pd_cmod_points)");
  PetscCall(PDOptionInt(PetscOptionsObject, "-pd_limiter_max_bonds",
                        "Damage limiter: bond events (entering softening, breaking) per Newton iteration; 0: no cap; default 10 per "
                        "150,000 bonds, at least 10",
                        &sc->limiter_max, &set));
  PetscCheck(!set || sc->limiter_max >= 0, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_limiter_max_bonds: must be non-negative, got %" PetscInt_FMT, sc->limiter_max);
  PetscCall(PDOptionInt(PetscOptionsObject, "-pd_limiter_stage_its", "Newton iterations between two grants of the limiter",
                        &sc->limiter_stage_its, NULL));
  PetscCheck(sc->limiter_stage_its >= 1, comm, PETSC_ERR_USER_INPUT, "Option -pd_limiter_stage_its: must be at least 1, got %" PetscInt_FMT,
             sc->limiter_stage_its);
  PetscCall(PDOptionInt(PetscOptionsObject, "-pd_limiter_sublevels",
                        "Damage limiter: levels on the softening branch (geometric in stretch from s0 to sc), each granted as an event; "
                        "1: the whole branch at once",
                        &sc->limiter_sublevels, NULL));
  PetscCheck(sc->limiter_sublevels >= 1 && sc->limiter_sublevels <= 100, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_limiter_sublevels: must be 1 to 100, got %" PetscInt_FMT, sc->limiter_sublevels);
  PetscCall(PDOptionInt(PetscOptionsObject, "-pd_fields_every", "Write fields every N steps (0: last step only)", &sc->fields_every, NULL));
  PetscCheck(sc->fields_every >= 0, comm, PETSC_ERR_USER_INPUT, "Option -pd_fields_every: must be non-negative, got %" PetscInt_FMT,
             sc->fields_every);
  {
    PetscBool every, restart;
    PetscCall(PDOptionInt(PetscOptionsObject, "-pd_checkpoint_every",
                          "Path following: write checkpoint.h5 every N accepted steps (0: only when the run stops early)",
                          &sc->checkpoint_every, &every));
    PetscCheck(sc->checkpoint_every >= 0, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_checkpoint_every: must be non-negative, got %" PetscInt_FMT, sc->checkpoint_every);
    PetscCall(PDOptionString(PetscOptionsObject, "-pd_restart", "Path following: go on from this checkpoint.h5 of the same scene",
                             sc->restart, sizeof sc->restart, &restart));
    PetscCheck(!(every || restart) || (sc->control >= PD_CONTROL_ARCLENGTH && !sc->explicit_mode), comm, PETSC_ERR_USER_INPUT,
               "Option %s: checkpoints belong to path following (-pd_control arclength or auto, implicit)",
               restart ? "-pd_restart" : "-pd_checkpoint_every");
  }
  PetscCall(PetscSNPrintf(sc->output_dir, sizeof sc->output_dir, "output/%s", sc->name));
  PetscCall(PDOptionString(PetscOptionsObject, "-pd_output_dir", "Output directory", sc->output_dir, sizeof sc->output_dir, NULL));
  PetscCall(PDOptionString(PetscOptionsObject, "-pd_data_file",
                           "Experimental CSV (cmod_mm, load mean/min/max kN) overlaid on curve.svg; relative to the options file",
                           sc->data_file, sizeof sc->data_file, NULL));
  sc->progress = PETSC_FALSE;
  PetscCall(PDOptionBool(PetscOptionsObject, "-pd_progress", "One-line progress display on stderr", &sc->progress, NULL));
  PetscCall(PDOptionBool(PetscOptionsObject, "-pd_dry_run",
                         "Build the scene and write summary.json (counts, law, memory estimate) without solving", &sc->dry_run, NULL));
  PetscOptionsEnd();
  if (sc->data_file[0]) {
    PetscBool exists;
    PetscCall(ResolveNextToOptionsFile(sc->data_file, sizeof sc->data_file));
    PetscCall(PetscTestFile(sc->data_file, 'r', &exists));
    PetscCheck(exists, comm, PETSC_ERR_FILE_OPEN, "Option -pd_data_file: cannot read '%s'", sc->data_file);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode PDSceneView(const PDScene *sc, PetscViewer v) {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(v, "Scene %s: %s, domain [%g %g %g] to [%g %g %g] m, dx %g m, horizon %g dx, influence %s\n", sc->name,
                                   PDModelKinds[sc->model], (double)sc->domain[0], (double)sc->domain[1], (double)sc->domain[2],
                                   (double)sc->domain[3], (double)sc->domain[4], (double)sc->domain[5], (double)sc->dx,
                                   (double)sc->horizon_ratio, PDInfluences[sc->influence]));
  PetscCall(PetscViewerASCIIPrintf(
      v, "  %" PetscInt_FMT " materials, %" PetscInt_FMT " notches, %" PetscInt_FMT " regions, %" PetscInt_FMT " steps, kinematics %s\n",
      sc->nmaterials, sc->nnotches, sc->nregions, sc->steps, PDKinematicsNames[sc->kinematics]));
  PetscFunctionReturn(0);
}
