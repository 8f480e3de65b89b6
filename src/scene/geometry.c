/* Which nodes a box or cylinder selects. */
#include "pd_scene.h"

PetscBool PDGeometryContains(const PDGeometry *g, const PetscReal x[3], const PDScene *sc) {
  const PetscReal dx = sc->dx, tol = 1e-9 * dx;

  if (g->shape == PD_SHAPE_CYLINDER) {
    PetscReal r2 = 0;
    for (PetscInt a = 0; a < sc->dim; a++)
      if (a != g->axis) r2 += (x[a] - g->center[a]) * (x[a] - g->center[a]);
    return r2 <= (g->radius + tol) * (g->radius + tol) ? PETSC_TRUE : PETSC_FALSE;
  }
  for (PetscInt a = 0; a < sc->dim; a++) {
    const PetscReal lo = g->box[a], hi = g->box[3 + a];
    if (hi - lo > tol) {
      if (x[a] < lo - tol || x[a] > hi + tol) return PETSC_FALSE;
    } else {
      /* one layer: a plane between two layers must not select both, or a support line becomes a
         clamp (two pinned lines resist rotation) */
      const PetscReal d     = x[a] - lo;
      const PetscBool upper = lo >= sc->domain[3 + a] - tol;
      if (PetscAbsReal(d) < 0.5 * dx - tol) continue;
      if (PetscAbsReal(d - 0.5 * dx) <= tol && !upper) continue;
      if (PetscAbsReal(d + 0.5 * dx) <= tol && upper) continue;
      return PETSC_FALSE;
    }
  }
  return PETSC_TRUE;
}
