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
      if (PDGeometryContains(&sc->material[m].where, &lat->x[3 * l], sc->dx, sc->dim)) {
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

/* Nearest lattice node to a point; ties go to the lower index so every rank agrees. */
PetscInt PDLatticeNearestNode(const PDLattice *lat, const PetscReal p[3]) {
  PetscInt idx[3] = {0, 0, 0};
  for (PetscInt a = 0; a < lat->dim; a++) {
    const PetscReal f = (p[a] - lat->origin[a]) / lat->dx;
    idx[a]            = (PetscInt)PetscCeilReal(f - 0.5 - 1e-9);
    idx[a]            = PetscMin(PetscMax(idx[a], 0), lat->n[a] - 1);
  }
  return (idx[0] * lat->n[1] + idx[1]) * lat->n[2] + idx[2];
}
