/* Quasi-static path state shared by the load/displacement-control and path-following drivers. */
#pragma once
#include "pd_solve.h"

typedef struct {
  Vec       u_n;      /* last accepted displacement */
  Vec       f_n;      /* internal force there (applied forces and reactions) */
  Vec       du, ku;   /* du: the last accepted increment (read by the secant predictor); ku: work */
  PetscReal lambda_n; /* last accepted load factor */
  PetscReal w_ext;    /* external work so far (J) */
  PetscInt  step;     /* accepted steps */
} PDPath;

PetscErrorCode PDPathCreate(PDModel *, PDPath *);
PetscErrorCode PDPathAccept(PDModel *, PDRecord *, PDPath *, Vec u, PetscReal lambda, PetscInt its, PetscInt lits, PDCurveRow *);
PetscErrorCode PDPathDestroy(PDPath *);
/* The stop criteria both drivers share, after an accepted step with curve row row: the CMOD gauge opened
   -pd_stop_cmod ("completed"), or, where separation may be judged, the load fell below -pd_stop_fraction of
   the peak so far ("separated"). Sets *stop and the status when one is met. */
PetscErrorCode PDPathStopCriteria(const PDScene *, PDRecord *, const PDCurveRow *row, PetscReal peak, PetscBool judge_separation,
                                  PetscBool *stop);
/* Path following from the accepted state of plain control (PDStaticRun), whose last increment was
   dlam_last: its fallback where it finds no equilibrium. */
PetscErrorCode PDArcLengthTakeOver(PDModel *, PDRecord *, const PDPath *, PetscReal dlam_last);
