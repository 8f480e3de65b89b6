/* Steel bars of a scene (-pd_barK_*): straight, along a lattice direction or embedded, numbered without gaps; a bar
   exists once its line is given. */
#include "option_values.h"
#include "scene_read.h"
#include "pd_lattice.h"

static PetscErrorCode BarReal(PetscOptionItems *PetscOptionsObject, PDScene *sc, const PDBar *b, const char *name, PetscReal *v) {
  char opt[64];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s%s", b->option, name));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, opt, v, NULL));
  PetscFunctionReturn(0);
}

/* The lattice offset a bar's chain of nodes steps by: of the offsets within the horizon, the one closest
   in direction to the bar (the shortest of those equally close, so that an axis gives (1, 0, 0)). The
   chain keeps the bar's direction only if the bar runs along that offset: its far end may lie at most
   half a spacing off the line the chain follows, the rounding every bar position gets. A bar that does
   not is embedded (*off: how far off, in spacings). */
static PetscErrorCode BarStep(const PDScene *sc, PDBar *b, PetscReal *off, PetscReal *along) {
  PetscReal d[3], len = 0, best = -2;
  PetscInt  bn2 = 0, st[4] = {0, 0, 0, -1};

  PetscFunctionBeginUser;
  for (PetscInt a = 0; a < 3; a++) {
    d[a] = (b->line[3 + a] - b->line[a]) / sc->dx;
    len += d[a] * d[a];
  }
  len = PetscSqrtReal(len);
  PetscCheck(len >= 1 - 1e-9, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s_line: a bar spans at least one grid spacing (%g m) to hold a segment, this one %g m", b->option, (double)sc->dx,
             (double)(len * sc->dx));
  while (PDFamilyNext(sc->horizon_ratio, sc->dim, st)) {
    const PetscReal c = (st[0] * d[0] + st[1] * d[1] + st[2] * d[2]) / (len * PetscSqrtReal((PetscReal)st[3]));
    if (c > best + 1e-12 || (c > best - 1e-12 && st[3] < bn2)) {
      best = c;
      bn2  = st[3];
      for (PetscInt a = 0; a < 3; a++) b->step[a] = st[a];
    }
  }
  *along = len * best;
  *off   = PetscSqrtReal(PetscMax(0, len * len - *along * *along));
  PetscFunctionReturn(0);
}

/* An embedded bar's unit vectors (along it, then across: in 2D the normal in the plane, in 3D the bar crossed
   with the axis it is least along, then the bar crossed with that) and its nodes. */
static void EmbeddedGeometry(const PDScene *sc, PDBar *b) {
  PetscReal *t = b->dir[0], *n1 = b->dir[1], *n2 = b->dir[2], len = 0, l1 = 0;
  PetscInt   a = 0;

  for (PetscInt c = 0; c < 3; c++) {
    t[c] = c < sc->dim ? b->line[3 + c] - b->line[c] : 0;
    len += t[c] * t[c];
  }
  len = PetscSqrtReal(len);
  for (PetscInt c = 0; c < 3; c++) t[c] /= len;
  b->nstation = (PetscInt)PetscCeilReal(len / sc->dx - 1e-9) + 1;
  b->spacing  = len / (b->nstation - 1);
  if (sc->dim == 2) {
    n1[0] = -t[1];
    n1[1] = t[0];
    n1[2] = 0;
    n2[0] = n2[1] = n2[2] = 0;
    return;
  }
  for (PetscInt c = 1; c < 3; c++)
    if (PetscAbsReal(t[c]) < PetscAbsReal(t[a])) a = c;
  n1[0] = a == 0 ? 0 : (a == 1 ? -t[2] : t[1]); /* t x e_a */
  n1[1] = a == 1 ? 0 : (a == 0 ? t[2] : -t[0]);
  n1[2] = a == 2 ? 0 : (a == 0 ? -t[1] : t[0]);
  for (PetscInt c = 0; c < 3; c++) l1 += n1[c] * n1[c];
  for (PetscInt c = 0; c < 3; c++) n1[c] /= PetscSqrtReal(l1);
  n2[0] = t[1] * n1[2] - t[2] * n1[1];
  n2[1] = t[2] * n1[0] - t[0] * n1[2];
  n2[2] = t[0] * n1[1] - t[1] * n1[0];
}

