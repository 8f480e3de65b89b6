/* Solvers: quasi-static path under load or displacement control. */
#pragma once
#include "pd_model.h"
#include "pd_io.h"

PetscErrorCode PDStaticRun(PDModel *, PDRecord *);
PetscErrorCode PDArcLengthRun(PDModel *, PDRecord *);
/* A checkpoint named by -pd_restart, checked before anything is written (PDCheckpointValidate). */
PetscErrorCode PDArcLengthValidateRestart(const PDModel *, const char *path);
PetscErrorCode PDSolverConfigureKSP(PDModel *, KSP);
/* Flexible GMRES preconditioned on the right where GMRES would take block ICC(0) or GAMG in 3D, unless the
   command line chose the preconditioner or the side; before the KSP reads its options. */
PetscErrorCode PDSolverPreferFlexible(PDModel *, KSP);
PetscErrorCode PDExplicitRun(PDModel *, PDRecord *);
PetscErrorCode PDExplicitPlan(PDModel *, PDRecord *);
PetscErrorCode PDFailureSearchRun(PDModel *, PDRecord *);
/* SIGTERM, SIGINT and SIGHUP end a run after the step under way (src/solve/interrupt.c). */
PetscErrorCode PDInterruptInstall(void);
PetscErrorCode PDInterrupted(MPI_Comm, PetscBool *);
PetscErrorCode PDStopOnSignal(MPI_Comm, PDRecord *, PetscBool *);
/* The name of the signal PDInterrupted saw, for statuses. */
const char *PDInterruptSignal(void);
/* Whether PDInterrupted has seen a signal (the same on every rank: only that collective sets it). */
PetscBool PDInterruptSeen(void);
/* Newton and Krylov iterations that look for a signal and stop the solve under way. */
PetscErrorCode PDInterruptWatchKSP(KSP);
PetscErrorCode PDInterruptWatchSNES(SNES);
/* After a step that did not finish: stop, with the status, if a signal ended it. */
PetscErrorCode PDStopInsideStep(PDRecord *, PetscBool *);
