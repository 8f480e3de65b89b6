/* Micromodulus constants and influence functions (THEORY.md Sec. 1). For omega(xi), matching the strain
   energy of isotropic expansion gives c0 = 3E / (pi I3) in 3D with I3 = int_0^delta omega xi^3 dxi,
   c0 = 3E / (pi t I2) in plane stress and c0 = 16E / (5 pi t I2) in plane strain, I2 = int omega xi^2;
   these reproduce the constants printed in Hobbs Table 3.1 and Eq. 3.27/3.28. */
#include "pd_material.h"

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

PetscReal PDMicromodulus(const PDScene *sc, PetscReal E) {
  const PetscReal delta = sc->horizon_ratio * sc->dx;
  switch (sc->model) {
  case PD_MODEL_PLANE_STRESS:
    return 3 * E / (PETSC_PI * sc->thickness * PDInfluenceMoment(sc->influence, 2) * delta * delta * delta);
  case PD_MODEL_PLANE_STRAIN:
    return 16 * E / (5 * PETSC_PI * sc->thickness * PDInfluenceMoment(sc->influence, 2) * delta * delta * delta);
  default:
    return 3 * E / (PETSC_PI * PDInfluenceMoment(sc->influence, 3) * delta * delta * delta * delta);
  }
}
