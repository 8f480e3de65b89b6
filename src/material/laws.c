/* Tension-softening bond laws (THEORY.md Sec. 3; Hobbs Sec. 5.3). All are pure functions of the
   largest stretch kappa; the force is g = c_b (1 - d(kappa)) s.

   Every formula for a critical stretch in the thesis contains pi c delta^5 (constant influence, 3D).
   It comes from the work needed to break every bond crossing a unit area, G = geo * A, where A is the
   area under g/c up to s_c and geo = pi c int_0^delta omega xi^4 dxi in 3D (2 t c int omega xi^3 in 2D).
   Writing pi c delta^5 = 5 geo extends the printed formulas to other influence functions and to 2D, and
   to a bond whose micromodulus is lambda c (Eq. 5.32 generalised): geo scales with lambda. */
#include "pd_material.h"

/* s0, s1, sc for a given 5 geo (the thesis's pi c delta^5) and tensile strength ft: the nominal bond's, and
   the reference PDLawBondThresholdsScaled is tested against (per bond it scales the nominal ones). */
static void Thresholds(const PDLaw *law, PetscReal pcd5, PetscReal ft, PDLawBond *t) {
  const PetscReal G = law->Gf;
  t->s0 = t->s1 = t->sc = PETSC_MAX_REAL;
  switch (law->kind) {
  case PD_LAW_LINEAR:
    t->sc = PetscSqrtReal(10 * G / pcd5);
    t->s0 = t->s1 = t->sc;
    break;
  case PD_LAW_BILINEAR:
    if (law->bobaru) {
      t->s0 = ft / law->E;
      t->sc = 10 * G / (pcd5 * t->s0);
    } else {
      t->s0 = PetscSqrtReal(10 * (G / law->kr) / pcd5);
      t->sc = law->kr * t->s0;
    }
    t->s1 = t->sc;
    break;
  case PD_LAW_TRILINEAR: {
    const PetscReal b = law->beta, gamma = (3 + 2 * b) / (2 * b * (1 - b));
    t->s0 = ft / law->E;
    t->sc = 10 * gamma * G / (pcd5 * t->s0 * (1 + gamma * b)) + t->s0;
    t->s1 = t->s0 + (t->sc - t->s0) / gamma;
  } break;
  case PD_LAW_SLIP: /* it leaves the initial slope at once and never breaks; s1 the end of the rise */
    t->s0 = 0;
    t->s1 = law->slip.x[1] / law->slip_length;
    break;
  case PD_LAW_NONLINEAR: /* corrected Eq. 5.21 (THEORY.md), its shape factor from PDLawSetUp */
    t->s0 = ft / law->E;
    t->sc = t->s0 + law->shape * G / (pcd5 * t->s0);
    t->s1 = t->sc;
    break;
  default:
    break;
  }
}

