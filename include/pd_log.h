/* PETSc log stages and events of pdimplicit, so that -log_view says where a run spends its time. */
#pragma once
#include <petscsys.h>

typedef struct {
  PetscLogStage setup, solve, output;
  PetscLogEvent force;    /* bond loop: internal forces */
  PetscLogEvent tangent;  /* bond loop: tangent scalars */
  PetscLogEvent assembly; /* stiffness rows gathered into the matrix */
  PetscLogEvent product;  /* tangent products from the bond scalars */
  PetscLogEvent limiter;  /* damage limiter: candidates ranked, events granted */
  PetscLogEvent history;  /* bond histories committed at an accepted step */
  PetscLogEvent energy;   /* bond loop: stored and dissipated energy */
  PetscLogEvent fields;   /* fields written to HDF5 */
} PDLog;

extern PDLog PD_LOG;

/* Registers the stages and events once; later calls do nothing. */
PetscErrorCode PDLogRegister(void);
