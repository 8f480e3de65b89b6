/* Which nodes a box or cylinder selects. */
#include "pd_scene.h"

PetscBool PDGeometryContains(const PDGeometry *g, const PetscReal x[3], PetscReal dx, PetscInt dim) {
  const PetscReal tol = 1e-9 * dx;

  if (g->shape == PD_SHAPE_CYLINDER) {
    PetscReal r2 = 0;
    for (PetscInt a = 0; a < dim; a++)
      if (a != g->axis) r2 += (x[a] - g->center[a]) * (x[a] - g->center[a]);
    return r2 <= (g->radius + tol) * (g->radius + tol) ? PETSC_TRUE : PETSC_FALSE;
  }
  for (PetscInt a = 0; a < dim; a++) {
    const PetscReal lo = g->box[a], hi = g->box[3 + a];
    if (hi - lo > tol) {
      if (x[a] < lo - tol || x[a] > hi + tol) return PETSC_FALSE;
    } else if (PetscAbsReal(x[a] - lo) > 0.5 * dx + tol)
      return PETSC_FALSE; /* flat: the layer of cells the plane cuts */
  }
  return PETSC_TRUE;
}
