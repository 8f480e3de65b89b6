/* Material: micromodulus and influence functions (THEORY.md Sec. 1), bond laws (Sec. 3). */
#pragma once
#include "pd_scene.h"

PetscReal PDMicromodulus(const PDScene *, PetscReal E);
PetscReal PDInfluenceValue(PDInfluence, PetscReal len, PetscReal horizon);
PetscReal PDInfluenceMoment(PDInfluence, PetscInt k); /* int_0^1 omega(r) r^k dr */
PetscReal PDLatticeFractureRatio(const PDScene *);
PetscReal PDLatticeStiffnessRatio(const PDScene *); /* the lattice bulk's Young's modulus along an axis over the continuum's */
PetscReal PDLatticePoissonRatio(const PDScene *);   /* the lattice bulk's Poisson ratio under uniaxial stress along an axis */

/* Bond states the damage limiter hands out one level at a time: elastic, then the softening branch in
   -pd_limiter_sublevels parts (geometric in stretch from s0 to sc), then broken. */
typedef enum { PD_BOND_ELASTIC = 0, PD_BOND_SOFTENING = 1 } PDBondLevel;
#define PD_BOND_LEVEL_OPEN 255 /* every threshold passed: the explicit path, which has no limiter */

/* Stretch thresholds of one bond: end of the elastic branch, trilinear kink, critical stretch. */
typedef struct {
  PetscReal s0, s1, sc;
} PDLawBond;

/* The fib Model Code 2010 bond stress-slip envelope of ribbed bars (Sec. 6.1.1, pull-out, good bond), in
   slip x >= 0 (m) and bond stress (Pa): tau_max (x/s1)^alpha up to s1, tau_max to s2, a linear fall to
   tau_f at s3, tau_f beyond. The power law starts with an infinite slope: below x_lin = PD_SLIP_LINEAR s1
   a parabola takes its place, with the curve's value and slope at x_lin (so that Newton meets no kink
   there); k0 is its slope at zero slip, the bond's initial stiffness. */
typedef struct {
  PetscReal tau_max, tau_f, alpha;
  PetscReal x[4]; /* x_lin, s1, s2, s3 */
  PetscReal k0;   /* Pa/m */
} PDSlipEnvelope;
#define PD_SLIP_LINEAR 0.02
void      PDSlipEnvelopeSetUp(const PDBar *, PDSlipEnvelope *);
PetscReal PDSlipStress(const PDSlipEnvelope *, PetscReal x, PetscReal *slope);
PetscReal PDSlipWork(const PDSlipEnvelope *, PetscReal x); /* int_0^x tau */

/* A tension-softening bond law. Force g = c_b (1 - d(kappa)) s for s >= 0 and c_b s in compression,
   kappa the largest stretch reached; d is irreversible, unloading follows the secant. */
typedef struct {
  PDLawKind kind;
  PetscReal c;         /* micromodulus c0 of the material (influence-normalised) */
  PetscReal E, ft, Gf; /* modulus, tensile strength, fracture energy */
  PetscReal geo;       /* pi * c * 5 * int_0^delta omega xi^4 dxi: pi c delta^5 for constant influence */
  PDLawBond nominal;   /* thresholds of a bulk bond (lambda = 1) */
  PetscReal kr;        /* bilinear sc/s0 (Zaccariotto) */
  PetscBool bobaru;    /* bilinear form: s0 = ft/E */
  PetscReal beta;      /* trilinear force ratio at s1 */
  PetscReal k, alpha;  /* non-linear law shape */
  PetscReal shape;     /* non-linear law: (sc - s0) s0 pcd5 / G_F, a function of k and alpha alone */
  PetscBool per_bond;  /* critical stretch from lambda_ij c (Eq. 5.32 generalised) */
  PetscInt  sublevels; /* limiter levels on the softening branch */
  PetscReal confine;   /* rise of the thresholds per unit nodal compression (-pd_fc, docs/softening.md); 0: off */
  /* PD_LAW_SLIP: the envelope, and the length of the links it acts on (m), which turns their stretch into slip. Its
     force is symmetric, g = c (1 - d(kappa)) s with kappa the largest |s|, and unloading follows the secant */
  PDSlipEnvelope slip;
  PetscReal      slip_length;
} PDLaw;

/* The stretch a bond's history follows: s, or |s| for a bond-slip link, whose law is symmetric. */
static inline PetscReal PDLawHistoryStretch(const PDLaw *law, PetscReal s) {
  return law->kind == PD_LAW_SLIP ? PetscAbsReal(s) : s;
}
/* The law of bar k's bond-slip links, whose length is link_length. */
void PDLawSetUpSlip(const PDBar *, PetscReal link_length, PDLaw *);

