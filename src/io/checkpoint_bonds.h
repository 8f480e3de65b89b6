/* The per-bond datasets of checkpoint.h5 (checkpoint_bonds.c). */
#pragma once
#include "pd_model.h"

typedef enum {
  PD_BOND_KAPPA,
  PD_BOND_LEVEL,
  PD_BOND_KAPPA_PREVIOUS,
  PD_BOND_RISE,
  PD_BOND_STEEL_PLASTIC,
  PD_BOND_STEEL_RUPTURED,
  PD_BOND_STEEL_DISSIPATED
} PDBondField;
extern const char *const PDBondFieldNames[];
/* A largest stretch beyond this is no state a path reaches; it only guards the arithmetic (kappa^2). */
#define PD_KAPPA_MAX 1e6

PetscBool      PDBondFieldKept(const PDModel *, const PetscReal *kappa_prev, PDBondField);
PetscErrorCode PDBondFieldWrite(const PDModel *, const PetscReal *kappa_prev, PDBondField, PetscViewer);
PetscErrorCode PDBondFieldCheck(const PDModel *, PDBondField, PetscViewer, PetscBool *ok);
PetscErrorCode PDBondFieldRead(PDModel *, PetscReal *kappa_prev, PDBondField, PetscViewer);
