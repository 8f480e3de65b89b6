/* Path following with a constraint linear in (u, lambda) (cmod, dissipation) in one Krylov solve per
   Newton iteration.

   Bordering solves K du_I = -R and K du_II = -dG/dlambda, two solves to the same tolerance with one
   preconditioner, and takes dlambda from the constraint. The same update is the solution of the
   augmented system

       [ K    q ] [ du ]   [ -R ]
       [ c^T  d ] [ t  ] = [  r ]

   (q the lambda column, c and d the linearised constraint, t the scaled load-factor change). GMRES solves
   it preconditioned by the block lower-triangular

       [ P_K  0 ]
       [ c^T  s ]

   where P_K is the Newton preconditioner of K itself (no second hierarchy or factor is built) and s
   estimates the Schur complement d - c.K^-1 q; the caller passes it from the direction v of the step's
   predictor, where it is exact for the tangent of that moment. The preconditioned operator is block
   lower triangular with diagonal blocks P_K^-1 K and d/s, plus the rank-one column q: GMRES needs about
   the iterations of one solve with K, where bordering needs two. FGMRES, on the right: its residual is
   the true one, which the corrector's floor measures. The operator is a MATNEST of the
   tangent and dense border blocks; the preconditioner is a PCSHELL because it must apply the Newton
   PC object as is (PCFIELDSPLIT would set up its own preconditioner for the K block). */
#include "augmented.h"
#include "pd_solve.h"

static PetscErrorCode ApplyLowerTriangular(PC pc, Vec x, Vec y) {
  PDAugmented *aug;
  Vec          xu, yu, xl, yl, c;
  PC           pk; /* the Newton preconditioner of K, shared, set up by knewton */
  PetscScalar  xlam, cy;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &aug));
  PetscCall(VecGetSubVector(x, aug->is_u, &xu));
  PetscCall(VecGetSubVector(y, aug->is_u, &yu));
  PetscCall(KSPGetPC(aug->knewton, &pk));
  PetscCall(PCApply(pk, xu, yu));
  PetscCall(MatDenseGetColumnVecRead(aug->Cc, 0, &c));
  PetscCall(VecDot(yu, c, &cy));
  PetscCall(MatDenseRestoreColumnVecRead(aug->Cc, 0, &c));
  PetscCall(VecRestoreSubVector(x, aug->is_u, &xu));
  PetscCall(VecRestoreSubVector(y, aug->is_u, &yu));
  /* the lambda block has one entry, owned by rank 0: the sum gives it on every rank */
  PetscCall(VecGetSubVector(x, aug->is_l, &xl));
  PetscCall(VecSum(xl, &xlam));
  PetscCall(VecRestoreSubVector(x, aug->is_l, &xl));
  PetscCall(VecGetSubVector(y, aug->is_l, &yl));
  PetscCall(VecSet(yl, (xlam - cy) / aug->schur));
  PetscCall(VecRestoreSubVector(y, aug->is_l, &yl));
  PetscFunctionReturn(0);
}

PetscErrorCode PDAugmentedCreate(Mat K, KSP knewton, PDAugmented *aug) {
  MPI_Comm    comm;
  PetscMPIInt rank;
  PetscInt    n, N, nl;
  IS         *is;
  PC          pc;
  PetscReal   rtol;
  PetscInt    maxit;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(aug, sizeof *aug));
  PetscCall(PetscObjectGetComm((PetscObject)K, &comm));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(MatGetLocalSize(K, &n, NULL));
  PetscCall(MatGetSize(K, &N, NULL));
  nl = rank == 0 ? 1 : 0; /* the load factor lives on rank 0 */
  PetscCall(MatCreateDense(comm, n, nl, N, 1, NULL, &aug->Q));
  PetscCall(MatCreateDense(comm, n, nl, N, 1, NULL, &aug->Cc));
  PetscCall(MatCreateDense(comm, nl, nl, 1, 1, NULL, &aug->D));
  {
    Mat dense[] = {aug->Q, aug->Cc, aug->D};
    for (size_t k = 0; k < 3; k++) {
      PetscCall(MatZeroEntries(dense[k]));
      PetscCall(MatAssemblyBegin(dense[k], MAT_FINAL_ASSEMBLY));
      PetscCall(MatAssemblyEnd(dense[k], MAT_FINAL_ASSEMBLY));
    }
  }
  /* the row as the transpose of a column: its product is a local dot product and one reduction */
  PetscCall(MatCreateTranspose(aug->Cc, &aug->C));
  {
    Mat blocks[] = {K, aug->Q, aug->C, aug->D};
    PetscCall(MatCreateNest(comm, 2, NULL, 2, NULL, blocks, &aug->A));
  }
  PetscCall(PetscMalloc1(2, &is));
  PetscCall(MatNestGetISs(aug->A, is, NULL));
  aug->is_u = is[0];
  aug->is_l = is[1];
  PetscCall(PetscObjectReference((PetscObject)aug->is_u));
  PetscCall(PetscObjectReference((PetscObject)aug->is_l));
  PetscCall(PetscFree(is));
  PetscCall(VecCreateMPI(comm, n + nl, N + 1, &aug->x));
  PetscCall(VecDuplicate(aug->x, &aug->b));

  aug->knewton = knewton;
  PetscCall(KSPCreate(comm, &aug->ksp));
  PetscCall(KSPSetOptionsPrefix(aug->ksp, "pd_augmented_"));
  /* preconditioned on the right, so that the residual it stops on is the true one (the corrector's floor,
     arclength.c); flexible, so that the last iteration needs no extra preconditioner application */
  PetscCall(KSPSetType(aug->ksp, KSPFGMRES));
  PetscCall(KSPSetPCSide(aug->ksp, PC_RIGHT));
  PetscCall(PDInterruptWatchKSP(aug->ksp));
  PetscCall(KSPGMRESSetRestart(aug->ksp, 60));
  PetscCall(KSPGetTolerances(knewton, &rtol, NULL, NULL, &maxit));
  PetscCall(KSPSetTolerances(aug->ksp, rtol, PETSC_DEFAULT, PETSC_DEFAULT, maxit));
  PetscCall(KSPGetPC(aug->ksp, &pc));
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PCShellSetContext(pc, aug));
  PetscCall(PCShellSetApply(pc, ApplyLowerTriangular));
  PetscCall(PCShellSetName(pc, "block lower-triangular: the Newton PC of K, then the constraint row"));
  PetscCall(KSPSetOperators(aug->ksp, aug->A, aug->A));
  PetscCall(KSPSetFromOptions(aug->ksp)); /* -pd_augmented_ksp_* */
  PetscFunctionReturn(0);
}

