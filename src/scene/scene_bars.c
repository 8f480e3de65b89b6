/* Steel bars of a scene (-pd_barK_*): straight, along a lattice direction, numbered without gaps; a bar
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
   half a spacing off the line the chain follows, the rounding every bar position gets. */
static PetscErrorCode BarStep(const PDScene *sc, PDBar *b, const char *opt) {
  PetscReal d[3], len = 0, best = -2, off, along;
  PetscInt  bn2 = 0, st[4] = {0, 0, 0, -1};

  PetscFunctionBeginUser;
  for (PetscInt a = 0; a < 3; a++) {
    d[a] = (b->line[3 + a] - b->line[a]) / sc->dx;
    len += d[a] * d[a];
  }
  len = PetscSqrtReal(len);
  PetscCheck(len >= 1 - 1e-9, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: a bar spans at least one grid spacing (%g m) to hold a segment, this one %g m", opt, (double)sc->dx,
             (double)(len * sc->dx));
  while (PDFamilyNext(sc->horizon_ratio, sc->dim, st)) {
    const PetscReal c = (st[0] * d[0] + st[1] * d[1] + st[2] * d[2]) / (len * PetscSqrtReal((PetscReal)st[3]));
    if (c > best + 1e-12 || (c > best - 1e-12 && st[3] < bn2)) {
      best = c;
      bn2  = st[3];
      for (PetscInt a = 0; a < 3; a++) b->step[a] = st[a];
    }
  }
  along = len * best;
  off   = PetscSqrtReal(PetscMax(0, len * len - along * along));
  PetscCheck(off <= 0.5 + 1e-9, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: the bar does not run along a lattice direction within the horizon: the nearest, (%" PetscInt_FMT ", %" PetscInt_FMT
             ", %" PetscInt_FMT "), would leave its far end %g m off the bar (at most dx/2 = %g m)",
             opt, b->step[0], b->step[1], b->step[2], (double)(off * sc->dx), (double)(0.5 * sc->dx));
  PetscCheck(along >= PetscSqrtReal((PetscReal)bn2) - 1e-9, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: the bar is shorter than one step (%g m) of its lattice direction (%" PetscInt_FMT ", %" PetscInt_FMT
             ", %" PetscInt_FMT ") and would hold no segment",
             opt, (double)(PetscSqrtReal((PetscReal)bn2) * sc->dx), b->step[0], b->step[1], b->step[2]);
  PetscFunctionReturn(0);
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
  PetscReal v[6] = {0, 0, 0, 0, 0, 0};
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
  PetscCall(BarStep(sc, b, opt));
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