PetscErrorCode PDLawSetUp(const PDScene *sc, const PDMaterial *mat, PDLaw *law) {
  const PetscReal delta = sc->horizon_ratio * sc->dx;
  PetscReal       geo;
  PDLawBond       t;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(law, sizeof *law));
  law->kind      = mat->law;
  law->sublevels = PetscMax(1, sc->limiter_sublevels); /* a zeroed scene (unit tests) means one */
  law->c         = PDMicromodulus(sc, mat->E);
  law->E         = mat->E;
  law->ft        = mat->ft;
  law->Gf        = mat->Gf;
  law->kr        = mat->kr;
  law->bobaru    = mat->bobaru;
  law->beta      = mat->beta;
  law->k         = mat->k;
  law->alpha     = mat->alpha;
  law->per_bond  = sc->surface_correction && sc->sc_correction;
  if (sc->dim == 3)
    geo = PETSC_PI * law->c * PDInfluenceMoment(sc->influence, 4) * PetscPowReal(delta, 5);
  else
    geo = 2 * sc->thickness * law->c * PDInfluenceMoment(sc->influence, 3) * PetscPowReal(delta, 4);
  if (sc->gf_lattice) geo *= PDLatticeFractureRatio(sc);
  law->geo = geo;
  if (law->kind == PD_LAW_NONLINEAR) {
    /* the printed Eq. 5.21 is too large by alpha s0 (THEORY.md). (1 - e^k)/Q is evaluated as
       (e^-k - 1)/(Q e^-k) so that k = 25 does not overflow anything. */
    const PetscReal k = law->k, a = law->alpha, emk = PetscExpReal(-k);
    const PetscReal Qs = (2 * k + a * k + 2) * emk - 2 - a * k; /* Q e^-k */
    law->shape         = 10 * k * (emk - 1) * (1 + a) / Qs;
  }
  Thresholds(law, 5 * geo, law->ft, &t);
  law->nominal = t;
  if (mat->fc > 0 && law->kind != PD_LAW_ELASTIC) {
    /* Uniaxial compression eps < 0 along a lattice axis stretches the bonds across it by nu |eps| and gives
       the nodes the dilatation k eps, k = 1 - 2 nu (3D) or 1 - nu (plane), nu the stencil's own Poisson
       ratio (the continuum's 1/4 or 1/3 is not the lattice's, and the onset below is the small difference
       of two terms): without a rise, the lateral bonds soften at |sigma| = E s0 / nu. A rise of confine
       times the compression -theta puts that at |sigma| = fc: nu fc / E = s0 + confine k fc / E. */
    const PetscReal nu = PDLatticePoissonRatio(sc), k = sc->dim == 3 ? 1 - 2 * nu : 1 - nu;
    law->confine = (nu * mat->fc / mat->E - t.s0) / (k * mat->fc / mat->E);
    PetscCheck(law->confine > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s_fc: %g Pa is not above the compressive strength the lattice has without it, E s0 / nu = %g Pa", mat->option,
               (double)mat->fc, (double)(mat->E * t.s0 / nu));
  }
  PetscFunctionReturn(0);
}

void PDLawSetUpSlip(const PDBar *b, PetscReal link_length, PDLaw *law) {
  *law             = (PDLaw){0};
  law->kind        = PD_LAW_SLIP;
  law->sublevels   = 1;
  law->slip_length = link_length;
  PDSlipEnvelopeSetUp(b, &law->slip);
  Thresholds(law, 0, 0, &law->nominal);
}

void PDLawBondThresholds(const PDLaw *law, PetscReal lambda, PetscReal strength, PDLawBond *t) {
  Thresholds(law, 5 * law->geo * (law->per_bond ? lambda : 1), strength * law->ft, t);
}

PetscReal PDLawDamage(const PDLaw *law, const PDLawBond *t, PetscReal kappa, PetscReal *dd) {
  const PetscReal s0 = t->s0, s1 = t->s1, sc = t->sc;
  *dd = 0;
  if (law->kind == PD_LAW_ELASTIC) return 0;
  if (kappa >= sc) return 1;
  if (law->kind == PD_LAW_LINEAR || kappa <= s0) return 0;
  switch (law->kind) {
  case PD_LAW_BILINEAR: /* Eq. 5.5 */
    *dd = (s0 / (kappa * kappa)) * sc / (sc - s0);
    return (1 - s0 / kappa) * sc / (sc - s0);
  case PD_LAW_TRILINEAR: { /* Eqs. 5.6 to 5.15 */
    const PetscReal b = law->beta, eta = s1 / s0;
    if (kappa < s1) {
      *dd = ((eta - b) / (eta - 1)) * s0 / (kappa * kappa);
      return 1 - ((eta - b) / (eta - 1)) * (s0 / kappa) + (1 - b) / (eta - 1);
    }
    *dd = b * s0 * sc / ((sc - s1) * kappa * kappa);
    return 1 - b * (s0 / kappa) * (sc - kappa) / (sc - s1);
  }
  case PD_LAW_SLIP: { /* 1 - d = tau(x) / (k0 x) at slip x = kappa L */
    const PetscReal L = law->slip_length, x = kappa * L, k0 = law->slip.k0;
    PetscReal       dtau, tau = PDSlipStress(&law->slip, x, &dtau);
    *dd = -L * (dtau * x - tau) / (k0 * x * x);
    return 1 - tau / (k0 * x);
  }
  case PD_LAW_NONLINEAR: { /* Eq. 5.16 */
    const PetscReal k = law->k, a = law->alpha, x = (kappa - s0) / (sc - s0), ek = PetscExpReal(-k * x), den = 1 - PetscExpReal(-k);
    const PetscReal h = (1 - (1 - ek) / den + a * (1 - x)) / (1 + a), dh = (-k * ek / den - a) / (1 + a);
    *dd = (s0 / (kappa * kappa)) * h - (s0 / kappa) * dh / (sc - s0);
    return 1 - (s0 / kappa) * h;
  }
  default:
    return 0;
  }
}

