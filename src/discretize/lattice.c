/* The regular lattice: sizes, slab partition over ranks, owned and ghost nodes, materials. */
#include "pd_lattice.h"

static PetscInt LayerStart(PetscInt nx, PetscMPIInt size, PetscMPIInt rank) {
  return (PetscInt)(((PetscInt64)nx * rank) / size);
}

static void NodePosition(const PDLattice *lat, PetscInt gid, PetscReal x[3]) {
  const PetscInt k = gid % lat->n[2], j = (gid / lat->n[2]) % lat->n[1], i = gid / (lat->n[1] * lat->n[2]);
  x[0] = lat->origin[0] + i * lat->dx;
  x[1] = lat->origin[1] + j * lat->dx;
  x[2] = lat->dim == 3 ? lat->origin[2] + k * lat->dx : 0;
}

PetscErrorCode PDLatticeCreate(MPI_Comm comm, const PDScene *sc, PDLattice *lat) {
  PetscMPIInt size, rank;
  PetscInt    layer, R, g0, g1, g2, g3;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(lat, sizeof *lat));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  lat->comm        = comm;
  lat->dim         = sc->dim;
  lat->dx          = sc->dx;
  lat->horizon     = sc->horizon_ratio * sc->dx;
  lat->cell_volume = sc->dim == 3 ? sc->dx * sc->dx * sc->dx : sc->dx * sc->dx * sc->thickness;
  for (PetscInt a = 0; a < 3; a++) {
    const PetscReal len = sc->domain[3 + a] - sc->domain[a];
    lat->n[a]           = a < sc->dim ? PetscMax(1, (PetscInt)PetscFloorReal(len / sc->dx + 0.5)) : 1;
    /* when dx does not divide the box, the lattice is centred in it */
    lat->origin[a] = a < sc->dim ? sc->domain[a] + 0.5 * (len - lat->n[a] * sc->dx) + 0.5 * sc->dx : 0;
  }
  PetscCheck((PetscInt64)lat->n[0] * lat->n[1] * lat->n[2] < PETSC_MAX_INT / 3, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_dx: %g gives too many nodes for 32-bit indices", (double)sc->dx);
  PetscCheck(lat->n[0] >= size, comm, PETSC_ERR_USER_INPUT, "Option -pd_dx: %" PetscInt_FMT " layers along x cannot be shared by %d ranks",
             lat->n[0], size);
  lat->nglobal     = lat->n[0] * lat->n[1] * lat->n[2];
  layer            = lat->n[1] * lat->n[2];
  lat->layer_start = LayerStart(lat->n[0], size, rank);
  lat->layer_end   = LayerStart(lat->n[0], size, rank + 1);
  lat->nowned      = (lat->layer_end - lat->layer_start) * layer;
  lat->gid_start   = lat->layer_start * layer;
  /* ghosts: every node within one horizon, i.e. the R nearest layers on either side */
  R           = (PetscInt)PetscFloorReal(sc->horizon_ratio * (1 + 1e-10));
  g0          = PetscMax(0, lat->layer_start - R) * layer;
  g1          = lat->layer_start * layer;
  g2          = lat->layer_end * layer;
  g3          = PetscMin(lat->n[0], lat->layer_end + R) * layer;
  lat->nghost = (g1 - g0) + (g3 - g2);
  lat->nlocal = lat->nowned + lat->nghost;
  PetscCall(PetscMalloc3(lat->nlocal, &lat->gid, 3 * lat->nlocal, &lat->x, lat->nlocal, &lat->material));
  {
    PetscInt l = 0;
    for (PetscInt g = g1; g < g2; g++) lat->gid[l++] = g;
    for (PetscInt g = g0; g < g1; g++) lat->gid[l++] = g;
    for (PetscInt g = g2; g < g3; g++) lat->gid[l++] = g;
  }
  for (PetscInt l = 0; l < lat->nlocal; l++) {
    NodePosition(lat, lat->gid[l], &lat->x[3 * l]);
    lat->material[l] = 0;
    for (PetscInt m = sc->nmaterials - 1; m > 0; m--)
      if (PDGeometryContains(&sc->material[m].where, &lat->x[3 * l], sc)) {
        lat->material[l] = m;
        break;
      }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode PDLatticeDestroy(PDLattice *lat) {
  PetscFunctionBeginUser;
  PetscCall(PetscFree3(lat->gid, lat->x, lat->material));
  PetscFunctionReturn(0);
}

PetscErrorCode PDLatticeCreateGhostVec(const PDLattice *lat, PetscInt bs, Vec *v) {
  PetscFunctionBeginUser;
  PetscCall(VecCreateGhostBlock(lat->comm, bs, bs * lat->nowned, PETSC_DECIDE, lat->nghost, lat->gid + lat->nowned, v));
  PetscCall(VecSetBlockSize(*v, bs));
  PetscFunctionReturn(0);
}

/* Nodes and weights that interpolate a nodal field linearly at p (extrapolating within the outer half
   cell); the same on every rank. */
void PDLatticeInterpolation(const PDLattice *lat, const PetscReal p[3], PetscInt gid[8], PetscReal w[8], PetscInt *n) {
  PetscInt  i0[3] = {0, 0, 0}, m[3] = {1, 1, 1};
  PetscReal t[3] = {0, 0, 0};

  for (PetscInt a = 0; a < lat->dim; a++) {
    const PetscReal f = (p[a] - lat->origin[a]) / lat->dx;
    if (lat->n[a] == 1) continue;
    i0[a] = PetscMin(PetscMax((PetscInt)PetscFloorReal(f + 1e-12), 0), lat->n[a] - 2);
    t[a]  = f - i0[a];
    if (PetscAbsReal(t[a]) < 1e-12) t[a] = 0;
    m[a] = t[a] == 0 ? 1 : 2; /* on a node layer: one layer is enough */
  }
  *n = 0;
  for (PetscInt i = 0; i < m[0]; i++)
    for (PetscInt j = 0; j < m[1]; j++)
      for (PetscInt k = 0; k < m[2]; k++) {
        gid[*n] = ((i0[0] + i) * lat->n[1] + i0[1] + j) * lat->n[2] + i0[2] + k;
        w[*n]   = (i ? t[0] : 1 - t[0]) * (j ? t[1] : 1 - t[1]) * (k ? t[2] : 1 - t[2]);
        (*n)++;
      }
}
