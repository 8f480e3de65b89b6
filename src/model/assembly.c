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
  PetscBool      fresh;  /* nothing assembled yet: every row due */
  /* a reduced matrix (PDModelCreateMatrix): the bonds up to the squared length reach2 (0: every bond),
     their blocks times scale; ncols[i] blocks in row i */
  PetscReal  reach2, scale;
  PetscInt  *ncols;
  PDStencil *stencil; /* the same scalars by stencil offset, or NULL (stencil_product.c) */
} PDAssembled;

static PetscErrorCode AssembledDestroy(void *ctx) {
  PDAssembled *rec = (PDAssembled *)ctx;

  PetscFunctionBeginUser;
  PetscCall(PetscFree(rec->kl));
  PetscCall(PetscFree2(rec->reg, rec->ncols));
  PetscCall(PDStencilDestroy(&rec->stencil));
  PetscCall(PetscFree(rec));
  PetscFunctionReturn(0);
}

/* Composes on J the record of what it holds, before anything is assembled. J keeps the bonds up to the
   squared length reach2 (0: every bond), ncols[i] blocks in row i as preallocated (PDModelCreateMatrix). A reduced matrix (the
   preconditioner's, where Krylov solves apply the tangent from the bond scalars) scales its bonds by the ratio of the whole stencil's bulk
   stiffness to theirs: a homogeneous strain eps gives a bond the energy ka |xi|^2 (e.eps.e)^2 / 2, so
   the sums of the micromodulus times |xi|^2 over all bonds and over the kept ones compare the two, and
   the matrix keeps the elastic response at scales above the reach, which is what multigrid's coarse
   levels see. */
PetscErrorCode PDModelAssembledAttach(PDModel *m, Mat J, PetscReal reach2, const PetscInt *ncols) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  PDAssembled     *rec;
  PetscContainer   c;
  PetscReal        w[2] = {0, 0}, wg[2];

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&rec));
  PetscCall(PetscMalloc1(PetscMax(1, bd->nbonds), &rec->kl));
  PetscCall(PetscMalloc2(PetscMax(1, lat->nowned), &rec->reg, PetscMax(1, lat->nowned), &rec->ncols));
  rec->fresh  = PETSC_TRUE;
  rec->reach2 = reach2;
  for (PetscInt i = 0; i < lat->nowned; i++) {
    rec->ncols[i] = ncols[i];
    rec->maxrow   = PetscMax(rec->maxrow, ncols[i]);
  }
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    /* each bond once over the ranks, so that the scale does not depend on the partition */
    const PetscReal wb =
        PDBondCountedHere(lat, bd, e) ? PDBondStiffness(bd, e) * PetscSqrtReal(PDBondLength2(m->bs, lat->x, bd->a[e], bd->b[e])) : 0;
    w[0] += wb;
    if (PDBondInReach(m->bs, lat->x, bd->a[e], bd->b[e], reach2)) w[1] += wb;
  }
  PetscCall(MPIU_Allreduce(w, wg, 2, MPIU_REAL, MPIU_SUM, lat->comm));
  rec->scale = wg[1] > 0 ? wg[0] / wg[1] : 1;
  PetscCall(PetscInfo(J, "Bonds up to %g m, stiffened %g times\n", (double)PetscSqrtReal(reach2), (double)rec->scale));
  PetscCall(PetscContainerCreate(PetscObjectComm((PetscObject)J), &c));
  PetscCall(PetscContainerSetPointer(c, rec));
  PetscCall(PetscContainerSetUserDestroy(c, AssembledDestroy));
  PetscCall(PetscObjectCompose((PetscObject)J, "PDAssembled", (PetscObject)c));
  PetscCall(PetscContainerDestroy(&c));
  PetscFunctionReturn(0);
}

static PetscErrorCode AssembledGet(Mat J, PDAssembled **rec) {
  PetscContainer c;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectQuery((PetscObject)J, "PDAssembled", (PetscObject *)&c));
  PetscCheck(c, PetscObjectComm((PetscObject)J), PETSC_ERR_ORDER, "The matrix was not made by PDModelCreateMatrix");
  PetscCall(PetscContainerGetPointer(c, (void **)rec));
  PetscFunctionReturn(0);
}

/* One node's row: blocks -K of its bonds (those the matrix keeps, times its scale) and the diagonal
   block, in the order of the global ids of the columns' nodes where the row is copied whole (cols, vals
   with leading dimension ld). Constrained dofs are eliminated symmetrically: their rows and columns are
   zero but for bc_scale on the diagonal. A free direction left without stiffness (every bond of the node
   broken) gets a small diagonal so that the matrix stays regular; the residual is not changed, so the
   solution is not either. Whether a direction has stiffness is judged on all its bonds, so that a
   reduced matrix regularises the dofs the whole one does (the product from the bond scalars adds the
   same diagonal); a direction whose kept bonds are all broken while others hold gets their diagonal. */
