/* One Krylov solve per Newton iteration of path following with a constraint linear in (u, lambda). */
#pragma once
#include <petscksp.h>

typedef struct {
  Mat       A;           /* [K, Q; C, D]: the tangent bordered by the lambda column and the constraint row */
  Mat       Q, Cc, C, D; /* n x 1 column, n x 1 row (C is its transpose), 1 x 1 corner */
  KSP       ksp;         /* GMRES on A, preconditioned by the shell below */
  KSP       knewton;     /* its KSP, which sets it up (and lags it) */
  IS        is_u, is_l;  /* the two blocks of an augmented vector */
  Vec       x, b;
  PetscReal schur; /* estimate of the 1 x 1 Schur complement D - C K^-1 Q */
} PDAugmented;

PetscErrorCode PDAugmentedCreate(Mat K, KSP knewton, PDAugmented *);
PetscErrorCode PDAugmentedSolve(PDAugmented *, Vec q, Vec c, PetscReal d, PetscReal schur, Vec rhs_u, PetscReal rhs_l, Vec du, PetscReal *t,
                                PetscInt *its, KSPConvergedReason *);
PetscErrorCode PDAugmentedDestroy(PDAugmented *);