PetscErrorCode PDLawSetUp(const PDScene *, const PDMaterial *, PDLaw *);
/* Moves a bond's three thresholds by d (crushing's rise under compression, -pd_fc). */
static inline void PDLawBondRaise(PDLawBond *t, PetscReal d) {
  t->s0 += d;
  t->s1 += d;
  t->sc += d;
}
/* The thresholds of a bond whose micromodulus is lambda c and whose tensile strength is strength ft, from
   the formulas (laws.c). */
void PDLawBondThresholds(const PDLaw *, PetscReal lambda, PetscReal strength, PDLawBond *);
/* The same from the nominal thresholds, by how the formulas scale: a law that leaves its elastic branch at
   ft/E moves s0 with the strength and its softening span (sc - s0, s1 - s0; sc itself for the bilinear law
   of Bobaru) with 1/(lambda strength); the linear law and Zaccariotto's bilinear one scale every threshold
   with 1/sqrt(lambda), whatever ft. A few operations: cheaper per bond and residual than stored thresholds
   are to load (tests/test_laws.c compares both forms). */
static inline void PDLawBondThresholdsScaled(const PDLaw *law, PetscReal lambda, PetscReal strength, PDLawBond *t) {
  const PDLawBond *n = &law->nominal;
  PetscReal        k;
  if (!law->per_bond) lambda = 1;
  switch (law->kind) {
  case PD_LAW_LINEAR:
    k     = 1 / PetscSqrtReal(lambda);
    t->s0 = n->s0 * k;
    t->s1 = n->s1 * k;
    t->sc = n->sc * k;
    break;
  case PD_LAW_BILINEAR:
    if (!law->bobaru) {
      k     = 1 / PetscSqrtReal(lambda);
      t->s0 = n->s0 * k;
      t->s1 = n->s1 * k;
      t->sc = n->sc * k;
    } else {
      t->s0 = n->s0 * strength;
      t->s1 = t->sc = n->sc / (lambda * strength);
    }
    break;
  case PD_LAW_TRILINEAR:
  case PD_LAW_NONLINEAR:
    k     = 1 / (lambda * strength);
    t->s0 = n->s0 * strength;
    t->s1 = t->s0 + (n->s1 - n->s0) * k;
    t->sc = t->s0 + (n->sc - n->s0) * k;
    break;
  default: /* elastic, bond slip: no thresholds of their own */
    *t = *n;
  }
}
/* Damage d(kappa) and its derivative; kappa >= 0. */
PetscReal PDLawDamage(const PDLaw *, const PDLawBond *, PetscReal kappa, PetscReal *dd);
/* Area under the envelope g/c from 0 to kappa (capped at sc), per unit micromodulus: the work that took
   the bond to its largest stretch. Stored energy at stretch s is (1 - d) s^2 / 2, the rest is dissipated. */
PetscReal PDLawEnvelopeWork(const PDLaw *, const PDLawBond *, PetscReal kappa);
/* Area under g/c from 0 to sc for the nominal bond (per unit micromodulus): the bond's fracture work. */
PetscReal PDLawWorkOfFracture(const PDLaw *);
/* The threshold at which a bond of the given level leaves it (s0 into softening, s0 (sc/s0)^(L/K) to the
   next of K softening levels, sc into breaking). */
PetscReal PDLawNextThreshold(const PDLaw *, const PDLawBond *, PetscInt level);
/* The level consistent with a history kappa: the number of thresholds at or below it. */
PetscInt PDLawLevelOf(const PDLaw *, const PDLawBond *, PetscReal kappa);

/* Steel of a bar segment (docs/reinforcement.md), per unit axial stiffness E A: force g = E A (s - sp)
   with yield surface |s - sp - H sp| <= s_y (linear kinematic hardening, H = h/(1 - h) for the post-yield
   tangent h E), elastic unloading, and rupture for good once the stretch reaches s_u. The state is the
   plastic stretch sp and the rupture flag, committed at accepted steps; the response is a pure function
   of the stretch and the committed state. */
typedef struct {
  PetscReal sy; /* yield stretch f_y/E */
  PetscReal h;  /* post-yield tangent over E */
  PetscReal su; /* rupture stretch; PETSC_MAX_REAL: none */
} PDSteel;

void PDSteelSetUp(const PDBar *, PDSteel *);
/* Force over E A at stretch s from the committed state (sp_n, broken_n), its slope (the consistent
   tangent over E A: 1 elastic, h plastic, 0 broken) and the state it leaves (sp, broken). */
void PDSteelResponse(const PDSteel *, PetscReal s, PetscReal sp_n, PetscBool broken_n, PetscReal *g, PetscReal *gp, PetscReal *sp,
                     PetscBool *broken);
/* Energy per unit E A and unit length at stretch s and plastic stretch sp: stored, elastic and in the
   hardening, (s - sp)^2 / 2 + H sp^2 / 2. Plastic flow dissipates s_y per unit of accumulated |d sp|. */
PetscReal PDSteelStored(const PDSteel *, PetscReal s, PetscReal sp);
