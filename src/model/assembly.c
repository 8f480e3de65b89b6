/* The stiffness rows, gathered node by node from the bond scalars, and rewritten on later assemblies only
   where a bond's scalar changed. */
#include "pd_model.h"
#include "kernel.h"
#include "pd_log.h"

/* What a matrix holds, composed on it: the tangent scalar ka each bond's blocks were last assembled with,
   over the bond's squared length (the factor of xi xi^T in its block, which the matrix-free product
   multiplies by without a division), and the dofs each row regularised. Under small kinematics a bond's block depends on the state through
   ka alone, and only the bonds of a softening band change it between Newton iterations: a later
   assembly rewrites the rows of the nodes one of whose bonds changed, and leaves the others as they are
   (docs/solvers.md "Assembly"). */
typedef struct {
  PetscReal     *kl;     /* [nbonds] ka / |xi|^2, or -1 for the micromodulus */
  unsigned char *reg;    /* [nowned] dofs of the row given the regularising diagonal, bit r for dof r */
  PetscInt       maxrow; /* blocks in the longest row */
} PDAssembled;

static PetscErrorCode AssembledDestroy(void *ctx) {
  PDAssembled *rec = (PDAssembled *)ctx;

  PetscFunctionBeginUser;
  PetscCall(PetscFree2(rec->kl, rec->reg));
  PetscCall(PetscFree(rec));
  PetscFunctionReturn(0);
}

/* The record composed on J, created (empty: every row due) on first use. */
static PetscErrorCode AssembledGet(PDModel *m, Mat J, PDAssembled **rec, PetscBool *fresh) {
  PetscContainer c;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectQuery((PetscObject)J, "PDAssembled", (PetscObject *)&c));
  *fresh = c ? PETSC_FALSE : PETSC_TRUE;
  if (c) {
    PetscCall(PetscContainerGetPointer(c, (void **)rec));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscNew(rec));
  PetscCall(PetscMalloc2(PetscMax(1, m->bonds->nbonds), &(*rec)->kl, PetscMax(1, m->lat->nowned), &(*rec)->reg));
  for (PetscInt i = 0; i < m->lat->nowned; i++)
    (*rec)->maxrow = PetscMax((*rec)->maxrow, m->bonds->inc_start[i + 1] - m->bonds->inc_start[i] + 1);
  PetscCall(PetscContainerCreate(PetscObjectComm((PetscObject)J), &c));
  PetscCall(PetscContainerSetPointer(c, *rec));
  PetscCall(PetscContainerSetUserDestroy(c, AssembledDestroy));
  PetscCall(PetscObjectCompose((PetscObject)J, "PDAssembled", (PetscObject)c));
  PetscCall(PetscContainerDestroy(&c));
  PetscFunctionReturn(0);
}

/* One node's row: blocks -K of its bonds and the diagonal block, in the order of the global ids of the
   columns' nodes where the row is copied whole (cols, vals with leading dimension ld). Constrained dofs
   are eliminated symmetrically: their rows and columns are zero but for bc_scale on the diagonal. A free
   direction left without stiffness (every bond of the node broken) gets a small diagonal so that the
   matrix stays regular; the residual is not changed, so the solution is not either. */
static unsigned char NodeRow(PDModel *m, const PetscScalar *u, const PetscReal *ka, const PetscReal *kb, PetscInt i, PetscInt *cols,
                             PetscScalar *vals) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscInt   bs = m->bs, s = bd->inc_start[i], n = bd->inc_start[i + 1] - s, ld = (n + 1) * bs;
  PetscInt         diag = n, c = 0;
  unsigned char    reg  = 0;
  PetscReal        D[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}, Dref[3] = {0, 0, 0};

  for (PetscInt p = 0; p < n; p++) {
    const PetscInt e = bd->inc_bond[s + p], j = bd->a[e] == i ? bd->b[e] : bd->a[e];
    PetscReal      dir[3], L0, L, st, q, K[9], a, b;
    if (diag == n && lat->gid[j] > lat->gid[i]) diag = c++;
    BondState(m->scene, bs, &lat->x[3 * i], &lat->x[3 * j], &u[bs * i], &u[bs * j], dir, &L0, &L, &st, &q);
    /* without per-bond scalars the tangent is the constant linearised micromodulus */
    a = ka ? ka[e] : PDBondStiffness(bd, e) / L0;
    b = kb ? kb[e] : 0;
    for (PetscInt r = 0; r < bs; r++) {
      Dref[r] += PDBondStiffness(bd, e) / L0 * dir[r] * dir[r];
      for (PetscInt qq = 0; qq < bs; qq++) {
        K[r * bs + qq] = a * dir[r] * dir[qq] + (r == qq ? b : 0);
        D[r * bs + qq] += K[r * bs + qq];
      }
    }
    cols[c] = lat->gid[j];
    for (PetscInt r = 0; r < bs; r++)
      for (PetscInt qq = 0; qq < bs; qq++) {
        const PetscBool zero       = m->fixed_local[bs * i + r] || m->fixed_local[bs * j + qq];
        vals[r * ld + c * bs + qq] = zero ? 0 : -K[r * bs + qq];
      }
    c++;
  }
  if (diag == n) diag = c;
  cols[diag] = lat->gid[i];
  for (PetscInt r = 0; r < bs; r++) {
    if (!m->fixed_local[bs * i + r] && PetscAbsReal(D[r * bs + r]) <= 1e-10 * Dref[r]) {
      D[r * bs + r] += PD_REGULARISATION * m->bc_scale;
      reg |= (unsigned char)(1u << r);
    }
    for (PetscInt qq = 0; qq < bs; qq++) {
      const PetscBool fr = m->fixed_local[bs * i + r], fq = m->fixed_local[bs * i + qq];
      vals[r * ld + diag * bs + qq] = (fr || fq) ? (r == qq ? m->bc_scale : 0) : D[r * bs + qq];
    }
  }
  return reg;
}

