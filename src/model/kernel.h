/* Bond loop entry points shared by the residual, the Jacobian and the measurements. */
#pragma once
#include "pd_model.h"

PetscErrorCode PDModelInternalForceLocal(PDModel *, const PetscScalar *u, PetscScalar *f);
PetscErrorCode PDModelTangentScalars(PDModel *, const PetscScalar *u, PetscReal *ka, PetscReal *kb);
PetscErrorCode PDModelAssembleRows(PDModel *, const PetscScalar *u, const PetscReal *ka, const PetscReal *kb, Mat J);
