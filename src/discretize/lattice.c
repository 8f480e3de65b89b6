/* The regular lattice: sizes, slab partition over ranks, owned and ghost nodes, materials, and the
   stencil of lattice offsets that makes up a node's bond family. */
#include "pd_lattice.h"

PDFamilyMember PDFamilyRule(PetscReal m, PetscInt n2) {
  const PetscReal m2 = m * m, d = (PetscReal)n2 - m2;

  if (PetscAbsReal(d) <= 4 * PETSC_MACHINE_EPSILON * m2) return PD_FAMILY_EDGE;
  return d < 0 ? PD_FAMILY_IN : PD_FAMILY_OUT;
}

PetscReal PDFamilyPartialVolume(PetscReal m, PetscInt n2, PetscBool partial_volume) {
  PetscReal r;

  if (!partial_volume) return 1;
  if (PDFamilyRule(m, n2) == PD_FAMILY_EDGE) return 0.5;
  r = PetscSqrtReal((PetscReal)n2);
  return r <= m - 0.5 ? 1 : m + 0.5 - r;
}

PetscBool PDFamilyNext(PetscReal m, PetscInt dim, PetscInt st[4]) {
  const PetscInt R = (PetscInt)PetscFloorReal(m) + 1, Rz = dim == 3 ? R : 0;

  if (st[3] < 0) { /* start: one before the first offset */
    st[0] = -R;
    st[1] = -R;
    st[2] = -Rz - 1;
  }
  for (;;) {
    if (++st[2] > Rz) {
      st[2] = -Rz;
      if (++st[1] > R) {
        st[1] = -R;
        if (++st[0] > R) return PETSC_FALSE;
      }
    }
    st[3] = st[0] * st[0] + st[1] * st[1] + st[2] * st[2];
    if (st[3] > 0 && PDFamilyRule(m, st[3]) != PD_FAMILY_OUT) return PETSC_TRUE;
  }
}

/* Offsets (di, dj, dk) of the bond family, dk = 0 in 2D, in lexicographic order, and the reach along
   one axis. Built once; the neighbour search walks it from every node. */
static PetscErrorCode BuildStencil(PDLattice *lat, PetscReal m) {
  const PetscInt R = (PetscInt)PetscFloorReal(m) + 1, Rz = lat->dim == 3 ? R : 0;
  PetscInt       st[4] = {0, 0, 0, -1};

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(4 * (2 * R + 1) * (2 * R + 1) * (2 * Rz + 1), &lat->stencil));
  while (PDFamilyNext(m, lat->dim, st)) {
    for (PetscInt c = 0; c < 4; c++) lat->stencil[4 * lat->nstencil + c] = st[c];
    lat->reach = PetscMax(lat->reach, st[0]);
    lat->nstencil++;
  }
  PetscFunctionReturn(0);
}

void PDLatticeNodeIndices(const PDLattice *lat, PetscInt gid, PetscInt ijk[3]) {
  const PetscInt r = gid % lat->layer;

  ijk[0] = gid / lat->layer;
  if (r >= lat->n[1] * lat->n[2]) { /* a slot: the bar node's shadow, or the layer's first node for an unused one */
    const PetscInt b = lat->slot_node[ijk[0] * lat->nslot + r - lat->n[1] * lat->n[2]];
    for (PetscInt c = 0; c < 3; c++) ijk[c] = b >= 0 ? lat->bn_ijk[3 * b + c] : (c ? 0 : ijk[0]);
    return;
  }
  ijk[2] = r % lat->n[2];
  ijk[1] = r / lat->n[2];
}

static PetscInt LayerStart(PetscInt nx, PetscMPIInt size, PetscMPIInt rank) {
  return (PetscInt)(((PetscInt64)nx * rank) / size);
}

static void NodePosition(const PDLattice *lat, PetscInt gid, PetscReal x[3]) {
  PetscInt ijk[3];

  PDLatticeNodeIndices(lat, gid, ijk);
  PDLatticePlace(lat, ijk, x);
}

/* The ghost ranges: global ids [g[0], g[1]) below the owned slab and [g[2], g[3]) above it. */
static void GhostRanges(const PDLattice *lat, PetscInt g[4]) {
  const PetscInt layer = lat->layer;

  g[0] = PetscMax(0, lat->layer_start - lat->reach) * layer;
  g[1] = lat->layer_start * layer;
  g[2] = lat->layer_end * layer;
  g[3] = PetscMin(lat->n[0], lat->layer_end + lat->reach) * layer;
}

