/* Materials, notches, node regions and voids of a scene. Members of each family are numbered without
   gaps; a member exists once its box (a region or void: its box or cylinder) is given. */
#include "scene_read.h"
#include "option_values.h"

/* 2D scenes give boxes as x0,y0,x1,y1 and points as x,y; store them in 3D form with z = 0. */
static PetscErrorCode ReadBox(PetscOptionItems *PetscOptionsObject, PDScene *sc, const char *opt, PetscReal box[6], PetscBool *set) {
  PetscReal v[6];
  PetscInt  n = 2 * sc->dim;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < 6; i++) v[i] = 0;
  for (PetscInt a = 0; a < sc->dim; a++) {
    v[a]           = box[a];
    v[sc->dim + a] = box[3 + a];
  }
  PetscCall(PDOptionRealArray(PetscOptionsObject, sc, opt, v, &n, set));
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

static PetscErrorCode ReadDofs(PetscOptionItems *PetscOptionsObject, PDScene *sc, const char *opt, PetscBool dof[3], PetscBool *set) {
  char buf[64] = "";

  PetscFunctionBeginUser;
  PetscCall(PDOptionString(PetscOptionsObject, sc, opt, buf, sizeof buf, set));
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

static PetscErrorCode ReadVector(PetscOptionItems *PetscOptionsObject, PDScene *sc, const char *opt, PetscReal vec[3], PetscBool *set) {
  PetscInt n = sc->dim;

  PetscFunctionBeginUser;
  PetscCall(PDOptionRealArray(PetscOptionsObject, sc, opt, vec, &n, set));
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

/* Reads m->option followed by suffix. */
static PetscErrorCode MaterialReal(PetscOptionItems *PetscOptionsObject, PDScene *sc, const PDMaterial *m, const char *suffix,
                                   PetscReal *value, PetscBool *set) {
  char opt[64];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s%s", m->option, suffix));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, opt, value, set));
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadLaw(PetscOptionItems *PetscOptionsObject, PDScene *sc, PDMaterial *m) {
  char      opt[64];
  PetscReal fcm = 0;
  PetscBool set_fcm;
  PetscInt  law = m->law, form = m->bobaru;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_law", m->option));
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, opt, &law, NULL));
  m->law = (PDLawKind)law;
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_bilinear_form", m->option));
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, opt, &form, NULL));
  m->bobaru = form ? PETSC_TRUE : PETSC_FALSE;
  /* strength and fracture energy are material data, read with every law */
  PetscCall(MaterialReal(PetscOptionsObject, sc, m, "_ft", &m->ft, NULL));
  PetscCheck(m->ft > 0 || m->law == PD_LAW_ELASTIC || m->law == PD_LAW_LINEAR || (m->law == PD_LAW_BILINEAR && !m->bobaru), PETSC_COMM_SELF,
             PETSC_ERR_USER_INPUT, "Option %s_ft: the %s law needs a positive tensile strength, got %g", m->option, PDLawNames[m->law],
             (double)m->ft);
  PetscCall(MaterialReal(PetscOptionsObject, sc, m, "_fc", &m->fc, NULL)); /* material data, like _ft: an elastic law ignores it */
  PetscCall(MaterialReal(PetscOptionsObject, sc, m, "_eps_cu", &m->eps_cu, NULL));
  PetscCall(MaterialReal(PetscOptionsObject, sc, m, "_fcm", &fcm, &set_fcm));
  if (set_fcm) m->Gf = 73 * PetscPowReal(fcm, 0.18); /* fib MC2010; a given _Gf overrides it */
  PetscCall(MaterialReal(PetscOptionsObject, sc, m, "_Gf", &m->Gf, NULL));
  PetscCheck(m->Gf > 0 || m->law == PD_LAW_ELASTIC, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s_Gf: the %s law needs a positive fracture energy (or %s_fcm), got %g", m->option, PDLawNames[m->law], m->option,
             (double)m->Gf);
  PetscCall(MaterialReal(PetscOptionsObject, sc, m, "_bilinear_kr", &m->kr, NULL));
  PetscCall(MaterialReal(PetscOptionsObject, sc, m, "_trilinear_beta", &m->beta, NULL));
  PetscCall(MaterialReal(PetscOptionsObject, sc, m, "_nonlinear_k", &m->k, NULL));
  PetscCall(MaterialReal(PetscOptionsObject, sc, m, "_nonlinear_alpha", &m->alpha, NULL));
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadMaterial(PetscOptionItems *PetscOptionsObject, PDScene *sc, PetscInt k) {
  PDMaterial *m = &sc->material[k];
  char        opt[64];
  PetscBool   set;

  PetscFunctionBeginUser;
  if (k == 0) {
    PetscCall(PetscStrncpy(m->option, "-pd", sizeof m->option));
    m->where.shape = PD_SHAPE_BOX;
    PetscCall(PetscArraycpy(m->where.box, sc->domain, 6));
  } else {
    *m = sc->material[0]; /* a further material starts from the base one */
    PetscCall(PetscSNPrintf(m->option, sizeof m->option, "-pd_material%" PetscInt_FMT, k));
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_box", m->option));
    PetscCall(ReadBox(PetscOptionsObject, sc, opt, m->where.box, &set));
    PetscCheck(BoxesOverlap(m->where.box, sc->domain, sc->dim, 0), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s: box lies outside the domain -pd_domain", opt);
  }
  PetscCall(MaterialReal(PetscOptionsObject, sc, m, "_E", &m->E, NULL));
  PetscCall(MaterialReal(PetscOptionsObject, sc, m, "_rho", &m->rho, NULL));
  PetscCall(ReadLaw(PetscOptionsObject, sc, m));
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
  PetscCall(ReadBox(PetscOptionsObject, sc, opt, n->box, &set));
  for (PetscInt a = 0; a < sc->dim; a++)
    if (n->box[3 + a] - n->box[a] <= tol) {
      n->normal = a;
      nflat++;
    }
  PetscCheck(nflat == 1, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: a notch box must be flat (zero width) along exactly one axis, %" PetscInt_FMT " are flat", opt, nflat);
  PetscCheck(BoxesOverlap(n->box, sc->domain, sc->dim, tol), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: notch lies outside the domain -pd_domain", opt);
  PetscFunctionReturn(0);
}

/* The box or cylinder of a region or void whose options start with prefix. */
static PetscErrorCode ReadShape(PetscOptionItems *PetscOptionsObject, PDScene *sc, const char *prefix, PDGeometry *g) {
  char      opt[64], opt2[64];
  PetscBool set_box, set_cyl;
  PetscInt  axis = 2, n = 4;
  PetscReal cyl[4] = {0, 0, 0, 0};

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_box", prefix));
  PetscCall(ReadBox(PetscOptionsObject, sc, opt, g->box, &set_box));
  PetscCall(PetscSNPrintf(opt2, sizeof opt2, "%s_cylinder", prefix));
  PetscCall(PDOptionRealArray(PetscOptionsObject, sc, opt2, cyl, &n, &set_cyl));
  PetscCheck(set_box != set_cyl, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Options %s and %s: give exactly one of them", opt, opt2);
  if (set_box) {
    g->shape = PD_SHAPE_BOX;
    PetscCheck(BoxesOverlap(g->box, sc->domain, sc->dim, 0.5 * sc->dx), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s: the box lies outside the domain -pd_domain", opt);
    PetscFunctionReturn(0);
  }
  PetscCheck(n == 4, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: expected 4 numbers (x,y,z,radius), got %" PetscInt_FMT, opt2, n);
  PetscCheck(cyl[3] > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: radius must be positive, got %g", opt2, (double)cyl[3]);
  g->shape = PD_SHAPE_CYLINDER;
  PetscCall(PetscArraycpy(g->center, cyl, 3));
  g->radius = cyl[3];
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_axis", prefix));
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, opt, &axis, NULL));
  PetscCheck(sc->dim == 3 || axis == 2, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: a 2D scene's cylinder (a disc) has axis z", opt);
  g->axis = axis;
  for (PetscInt a = 0; a < sc->dim; a++)
    if (a != axis)
      PetscCheck(cyl[a] + cyl[3] >= sc->domain[a] && cyl[a] - cyl[3] <= sc->domain[3 + a], PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                 "Option %s: the cylinder lies outside the domain -pd_domain", opt2);
  PetscFunctionReturn(0);
}

/* A void removes material, so it has volume: a flat box would select a layer of nodes and cut the body
   along it, which is what a notch is for. */
static PetscErrorCode ReadVoid(PetscOptionItems *PetscOptionsObject, PDScene *sc, PetscInt k) {
  PDVoid *v = &sc->voids[k];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(v->option, sizeof v->option, "-pd_void%" PetscInt_FMT, k));
  PetscCall(ReadShape(PetscOptionsObject, sc, v->option, &v->where));
  if (v->where.shape == PD_SHAPE_BOX)
    for (PetscInt a = 0; a < sc->dim; a++)
      PetscCheck(
          v->where.box[3 + a] - v->where.box[a] >= sc->dx, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
          "Option %s_box: a void is at least one grid spacing (%g m) wide along every axis, it is %g m along %c (a crack is a notch, "
          "-pd_notch%" PetscInt_FMT "_box)",
          v->option, (double)sc->dx, (double)(v->where.box[3 + a] - v->where.box[a]), (char)('x' + a), sc->nnotches);
  else
    PetscCheck(v->where.radius >= 0.5 * sc->dx, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s_cylinder: a void's radius is at least half a grid spacing (%g m), got %g m", v->option, (double)(0.5 * sc->dx),
               (double)v->where.radius);
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadRegion(PetscOptionItems *PetscOptionsObject, PDScene *sc, PetscInt k) {
  PDRegion *r = &sc->region[k];
  char      opt[64];
  PetscBool set, set_vec;
  PetscInt  kind = PD_REGION_MONITOR;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(r->option, sizeof r->option, "-pd_region%" PetscInt_FMT, k));
  PetscCall(ReadShape(PetscOptionsObject, sc, r->option, &r->where));
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_kind", r->option));
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, opt, &kind, &set));
  PetscCheck(set, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s is required (support, displacement, force or monitor)", opt);
  r->kind = (PDRegionKind)kind;
  {
    PetscInt nodes = 0;
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_nodes", r->option));
    PetscCall(PDOptionEnum(PetscOptionsObject, sc, opt, &nodes, NULL));
    r->on_bars = nodes == 1 ? PETSC_TRUE : PETSC_FALSE;
  }
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_dofs", r->option));
  PetscCall(ReadDofs(PetscOptionsObject, sc, opt, r->dof, &set));
  if (r->kind == PD_REGION_SUPPORT || r->kind == PD_REGION_DISPLACEMENT)
    PetscCheck(set && (r->dof[0] || r->dof[1] || r->dof[2]), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s is required for a %s region",
               opt, PDRegionKinds[r->kind]);
  else
    PetscCheck(!set, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: a %s region constrains no components", opt, PDRegionKinds[r->kind]);
  if (r->kind != PD_REGION_FORCE && r->kind != PD_REGION_DISPLACEMENT) PetscFunctionReturn(0);
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_%s", r->option, r->kind == PD_REGION_FORCE ? "force" : "displacement"));
  PetscCall(ReadVector(PetscOptionsObject, sc, opt, r->vector, &set_vec));
  PetscCheck(set_vec, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s is required for a %s region", opt, PDRegionKinds[r->kind]);
  PetscCheck(r->vector[0] != 0 || r->vector[1] != 0 || r->vector[2] != 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: the vector is zero", opt);
  for (PetscInt a = 0; a < 3 && r->kind == PD_REGION_DISPLACEMENT; a++)
    PetscCheck(r->dof[a] || r->vector[a] == 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s: component %c is non-zero but not listed in %s_dofs", opt, (char)('x' + a), r->option);
  PetscFunctionReturn(0);
}

static PetscErrorCode HasOption(const char *fmt, PetscInt k, PetscBool *has) {
  char opt[64];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(opt, sizeof opt, fmt, k));
  PetscCall(PetscOptionsHasName(NULL, NULL, opt, has));
  PetscFunctionReturn(0);
}

/* A region or void exists once its box or its cylinder is given. */
static PetscErrorCode HasShape(const char *prefix, PetscInt k, PetscBool *has) {
  char      opt[64];
  PetscBool box, cyl;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s%" PetscInt_FMT "_box", prefix, k));
  PetscCall(PetscOptionsHasName(NULL, NULL, opt, &box));
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s%" PetscInt_FMT "_cylinder", prefix, k));
  PetscCall(PetscOptionsHasName(NULL, NULL, opt, &cyl));
  *has = box || cyl ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* A member is counted before it is read, so that the schema sees it exist; options of members after a
   gap are left unread, and reported as unused. */
PetscErrorCode PDSceneReadParts(PetscOptionItems *PetscOptionsObject, PDScene *sc) {
  PetscBool has;

  PetscFunctionBeginUser;
  sc->nmaterials = 1;
  PetscCall(ReadMaterial(PetscOptionsObject, sc, 0));
  for (PetscInt k = 1; k < PD_MAX_MATERIALS; k++) {
    PetscCall(HasOption("-pd_material%" PetscInt_FMT "_box", k, &has));
    if (!has) break;
    sc->nmaterials = k + 1;
    PetscCall(ReadMaterial(PetscOptionsObject, sc, k));
  }
  for (PetscInt k = 0; k < PD_MAX_NOTCHES; k++) {
    PetscCall(HasOption("-pd_notch%" PetscInt_FMT "_box", k, &has));
    if (!has) break;
    sc->nnotches = k + 1;
    PetscCall(ReadNotch(PetscOptionsObject, sc, k));
  }
  for (PetscInt k = 0; k < PD_MAX_REGIONS; k++) {
    PetscCall(HasShape("-pd_region", k, &has));
    if (!has) break;
    sc->nregions = k + 1;
    PetscCall(ReadRegion(PetscOptionsObject, sc, k));
  }
  for (PetscInt k = 0; k < PD_MAX_VOIDS; k++) {
    PetscCall(HasShape("-pd_void", k, &has));
    if (!has) break;
    sc->nvoids = k + 1;
    PetscCall(ReadVoid(PetscOptionsObject, sc, k));
  }
  for (PetscInt k = 0; k < PD_MAX_MATERIALS; k++) {
    PDMaterial *p;
    char        opt[64];
    PetscBool   set;
    PetscCall(HasOption("-pd_plate%" PetscInt_FMT "_box", k, &has));
    if (!has) break;
    PetscCheck(sc->nmaterials + k < PD_MAX_MATERIALS, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option -pd_plate%" PetscInt_FMT "_box: materials and plates together are at most %d", k, PD_MAX_MATERIALS);
    sc->nplates = k + 1;
    p           = &sc->material[sc->nmaterials + k];
    PetscCall(PetscMemzero(p, sizeof *p));
    PetscCall(PetscSNPrintf(p->option, sizeof p->option, "-pd_plate%" PetscInt_FMT, k));
    p->law         = PD_LAW_ELASTIC;
    p->where.shape = PD_SHAPE_BOX;
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_box", p->option));
    PetscCall(ReadBox(PetscOptionsObject, sc, opt, p->where.box, &set));
    PetscCheck(BoxesOverlap(p->where.box, sc->domain, sc->dim, 0), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s: box lies outside the domain -pd_domain", opt);
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_E", p->option));
    PetscCall(PDOptionReal(PetscOptionsObject, sc, opt, &p->E, NULL));
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_rho", p->option));
    PetscCall(PDOptionReal(PetscOptionsObject, sc, opt, &p->rho, NULL));
  }
  for (PetscInt k = 0; k < PD_MAX_NOFAIL; k++) {
    PetscCall(HasShape("-pd_nofail", k, &has));
    if (!has) break;
    sc->nnofail = k + 1;
    PetscCall(PetscSNPrintf(sc->nofail[k].option, sizeof sc->nofail[k].option, "-pd_nofail%" PetscInt_FMT, k));
    PetscCall(ReadShape(PetscOptionsObject, sc, sc->nofail[k].option, &sc->nofail[k].where));
  }
  PetscCheck(sc->nregions > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option -pd_region0_box: the scene defines no node regions (supports and loads)");
  PetscFunctionReturn(0);
}