static PetscErrorCode SetColumn(Mat M, Vec v) {
  Vec col;

  PetscFunctionBeginUser;
  PetscCall(MatDenseGetColumnVecWrite(M, 0, &col));
  PetscCall(VecCopy(v, col));
  PetscCall(MatDenseRestoreColumnVecWrite(M, 0, &col));
  PetscFunctionReturn(0);
}

/* Solve [K q; c^T d] [du; t] = [rhs_u; rhs_l] with K the operator of knewton, whose preconditioner is set up
   (or lagged) by its own rules before the solve. */
PetscErrorCode PDAugmentedSolve(PDAugmented *aug, Vec q, Vec c, PetscReal d, PetscReal schur, Vec rhs_u, PetscReal rhs_l, Vec du,
                                PetscReal *t, PetscInt *its, KSPConvergedReason *reason) {
  Vec         sub;
  PetscScalar tl;

  PetscFunctionBeginUser;
  PetscCall(SetColumn(aug->Q, q));
  PetscCall(SetColumn(aug->Cc, c));
  {
    PetscScalar *corner;
    PetscInt     mine;
    PetscCall(MatGetLocalSize(aug->D, &mine, NULL));
    PetscCall(MatDenseGetArrayWrite(aug->D, &corner));
    if (mine) corner[0] = d; /* rank 0 */
    PetscCall(MatDenseRestoreArrayWrite(aug->D, &corner));
  }
  /* the blocks changed under the nest; assembling it checks them (no copy) */
  PetscCall(MatAssemblyBegin(aug->A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(aug->A, MAT_FINAL_ASSEMBLY));
  aug->schur = schur;
  /* what KSPSolve on knewton would do first: set up the preconditioner, blocks included */
  PetscCall(KSPSetUp(aug->knewton));
  PetscCall(KSPSetUpOnBlocks(aug->knewton));
  PetscCall(VecGetSubVector(aug->b, aug->is_u, &sub));
  PetscCall(VecCopy(rhs_u, sub));
  PetscCall(VecRestoreSubVector(aug->b, aug->is_u, &sub));
  PetscCall(VecGetSubVector(aug->b, aug->is_l, &sub));
  PetscCall(VecSet(sub, rhs_l));
  PetscCall(VecRestoreSubVector(aug->b, aug->is_l, &sub));
  PetscCall(KSPSolve(aug->ksp, aug->b, aug->x));
  PetscCall(KSPGetIterationNumber(aug->ksp, its));
  PetscCall(KSPGetConvergedReason(aug->ksp, reason));
  PetscCall(VecGetSubVector(aug->x, aug->is_u, &sub));
  PetscCall(VecCopy(sub, du));
  PetscCall(VecRestoreSubVector(aug->x, aug->is_u, &sub));
  PetscCall(VecGetSubVector(aug->x, aug->is_l, &sub));
  PetscCall(VecSum(sub, &tl));
  PetscCall(VecRestoreSubVector(aug->x, aug->is_l, &sub));
  *t = PetscRealPart(tl);
  PetscFunctionReturn(0);
}

PetscErrorCode PDAugmentedDestroy(PDAugmented *aug) {
  PetscFunctionBeginUser;
  PetscCall(KSPDestroy(&aug->ksp));
  PetscCall(MatDestroy(&aug->A));
  PetscCall(MatDestroy(&aug->C));
  PetscCall(MatDestroy(&aug->Q));
  PetscCall(MatDestroy(&aug->Cc));
  PetscCall(MatDestroy(&aug->D));
  PetscCall(ISDestroy(&aug->is_u));
  PetscCall(ISDestroy(&aug->is_l));
  PetscCall(VecDestroy(&aug->x));
  PetscCall(VecDestroy(&aug->b));
  PetscFunctionReturn(0);
}