/* Rows of J from the bond scalars (ka NULL: the linearised micromodulus; kb NULL: small kinematics). The
   first assembly of J, and every one under finite kinematics (where a block's direction follows the
   displacement), writes all rows; later ones only the rows of nodes with a bond whose ka changed. */
PetscErrorCode PDModelAssembleRows(PDModel *m, const PetscScalar *u, const PetscReal *ka, const PetscReal *kb, Mat J,
                                   PetscInt *nregularised) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscInt   bs = m->bs, bs2 = bs * bs;
  PetscInt        *cols, nreg = 0, nrows = 0;
  PetscScalar     *vals;
  PetscBool        assembled, aij, rowcopy, fresh = PETSC_TRUE, every;
  PDAssembled     *rec;
  PetscBool       *due;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PD_LOG.assembly, 0, 0, 0, 0));
  /* Once an AIJ matrix holds its (exact, fixed) pattern, each scalar row is copied in place in column
     order: MatSetValues would search every column of the row, which made AIJ assembly six times slower
     than SBAIJ's (the storage GAMG needs). Blocked storage keeps MatSetValuesBlocked. */
  PetscCall(MatAssembled(J, &assembled));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)J, &aij, MATSEQAIJ, MATMPIAIJ, ""));
  rowcopy = assembled && aij;
  PetscCall(AssembledGet(m, J, &rec, &fresh));
  every = !assembled || fresh || kb || !m->scene->assembly_changed_rows ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PetscMalloc1(PetscMax(1, lat->nowned), &due));
  for (PetscInt i = 0; i < lat->nowned; i++) due[i] = every;
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    /* -1: the micromodulus, never a stored value of this matrix */
    const PetscReal a = ka ? ka[e] / PDBondLength2(bs, lat->x, bd->a[e], bd->b[e]) : -1;
    if (!every && a == rec->kl[e]) continue;
    rec->kl[e] = a;
    if (bd->a[e] < lat->nowned) due[bd->a[e]] = PETSC_TRUE;
    if (bd->b[e] < lat->nowned) due[bd->b[e]] = PETSC_TRUE;
  }
  PetscCall(PetscMalloc2(rec->maxrow, &cols, rec->maxrow * bs2, &vals));
  for (PetscInt i = 0; i < lat->nowned; i++) {
    const PetscInt ncols = bd->inc_start[i + 1] - bd->inc_start[i] + 1;
    if (due[i]) {
      nrows++;
      rec->reg[i] = NodeRow(m, u, ka, kb, i, cols, vals);
      if (rowcopy)
        for (PetscInt r = 0; r < bs; r++) PetscCall(MatSetValuesRow(J, bs * lat->gid[i] + r, &vals[r * ncols * bs]));
      else
        PetscCall(MatSetValuesBlocked(J, 1, &lat->gid[i], ncols, cols, vals, INSERT_VALUES));
    }
    for (PetscInt r = 0; r < bs; r++) nreg += (rec->reg[i] >> r) & 1;
  }
  PetscCall(PetscFree2(cols, vals));
  PetscCall(PetscFree(due));
  m->rows_assembled += nrows;
  PetscCall(PetscInfo(J, "%" PetscInt_FMT " of %" PetscInt_FMT " rows assembled\n", nrows, lat->nowned));
  PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MPIU_Allreduce(&nreg, nregularised, 1, MPIU_INT, MPI_SUM, lat->comm));
  PetscCall(PetscLogEventEnd(PD_LOG.assembly, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* What P was last assembled with: each bond's ka / |xi|^2 and each owned row's regularised dofs (NULL
   before the first assembly). Read by the matrix-free product of the same matrix (tangent_product.c). */
PetscErrorCode PDModelAssembledState(Mat P, const PetscReal **kl, const unsigned char **reg) {
  PetscContainer c;
  PDAssembled   *rec;

  PetscFunctionBeginUser;
  *kl  = NULL;
  *reg = NULL;
  PetscCall(PetscObjectQuery((PetscObject)P, "PDAssembled", (PetscObject *)&c));
  if (!c) PetscFunctionReturn(0);
  PetscCall(PetscContainerGetPointer(c, (void **)&rec));
  *kl  = rec->kl;
  *reg = rec->reg;
  PetscFunctionReturn(0);
}
