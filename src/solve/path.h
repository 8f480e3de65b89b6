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

/* When to rebuild the preconditioner (src/solve/pc_refresh.c): every sixth assembly for block ICC(0) in
   3D, every third for the others, or, for 3D models under GAMG, when the Krylov solver finds it stale.
   Under SNES (snes given) the decision reaches SNES as its lag; otherwise PDPCRefreshAssembled tells the
   KSP, after every assembly of its operator, whether to reuse the preconditioner. */
typedef struct {
  SNES      snes;       /* the SNES whose lag carries the decision, or NULL */
  PetscBool when_stale; /* the policy: when stale, or every lag-th assembly */
  PetscInt  lag;        /* assemblies between rebuilds under the fixed lag */
  PetscReal fresh;      /* Krylov iterations per decade of the first solve after the last rebuild */
  PetscBool due;        /* rebuild at the next assembly */
  PetscBool measure;    /* the next solve is the first after a rebuild */
  PetscInt  assemblies; /* since the last rebuild, for the fixed lag */
  PetscReal fnorm;      /* under SNES: the last residual norm its monitor saw */
} PDPCRefresh;

/* The policy follows ksp's preconditioner, set from the options already. */
PetscErrorCode PDPCRefreshAttach(const PDModel *, KSP, SNES, PDPCRefresh *);
PetscErrorCode PDPCRefreshAssembled(PDPCRefresh *, KSP);
PetscErrorCode PDPCRefreshRequest(PDPCRefresh *);
/* After a solve (called by the SNES monitor PDPCRefreshAttach installs, or by the driver without SNES).
   *again (if given): the solve failed with a kept preconditioner; after PDPCRefreshAssembled it may be
   made again with a fresh one. */
PetscErrorCode PDPCRefreshSolved(PDPCRefresh *, KSP, PetscBool *again);
/* After a failed solve: a preconditioner whose set-up failed is reset, so that the next solve builds it anew. */
PetscErrorCode PDPCForgetFailed(KSP);
