/* Whether the bonds hold the body together. Notches and voids can cut a piece off (two notches that meet,
   a notch ending a hair short of a face, a void across a section); a piece without supports is a
   rigid-body mechanism, and a load on it "completes" with nonsense. So the parts of the bond graph are
   counted before anything is solved: each rank joins its nodes along its bonds (union-find over owned and
   ghost nodes), every node takes the smallest global id of its part, and owners and ghosts exchange
   labels (VecGhostUpdate with MIN_VALUES) until no label changes; a slab partition needs about one round
   per rank. Nodes without any bond (cut out whole, or in a void) are pinned elsewhere and not counted. */
#include "pd_lattice.h"

static PetscInt Root(PetscInt *parent, PetscInt i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i         = parent[i];
  }
  return i;
}

/* Smallest global id of each node's part, over the bonds this rank holds, then across ranks. */
static PetscErrorCode LabelParts(const PDLattice *lat, const PDBonds *bd, Vec label) {
  PetscInt    *parent;
  PetscReal   *low;
  PetscScalar *l;
  Vec          loc;
  PetscBool    changed = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(lat->nlocal, &parent, lat->nlocal, &low));
  for (PetscInt i = 0; i < lat->nlocal; i++) parent[i] = i;
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt ra = Root(parent, bd->a[e]), rb = Root(parent, bd->b[e]);
    if (ra != rb) parent[PetscMax(ra, rb)] = PetscMin(ra, rb);
  }
  PetscCall(VecGhostGetLocalForm(label, &loc));
  PetscCall(VecGetArray(loc, &l));
  for (PetscInt i = 0; i < lat->nlocal; i++) l[i] = (PetscReal)lat->gid[i];
  PetscCall(VecRestoreArray(loc, &l));
  while (changed) {
    PetscBool mine = PETSC_FALSE;
    PetscCall(VecGetArray(loc, &l));
    for (PetscInt i = 0; i < lat->nlocal; i++) low[i] = PETSC_MAX_REAL;
    for (PetscInt i = 0; i < lat->nlocal; i++) low[Root(parent, i)] = PetscMin(low[Root(parent, i)], PetscRealPart(l[i]));
    for (PetscInt i = 0; i < lat->nlocal; i++) {
      const PetscReal v = low[Root(parent, i)];
      if (v < PetscRealPart(l[i])) {
        l[i] = v;
        mine = PETSC_TRUE;
      }
    }
    PetscCall(VecRestoreArray(loc, &l));
    /* owners take the smallest label any rank gave their node, then ghosts take the owners' */
    PetscCall(VecGhostUpdateBegin(label, MIN_VALUES, SCATTER_REVERSE));
    PetscCall(VecGhostUpdateEnd(label, MIN_VALUES, SCATTER_REVERSE));
    PetscCall(VecGhostUpdateBegin(label, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecGhostUpdateEnd(label, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(MPIU_Allreduce(&mine, &changed, 1, MPIU_BOOL, MPI_LOR, lat->comm));
  }
  PetscCall(VecGhostRestoreLocalForm(label, &loc));
  PetscCall(PetscFree2(parent, low));
  PetscFunctionReturn(0);
}

PetscErrorCode PDBondsCountParts(const PDLattice *lat, const PDBonds *bd, PetscInt *nparts, PetscInt first[2]) {
  Vec                label;
  const PetscScalar *l;
  PetscInt           mine = 0, lowest[2] = {PETSC_MAX_INT, PETSC_MAX_INT}, all[2];

  PetscFunctionBeginUser;
  PetscCall(PDLatticeCreateGhostVec(lat, 1, &label));
  PetscCall(LabelParts(lat, bd, label));
  PetscCall(VecGetArrayRead(label, &l));
  /* a part is counted once, by its lowest node, where that node is owned and has a bond */
  for (PetscInt i = 0; i < lat->nowned; i++) {
    if (bd->inc_start[i + 1] == bd->inc_start[i] || PetscRealPart(l[i]) != (PetscReal)lat->gid[i]) continue;
    mine++;
    if (lat->gid[i] < lowest[0]) {
      lowest[1] = lowest[0];
      lowest[0] = lat->gid[i];
    } else if (lat->gid[i] < lowest[1])
      lowest[1] = lat->gid[i];
  }
  PetscCall(VecRestoreArrayRead(label, &l));
  PetscCall(VecDestroy(&label));
  PetscCall(MPIU_Allreduce(&mine, nparts, 1, MPIU_INT, MPI_SUM, lat->comm));
  /* the two lowest representatives: the lowest of all, then the lowest of the others */
  PetscCall(MPIU_Allreduce(&lowest[0], &all[0], 1, MPIU_INT, MPI_MIN, lat->comm));
  mine = lowest[0] == all[0] ? lowest[1] : lowest[0];
  PetscCall(MPIU_Allreduce(&mine, &all[1], 1, MPIU_INT, MPI_MIN, lat->comm));
  first[0] = all[0];
  first[1] = all[1];
  PetscFunctionReturn(0);
}
