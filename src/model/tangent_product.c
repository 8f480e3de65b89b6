/* The tangent's product from the bond scalars instead of the matrix entries. Under small kinematics a
   bond's block is ka xi xi^T / |xi|^2 (THEORY.md Sec. 4): the product needs, per bond, one scalar and
   the two node ids, where a mat-vec of the assembled tangent streams two 3 x 3 blocks and their column
   indices (about 220 bytes per bond in AIJ). Krylov solves and multigrid's finest smoother are bound by
   that traffic (docs/benchmarks/solve_profile.md); the assembled matrix stays the preconditioner's.
   The product is that of the assembled matrix P: it reads the ka / |xi|^2 P's rows were last assembled with
   (a multiplication per bond where the division by |xi|^2 made the loop wait) and
   the dofs P regularised (assembly.c), and eliminates constrained dofs as P does. The bond loop is
   PDModelTangentApplyLocal (kernel.c), which path following's products share. */
#include "pd_model.h"
#include "kernel.h"
#include "pd_log.h"

typedef struct {
  PDModel *m;
  Mat      P; /* the assembled matrix whose product this is */
} TangentProduct;

static PetscErrorCode Mult(Mat A, Vec x, Vec y) {
  TangentProduct      *tp;
  PDModel             *m;
  const PetscReal     *kl;
  const unsigned char *reg;
  PDStencil           *st;
  const PetscScalar   *xx;
  PetscScalar         *yy;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &tp));
  m = tp->m;
  PetscCall(PDModelAssembledState(tp->P, &kl, &st, &reg));
  PetscCheck(kl || st, PetscObjectComm((PetscObject)A), PETSC_ERR_ORDER, "The tangent product needs an assembled matrix");
  PetscCall(PetscLogEventBegin(PD_LOG.product, A, x, y, 0));
  if (st)
    PetscCall(PDStencilApply(st, m, x, y));
  else
    PetscCall(PDModelTangentApplyScalars(m, NULL, kl, NULL, PETSC_TRUE, PETSC_TRUE, x, y));
  /* constrained rows are bc_scale on the diagonal, and a free dof without stiffness has the regularising
     diagonal P was given */
  PetscCall(VecGetArrayRead(x, &xx));
  PetscCall(VecGetArray(y, &yy));
  for (PetscInt i = 0; i < m->lat->nowned; i++)
    for (PetscInt r = 0; r < m->bs; r++) {
      const PetscInt k = m->bs * i + r;
      if (m->fixed_local[k])
        yy[k] = m->bc_scale * xx[k];
      else if ((reg[i] >> r) & 1)
        yy[k] += PD_REGULARISATION * m->bc_scale * xx[k];
    }
  PetscCall(VecRestoreArray(y, &yy));
  PetscCall(VecRestoreArrayRead(x, &xx));
  PetscCall(PetscLogEventEnd(PD_LOG.product, A, x, y, 0));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(Mat A) {
  TangentProduct *tp;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &tp));
  PetscCall(MatDestroy(&tp->P));
  PetscCall(PetscFree(tp));
  PetscFunctionReturn(0);
}

/* Whether the tangent is applied from the bond scalars (-pd_tangent_product bonds): small kinematics, where a
   block is one scalar times a fixed direction, and a preconditioning matrix that is the tangent itself
   (the secant one of -pd_pc_matrix secant is not the operator). */
static PetscBool TangentFromBonds(const PDModel *m) {
  return m->scene->tangent_product == PD_TANGENT_PRODUCT_BONDS && m->ka && !m->kb && !m->kp ? PETSC_TRUE : PETSC_FALSE;
}

/* The squared length of the longest bond the preconditioning matrix keeps (-pd_pc_reach, in grid
   spacings; the margin takes round-off in the coordinates): 0, every bond, unless Krylov solves apply
   the tangent from the bond scalars, which then hold the bonds P leaves out. The default reach in 3D
   keeps the offsets up to (2, 1, 0): on the default scene GAMG then needs no more Krylov iterations than
   with every bond, for a matrix of half the size. 2D models keep every bond: their matrices are small,
   and a 2D path-following test lost its path with the near bonds only (docs/solvers.md). */
#define PD_PC_REACH_DEFAULT_3D 2.25
static PetscErrorCode PreconditionerReach2(PDModel *m, PetscReal *reach2) {
  char      ksptype[64] = "";
  PetscBool direct;
  PetscReal r;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-ksp_type", ksptype, sizeof ksptype, NULL));
  PetscCall(PetscStrcmp(ksptype, KSPPREONLY, &direct));
  /* by default every bond where a direct solver (-ksp_type preonly) applies P's factor as the inverse,
     and where steel bars run: their segments are single stiff bonds, whose slopes no scale stands in
     for, and a bar's bonds can be longer than the reach */
  r           = m->scene->pc_reach >= 0 ? m->scene->pc_reach : (m->bs == 3 && !direct && !m->scene->nbars ? PD_PC_REACH_DEFAULT_3D : 0);
  m->pc_reach = TangentFromBonds(m) ? r : 0;
  *reach2     = PetscSqr(m->pc_reach * m->lat->dx) * (1 + 1e-9);
  PetscFunctionReturn(0);
}

/* The Newton operator J and its preconditioning matrix P: P assembled (the tangent, or the secant one), J
   the product of the tangent from the bond scalars, the assembled tangent, or P itself. */
PetscErrorCode PDModelCreateOperators(PDModel *m, Mat *J, Mat *P) {
  TangentProduct *tp;
  PetscInt        n, N;
  PetscReal       reach2 = 0;

  PetscFunctionBeginUser;
  PetscCall(PreconditionerReach2(m, &reach2));
  PetscCall(PDModelCreateMatrix(m, reach2, P));
  if (m->kp) {
    PetscCall(PDModelCreateMatrix(m, 0, J));
    PetscFunctionReturn(0);
  }
  if (!TangentFromBonds(m)) {
    *J = *P;
    PetscFunctionReturn(0);
  }
  {
    PDStencil *st;
    PetscCall(PDStencilCreate(m, &st));
    if (st) PetscCall(PDModelAssembledSetStencil(*P, st));
  }
  PetscCall(PetscNew(&tp));
  tp->m = m;
  tp->P = *P;
  PetscCall(PetscObjectReference((PetscObject)*P));
  PetscCall(MatGetLocalSize(*P, &n, NULL));
  PetscCall(MatGetSize(*P, &N, NULL));
  PetscCall(MatCreateShell(m->lat->comm, n, n, N, N, tp, J));
  PetscCall(MatSetBlockSize(*J, m->bs));
  PetscCall(MatShellSetOperation(*J, MATOP_MULT, (void (*)(void))Mult));
  PetscCall(MatShellSetOperation(*J, MATOP_MULT_TRANSPOSE, (void (*)(void))Mult));
  PetscCall(MatShellSetOperation(*J, MATOP_DESTROY, (void (*)(void))Destroy));
  PetscCall(MatSetOption(*J, MAT_SYMMETRIC, PETSC_TRUE));
  PetscCall(MatSetOption(*J, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
  PetscCall(PetscObjectSetName((PetscObject)*J, "tangent from the bond scalars"));
  PetscFunctionReturn(0);
}

/* Destroys what PDModelCreateOperators made. */
PetscErrorCode PDModelDestroyOperators(Mat *J, Mat *P) {
  PetscFunctionBeginUser;
  if (*J != *P) PetscCall(MatDestroy(J));
  PetscCall(MatDestroy(P));
  *J = NULL;
  PetscFunctionReturn(0);
}
