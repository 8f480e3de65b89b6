/* The tangent's product from the bond scalars instead of the matrix entries. Under small kinematics a
   bond's block is ka xi xi^T / |xi|^2 (THEORY.md Sec. 4): the product needs, per bond, one scalar and
   the two node ids, where a mat-vec of the assembled tangent streams two 3 x 3 blocks and their column
   indices (about 220 bytes per bond in AIJ). Krylov solves and multigrid's finest smoother are bound by
   that traffic (docs/benchmarks/solve_profile.md); the assembled matrix stays the preconditioner's.
   The product is that of the assembled matrix P: it reads the ka P's rows were last assembled with and
   the dofs P regularised (assembly.c), and eliminates constrained dofs as P does. */
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
  const PDBonds       *bd;
  const PDLattice     *lat;
  const PetscReal     *ka;
  const unsigned char *reg;
  const PetscScalar   *xx;
  PetscScalar         *xl, *yl, *yy;
  Vec                  xloc, yloc;
  PetscInt             bs;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &tp));
  m   = tp->m;
  bd  = m->bonds;
  lat = m->lat;
  bs  = m->bs;
  PetscCall(PDModelAssembledState(tp->P, &ka, &reg));
  PetscCheck(ka, PetscObjectComm((PetscObject)A), PETSC_ERR_ORDER, "The tangent product needs an assembled matrix");
  PetscCall(PetscLogEventBegin(PD_LOG.product, A, x, y, 0));
  if (!m->x_local) PetscCall(VecDuplicate(m->u_local, &m->x_local));
  PetscCall(VecCopy(x, m->x_local));
  PetscCall(VecGhostUpdateBegin(m->x_local, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(m->x_local, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostGetLocalForm(m->x_local, &xloc));
  PetscCall(VecGhostGetLocalForm(m->f_local, &yloc));
  PetscCall(VecGetArray(xloc, &xl));
  PetscCall(VecGetArray(yloc, &yl));
  /* constrained columns are eliminated: their entries of x take no part in the bonds' products */
  for (PetscInt k = 0; k < bs * lat->nlocal; k++)
    if (m->fixed_local[k]) xl[k] = 0;
  PetscCall(PetscArrayzero(yl, bs * lat->nlocal));
  /* bonds come in runs of one first node (the neighbour search's order): its coordinates, x and the sum
     of its row stay in registers for the run, so that no bond waits on the store of the one before */
  {
    PetscInt  cur   = -1;
    PetscReal xc[3] = {0, 0, 0}, vc[3] = {0, 0, 0}, acc[3] = {0, 0, 0};
    for (PetscInt e = 0; e < bd->nbonds; e++) {
      const PetscInt   i = bd->a[e], j = bd->b[e];
      const PetscReal *xb = &lat->x[3 * j];
      PetscReal        xi[3], L2 = 0, dot = 0, t;
      if (i != cur) {
        for (PetscInt r = 0; r < bs && cur >= 0; r++) yl[bs * cur + r] += acc[r];
        cur = i;
        for (PetscInt r = 0; r < bs; r++) {
          xc[r]  = lat->x[3 * i + r];
          vc[r]  = PetscRealPart(xl[bs * i + r]);
          acc[r] = 0;
        }
      }
      for (PetscInt r = 0; r < bs; r++) {
        xi[r] = xb[r] - xc[r];
        L2 += xi[r] * xi[r];
        dot += xi[r] * (PetscRealPart(xl[bs * j + r]) - vc[r]);
      }
      t = ka[e] * dot / L2;
      for (PetscInt r = 0; r < bs; r++) {
        acc[r] -= t * xi[r];
        yl[bs * j + r] += t * xi[r];
      }
    }
    for (PetscInt r = 0; r < bs && cur >= 0; r++) yl[bs * cur + r] += acc[r];
  }
  PetscCall(PetscLogFlops((bs == 3 ? 25.0 : 18.0) * bd->nbonds));
  /* owned rows only (ghost entries are partial sums); constrained rows are bc_scale on the diagonal, and a
     free dof without stiffness has the regularising diagonal P was given */
  PetscCall(VecGetArrayRead(x, &xx));
  PetscCall(VecGetArray(y, &yy));
  for (PetscInt i = 0; i < lat->nowned; i++)
    for (PetscInt r = 0; r < bs; r++) {
      const PetscInt k = bs * i + r;
      if (m->fixed_local[k])
        yy[k] = m->bc_scale * xx[k];
      else
        yy[k] = yl[k] + ((reg[i] >> r) & 1 ? PD_REGULARISATION * m->bc_scale * xx[k] : 0);
    }
  PetscCall(VecRestoreArray(y, &yy));
  PetscCall(VecRestoreArrayRead(x, &xx));
  PetscCall(VecRestoreArray(yloc, &yl));
  PetscCall(VecRestoreArray(xloc, &xl));
  PetscCall(VecGhostRestoreLocalForm(m->f_local, &yloc));
  PetscCall(VecGhostRestoreLocalForm(m->x_local, &xloc));
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
PetscBool PDModelTangentFromBonds(const PDModel *m) {
  return m->scene->tangent_product == PD_TANGENT_PRODUCT_BONDS && m->ka && !m->kb && !m->kp ? PETSC_TRUE : PETSC_FALSE;
}

/* The Newton operator J and its preconditioning matrix P: P assembled (the tangent, or the secant one), J
   the product of the tangent from the bond scalars, the assembled tangent, or P itself. */
PetscErrorCode PDModelCreateOperators(PDModel *m, Mat *J, Mat *P) {
  TangentProduct *tp;
  PetscInt        n, N;

  PetscFunctionBeginUser;
  PetscCall(PDModelCreateMatrix(m, P));
  if (m->kp) {
    PetscCall(PDModelCreateMatrix(m, J));
    PetscFunctionReturn(0);
  }
  if (!PDModelTangentFromBonds(m)) {
    *J = *P;
    PetscFunctionReturn(0);
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
