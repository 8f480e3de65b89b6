/* Material: micromodulus and influence functions (THEORY.md Sec. 1), bond laws (Sec. 3). */
#pragma once
#include "pd_scene.h"

PetscReal PDMicromodulus(const PDScene *, PetscReal E);
PetscReal PDInfluenceValue(PDInfluence, PetscReal len, PetscReal horizon);
PetscReal PDInfluenceMoment(PDInfluence, PetscInt k); /* int_0^1 omega(r) r^k dr */
PetscReal PDLatticeFractureRatio(const PDScene *);

/* Bond states the damage limiter hands out one level at a time: elastic, then the softening branch in
   -pd_limiter_sublevels parts (geometric in stretch from s0 to sc), then broken. */
typedef enum { PD_BOND_ELASTIC = 0, PD_BOND_SOFTENING = 1 } PDBondLevel;
#define PD_BOND_LEVEL_OPEN 255 /* every threshold passed: the explicit path, which has no limiter */

/* Stretch thresholds of one bond: end of the elastic branch, trilinear kink, critical stretch. */
typedef struct {
  PetscReal s0, s1, sc;
} PDLawBond;

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
  PetscBool per_bond;  /* critical stretch from lambda_ij c (Eq. 5.32 generalised) */
  PetscInt  sublevels; /* limiter levels on the softening branch */
} PDLaw;

PetscErrorCode PDLawSetUp(const PDScene *, const PDMaterial *, PDLaw *);
void           PDLawBondThresholds(const PDLaw *, PetscReal lambda, PDLawBond *);
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
