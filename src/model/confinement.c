/* Crushing through confinement (-pd_fc, docs/softening.md "Compression"). A bond-based lattice in uniaxial
   compression fails when the bonds across the load soften in tension, at |sigma| = E s0 / nu, about three
   times ft: far below the compressive strength of concrete. Compression raises the tensile strength of the
   bonds across it, as in Silling and Askari's s0 - alpha s_min (2005), here through the dilatation of the
   bond's two nodes so that a uniform compression raises every bond of a node alike. The rise follows the
   committed state (an accepted step, or every tenth explicit step) and applies to the next increments. */
#include "pd_model.h"
#include "kernel.h"

/* Dilatation of each owned node, theta = dim sum w s / sum w over its bonds with w = c |xi|^2: for a
   homogeneous strain eps, the mean of s = n.eps.n over a symmetric family is tr(eps) / dim. Ghosts by
   the ghosted vector. */
PetscErrorCode PDModelNodalDilatation(PDModel *m, const PetscScalar *u) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  PetscScalar     *th;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(m->dilatation, &th));
  for (PetscInt i = 0; i < lat->nowned; i++) {
    PetscReal num = 0, den = 0;
    for (PetscInt p = bd->inc_start[i]; p < bd->inc_start[i + 1]; p++) {
      const PetscInt   e  = bd->inc_bond[p];
      const PetscReal *xa = &lat->x[3 * bd->a[e]], *xb = &lat->x[3 * bd->b[e]];
      PetscReal        w = 0;
      for (PetscInt a = 0; a < 3; a++) w += (xb[a] - xa[a]) * (xb[a] - xa[a]);
      w *= bd->coef[e];
      num += w * PDModelBondStretch(m, u, e);
      den += w;
    }
    th[i] = den > 0 ? lat->dim * num / den : 0;
  }
  PetscCall(VecRestoreArray(m->dilatation, &th));
  PetscCall(VecGhostUpdateBegin(m->dilatation, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(m->dilatation, INSERT_VALUES, SCATTER_FORWARD));
  PetscFunctionReturn(0);
}

/* From the dilatations of the last PDModelStrainState. */
PetscErrorCode PDModelConfine(PDModel *m) {
  const PDBonds     *bd = m->bonds;
  Vec                loc;
  const PetscScalar *th;

  PetscFunctionBeginUser;
  if (!m->shift) PetscFunctionReturn(0);
  PetscCall(VecGhostGetLocalForm(m->dilatation, &loc));
  PetscCall(VecGetArrayRead(loc, &th));
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PDLaw    *law  = &m->law[bd->material[e]];
    const PetscReal rise = law->confine * PetscMax(0, -0.5 * PetscRealPart(th[bd->a[e]] + th[bd->b[e]]));
    /* only a bond that has not begun to soften: raising the thresholds of a softened one would heal it */
    if (law->confine == 0 || rise <= m->shift[e] || m->kappa[e] >= PDModelBondThresholds(m, e, law).s0) continue;
    m->shift[e] = rise; /* the bond's thresholds are its unconfined ones raised by it */
  }
  PetscCall(VecRestoreArrayRead(loc, &th));
  PetscCall(VecGhostRestoreLocalForm(m->dilatation, &loc));
  PetscFunctionReturn(0);
}