/* Envelope work W(kappa) = int_0^kappa (1 - d(x)) x dx, in closed form: the branches of g/c are linear
   except the non-linear law's exponential, whose h integrates exactly. */
PetscReal PDLawEnvelopeWork(const PDLaw *law, const PDLawBond *t, PetscReal kappa) {
  const PetscReal s0 = t->s0, s1 = t->s1, sc = t->sc, x = PetscMin(kappa, sc);
  if (law->kind == PD_LAW_ELASTIC || law->kind == PD_LAW_LINEAR || x <= s0) return 0.5 * x * x;
  switch (law->kind) {
  case PD_LAW_BILINEAR: /* g/c falls linearly from s0 at s0 to 0 at sc */
    return 0.5 * s0 * s0 + 0.5 * (x - s0) * (s0 + s0 * (sc - x) / (sc - s0));
  case PD_LAW_TRILINEAR: { /* s0 -> beta s0 at s1, then -> 0 at sc */
    const PetscReal b = law->beta;
    if (x <= s1) return 0.5 * s0 * s0 + 0.5 * (x - s0) * (s0 + s0 * (1 + (b - 1) * (x - s0) / (s1 - s0)));
    return 0.5 * s0 * s0 + 0.5 * (s1 - s0) * (1 + b) * s0 + 0.5 * (x - s1) * (b * s0 + b * s0 * (sc - x) / (sc - s1));
  }
  case PD_LAW_SLIP: /* g/c = tau(x L) / (k0 L) */
    return PDSlipWork(&law->slip, x * law->slip_length) / (law->slip.k0 * law->slip_length * law->slip_length);
  case PD_LAW_NONLINEAR: { /* g/c = s0 h((x - s0)/(sc - s0)) */
    const PetscReal k = law->k, a = law->alpha, den = 1 - PetscExpReal(-k), X = (x - s0) / (sc - s0);
    const PetscReal Ih = (X - (X - (1 - PetscExpReal(-k * X)) / k) / den + a * (X - 0.5 * X * X)) / (1 + a);
    return 0.5 * s0 * s0 + s0 * (sc - s0) * Ih;
  }
  default:
    return 0.5 * x * x;
  }
}

PetscReal PDLawWorkOfFracture(const PDLaw *law) {
  return PDLawEnvelopeWork(law, &law->nominal, law->nominal.sc);
}

PetscReal PDLawNextThreshold(const PDLaw *law, const PDLawBond *t, PetscInt level) {
  if (law->kind == PD_LAW_ELASTIC || law->kind == PD_LAW_SLIP) return PETSC_MAX_REAL; /* the limiter holds neither */
  if (law->kind == PD_LAW_LINEAR) return level <= 1 ? t->sc : PETSC_MAX_REAL;         /* no softening branch to divide */
  if (level > law->sublevels) return PETSC_MAX_REAL;
  if (level == PD_BOND_ELASTIC) return t->s0;
  /* sub-levels hold a bond that snaps along its envelope at points the limiter grants one at a time */
  return level == law->sublevels ? t->sc : t->s0 * PetscPowReal(t->sc / t->s0, (PetscReal)level / law->sublevels);
}

PetscInt PDLawLevelOf(const PDLaw *law, const PDLawBond *t, PetscReal kappa) {
  PetscInt level = 0;
  while (level <= law->sublevels && kappa >= PDLawNextThreshold(law, t, level)) level++;
  return level;
}
