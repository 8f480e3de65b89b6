/* Micromodulus constants and influence functions (THEORY.md Sec. 1). For omega(xi), matching the strain
   energy of isotropic expansion gives c0 = 3E / (pi I3) in 3D with I3 = int_0^delta omega xi^3 dxi,
   c0 = 3E / (pi t I2) in plane stress and c0 = 16E / (5 pi t I2) in plane strain, I2 = int omega xi^2;
   these reproduce the constants printed in Hobbs Table 3.1 and Eq. 3.27/3.28. */
#include "pd_material.h"
#include "pd_lattice.h"

PetscReal PDInfluenceValue(PDInfluence w, PetscReal len, PetscReal horizon) {
  const PetscReal r = len / horizon;
  switch (w) {
  case PD_INFLUENCE_CONICAL:
    return 1 - r;
  case PD_INFLUENCE_QUARTIC:
    return r * r * r * r - 2 * r * r + 1;
  default:
    return 1;
  }
}

/* Moments int_0^1 omega(r) r^k dr of the influence functions. */
PetscReal PDInfluenceMoment(PDInfluence w, PetscInt k) {
  switch (w) {
  case PD_INFLUENCE_CONICAL:
    return 1.0 / (k + 1) - 1.0 / (k + 2);
  case PD_INFLUENCE_QUARTIC:
    return 1.0 / (k + 5) - 2.0 / (k + 3) + 1.0 / (k + 1);
  default:
    return 1.0 / (k + 1);
  }
}

/* The continuum micromodulus, in units where dx = 1 (and t = 1 in 2D) when unit is set. */
static PetscReal ContinuumMicromodulus(const PDScene *sc, PetscReal E, PetscBool unit) {
  const PetscReal delta = sc->horizon_ratio * (unit ? 1 : sc->dx), t = unit ? 1 : sc->thickness;
  switch (sc->model) {
  case PD_MODEL_PLANE_STRESS:
    return 3 * E / (PETSC_PI * t * PDInfluenceMoment(sc->influence, 2) * delta * delta * delta);
  case PD_MODEL_PLANE_STRAIN:
    return 16 * E / (5 * PETSC_PI * t * PDInfluenceMoment(sc->influence, 2) * delta * delta * delta);
  default:
    return 3 * E / (PETSC_PI * PDInfluenceMoment(sc->influence, 3) * delta * delta * delta * delta);
  }
}

/* Young's modulus of the lattice's bulk along a lattice axis over the continuum model's, for bonds with the
   continuum micromodulus. A bulk node's strain energy under a homogeneous strain eps is
   1/2 eps:C:eps with C_abcd = 1/2 sum_j c omega beta V |xi| e_a e_b e_c e_d over its stencil. The stencil
   has the symmetry of the cube (square in 2D), so C has two constants, C11 = C_xxxx and C12 = C_xxyy
   (= C_xyxy, bond-based), and uniaxial stress along an axis gives E_lattice = (C11 - C12)(C11 + 2 C12) /
   (C11 + C12) in 3D, (C11^2 - C12^2) / C11 in 2D. The continuum's is E (3D, plane stress) or E / (1 - nu^2)
   = 16 E / 15 (plane strain, nu = 1/4). One-point quadrature over the stencil misses the horizon's curved
   edge: the ratio is 0.74 to 0.85 in 3D for m = 3 to 4, and it does not tend to 1 under refinement at a
   fixed m (docs/calibration.md). */
static void StencilConstants(const PDScene *sc, PetscReal *c11, PetscReal *c12) {
  const PetscReal m = sc->horizon_ratio, c = ContinuumMicromodulus(sc, 1, PETSC_TRUE);
  PetscInt        st[4] = {0, 0, 0, -1};

  *c11 = *c12 = 0;
  while (PDFamilyNext(m, sc->dim, st)) {
    const PetscInt  i = st[0], j = st[1], n2 = st[3];
    const PetscReal len = PetscSqrtReal((PetscReal)n2);
    const PetscReal w   = 0.5 * c * PDInfluenceValue(sc->influence, len, m) * PDFamilyPartialVolume(m, n2, sc->partial_volume) * len;
    *c11 += w * (i * i) * (i * i) / (PetscReal)(n2 * n2);
    *c12 += w * (i * i) * (j * j) / (PetscReal)(n2 * n2);
  }
}

PetscReal PDLatticeStiffnessRatio(const PDScene *sc) {
  PetscReal c11, c12, Elat;

  StencilConstants(sc, &c11, &c12);
  Elat = sc->dim == 3 ? (c11 - c12) * (c11 + 2 * c12) / (c11 + c12) : (c11 * c11 - c12 * c12) / c11;
  return Elat / (sc->model == PD_MODEL_PLANE_STRAIN ? 16.0 / 15.0 : 1.0);
}

/* The stencil's Poisson ratio under uniaxial stress along an axis: C12 / (C11 + C12) in 3D, C12 / C11 in the
   plane. The continuum bond-based values are 1/4 and 1/3 (C11 = 3 C12); the stencil's differ with m. */
PetscReal PDLatticePoissonRatio(const PDScene *sc) {
  PetscReal c11, c12;

  StencilConstants(sc, &c11, &c12);
  return sc->dim == 3 ? c12 / (c11 + c12) : c12 / c11;
}

/* The bond constant c0 of material modulus E: the continuum micromodulus, divided by the lattice's stiffness
   ratio under -pd_calibration stencil so that the lattice's bulk has modulus E along its axes. */
PetscReal PDMicromodulus(const PDScene *sc, PetscReal E) {
  const PetscReal c = ContinuumMicromodulus(sc, E, PETSC_FALSE);
  return sc->calibration == PD_CALIBRATION_STENCIL ? c / PDLatticeStiffnessRatio(sc) : c;
}

/* The fracture energy the lattice releases across a plane, over the continuum value (Sec. 5.3's
   pi c delta^5 form): the sum of c omega beta V^2 |xi| over the bonds that cross a lattice plane midway
   between node layers, per unit area, against geo = pi c delta^5 I4 (3D) or 2 t c delta^4 I3 (2D).
   Neighbours are the lattice's bond family, which ends at the horizon, and the outer shell counts with
   its partial volume, so the lattice misses part of the continuum integral: about 0.74 (2D) and 0.76
   (3D) at delta = pi dx. */
PetscReal PDLatticeFractureRatio(const PDScene *sc) {
  const PetscReal m = sc->horizon_ratio;
  const PetscInt  R = (PetscInt)PetscCeilReal(m) + 1, nz = sc->dim == 3 ? R : 0;
  PetscReal       sum = 0, geo;

  /* unit spacing, c = 1: node i at x = -(k - 1/2), node j at (l + 1/2, jy, jz) */
  for (PetscInt k = 1; k <= R; k++)
    for (PetscInt l = 0; l <= R; l++)
      for (PetscInt jy = -R; jy <= R; jy++)
        for (PetscInt jz = -nz; jz <= nz; jz++) {
          const PetscInt  n2  = (k + l) * (k + l) + jy * jy + jz * jz;
          const PetscReal len = PetscSqrtReal((PetscReal)n2);
          if (PDFamilyRule(m, n2) == PD_FAMILY_OUT) continue;
          sum += PDInfluenceValue(sc->influence, len, m) * PDFamilyPartialVolume(m, n2, sc->partial_volume) * len;
        }
  geo = sc->dim == 3 ? PETSC_PI * PDInfluenceMoment(sc->influence, 4) * PetscPowReal(m, 5)
                     : 2 * PDInfluenceMoment(sc->influence, 3) * PetscPowReal(m, 4);
  return sum / geo;
}
