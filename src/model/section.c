/* A section cut (-pd_section_x): the forces that the bonds crossing a plane normal to x carry, split into
   the bars' and the concrete's in tension and in compression. The plane lies halfway between two node
   columns, so each crossing bond is cut once; by equilibrium of the part before the plane their sum is the
   reaction on that part, and their moment the bending moment there (docs/reinforcement.md, Section forces). */
#include "kernel.h"

/* This rank's bonds whose ends lie on both sides of the plane, each counted once (a bond with a ghost end is
   held by two ranks): fixed by the reference configuration, so found once. */
static PetscErrorCode CrossingBonds(PDModel *m) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscReal  X   = m->scene->section_x;

  PetscFunctionBeginUser;
  for (PetscInt pass = 0; pass < 2; pass++) { /* count, then fill */
    PetscInt n = 0;
    for (PetscInt e = 0; e < bd->nbonds; e++)
      if ((lat->x[3 * bd->a[e]] - X) * (lat->x[3 * bd->b[e]] - X) < 0 && PDBondCountedHere(lat, bd, e)) {
        if (pass) m->section_bonds[n] = e;
        n++;
      }
    if (!pass) PetscCall(PetscMalloc1(PetscMax(1, n), &m->section_bonds));
    m->nsection = n;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode PDModelSection(PDModel *m, Vec u, PetscReal out[PD_SECTION_N]) {
  const PetscScalar *ul;
  Vec                loc;
  PetscReal          mine[PD_SECTION_N];

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < PD_SECTION_N; k++) out[k] = 0;
  if (!m->scene->has_section) PetscFunctionReturn(0);
  if (!m->section_bonds) PetscCall(CrossingBonds(m));
  PetscCall(PDModelScatterToLocal(m, u, &ul, &loc));
  PDModelSectionLocal(m, ul, mine);
  PetscCall(PDModelRestoreLocal(m, &ul, &loc));
  PetscCall(MPIU_Allreduce(mine, out, PD_SECTION_N, MPIU_REAL, MPIU_SUM, m->lat->comm));
  /* moments to the heights at which the resultants act (none where nothing acts) */
  for (PetscInt k = PD_SECTION_STEEL; k <= PD_SECTION_COMPRESSION; k++) {
    const PetscInt y = k + PD_SECTION_STEEL_Y - PD_SECTION_STEEL;
    out[y]           = out[k] != 0 ? out[y] / out[k] : 0;
  }
  PetscFunctionReturn(0);
}