static unsigned char NodeRow(PDModel *m, const PDAssembled *rec, const PetscScalar *u, const PetscReal *ka, const PetscReal *kb, PetscInt i,
                             PetscInt *cols, PetscScalar *vals) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscInt   bs = m->bs, s = bd->inc_start[i], n = bd->inc_start[i + 1] - s, ld = rec->ncols[i] * bs;
  PetscInt         diag = -1, c = 0;
  unsigned char    reg  = 0;
  PetscReal        D[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}, Dref[3] = {0, 0, 0}, Dall[3] = {0, 0, 0};

  for (PetscInt p = 0; p < n; p++) {
    const PetscInt e = bd->inc_bond[s + p], j = bd->a[e] == i ? bd->b[e] : bd->a[e];
    PetscReal      dir[3], L0, L, st, q, K[9], a, b;
    BondState(m->scene, bs, &lat->x[3 * i], &lat->x[3 * j], &u[bs * i], &u[bs * j], dir, &L0, &L, &st, &q);
    /* without per-bond scalars the tangent is the constant linearised micromodulus */
    a = ka ? ka[e] : PDBondStiffness(bd, e) / L0;
    b = kb ? kb[e] : 0;
    for (PetscInt r = 0; r < bs; r++) {
      Dref[r] += PDBondStiffness(bd, e) / L0 * dir[r] * dir[r];
      Dall[r] += a * dir[r] * dir[r] + b;
    }
    if (!PDBondInReach(bs, lat->x, i, j, rec->reach2)) continue;
    /* the scale stands in for the left-out bonds' stiffness; a softening bond's negative slope is its
       own, and scaled up it made the matrix far more indefinite than the tangent */
    if (a > 0) a *= rec->scale;
    b *= rec->scale;
    if (diag < 0 && lat->gid[j] > lat->gid[i]) diag = c++;
    for (PetscInt r = 0; r < bs; r++) {
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
  if (diag < 0) diag = c;
  cols[diag] = lat->gid[i];
  for (PetscInt r = 0; r < bs; r++) {
    if (!m->fixed_local[bs * i + r] && PetscAbsReal(Dall[r]) <= 1e-10 * Dref[r]) {
      D[r * bs + r] += PD_REGULARISATION * m->bc_scale;
      reg |= (unsigned char)(1u << r);
    } else if (PetscAbsReal(D[r * bs + r]) <= 1e-10 * Dref[r])
      D[r * bs + r] = Dall[r] > 0 ? rec->scale * Dall[r] : Dall[r];
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
  PetscBool        assembled, aij, rowcopy, every;
  PDAssembled     *rec;
  PetscBool       *due;
  PetscReal       *store;
  const PetscInt  *slot = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PD_LOG.assembly, 0, 0, 0, 0));
  /* Once an AIJ matrix holds its (exact, fixed) pattern, each scalar row is copied in place in column
     order: MatSetValues would search every column of the row, which made AIJ assembly six times slower
     than SBAIJ's (the storage GAMG needs). Blocked storage keeps MatSetValuesBlocked. */
  PetscCall(MatAssembled(J, &assembled));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)J, &aij, MATSEQAIJ, MATMPIAIJ, ""));
  rowcopy = assembled && aij;
  PetscCall(AssembledGet(J, &rec));
  every      = !assembled || rec->fresh || kb || !m->scene->assembly_changed_rows ? PETSC_TRUE : PETSC_FALSE;
  rec->fresh = PETSC_FALSE;
  PetscCall(PetscMalloc1(PetscMax(1, lat->nowned), &due));
  for (PetscInt i = 0; i < lat->nowned; i++) due[i] = every;
  /* the record's scalars: its bond array, or the stencil view's places of the bonds */
  if (rec->stencil)
    PDStencilScalars(rec->stencil, &store, &slot);
  else
    store = rec->kl;
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    /* -1: the micromodulus, never a stored value of this matrix */
    const PetscReal a  = ka ? ka[e] / PDBondLength2(bs, lat->x, bd->a[e], bd->b[e]) : -1;
    PetscReal      *at = &store[slot ? slot[e] : e];
    if (!every && a == *at) continue;
    *at = a;
    if (bd->a[e] < lat->nowned) due[bd->a[e]] = PETSC_TRUE;
    if (bd->b[e] < lat->nowned) due[bd->b[e]] = PETSC_TRUE;
  }
  PetscCall(PetscMalloc2(rec->maxrow, &cols, rec->maxrow * bs2, &vals));
  for (PetscInt i = 0; i < lat->nowned; i++) {
    const PetscInt ncols = rec->ncols[i];
    if (due[i]) {
      nrows++;
      rec->reg[i] = NodeRow(m, rec, u, ka, kb, i, cols, vals);
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

/* What P was last assembled with: each bond's ka / |xi|^2, in the record's bond array (kl) or in the
   stencil view (st; the other NULL), and each owned row's regularised dofs (all NULL before the first
   assembly). Read by the matrix-free product of the tangent P preconditions (tangent_product.c). */
PetscErrorCode PDModelAssembledState(Mat P, const PetscReal **kl, PDStencil **st, const unsigned char **reg) {
  PetscContainer c;
  PDAssembled   *rec;

  PetscFunctionBeginUser;
  *kl  = NULL;
  *st  = NULL;
  *reg = NULL;
  PetscCall(PetscObjectQuery((PetscObject)P, "PDAssembled", (PetscObject *)&c));
  if (!c) PetscFunctionReturn(0);
  PetscCall(PetscContainerGetPointer(c, (void **)&rec));
  if (rec->fresh) PetscFunctionReturn(0);
  *kl  = rec->kl;
  *st  = rec->stencil;
  *reg = rec->reg;
  PetscFunctionReturn(0);
}

/* Hands the stencil view of the bond scalars to P's record before P's first assembly: the record then
   keeps the scalars there, in place of its bond array, and destroys the view. */
PetscErrorCode PDModelAssembledSetStencil(Mat P, PDStencil *st) {
  PDAssembled *rec;

  PetscFunctionBeginUser;
  PetscCall(AssembledGet(P, &rec));
  PetscCheck(rec->fresh && !rec->stencil, PetscObjectComm((PetscObject)P), PETSC_ERR_ORDER,
             "The stencil view is set once, before the first assembly");
  PetscCall(PetscFree(rec->kl));
  rec->stencil = st;
  PetscFunctionReturn(0);
}