/* The bond-slip law of a bar (fib Model Code 2010, Sec. 6.1.1, pull-out, good bond): tau_max from f_cm, which
   defaults to the concrete's compressive strength where -pd_fc gives one; s1 = 1 mm and s2 = 2 mm as the code,
   s3 the clear rib spacing, which the code leaves to the bar (0.6 d by default, a typical rib spacing). */
static PetscErrorCode ReadSlip(PetscOptionItems *PetscOptionsObject, PDScene *sc, PDBar *b) {
  char      opt[64];
  PetscInt  n = 3;
  PetscBool set;

  PetscFunctionBeginUser;
  b->fcm = sc->material[0].fc;
  PetscCall(BarReal(PetscOptionsObject, sc, b, "_fcm", &b->fcm));
  PetscCheck(b->fcm > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s_fcm is required for a bar with bond slip (the concrete's mean compressive strength, Pa), unless -pd_fc gives it",
             b->option);
  PetscCheck(sc->kinematics == PD_KINEMATICS_SMALL, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s_bond slip needs -pd_kinematics small: the link to the concrete is 1e-4 dx long, and under finite "
             "kinematics a sideways move of the bar would read as slip",
             b->option);
  b->slips[0] = 1e-3;
  b->slips[1] = 2e-3;
  b->slips[2] = 0.6 * b->diameter;
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_slips", b->option));
  PetscCall(PDOptionRealArray(PetscOptionsObject, sc, opt, b->slips, &n, &set));
  PetscCheck(set || b->slips[2] > b->slips[1], PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s_slips is required for a bar this thin: the default s3 = 0.6 d = %g m is not above s2 = 2 mm", b->option,
             (double)b->slips[2]);
  PetscCheck(!set || n == 3, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: expected three slips s1,s2,s3 (m), got %" PetscInt_FMT, opt,
             n);
  PetscCheck(b->slips[0] > 0 && b->slips[0] <= b->slips[1] && b->slips[1] < b->slips[2], PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: the slips must satisfy 0 < s1 <= s2 < s3, got %g,%g,%g m", opt, (double)b->slips[0], (double)b->slips[1],
             (double)b->slips[2]);
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadBar(PetscOptionItems *PetscOptionsObject, PDScene *sc, PetscInt k) {
  PDBar    *b = &sc->bar[k];
  char      opt[64];
  PetscInt  n = 6, d = sc->dim;
  PetscReal v[6] = {0, 0, 0, 0, 0, 0}, off, along;
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(b->option, sizeof b->option, "-pd_bar%" PetscInt_FMT, k));
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_line", b->option));
  PetscCall(PDOptionRealArray(PetscOptionsObject, sc, opt, v, &n, &set));
  PetscCheck(n == 2 * d, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: expected %" PetscInt_FMT " numbers (%s of each end), got %" PetscInt_FMT, opt, 2 * d, d == 3 ? "x,y,z" : "x,y", n);
  for (PetscInt a = 0; a < d; a++) {
    b->line[a]     = v[a];
    b->line[3 + a] = v[d + a];
  }
  for (PetscInt a = 0; a < sc->dim; a++) {
    const PetscReal lo = PetscMin(b->line[a], b->line[3 + a]), hi = PetscMax(b->line[a], b->line[3 + a]);
    PetscCheck(lo >= sc->domain[a] - 1e-9 * sc->dx && hi <= sc->domain[3 + a] + 1e-9 * sc->dx, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s: the bar leaves the domain -pd_domain along %c", opt, (char)('x' + a));
  }
  PetscCall(BarStep(sc, b, &off, &along));
  PetscCall(BarReal(PetscOptionsObject, sc, b, "_diameter", &b->diameter));
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_diameter", b->option));
  PetscCheck(b->diameter > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s is required for a bar", opt);
  b->count = 1;
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_count", b->option));
  PetscCall(PDOptionInt(PetscOptionsObject, sc, opt, &b->count, NULL));
  PetscCall(BarReal(PetscOptionsObject, sc, b, "_E", &b->E));
  PetscCall(BarReal(PetscOptionsObject, sc, b, "_fy", &b->fy));
  PetscCall(BarReal(PetscOptionsObject, sc, b, "_hardening", &b->hardening));
  PetscCall(BarReal(PetscOptionsObject, sc, b, "_rupture", &b->rupture));
  {
    PetscInt bond = 0;
    PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_bond", b->option));
    PetscCall(PDOptionEnum(PetscOptionsObject, sc, opt, &bond, NULL));
    b->perfect = bond == 1 ? PETSC_TRUE : PETSC_FALSE;
    b->slip    = bond == 2 ? PETSC_TRUE : PETSC_FALSE;
  }
  /* a bar off the lattice directions can only be embedded; one along them may be */
  PetscCall(PetscSNPrintf(opt, sizeof opt, "%s_embedded", b->option));
  PetscCall(PDOptionBool(PetscOptionsObject, sc, opt, &b->embedded, &set));
  PetscCheck(!set || b->embedded || off <= 0.5 + 1e-9, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s false: the bar does not run along a lattice direction within the horizon (its far end lies %g m off the "
             "nearest one), so it can only be embedded",
             opt, (double)(off * sc->dx));
  b->embedded = b->embedded || off > 0.5 + 1e-9 ? PETSC_TRUE : PETSC_FALSE;
  PetscCheck(!b->embedded || sc->kinematics == PD_KINEMATICS_SMALL, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s_line: an embedded bar needs -pd_kinematics small: its links to the concrete are 1e-4 dx long, and under finite "
             "kinematics a sideways move would read as slip",
             b->option);
  PetscCheck(!b->embedded || b->slip || b->perfect || off <= 0.5 + 1e-9, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s_line: the bar does not run along a lattice direction within the horizon (its far end lies %g m off the nearest "
             "one, (%" PetscInt_FMT ", %" PetscInt_FMT ", %" PetscInt_FMT ")), so it is embedded on nodes of its own, which needs "
             "%s_bond slip or perfect",
             b->option, (double)(off * sc->dx), b->step[0], b->step[1], b->step[2], b->option);
  PetscCheck(!b->embedded || b->slip || b->perfect, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s_embedded: an embedded bar is on nodes of its own, which needs %s_bond slip or perfect", b->option, b->option);
  if (b->embedded)
    EmbeddedGeometry(sc, b);
  else {
    const PetscReal ls = PetscSqrtReal((PetscReal)(b->step[0] * b->step[0] + b->step[1] * b->step[1] + b->step[2] * b->step[2]));
    for (PetscInt a = 0; a < 3; a++) b->dir[0][a] = b->step[a] / ls;
    PetscCheck(along >= ls - 1e-9, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s_line: the bar is shorter than one step (%g m) of its lattice direction (%" PetscInt_FMT ", %" PetscInt_FMT
               ", %" PetscInt_FMT ") and would hold no segment; embed it (%s_embedded)",
               b->option, (double)(ls * sc->dx), b->step[0], b->step[1], b->step[2], b->option);
  }
  if (b->slip) PetscCall(ReadSlip(PetscOptionsObject, sc, b));
  PetscCheck(b->rupture == 0 || b->rupture > b->fy / b->E, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s_rupture: the rupture strain lies above the yield strain f_y/E = %g, got %g", b->option, (double)(b->fy / b->E),
             (double)b->rupture);
  PetscFunctionReturn(0);
}

PetscErrorCode PDSceneReadBars(PetscOptionItems *PetscOptionsObject, PDScene *sc) {
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < PD_MAX_BARS; k++) {
    char      opt[64];
    PetscBool has;
    PetscCall(PetscSNPrintf(opt, sizeof opt, "-pd_bar%" PetscInt_FMT "_line", k));
    PetscCall(PetscOptionsHasName(NULL, NULL, opt, &has));
    if (!has) break;
    sc->nbars = k + 1;
    PetscCall(ReadBar(PetscOptionsObject, sc, k));
  }
  PetscFunctionReturn(0);
}
