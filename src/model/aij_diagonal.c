/* The diagonal of an AIJ stiffness read through an index of each row's diagonal entry.

   PETSc 3.18's MatGetDiagonal for AIJ storage searches every row for its diagonal entry. A 3D row holds
   about three times as many entries as a node has bonds, so the search streams half the column indices
   of the matrix. Point Jacobi, the smoother of GAMG's finest level, takes the diagonal of the
   preconditioning matrix each time that matrix changes, which is once per Newton iteration while the
   hierarchy is kept: on the half-notched beam the searches were a sizeable share of the solve
   (docs/benchmarks/solve_profile.md, row "diagonal by search"). The positions are found once per
   non-zero pattern and kept with the matrix; the values read are the matrix's own. */
#include "pd_model.h"

#define PD_DIAGONAL_INDEX "PDDiagonalIndex"

typedef struct {
  PetscObjectState nonzero_state; /* of the (diagonal block's) pattern the positions were found in */
  PetscInt         n;
  PetscInt        *pos; /* row i's diagonal entry in the (diagonal block's) value array; -1 if none */
} DiagonalIndex;

static PetscErrorCode DiagonalIndexDestroy(void *ctx) {
  DiagonalIndex *d = (DiagonalIndex *)ctx;

  PetscFunctionBeginUser;
  PetscCall(PetscFree(d->pos));
  PetscCall(PetscFree(d));
  PetscFunctionReturn(0);
}

/* The index of A, composed with it on first use and found again when the pattern has changed. */
static PetscErrorCode GetIndex(Mat A, Mat Ad, DiagonalIndex **index) {
  PetscContainer   c;
  DiagonalIndex   *d = NULL;
  PetscObjectState state;
  const PetscInt  *ia, *ja;
  PetscInt         n;
  PetscBool        done;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectQuery((PetscObject)A, PD_DIAGONAL_INDEX, (PetscObject *)&c));
  if (!c) {
    PetscCall(PetscNew(&d));
    PetscCall(PetscContainerCreate(PetscObjectComm((PetscObject)A), &c));
    PetscCall(PetscContainerSetPointer(c, d));
    PetscCall(PetscContainerSetUserDestroy(c, DiagonalIndexDestroy));
    PetscCall(PetscObjectCompose((PetscObject)A, PD_DIAGONAL_INDEX, (PetscObject)c));
    PetscCall(PetscContainerDestroy(&c));
  } else
    PetscCall(PetscContainerGetPointer(c, (void **)&d));
  PetscCall(MatGetNonzeroState(Ad, &state));
  if (!d->pos || state != d->nonzero_state) {
    PetscCall(MatGetRowIJ(Ad, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
    PetscCheck(done, PetscObjectComm((PetscObject)A), PETSC_ERR_SUP, "The stiffness's rows cannot be read");
    PetscCall(PetscFree(d->pos));
    PetscCall(PetscMalloc1(n, &d->pos));
    d->n = n;
    for (PetscInt i = 0; i < n; i++) {
      d->pos[i] = -1;
      for (PetscInt k = ia[i]; k < ia[i + 1]; k++)
        if (ja[k] == i) {
          d->pos[i] = k;
          break;
        }
    }
    PetscCall(MatRestoreRowIJ(Ad, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
    d->nonzero_state = state;
  }
  *index = d;
  PetscFunctionReturn(0);
}

static PetscErrorCode GetDiagonalIndexed(Mat A, Vec v) {
  Mat                Ad = A;
  DiagonalIndex     *d  = NULL;
  const PetscScalar *aa;
  PetscScalar       *x;
  PetscBool          mpi;

  PetscFunctionBeginUser;
  /* the diagonal of a distributed AIJ matrix lies in its diagonal block, whose local column i is row i */
  PetscCall(PetscObjectTypeCompare((PetscObject)A, MATMPIAIJ, &mpi));
  if (mpi) PetscCall(MatMPIAIJGetSeqAIJ(A, &Ad, NULL, NULL));
  PetscCall(GetIndex(A, Ad, &d));
  PetscCall(MatSeqAIJGetArrayRead(Ad, &aa));
  PetscCall(VecGetArrayWrite(v, &x));
  for (PetscInt i = 0; i < d->n; i++) x[i] = d->pos[i] >= 0 ? aa[d->pos[i]] : 0;
  PetscCall(VecRestoreArrayWrite(v, &x));
  PetscCall(MatSeqAIJRestoreArrayRead(Ad, &aa));
  PetscFunctionReturn(0);
}

PetscErrorCode PDMatUseDiagonalIndex(Mat A) {
  PetscBool aij;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompareAny((PetscObject)A, &aij, MATSEQAIJ, MATMPIAIJ, ""));
  if (aij) PetscCall(MatSetOperation(A, MATOP_GET_DIAGONAL, (void (*)(void))GetDiagonalIndexed));
  PetscFunctionReturn(0);
}
