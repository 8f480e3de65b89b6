/* A preconditioner whose set-up failed is reset, so that the next solve factors anew (PDPCForgetFailed,
   docs/design.md point 55). MUMPS meets a zero pivot on diag(1, 0, 1): the solve fails with
   KSP_DIVERGED_PC_FAILED. The matrix then becomes diag(1, 2, 4), as a new tangent would. Without the
   reset PETSc's MUMPS interface skips the new numeric factorisation and the solve stops with an error;
   with it the solve gives x = (1, 1/2, 1/4) for b = (1, 1, 1). */
#include "../src/solve/path.h"
#include "check.h"

static PetscErrorCode SetDiagonal(Mat A, const PetscScalar d[3]) {
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < 3; i++) PetscCall(MatSetValue(A, i, i, d[i], INSERT_VALUES));
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  const PetscScalar  singular[3] = {1, 0, 1}, regular[3] = {1, 2, 4};
  Mat                A;
  Vec                x, b;
  KSP                ksp;
  PC                 pc;
  KSPConvergedReason reason;
  const PetscScalar *xx;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(MatCreateSeqAIJ(PETSC_COMM_SELF, 3, 3, 1, NULL, &A));
  PetscCall(SetDiagonal(A, singular));
  PetscCall(MatCreateVecs(A, &x, &b));
  PetscCall(VecSet(b, 1));
  PetscCall(KSPCreate(PETSC_COMM_SELF, &ksp));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCLU));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  PetscCall(KSPSetOperators(ksp, A, A));
  PetscCall(KSPSolve(ksp, b, x));
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  Check(reason == KSP_DIVERGED_PC_FAILED ? PETSC_TRUE : PETSC_FALSE, "zero pivot: the solve fails (KSP_DIVERGED_PC_FAILED)", reason,
        KSP_DIVERGED_PC_FAILED);
  PetscCall(PDPCForgetFailed(ksp));
  PetscCall(SetDiagonal(A, regular));
  PetscCall(KSPSolve(ksp, b, x));
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  Check(reason > 0 ? PETSC_TRUE : PETSC_FALSE, "after the reset the new matrix is factored and solved", reason, 1);
  PetscCall(VecGetArrayRead(x, &xx));
  for (PetscInt i = 0; i < 3; i++) CheckRel("x_i = 1 / d_i", PetscRealPart(xx[i]), 1 / PetscRealPart(regular[i]), 1e-14);
  PetscCall(VecRestoreArrayRead(x, &xx));
  PetscCall(KSPDestroy(&ksp));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&b));
  PetscCall(MatDestroy(&A));
  {
    const int failed = CheckSummary();
    PetscCall(PetscFinalize());
    return failed;
  }
}
