/* The bond loop: internal forces and the tangent. Both the residual and the Jacobian use it, and so
   will the explicit path. Per bond the scalar force g and the tangent scalars are evaluated once per
   rank; rows of the stiffness are then gathered from them node by node. */
#include "pd_model.h"

/* Geometry of one bond in the current configuration. Small kinematics: s = xi.eta/|xi|^2 along
   e = xi/|xi| (the linearised micromodulus of Eq. 4.13). Finite: s = (|y| - |xi|)/|xi| along y/|y|. */
static inline void BondState(PDKinematics kin, PetscInt dim, const PetscReal *xi_pos, const PetscReal *xj_pos, const PetscScalar *ui,
                             const PetscScalar *uj, PetscReal e[3], PetscReal *len0, PetscReal *len, PetscReal *s)
{
  PetscReal xi[3] = {0, 0, 0}, eta[3] = {0, 0, 0}, L2 = 0;
  for (PetscInt a = 0; a < dim; a++) {
    xi[a]  = xj_pos[a] - xi_pos[a];
    eta[a] = PetscRealPart(uj[a] - ui[a]);
    L2 += xi[a] * xi[a];
  }
  *len0 = PetscSqrtReal(L2);
  if (kin == PD_KINEMATICS_SMALL) {
    PetscReal dot = 0;
    for (PetscInt a = 0; a < dim; a++) {
      dot += xi[a] * eta[a];
      e[a] = xi[a] / *len0;
    }
    *s   = dot / L2;
    *len = *len0;
  } else {
    PetscReal y2 = 0;
    for (PetscInt a = 0; a < dim; a++) y2 += (xi[a] + eta[a]) * (xi[a] + eta[a]);
    *len = PetscSqrtReal(y2);
    for (PetscInt a = 0; a < dim; a++) e[a] = (xi[a] + eta[a]) / *len;
    *s = (*len - *len0) / *len0;
  }
}

PetscErrorCode PDModelInternalForceLocal(PDModel *m, const PetscScalar *u, PetscScalar *f)
{
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscInt   bs  = m->bs;

  PetscFunctionBeginUser;
  PetscCall(PetscArrayzero(f, bs * lat->nlocal));
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt i = bd->a[e], j = bd->b[e];
    PetscReal      dir[3], L0, L, s, g;
    BondState(m->scene->kinematics, bs, &lat->x[3 * i], &lat->x[3 * j], &u[bs * i], &u[bs * j], dir, &L0, &L, &s);
    g = bd->coef[e] * s;
    for (PetscInt a = 0; a < bs; a++) {
      f[bs * i + a] -= g * dir[a];
      f[bs * j + a] += g * dir[a];
    }
  }
  PetscCall(PetscLogFlops(20.0 * bd->nbonds));
  PetscFunctionReturn(0);
}

/* Tangent scalars of each bond: block = ka e e^T + kb I (THEORY.md Sec. 4: ka = g'/|xi| - g/|y|, kb = g/|y|). */
PetscErrorCode PDModelTangentScalars(PDModel *m, const PetscScalar *u, PetscReal *ka, PetscReal *kb)
{
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscInt   bs  = m->bs;

  PetscFunctionBeginUser;
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt i = bd->a[e], j = bd->b[e];
    PetscReal      dir[3], L0, L, s;
    BondState(m->scene->kinematics, bs, &lat->x[3 * i], &lat->x[3 * j], &u[bs * i], &u[bs * j], dir, &L0, &L, &s);
    if (m->scene->kinematics == PD_KINEMATICS_SMALL) {
      ka[e] = bd->coef[e] / L0;
      kb[e] = 0;
    } else {
      const PetscReal g = bd->coef[e] * s;
      ka[e]             = bd->coef[e] / L0 - g / L;
      kb[e]             = g / L;
    }
  }
  PetscFunctionReturn(0);
}

/* Gathers one stiffness row per owned node from the bond scalars. Constrained dofs are eliminated
   symmetrically: their rows and columns are zero but for bc_scale on the diagonal. */
PetscErrorCode PDModelAssembleRows(PDModel *m, const PetscScalar *u, const PetscReal *ka, const PetscReal *kb, Mat J)
{
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscInt   bs = m->bs, bs2 = bs * bs;
  PetscInt         maxrow = 0, *cols;
  PetscScalar     *vals;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < lat->nowned; i++) maxrow = PetscMax(maxrow, bd->inc_start[i + 1] - bd->inc_start[i] + 1);
  PetscCall(PetscMalloc2(maxrow, &cols, maxrow * bs2, &vals));
  for (PetscInt i = 0; i < lat->nowned; i++) {
    const PetscInt s = bd->inc_start[i], n = bd->inc_start[i + 1] - s, ncols = n + 1, ld = ncols * bs;
    PetscInt       diag = n, c = 0;
    PetscReal      D[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (PetscInt p = 0; p < n; p++) {
      const PetscInt e = bd->inc_bond[s + p], j = bd->a[e] == i ? bd->b[e] : bd->a[e];
      PetscReal      dir[3], L0, L, st, K[9], a, b;
      if (diag == n && lat->gid[j] > lat->gid[i]) diag = c++;
      BondState(m->scene->kinematics, bs, &lat->x[3 * i], &lat->x[3 * j], &u[bs * i], &u[bs * j], dir, &L0, &L, &st);
      /* without per-bond scalars the tangent is the constant linearised micromodulus */
      a = ka ? ka[e] : bd->coef[e] / L0;
      b = kb ? kb[e] : 0;
      for (PetscInt r = 0; r < bs; r++)
        for (PetscInt q = 0; q < bs; q++) {
          K[r * bs + q] = a * dir[r] * dir[q] + (r == q ? b : 0);
          D[r * bs + q] += K[r * bs + q];
        }
      cols[c] = lat->gid[j];
      for (PetscInt r = 0; r < bs; r++)
        for (PetscInt q = 0; q < bs; q++) {
          const PetscBool zero = m->fixed_local[bs * i + r] || m->fixed_local[bs * j + q];
          vals[r * ld + c * bs + q] = zero ? 0 : -K[r * bs + q];
        }
      c++;
    }
    if (diag == n) diag = c;
    cols[diag] = lat->gid[i];
    for (PetscInt r = 0; r < bs; r++)
      for (PetscInt q = 0; q < bs; q++) {
        const PetscBool fr = m->fixed_local[bs * i + r], fq = m->fixed_local[bs * i + q];
        vals[r * ld + diag * bs + q] = (fr || fq) ? (r == q ? m->bc_scale : 0) : D[r * bs + q];
      }
    PetscCall(MatSetValuesBlocked(J, 1, &lat->gid[i], ncols, cols, vals, INSERT_VALUES));
  }
  PetscCall(PetscFree2(cols, vals));
  PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}
