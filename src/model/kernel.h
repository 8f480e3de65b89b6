/* Bond loop entry points shared by the residual, the Jacobian and the measurements. */
#pragma once
#include "pd_model.h"

PetscErrorCode PDModelInternalForceLocal(PDModel *, const PetscScalar *u, PetscScalar *f);
PetscErrorCode PDModelTangentScalars(PDModel *, const PetscScalar *u, PetscReal *ka, PetscReal *kb, PetscReal *kp);
PetscErrorCode PDModelAssembleRows(PDModel *, const PetscScalar *u, const PetscReal *ka, const PetscReal *kb, Mat J,
                                   PetscInt *nregularised);
PetscErrorCode PDModelEnergiesLocal(PDModel *, const PetscScalar *u, PetscReal *stored, PetscReal *dissipated);
PetscErrorCode PDModelTangentApplyLocal(PDModel *, const PetscScalar *u, const PetscReal *ka, const PetscReal *kb, const PetscScalar *x,
                                        PetscScalar *y);
PetscErrorCode PDModelStretches(PDModel *, const PetscScalar *u, PetscReal *s);
void           PDModelCommitBond(PDModel *, PetscInt e, PetscReal s);
void           PDModelCommitSegment(PDModel *, PetscInt sg, PetscReal s);
PetscReal      PDModelSteelStressLocal(PDModel *, const PetscScalar *u);

/* A bond's stretch thresholds: its own (scatter, surface correction) or its law's nominal ones. */
static inline const PDLawBond *PDModelBondThresholds(const PDModel *m, PetscInt e, const PDLaw *law) {
  return m->thr ? &m->thr[e] : &law->nominal;
}
PetscReal      PDModelBondDamage(const PDModel *, PetscInt e);
PetscErrorCode PDModelScatterToLocal(PDModel *, Vec u, const PetscScalar **ul, Vec *loc);
PetscErrorCode PDModelRestoreLocal(PDModel *, const PetscScalar **ul, Vec *loc);
