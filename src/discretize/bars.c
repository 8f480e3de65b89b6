/* Steel bar segments on the lattice (docs/reinforcement.md). A bar's line is laid on the nearest line of
   nodes along its axis; each pair of consecutive nodes on it within the bar's extent is a segment, an
   axial member of stiffness E A_s and yield force f_y A_s exactly, whatever dx. */
#include "pd_lattice.h"

/* The node line of bar b: the nearest node indices across its axis (line[a] for a != axis), and the first
   and last node index along it within the bar's ends. */
static void NodeLine(const PDLattice *lat, const PDBar *b, PetscInt line[3], PetscInt *first, PetscInt *last) {
  const PetscInt  a  = b->axis;
  const PetscReal lo = (PetscMin(b->line[a], b->line[3 + a]) - lat->origin[a]) / lat->dx;
  const PetscReal hi = (PetscMax(b->line[a], b->line[3 + a]) - lat->origin[a]) / lat->dx;
  for (PetscInt c = 0; c < 3; c++) {
    const PetscInt near = (PetscInt)PetscFloorReal((b->line[c] - lat->origin[c]) / lat->dx + 0.5);
    line[c]             = c < lat->dim ? PetscMin(PetscMax(near, 0), lat->n[c] - 1) : 0;
  }
  *first = PetscMax(0, (PetscInt)PetscCeilReal(lo - 1e-9));
  *last  = PetscMin(lat->n[a] - 1, (PetscInt)PetscFloorReal(hi + 1e-9));
}

/* Whether bar b's line holds the lattice node ijk within the bar's ends. */
static PetscBool Holds(const PDLattice *lat, const PDBar *b, const PetscInt ijk[3]) {
  PetscInt  line[3], first, last;
  PetscBool on = PETSC_TRUE;
  NodeLine(lat, b, line, &first, &last);
  for (PetscInt c = 0; c < 3 && on; c++) on = c == b->axis ? (ijk[c] >= first && ijk[c] <= last) : ijk[c] == line[c];
  return on;
}

PetscInt PDBarOfPair(const PDScene *sc, const PDLattice *lat, PetscInt gi, PetscInt gj) {
  PetscInt p[3], q[3];

  if (!sc->nbars) return -1;
  PDLatticeNodeIndices(lat, gi, p);
  PDLatticeNodeIndices(lat, gj, q);
  for (PetscInt k = 0; k < sc->nbars; k++) {
    const PDBar *b = &sc->bar[k];
    if (PetscAbsInt(p[b->axis] - q[b->axis]) == 1 && Holds(lat, b, p) && Holds(lat, b, q)) return k;
  }
  return -1;
}

PetscInt PDBarHoldingNode(const PDScene *sc, const PDLattice *lat, PetscInt gid) {
  PetscInt p[3];

  PDLatticeNodeIndices(lat, gid, p);
  for (PetscInt k = 0; k < sc->nbars; k++)
    if (Holds(lat, &sc->bar[k], p)) return k;
  return -1;
}

PetscErrorCode PDBondsSetUpBars(const PDScene *sc, const PDLattice *lat, PDBonds *bd) {
  PetscInt mine = 0, n = 0;

  PetscFunctionBeginUser;
  if (!sc->nbars) PetscFunctionReturn(0);
  /* two bars sharing a pair of nodes would give it two segments: one bar with both areas is what is meant */
  for (PetscInt k = 0; k < sc->nbars; k++) {
    const PDBar *b = &sc->bar[k];
    PetscInt     lb[3], fb, eb;
    NodeLine(lat, b, lb, &fb, &eb);
    PetscCheck(eb > fb, lat->comm, PETSC_ERR_USER_INPUT, "Option %s_line: the bar holds no two nodes of the lattice (dx = %g m)", b->option,
               (double)lat->dx);
    for (PetscInt l = 0; l < k; l++) {
      const PDBar *c = &sc->bar[l];
      PetscInt     lc[3], fc, ec;
      PetscBool    same = b->axis == c->axis ? PETSC_TRUE : PETSC_FALSE;
      NodeLine(lat, c, lc, &fc, &ec);
      for (PetscInt a = 0; a < 3 && same; a++)
        if (a != b->axis) same = lb[a] == lc[a] ? PETSC_TRUE : PETSC_FALSE;
      PetscCheck(!same || PetscMax(fb, fc) >= PetscMin(eb, ec), lat->comm, PETSC_ERR_USER_INPUT,
                 "Options %s_line and %s_line: the two bars lie on one line of nodes and overlap; give one bar with _count, or move one "
                 "by at least dx = %g m",
                 b->option, c->option, (double)lat->dx);
    }
  }
  /* the bar of each bond (or -1) in seg first, then its segment index */
  PetscCall(PetscMalloc1(PetscMax(1, bd->nbonds), &bd->seg));
  for (PetscInt e = 0; e < bd->nbonds; e++)
    if ((bd->seg[e] = PDBarOfPair(sc, lat, lat->gid[bd->a[e]], lat->gid[bd->b[e]])) >= 0) n++;
  bd->nseg = n;
  PetscCall(PetscMalloc3(PetscMax(1, n), &bd->seg_bond, PetscMax(1, n), &bd->seg_bar, PetscMax(1, n), &bd->seg_coef));
  n = 0;
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt k = bd->seg[e];
    if (k < 0) continue;
    bd->seg[e]      = n;
    bd->seg_bond[n] = e;
    bd->seg_bar[n]  = k;
    bd->seg_coef[n] = sc->bar[k].E * PDBarArea(&sc->bar[k]);
    if (PDBondCountedHere(lat, bd, e)) mine++;
    n++;
  }
  PetscCall(MPIU_Allreduce(&mine, &bd->nseg_global, 1, MPIU_INT, MPI_SUM, lat->comm));
  PetscFunctionReturn(0);
}
