/* Steel of a bar segment: elastic-plastic with linear kinematic hardening and rupture (pd_material.h).
   The return mapping of 1D plasticity: from the trial relative stress xi = (s - sp_n) - H sp_n, a plastic
   increment f/(1 + H) along sign(xi) when f = |xi| - s_y > 0. The slope on the plastic branch is then
   1 - 1/(1 + H) = h, the consistent tangent. */
#include "pd_material.h"

void PDSteelSetUp(const PDBar *b, PDSteel *st) {
  st->sy = b->fy / b->E;
  st->h  = b->hardening;
  st->su = b->rupture > 0 ? b->rupture : PETSC_MAX_REAL;
}

void PDSteelResponse(const PDSteel *st, PetscReal s, PetscReal sp_n, PetscBool broken_n, PetscReal *g, PetscReal *gp, PetscReal *sp,
                     PetscBool *broken) {
  const PetscReal H = st->h / (1 - st->h), xi = s - sp_n - H * sp_n, f = PetscAbsReal(xi) - st->sy;

  *sp     = sp_n;
  *broken = broken_n || s >= st->su ? PETSC_TRUE : PETSC_FALSE;
  if (*broken) {
    *g = *gp = 0;
    return;
  }
  if (f > 0) *sp = sp_n + (xi > 0 ? 1 : -1) * f / (1 + H);
  *g  = s - *sp;
  *gp = f > 0 ? st->h : 1;
}

PetscReal PDSteelStored(const PDSteel *st, PetscReal s, PetscReal sp) {
  const PetscReal H = st->h / (1 - st->h);
  return 0.5 * (s - sp) * (s - sp) + 0.5 * H * sp * sp;
}