PetscInt PDLatticeLocalIndex(const PDLattice *lat, PetscInt gid) {
  PetscInt g[4];

  GhostRanges(lat, g);
  if (gid >= g[1] && gid < g[2]) return gid - g[1];
  if (gid >= g[0] && gid < g[1]) return lat->nowned + gid - g[0];
  if (gid >= g[2] && gid < g[3]) return lat->nowned + (g[1] - g[0]) + gid - g[2];
  return -1;
}

PetscInt PDLatticeOffset(const PDLattice *lat, PetscInt k, PetscInt l, PetscInt d[3]) {
  PetscInt a[3], b[3];

  PDLatticeNodeIndices(lat, lat->gid[k], a);
  PDLatticeNodeIndices(lat, lat->gid[l], b);
  for (PetscInt c = 0; c < 3; c++) d[c] = b[c] - a[c];
  return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

PetscErrorCode PDLatticeCreate(MPI_Comm comm, const PDScene *sc, PDLattice *lat) {
  PetscMPIInt size, rank;
  PetscInt    layer, g[4], nvoid = 0, invoid_mine[PD_MAX_VOIDS] = {0}, invoid[PD_MAX_VOIDS];
  PetscInt    innofail_mine[PD_MAX_NOFAIL]   = {0}, innofail[PD_MAX_NOFAIL];
  PetscInt    inplate_mine[PD_MAX_MATERIALS] = {0}, inplate[PD_MAX_MATERIALS];

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
    lat->origin[a] = 0;
    lat->n[a]      = a < sc->dim ? PDSceneLayers(sc, a, &lat->origin[a]) : 1;
  }
  PetscCall(PDLatticeSetUpBarNodes(sc, lat));
  lat->layer   = lat->n[1] * lat->n[2] + lat->nslot;
  lat->nunused = lat->n[0] * lat->nslot - lat->nbarnodes; /* every layer has nslot slots */
  PetscCheck((PetscInt64)lat->n[0] * lat->layer < PETSC_MAX_INT / 3, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_dx: %g gives too many nodes for 32-bit indices", (double)sc->dx);
  PetscCheck(lat->n[0] >= size, comm, PETSC_ERR_USER_INPUT, "Option -pd_dx: %" PetscInt_FMT " layers along x cannot be shared by %d ranks",
             lat->n[0], size);
  lat->nglobal     = lat->n[0] * lat->layer;
  layer            = lat->layer;
  lat->layer_start = LayerStart(lat->n[0], size, rank);
  lat->layer_end   = LayerStart(lat->n[0], size, rank + 1);
  lat->nowned      = (lat->layer_end - lat->layer_start) * layer;
  lat->gid_start   = lat->layer_start * layer;
  /* ghosts: every node within one horizon, i.e. the reach nearest layers on either side */
  PetscCall(BuildStencil(lat, sc->horizon_ratio));
  GhostRanges(lat, g);
  lat->nghost = (g[1] - g[0]) + (g[3] - g[2]);
  lat->nlocal = lat->nowned + lat->nghost;
  PetscCall(PetscMalloc5(lat->nlocal, &lat->gid, 3 * lat->nlocal, &lat->x, lat->nlocal, &lat->material, lat->nlocal, &lat->hollow,
                         lat->nlocal, &lat->nofail));
  if (lat->nslot) PetscCall(PetscMalloc1(lat->nlocal, &lat->barnode));
  for (PetscInt id = g[0]; id < g[3]; id++) {
    const PetscInt l = PDLatticeLocalIndex(lat, id);
    lat->gid[l]      = id;
  }
  for (PetscInt l = 0; l < lat->nlocal; l++) {
    const PetscInt r = lat->gid[l] % layer - lat->n[1] * lat->n[2];
    NodePosition(lat, lat->gid[l], &lat->x[3 * l]);
    lat->material[l] = 0;
    if (lat->barnode) lat->barnode[l] = r >= 0 ? lat->slot_node[(lat->gid[l] / layer) * lat->nslot + r] : -1;
    if (r >= 0) { /* a slot: a bar node, steel only, or hollow */
      lat->hollow[l] = lat->barnode[l] < 0 ? PETSC_TRUE : PETSC_FALSE;
      for (PetscInt a = 0; a < 3 && !lat->hollow[l]; a++) lat->x[3 * l + a] += lat->bn_shift[3 * lat->barnode[l] + a];
      lat->nofail[l] = PETSC_FALSE;
      continue;
    }
    for (PetscInt m = sc->nmaterials + sc->nplates - 1; m > 0; m--) /* plates over materials, later over earlier */
      if (PDGeometryContains(&sc->material[m].where, &lat->x[3 * l], sc)) {
        lat->material[l] = m;
        break;
      }
    lat->hollow[l] = PETSC_FALSE;
    for (PetscInt v = 0; v < sc->nvoids; v++)
      if (PDGeometryContains(&sc->voids[v].where, &lat->x[3 * l], sc)) {
        lat->hollow[l] = PETSC_TRUE;
        if (l < lat->nowned) invoid_mine[v]++;
      }
    if (l < lat->nowned && lat->hollow[l]) nvoid++;
    lat->nofail[l] = lat->material[l] >= sc->nmaterials ? PETSC_TRUE : PETSC_FALSE; /* a plate's bonds never damage */
    if (l < lat->nowned && lat->nofail[l]) inplate_mine[lat->material[l] - sc->nmaterials]++;
    for (PetscInt v = 0; v < sc->nnofail; v++)
      if (PDGeometryContains(&sc->nofail[v].where, &lat->x[3 * l], sc)) {
        lat->nofail[l] = PETSC_TRUE;
        if (l < lat->nowned) innofail_mine[v]++;
      }
  }
  PetscCall(MPIU_Allreduce(&nvoid, &lat->nvoid, 1, MPIU_INT, MPI_SUM, comm));
  PetscCall(MPIU_Allreduce(invoid_mine, invoid, PD_MAX_VOIDS, MPIU_INT, MPI_SUM, comm));
  for (PetscInt v = 0; v < sc->nvoids; v++)
    PetscCheck(invoid[v] > 0, comm, PETSC_ERR_USER_INPUT,
               "Option %s_%s: the void contains no node (it must hold at least one node's cell centre)", sc->voids[v].option,
               sc->voids[v].where.shape == PD_SHAPE_BOX ? "box" : "cylinder");
  PetscCheck(lat->nvoid + lat->nunused + lat->nbarnodes < lat->nglobal, comm, PETSC_ERR_USER_INPUT,
             "Options -pd_void*: the voids leave no material in the domain");
  PetscCall(MPIU_Allreduce(innofail_mine, innofail, PD_MAX_NOFAIL, MPIU_INT, MPI_SUM, comm));
  PetscCall(MPIU_Allreduce(inplate_mine, inplate, PD_MAX_MATERIALS, MPIU_INT, MPI_SUM, comm));
  for (PetscInt p = 0; p < sc->nplates; p++)
    PetscCheck(inplate[p] > 0, comm, PETSC_ERR_USER_INPUT,
               "Option %s_box: the plate holds no node (or later materials and plates cover it)", sc->material[sc->nmaterials + p].option);
  for (PetscInt v = 0; v < sc->nnofail; v++)
    PetscCheck(innofail[v] > 0, comm, PETSC_ERR_USER_INPUT, "Option %s_%s: the no-fail zone contains no node", sc->nofail[v].option,
               sc->nofail[v].where.shape == PD_SHAPE_BOX ? "box" : "cylinder");
  PetscFunctionReturn(0);
}

PetscErrorCode PDLatticeDestroy(PDLattice *lat) {
  PetscFunctionBeginUser;
  PetscCall(PetscFree5(lat->gid, lat->x, lat->material, lat->hollow, lat->nofail));
  PetscCall(PetscFree(lat->stencil));
  PetscCall(PetscFree(lat->barnode));
  PetscCall(PetscFree5(lat->bn_bar, lat->bn_ijk, lat->bn_gid, lat->bn_length, lat->bn_shift));
  PetscCall(PetscFree(lat->bn_role));
  PetscCall(PetscFree(lat->slot_node));
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
        const PetscInt ijk[3] = {i0[0] + i, i0[1] + j, i0[2] + k};
        gid[*n]               = PDLatticeGid(lat, ijk);
        w[*n]                 = (i ? t[0] : 1 - t[0]) * (j ? t[1] : 1 - t[1]) * (k ? t[2] : 1 - t[2]);
        (*n)++;
      }
}
