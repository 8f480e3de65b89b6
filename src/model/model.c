/* Model set-up: boundary conditions from node regions, measurement patterns, residual and Jacobian. */
#include "pd_model.h"
#include <petscbt.h>
#include "kernel.h"
#include "pd_log.h"
#include <stdint.h>

static PetscErrorCode CreateGlobalVec(const PDLattice *lat, PetscInt bs, Vec *v) {
  PetscFunctionBeginUser;
  PetscCall(VecCreate(lat->comm, v));
  PetscCall(VecSetSizes(*v, bs * lat->nowned, PETSC_DECIDE));
  PetscCall(VecSetBlockSize(*v, bs));
  PetscCall(VecSetFromOptions(*v));
  PetscFunctionReturn(0);
}

/* Owned and ghost values of a ghosted vector whose owned part is set. */
static PetscErrorCode GhostedValues(Vec g, PetscReal *out) {
  Vec                loc;
  const PetscScalar *a;
  PetscInt           n;

  PetscFunctionBeginUser;
  PetscCall(VecGhostUpdateBegin(g, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(g, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostGetLocalForm(g, &loc));
  PetscCall(VecGetLocalSize(loc, &n));
  PetscCall(VecGetArrayRead(loc, &a));
  for (PetscInt k = 0; k < n; k++) out[k] = PetscRealPart(a[k]);
  PetscCall(VecRestoreArrayRead(loc, &a));
  PetscCall(VecGhostRestoreLocalForm(g, &loc));
  PetscFunctionReturn(0);
}

/* Diagonal of a node's 3x3 stiffness block, sum over its bonds of (c/|xi|) e e^T. */
/* A region selects the nodes of its box or cylinder that hold material (a void's nodes carry nothing):
   the concrete's, or those of the bars with bond slip (-pd_regionK_nodes), each at the place of the node it
   shadows. */
static PetscBool InRegion(const PDRegion *reg, const PDLattice *lat, PetscInt i, const PDScene *sc) {
  const PetscInt q = lat->barnode ? lat->barnode[i] : -1;
  PetscReal      x[3];
  if (lat->hollow[i] || (q >= 0) != reg->on_bars || (q >= 0 && lat->bn_role[q] != PD_BAR_NODE)) return PETSC_FALSE; /* not anchors */
  for (PetscInt a = 0; a < 3; a++) x[a] = lat->x[3 * i + a] - (q >= 0 && !sc->bar[lat->bn_bar[q]].embedded ? lat->bn_shift[3 * q + a] : 0);
  return PDGeometryContains(&reg->where, x, sc);
}

static void NodalStiffnessDiagonal(const PDModel *m, PetscInt i, PetscReal diag[3]) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  for (PetscInt p = bd->inc_start[i]; p < bd->inc_start[i + 1]; p++) {
    const PetscInt   e  = bd->inc_bond[p];
    const PetscReal *xa = &lat->x[3 * bd->a[e]], *xb = &lat->x[3 * bd->b[e]];
    PetscReal        L2 = 0;
    for (PetscInt a = 0; a < 3; a++) L2 += (xb[a] - xa[a]) * (xb[a] - xa[a]);
    for (PetscInt a = 0; a < m->bs; a++) diag[a] += PDBondStiffness(bd, e) / PetscSqrtReal(L2) * (xb[a] - xa[a]) * (xb[a] - xa[a]) / L2;
  }
}

/* Constrained dofs: supports, prescribed displacements and nodes that have no bond at all. Two regions
   constraining the same dof, or a force on a constrained dof, are conflicting input. */
static PetscErrorCode SetupConstraints(PDModel *m) {
  const PDScene   *sc  = m->scene;
  const PDLattice *lat = m->lat;
  const PetscInt   bs  = m->bs;
  /* the first conflicting pair of regions (a, b), coded a * PD_MAX_REGIONS + b so that one MPI_MIN finds
     the same pair on every rank */
  PetscInt    *owner, conflict = PETSC_MAX_INT, gconflict, nfix = 0, niso = 0, nzero = 0;
  PetscInt     count[PD_MAX_REGIONS], gcount[PD_MAX_REGIONS];
  Vec          fixl;
  PetscScalar *fx, *ur, *fr;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(bs * lat->nowned, &owner));
  for (PetscInt k = 0; k < bs * lat->nowned; k++) owner[k] = -1;
  PetscCall(PetscArrayzero(count, PD_MAX_REGIONS));
  PetscCall(VecGetArray(m->u_ref, &ur));
  PetscCall(VecGetArray(m->f_ref, &fr));
  for (PetscInt r = 0; r < sc->nregions; r++) {
    const PDRegion *reg = &sc->region[r];
    for (PetscInt i = 0; i < lat->nowned; i++)
      if (InRegion(reg, lat, i, sc)) count[r]++;
  }
  PetscCall(MPIU_Allreduce(count, gcount, PD_MAX_REGIONS, MPIU_INT, MPI_SUM, lat->comm));
  for (PetscInt r = 0; r < sc->nregions; r++)
    PetscCheck(!sc->region[r].on_bars || lat->nbarnodes, lat->comm, PETSC_ERR_USER_INPUT,
               "Option %s_nodes bars: the scene has no bar with nodes of its own (-pd_barK_bond slip, or embedded), whose nodes it "
               "would select",
               sc->region[r].option);
  for (PetscInt r = 0; r < sc->nregions; r++)
    PetscCheck(gcount[r] > 0, lat->comm, PETSC_ERR_USER_INPUT, "Option %s_%s: the region contains no %s (outside voids)",
               sc->region[r].option, sc->region[r].where.shape == PD_SHAPE_BOX ? "box" : "cylinder",
               sc->region[r].on_bars ? "node of a bar with bond slip (-pd_barK_bond slip)" : "nodes");
  for (PetscInt r = 0; r < sc->nregions; r++) {
    const PDRegion *reg = &sc->region[r];
    if (reg->kind == PD_REGION_MONITOR) continue;
    for (PetscInt i = 0; i < lat->nowned; i++) {
      if (!InRegion(reg, lat, i, sc)) continue;
      for (PetscInt a = 0; a < bs; a++) {
        const PetscInt k = bs * i + a;
        if (reg->kind == PD_REGION_FORCE) {
          fr[k] += reg->vector[a] / gcount[r];
          if (reg->vector[a] != 0 && owner[k] >= 0) conflict = PetscMin(conflict, r * PD_MAX_REGIONS + owner[k]);
          continue;
        }
        if (!reg->dof[a]) continue;
        if (owner[k] >= 0) conflict = PetscMin(conflict, r * PD_MAX_REGIONS + owner[k]);
        owner[k] = r;
        ur[k]    = reg->kind == PD_REGION_DISPLACEMENT ? reg->vector[a] : 0;
      }
    }
  }
  /* a force region applied on a dof that a later region constrains */
  for (PetscInt r = 0; r < sc->nregions; r++) {
    const PDRegion *reg = &sc->region[r];
    if (reg->kind != PD_REGION_FORCE) continue;
    for (PetscInt i = 0; i < lat->nowned; i++)
      if (InRegion(reg, lat, i, sc))
        for (PetscInt a = 0; a < bs; a++) {
          const PetscInt k = bs * i + a;
          if (reg->vector[a] != 0 && owner[k] > r) conflict = PetscMin(conflict, owner[k] * PD_MAX_REGIONS + r);
        }
  }
  PetscCall(MPIU_Allreduce(&conflict, &gconflict, 1, MPIU_INT, MPI_MIN, lat->comm));
  PetscCheck(gconflict == PETSC_MAX_INT, lat->comm, PETSC_ERR_USER_INPUT,
             "Options %s and %s: conflicting boundary conditions on the same degree of freedom",
             sc->region[gconflict / PD_MAX_REGIONS].option, sc->region[gconflict % PD_MAX_REGIONS].option);
  PetscCall(VecRestoreArray(m->u_ref, &ur));
  PetscCall(VecRestoreArray(m->f_ref, &fr));

  /* flags travel to the ghosts through a ghosted vector, so every rank masks the same columns */
  PetscCall(PDLatticeCreateGhostVec(lat, bs, &fixl));
  PetscCall(VecGetArray(fixl, &fx));
  for (PetscInt i = 0; i < lat->nowned; i++) {
    PetscReal diag[3] = {0, 0, 0}, trace = 0;
    NodalStiffnessDiagonal(m, i, diag);
    for (PetscInt a = 0; a < bs; a++) trace += diag[a];
    if (trace == 0 && !lat->hollow[i]) niso++;
    for (PetscInt a = 0; a < bs; a++) {
      /* a direction without stiffness (a node whose bonds were all cut, or the x-direction of nodes on a
         notch plane, which keep only in-plane bonds) is pinned: it carries no force either way */
      const PetscBool zero = diag[a] <= 1e-10 * trace;
      if (zero && owner[bs * i + a] < 0 && !lat->hollow[i]) nzero++;
      fx[bs * i + a] = (owner[bs * i + a] >= 0 || zero) ? 1.0 : 0.0;
      if (fx[bs * i + a] != 0.0) nfix++;
    }
  }
  PetscCall(VecRestoreArray(fixl, &fx));
  PetscCall(VecCopy(fixl, m->fixed)); /* same layout of owned entries */
  /* flags, and the prescribed values for the residual's lifting, travel to the ghosts */
  PetscCall(PetscMalloc2(bs * lat->nlocal, &m->fixed_local, bs * lat->nlocal, &m->uref_local));
  PetscCall(GhostedValues(fixl, m->uref_local)); /* flags first, through the same buffer */
  for (PetscInt k = 0; k < bs * lat->nlocal; k++) m->fixed_local[k] = m->uref_local[k] != 0 ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(VecCopy(m->u_ref, fixl));
  PetscCall(GhostedValues(fixl, m->uref_local));
  PetscCall(VecDestroy(&fixl));
  PetscCall(MPIU_Allreduce(&nfix, &m->nconstrained, 1, MPIU_INT, MPI_SUM, lat->comm));
  PetscCall(MPIU_Allreduce(&niso, &m->nisolated, 1, MPIU_INT, MPI_SUM, lat->comm));
  PetscCall(MPIU_Allreduce(&nzero, &m->nzero_dofs, 1, MPIU_INT, MPI_SUM, lat->comm));
  PetscCall(PetscFree(owner));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetupPatterns(PDModel *m) {
  const PDScene   *sc   = m->scene;
  const PDLattice *lat  = m->lat;
  const PDRegion  *dreg = &sc->region[sc->disp_region];
  const PetscInt   bs   = m->bs;
  PetscReal        dir[PD_MAX_REGIONS][3];
  PetscInt         n = 0, gn;
  PetscScalar     *lp, *dp;

  PetscFunctionBeginUser;
  /* the load sums the listed regions' forces or reactions, each along its own direction; where two regions
     share a node they constrain different components of it (a component in two regions is bad input), so
     their directions add */
  m->force_magnitude = 0;
  for (PetscInt r = 0; r < sc->nload_regions; r++) {
    const PDRegion *load = &sc->region[sc->load_regions[r]];
    PetscReal       norm = 0;
    for (PetscInt a = 0; a < 3; a++) norm += load->vector[a] * load->vector[a];
    norm = PetscSqrtReal(norm);
    for (PetscInt a = 0; a < 3; a++) dir[r][a] = load->vector[a] / norm;
    m->force_magnitude += norm;
  }
  PetscCall(VecGetArray(m->load_pattern, &lp));
  PetscCall(VecGetArray(m->disp_pattern, &dp));
  for (PetscInt i = 0; i < lat->nowned; i++) {
    for (PetscInt r = 0; r < sc->nload_regions; r++)
      if (InRegion(&sc->region[sc->load_regions[r]], lat, i, sc))
        for (PetscInt a = 0; a < bs; a++) lp[bs * i + a] += dir[r][a];
    if (InRegion(dreg, lat, i, sc)) n++;
  }
  PetscCall(MPIU_Allreduce(&n, &gn, 1, MPIU_INT, MPI_SUM, lat->comm));
  for (PetscInt i = 0; i < lat->nowned; i++)
    if (InRegion(dreg, lat, i, sc))
      for (PetscInt a = 0; a < bs; a++) dp[bs * i + a] = dir[0][a] / gn;
  PetscCall(VecRestoreArray(m->load_pattern, &lp));
  PetscCall(VecRestoreArray(m->disp_pattern, &dp));
  if (sc->has_cmod) {
    /* The gauge reads the displacement at its two points by (tri)linear interpolation of the lattice,
       extrapolated to points within dx/2 of the surface: the experiment's gauge sits on the face,
       half a cell outside the nearest nodes. The opening is the difference along the gauge line. */
    PetscReal e[3] = {0, 0, 0}, len = 0;
    for (PetscInt a = 0; a < lat->dim; a++) {
      e[a] = sc->cmod[3 + a] - sc->cmod[a];
      len += e[a] * e[a];
    }
    PetscCheck(len > 0, lat->comm, PETSC_ERR_USER_INPUT, "Option -pd_cmod_points: the two points coincide");
    for (PetscInt a = 0; a < 3; a++) e[a] /= PetscSqrtReal(len);
    for (PetscInt p = 0; p < 2; p++) {
      PetscInt  gid[8], nw;
      PetscReal w[8];
      PDLatticeInterpolation(lat, &sc->cmod[3 * p], gid, w, &nw);
      for (PetscInt k = 0; k < nw; k++) {
        PetscScalar v[3];
        if (gid[k] < lat->gid_start || gid[k] >= lat->gid_start + lat->nowned) continue;
        for (PetscInt a = 0; a < bs; a++) v[a] = (p ? 1 : -1) * w[k] * e[a];
        PetscCall(VecSetValuesBlocked(m->cmod_pattern, 1, &gid[k], v, ADD_VALUES));
      }
    }
    PetscCall(VecAssemblyBegin(m->cmod_pattern));
    PetscCall(VecAssemblyEnd(m->cmod_pattern));
  }
  PetscFunctionReturn(0);
}

/* Diagonal for constrained dofs: the mean diagonal of the bond stiffness, so that the eliminated
   rows do not spoil the conditioning. */
static PetscErrorCode SetupScale(PDModel *m) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  PetscReal        sum = 0, gsum;
  PetscInt         n   = lat->nowned, gn;

  PetscFunctionBeginUser;
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscReal *p = &lat->x[3 * bd->a[e]], *q = &lat->x[3 * bd->b[e]];
    const PetscReal  L = PetscSqrtReal((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]));
    sum += (bd->b[e] < lat->nowned ? 2.0 : 1.0) * bd->coef[e] / L / m->bs; /* the concrete's: bars are few */
  }
  PetscCall(MPIU_Allreduce(&sum, &gsum, 1, MPIU_REAL, MPI_SUM, lat->comm));
  PetscCall(MPIU_Allreduce(&n, &gn, 1, MPIU_INT, MPI_SUM, lat->comm));
  m->bc_scale = gsum > 0 ? gsum / gn : 1.0;
  {
    PetscReal fn, un;
    PetscCall(VecNorm(m->f_ref, NORM_2, &fn));
    PetscCall(VecNorm(m->u_ref, NORM_2, &un));
    m->force_scale = fn + m->bc_scale * un;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode PDModelCreate(const PDScene *sc, const PDLattice *lat, const PDBonds *bd, PDModel *m) {
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(m, sizeof *m));
  m->scene = sc;
  m->lat   = lat;
  m->bonds = bd;
  m->bs    = sc->dim;
  for (PetscInt k = 0; k < sc->nmaterials; k++) {
    PDLaw *tie = &m->law[PD_MATERIAL_TIE(k)];
    PetscCall(PDLawSetUp(sc, &sc->material[k], &m->law[k]));
    *tie = m->law[k]; /* the ties of embedded bars' anchors (pd_lattice.h) */
    tie->nominal.s0 /= PD_ANCHOR_STIFFNESS;
    tie->confine = 0;
  }
  for (PetscInt k = 0; k < sc->nbars; k++) {
    PDSteelSetUp(&sc->bar[k], &m->steel[k]);
    if (sc->bar[k].slip) PDLawSetUpSlip(&sc->bar[k], PD_BAR_NODE_SHIFT * sc->dx, &m->law[PD_MATERIAL_SLIP(k)]);
  }
  m->softening = PDSceneHasDamage(sc);
  m->linear    = (sc->kinematics == PD_KINEMATICS_SMALL && !m->softening && !sc->nbars) ? PETSC_TRUE : PETSC_FALSE;
  PetscCheck(sc->pc_reach <= 0 || !m->linear, lat->comm, PETSC_ERR_USER_INPUT,
             "Option -pd_pc_reach: applies to non-linear scenes (a linear one solves with the assembled matrix), got %g",
             (double)sc->pc_reach);
  /* limiter cap by default: a fixed number of events per 150,000 bonds, at least 10. The cap grows with the
     model: a finer lattice has more bonds in its process zone, and a cap fixed in events multiplies the
     Newton iterations of the increments near the peak. How many per 150,000 bonds was chosen on the
     default scene against one event per iteration (docs/softening.md, docs/benchmarks/solve_profile.md) */
  m->limiter_max = sc->limiter_max >= 0 ? sc->limiter_max : PetscMax(10, (PetscInt)(15.0 * bd->nbonds_global / 150000.0 + 0.5));
  PetscCall(PDLatticeCreateGhostVec(lat, m->bs, &m->u_local));
  PetscCall(VecDuplicate(m->u_local, &m->f_local));
  PetscCall(CreateGlobalVec(lat, m->bs, &m->f_ref));
  PetscCall(VecDuplicate(m->f_ref, &m->u_ref));
  PetscCall(VecDuplicate(m->f_ref, &m->fixed));
  PetscCall(VecDuplicate(m->f_ref, &m->load_pattern));
  PetscCall(VecDuplicate(m->f_ref, &m->disp_pattern));
  PetscCall(VecDuplicate(m->f_ref, &m->cmod_pattern));
  PetscCall(VecDuplicate(m->f_ref, &m->f_work));
  PetscCall(VecZeroEntries(m->f_ref));
  PetscCall(VecZeroEntries(m->u_ref));
  PetscCall(VecZeroEntries(m->load_pattern));
  PetscCall(VecZeroEntries(m->disp_pattern));
  PetscCall(VecZeroEntries(m->cmod_pattern));
  PetscCall(SetupConstraints(m));
  PetscCall(SetupPatterns(m));
  PetscCall(SetupScale(m));
  if (!m->linear) PetscCall(PetscMalloc1(PetscMax(1, bd->nbonds), &m->ka));
  /* the tangent's kb I part is the geometric term: zero under small kinematics, where no array is kept for it */
  if (!m->linear && sc->kinematics == PD_KINEMATICS_FINITE) PetscCall(PetscMalloc1(PetscMax(1, bd->nbonds), &m->kb));
  /* IMPL-EX's matrix is the secant one already: no second matrix for it */
  if (!m->linear && m->softening && sc->pc_matrix == PD_PC_MATRIX_SECANT && sc->arc_implex == 0)
    PetscCall(PetscMalloc1(PetscMax(1, bd->nbonds), &m->kp));
  /* history exists only when some law softens: an elastic scene allocates none */
  m->history_bytes = 0;
  if (m->softening) {
    const PetscInt nb = PetscMax(1, bd->nbonds);
    PetscCall(PetscCalloc3(nb, &m->kappa, nb, &m->level, nb, &m->level_n));
    m->history_bytes = (PetscInt64)bd->nbonds * (sizeof(PetscReal) + 2); /* kappa, two levels */
    PetscBool crush  = PETSC_FALSE;
    for (PetscInt k = 0; k < sc->nmaterials; k++) crush = crush || m->law[k].confine > 0 ? PETSC_TRUE : PETSC_FALSE;
    for (PetscInt k = 0; k < PD_MATERIALS_ALL; k++) m->onset[k] = PETSC_MAX_REAL;
    /* before crushing's rises exist: they only raise thresholds, so the floor holds */
    for (PetscInt e = 0; e < bd->nbonds; e++) {
      const PDLaw *law = &m->law[bd->material[e]];
      PDLawBond    t;
      if (law->kind == PD_LAW_ELASTIC) continue; /* no threshold at all (bar segments across a notch) */
      t                         = PDModelBondThresholds(m, e, law);
      m->onset[bd->material[e]] = PetscMin(m->onset[bd->material[e]], PetscMin(t.s0, t.sc));
    }
    if (crush) {
      PetscCall(PetscCalloc1(nb, &m->shift));
      m->history_bytes += (PetscInt64)bd->nbonds * sizeof(PetscReal);
    }
    PDModelResetThresholds(m);
  }
  for (PetscInt pass = 0; pass < 2 && lat->barnode; pass++) { /* the bond-slip links: count, then list */
    m->nslip = 0;
    for (PetscInt e = 0; e < bd->nbonds; e++)
      if (m->law[bd->material[e]].kind == PD_LAW_SLIP) {
        if (pass) m->slip_bond[m->nslip] = e;
        m->nslip++;
      }
    if (!pass) PetscCall(PetscMalloc1(PetscMax(1, m->nslip), &m->slip_bond));
  }
  /* crushing's rises and the crushing criterion read the nodes' dilatation */
  if (m->shift || PDSceneHasCrushingStrain(sc)) PetscCall(PDLatticeCreateGhostVec(lat, 1, &m->dilatation));
  if (sc->nbars) {
    PetscCall(
        PetscCalloc3(PetscMax(1, bd->nseg), &m->sp_n, PetscMax(1, bd->nseg), &m->ruptured_n, PetscMax(1, bd->nseg), &m->dissipated_n));
    m->history_bytes += (PetscInt64)bd->nseg * (2 * sizeof(PetscReal) + sizeof(PetscBool));
  }
  {
    PetscInt64 mine = m->history_bytes;
    PetscCall(MPIU_Allreduce(&mine, &m->history_bytes, 1, MPIU_INT64, MPI_SUM, lat->comm));
  }
  PetscFunctionReturn(0);
}

#define PD_STEEL_DENSITY 7850.0 /* kg/m^3 */

PetscReal PDModelNodeMass(const PDModel *m, PetscInt i) {
  const PDLattice *lat = m->lat;
  if (lat->barnode && lat->barnode[i] >= 0) {
    const PetscInt q = lat->barnode[i];
    return PD_STEEL_DENSITY * PDBarArea(&m->scene->bar[lat->bn_bar[q]]) * lat->bn_length[q];
  }
  return m->scene->material[lat->material[i]].rho * lat->cell_volume;
}

void PDModelResetThresholds(PDModel *m) {
  for (PetscInt e = 0; m->shift && e < m->bonds->nbonds; e++) m->shift[e] = 0;
}

PetscErrorCode PDModelDestroy(PDModel *m) {
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&m->u_local));
  PetscCall(VecDestroy(&m->f_local));
  PetscCall(VecDestroy(&m->x_local));
  PetscCall(VecDestroy(&m->f_ref));
  PetscCall(VecDestroy(&m->u_ref));
  PetscCall(VecDestroy(&m->fixed));
  PetscCall(VecDestroy(&m->load_pattern));
  PetscCall(VecDestroy(&m->disp_pattern));
  PetscCall(VecDestroy(&m->cmod_pattern));
  PetscCall(VecDestroy(&m->f_work));
  PetscCall(PetscFree2(m->fixed_local, m->uref_local));
  PetscCall(PetscFree(m->slip_bond));
  PetscCall(PetscFree(m->ka));
  PetscCall(VecDestroy(&m->ka_u)); /* left by a static run that stopped on an error */
  PetscCall(VecDestroy(&m->r_last));
  PetscCall(VecDestroy(&m->f_last));
  PetscCall(PetscFree(m->fchange_bond));
  PetscCall(PetscFree(m->fchange_g));
  PetscCall(PetscFree(m->changed));
  PetscCall(PDModelRowIndexDestroy(m));
  PetscCall(PetscFree(m->kb));
  PetscCall(PetscFree(m->kp));
  PetscCall(PetscFree3(m->kappa, m->level, m->level_n));
  PetscCall(PetscFree(m->shift));
  PetscCall(VecDestroy(&m->dilatation));
  PetscCall(PetscFree3(m->sp_n, m->ruptured_n, m->dissipated_n));
  PetscCall(PetscFree(m->section_bonds));
  PetscFunctionReturn(0);
}

/* u with its ghost entries in the ghosted vector g, constrained entries at lambda times their reference
   values; *ul is the local form's array. */
static PetscErrorCode ScatterGhosted(PDModel *m, Vec u, PetscReal lambda, Vec g, const PetscScalar **ul, Vec *loc) {
  PetscScalar *w;

  PetscFunctionBeginUser;
  PetscCall(VecCopy(u, g));
  PetscCall(VecGhostUpdateBegin(g, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(g, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostGetLocalForm(g, loc));
  PetscCall(VecGetArray(*loc, &w));
  for (PetscInt k = 0; k < m->bs * m->lat->nlocal; k++)
    if (m->fixed_local[k]) w[k] = lambda * m->uref_local[k];
  PetscCall(VecRestoreArray(*loc, &w));
  PetscCall(VecGetArrayRead(*loc, ul));
  PetscFunctionReturn(0);
}

/* Copies the owned displacement into the ghosted work vector and fetches the ghosts. Constrained
   dofs take their prescribed values whatever u holds (lifting), so the internal force of free dofs
   does not depend on constrained ones: the Jacobian with eliminated columns is then exact. */
PetscErrorCode PDModelScatterToLocal(PDModel *m, Vec u, const PetscScalar **ul, Vec *loc) {
  PetscFunctionBeginUser;
  PetscCall(ScatterGhosted(m, u, m->lambda, m->u_local, ul, loc));
  PetscFunctionReturn(0);
}

/* The same for a second state at load factor lambda, in the work vector x_local (a tangent product's input),
   undone by PDModelRestoreSecondLocal. */
PetscErrorCode PDModelScatterSecondToLocal(PDModel *m, Vec u, PetscReal lambda, const PetscScalar **ul, Vec *loc) {
  PetscFunctionBeginUser;
  if (!m->x_local) PetscCall(VecDuplicate(m->u_local, &m->x_local));
  PetscCall(ScatterGhosted(m, u, lambda, m->x_local, ul, loc));
  PetscFunctionReturn(0);
}

PetscErrorCode PDModelRestoreSecondLocal(PDModel *m, const PetscScalar **ul, Vec *loc) {
  PetscFunctionBeginUser;
  PetscCall(VecRestoreArrayRead(*loc, ul));
  PetscCall(VecGhostRestoreLocalForm(m->x_local, loc));
  PetscFunctionReturn(0);
}

PetscErrorCode PDModelRestoreLocal(PDModel *m, const PetscScalar **ul, Vec *loc) {
  PetscFunctionBeginUser;
  PetscCall(VecRestoreArrayRead(*loc, ul));
  PetscCall(VecGhostRestoreLocalForm(m->u_local, loc));
  PetscFunctionReturn(0);
}

PetscErrorCode PDModelStrainState(PDModel *m, Vec u) {
  const PetscScalar *ul;
  Vec                loc;

  PetscFunctionBeginUser;
  if (!m->dilatation) PetscFunctionReturn(0);
  PetscCall(PDModelScatterToLocal(m, u, &ul, &loc));
  PetscCall(PDModelNodalDilatation(m, ul));
  PetscCall(PDModelRestoreLocal(m, &ul, &loc));
  PetscFunctionReturn(0);
}

/* Internal forces at u; with tangent, the tangent scalars at u into m->ka and m->kb too. */
static PetscErrorCode InternalForce(PDModel *m, Vec u, Vec F, PetscBool tangent) {
  const PetscScalar *ul;
  PetscScalar       *fl, *f;
  Vec                uloc, floc;

  PetscFunctionBeginUser;
  PetscCall(PDModelScatterToLocal(m, u, &ul, &uloc));
  PetscCall(VecGhostGetLocalForm(m->f_local, &floc));
  PetscCall(VecGetArray(floc, &fl));
  PetscCall(PDModelInternalForceLocal(m, ul, fl, tangent ? m->ka : NULL, tangent ? m->kb : NULL));
  PetscCall(VecGetArray(F, &f));
  PetscCall(PetscArraycpy(f, fl, m->bs * m->lat->nowned)); /* ghost entries are partial sums: dropped */
  PetscCall(VecRestoreArray(F, &f));
  PetscCall(VecRestoreArray(floc, &fl));
  PetscCall(VecGhostRestoreLocalForm(m->f_local, &floc));
  PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  PetscFunctionReturn(0);
}

PetscErrorCode PDModelInternalForce(PDModel *m, Vec u, Vec F) {
  PetscFunctionBeginUser;
  PetscCall(InternalForce(m, u, F, PETSC_FALSE));
  PetscFunctionReturn(0);
}

/* Internal forces at u and, where the drivers take the tangent from the residual's loop (m->ka_with_residual),
   the tangent scalars at u from the same loop, kept with the point they belong to, so that a Jacobian at
   that point (PDModelJacobian) does not go over the bonds again; where the driver asks (m->keep_force), the
   force too, from which PDModelMeasure updates the bonds a history commit changes. */
PetscErrorCode PDModelInternalForceKeepTangent(PDModel *m, Vec u, Vec F) {
  PetscFunctionBeginUser;
  PetscCall(InternalForce(m, u, F, m->ka_with_residual));
  m->fchange_ready = PETSC_FALSE; /* a list of changed forces refers to the force before */
  m->f_last_valid  = PETSC_FALSE;
  if (m->keep_force) { /* for PDModelMeasure after the history commit (InternalForceByChange), at ka_u and ka_lambda */
    if (!m->f_last) PetscCall(VecDuplicate(F, &m->f_last));
    PetscCall(VecCopy(F, m->f_last));
    m->f_last_valid = PETSC_TRUE;
  }
  if (m->ka_with_residual) {
    if (!m->ka_u) PetscCall(VecDuplicate(u, &m->ka_u));
    PetscCall(VecCopy(u, m->ka_u));
    m->ka_lambda      = m->lambda;
    m->ka_at_residual = PETSC_TRUE;
  }
  PetscFunctionReturn(0);
}

/* After a limiter grant the driver evaluates the residual again where it evaluated the last one: only the
   rows of the nodes of the bonds the grant changed can differ. They are recomputed (in the whole loop's
   order, so to the last bit) into a copy of the last residual, with the tangent scalars of their bonds.
   *done is PETSC_FALSE where that does not hold and the whole loop must run. */
static PetscErrorCode ResidualRowsAfterGrant(PDModel *m, Vec u, Vec R, PetscBool *done) {
  const PetscInt     bs = m->bs, nowned = m->lat->nowned;
  const PetscScalar *ul, *fr;
  PetscScalar       *r, *fv;
  PetscInt          *rows, n = 0;
  PetscBT            mark;
  Vec                uloc;
  PetscBool          same = PETSC_FALSE, usable, all;

  PetscFunctionBeginUser;
  *done               = PETSC_FALSE;
  m->rows_after_grant = PETSC_FALSE;
  if (!m->r_last || !m->ka_at_residual || m->lambda != m->ka_lambda) PetscFunctionReturn(0);
  /* decided alike on every rank: the rows and the whole loop make different collective calls */
  PetscCall(PDModelRowsUsable(m, &usable));
  usable = usable && m->nchanged >= 0 ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(MPIU_Allreduce(&usable, &all, 1, MPIU_BOOL, MPI_LAND, m->lat->comm));
  if (!all) PetscFunctionReturn(0);
  PetscCall(VecEqual(u, m->ka_u, &same));
  if (!same) PetscFunctionReturn(0);
  PetscCall(PetscBTCreate(nowned, &mark));
  PetscCall(PetscMalloc2(2 * m->nchanged + 1, &rows, bs * (2 * m->nchanged + 1), &fv));
  for (PetscInt k = 0; k < m->nchanged; k++) {
    const PetscInt ends[2] = {m->bonds->a[m->changed[k]], m->bonds->b[m->changed[k]]};
    for (PetscInt t = 0; t < 2; t++)
      if (ends[t] < nowned && !PetscBTLookupSet(mark, ends[t])) rows[n++] = ends[t];
  }
  PetscCall(PDModelScatterToLocal(m, u, &ul, &uloc));
  PetscCall(PDModelInternalForceRows(m, ul, n, rows, fv, m->ka));
  PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  *done = PETSC_TRUE;
  /* the rows into the last residual, which then is this one */
  PetscCall(VecGetArray(m->r_last, &r));
  PetscCall(VecGetArrayRead(m->f_ref, &fr));
  for (PetscInt k = 0; k < n; k++)
    for (PetscInt c = 0; c < bs; c++) {
      const PetscInt d = bs * rows[k] + c;
      if (!m->fixed_local[d]) r[d] = fv[bs * k + c] - m->lambda * fr[d]; /* constrained rows depend on u alone */
    }
  PetscCall(VecRestoreArrayRead(m->f_ref, &fr));
  PetscCall(VecRestoreArray(m->r_last, &r));
  PetscCall(VecCopy(m->r_last, R));
  PetscCall(PetscFree2(rows, fv));
  PetscCall(PetscBTDestroy(&mark));
  PetscFunctionReturn(0);
}

/* R = F_int(u) - lambda F_ref on free dofs, bc_scale (u - lambda u_ref) on constrained ones. */
PetscErrorCode PDModelResidual(SNES snes, Vec u, Vec R, void *ctx) {
  PDModel           *m = (PDModel *)ctx;
  const PetscScalar *uu, *fr, *ur, *fx;
  PetscScalar       *r;
  PetscLogDouble     t0, t1;
  PetscBool          rows = PETSC_FALSE;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(PetscTime(&t0));
  if (m->rows_after_grant && m->ka_with_residual) PetscCall(ResidualRowsAfterGrant(m, u, R, &rows));
  m->nchanged = 0;
  if (rows) {
    m->fchange_ready = m->f_last_valid = PETSC_FALSE; /* the kept force is the one before the grant */
    m->residuals_by_rows++;
    PetscCall(PetscTime(&t1));
    m->t_residual += t1 - t0;
    PetscFunctionReturn(0);
  }
  PetscCall(PDModelInternalForceKeepTangent(m, u, R));
  PetscCall(VecGetArray(R, &r));
  PetscCall(VecGetArrayRead(u, &uu));
  PetscCall(VecGetArrayRead(m->f_ref, &fr));
  PetscCall(VecGetArrayRead(m->u_ref, &ur));
  PetscCall(VecGetArrayRead(m->fixed, &fx));
  for (PetscInt k = 0; k < m->bs * m->lat->nowned; k++)
    r[k] = PetscRealPart(fx[k]) != 0 ? m->bc_scale * (uu[k] - m->lambda * ur[k]) : r[k] - m->lambda * fr[k];
  PetscCall(VecRestoreArrayRead(m->fixed, &fx));
  PetscCall(VecRestoreArrayRead(m->u_ref, &ur));
  PetscCall(VecRestoreArrayRead(m->f_ref, &fr));
  PetscCall(VecRestoreArrayRead(u, &uu));
  PetscCall(VecRestoreArray(R, &r));
  if (m->track_grants) {
    if (!m->r_last) PetscCall(VecDuplicate(R, &m->r_last));
    PetscCall(VecCopy(R, m->r_last));
  }
  PetscCall(PetscTime(&t1));
  m->t_residual += t1 - t0;
  PetscFunctionReturn(0);
}

PetscErrorCode PDModelJacobian(SNES snes, Vec u, Mat J, Mat P, void *ctx) {
  PDModel           *m = (PDModel *)ctx;
  const PetscScalar *ul;
  Vec                uloc;
  PetscLogDouble     t0, t1;

  PetscFunctionBeginUser;
  (void)snes;
  /* a linear model's stiffness never changes: assemble it once, and the preconditioner is kept too (the
     count alone does not say so: a restart carries it over from the run before, to a matrix not yet filled) */
  if (m->linear && m->jacobian_assemblies > 0) {
    PetscBool filled;
    PetscCall(MatAssembled(P, &filled));
    if (filled) PetscFunctionReturn(0);
  }
  PetscCall(PetscTime(&t0));
  PetscCall(PDModelScatterToLocal(m, u, &ul, &uloc));
  if (m->ka) {
    PetscBool same = PETSC_FALSE;
    /* the residual at this u computed them already (unless the secant preconditioning matrix needs kp) */
    if (m->ka_at_residual && m->lambda == m->ka_lambda && !(J != P && m->kp)) PetscCall(VecEqual(u, m->ka_u, &same));
    if (!same) PetscCall(PDModelTangentScalars(m, ul, m->ka, m->kb, J != P ? m->kp : NULL));
  }
  /* a separate preconditioning matrix is the secant one when asked (-pd_pc_matrix secant), else the tangent */
  PetscCall(PDModelAssembleRows(m, ul, J != P && m->kp ? m->kp : m->ka, m->kb, P, &m->nregularised));
  if (m->nregularised) PetscCall(PetscInfo(NULL, "%" PetscInt_FMT " dofs without stiffness regularised\n", m->nregularised));
  m->max_regularised = PetscMax(m->max_regularised, m->nregularised);
  if (J != P) {
    PetscBool mf;
    /* -snes_mf_operator, or the product from the bond scalars P was just assembled with */
    PetscCall(PetscObjectTypeCompareAny((PetscObject)J, &mf, MATMFFD, MATSHELL, ""));
    if (mf) {
      PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
      PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
    } else
      PetscCall(PDModelAssembleRows(m, ul, m->ka, m->kb, J, &m->nregularised));
  }
  PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  m->jacobian_assemblies++;
  PetscCall(PetscTime(&t1));
  m->t_assembly += t1 - t0;
  PetscFunctionReturn(0);
}

/* Sets the constrained dofs of u to their prescribed values at load factor lambda. */
PetscErrorCode PDModelApplyBoundaryValues(PDModel *m, PetscReal lambda, Vec u) {
  const PetscScalar *ur, *fx;
  PetscScalar       *uu;

  PetscFunctionBeginUser;
  m->lambda = lambda;
  PetscCall(VecGetArray(u, &uu));
  PetscCall(VecGetArrayRead(m->u_ref, &ur));
  PetscCall(VecGetArrayRead(m->fixed, &fx));
  for (PetscInt k = 0; k < m->bs * m->lat->nowned; k++)
    if (PetscRealPart(fx[k]) != 0) uu[k] = lambda * ur[k];
  PetscCall(VecRestoreArrayRead(m->fixed, &fx));
  PetscCall(VecRestoreArrayRead(m->u_ref, &ur));
  PetscCall(VecRestoreArray(u, &uu));
  PetscFunctionReturn(0);
}

/* Bond e's force over its length at u (local) before the history commit, for PDModelMeasure. */
PetscErrorCode PDModelNoteForceChange(PDModel *m, const PetscScalar *u, PetscInt e) {
  PetscReal xi[3];

  PetscFunctionBeginUser;
  if (m->nfchange < 0) PetscFunctionReturn(0);
  if (m->nfchange == m->fchange_cap) {            /* grown as the limiter's record of changed bonds is (limiter.c Raise) */
    if (m->fchange_cap >= m->bonds->nbonds / 8) { /* beyond that the whole loop costs about as much */
      m->nfchange = -1;
      PetscFunctionReturn(0);
    }
    m->fchange_cap = PetscMax(256, 2 * m->fchange_cap);
    PetscCall(PetscRealloc(sizeof(PetscInt) * m->fchange_cap, &m->fchange_bond));
    PetscCall(PetscRealloc(sizeof(PetscReal) * m->fchange_cap, &m->fchange_g));
  }
  m->fchange_bond[m->nfchange] = e;
  m->fchange_g[m->nfchange++]  = PDModelBondForceSmall(m, u, e, xi);
  PetscFunctionReturn(0);
}

/* The internal force at u into F from the last residual's (at u, with the history before the commit) and the
   change of the bonds listed since (PDModelNoteForceChange), where every rank has such a list; *done says
   whether it did. */
static PetscErrorCode InternalForceByChange(PDModel *m, Vec u, Vec F, PetscBool *done) {
  PetscBool          mine, all, same = PETSC_FALSE;
  const PetscScalar *ul;
  PetscScalar       *f;
  Vec                uloc;

  PetscFunctionBeginUser;
  *done            = PETSC_FALSE;
  mine             = m->fchange_ready && m->nfchange >= 0 && m->f_last_valid && m->lambda == m->ka_lambda ? PETSC_TRUE : PETSC_FALSE;
  m->fchange_ready = PETSC_FALSE;
  PetscCall(MPIU_Allreduce(&mine, &all, 1, MPIU_BOOL, MPI_LAND, m->lat->comm));
  if (!all) PetscFunctionReturn(0);
  PetscCall(VecEqual(u, m->ka_u, &same));
  if (!same) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(PD_LOG.force, 0, 0, 0, 0));
  PetscCall(VecCopy(m->f_last, F));
  PetscCall(PDModelScatterToLocal(m, u, &ul, &uloc));
  PetscCall(VecGetArray(F, &f));
  PDModelForceChangeLocal(m, ul, m->nfchange, m->fchange_bond, m->fchange_g, f);
  PetscCall(VecRestoreArray(F, &f));
  PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  PetscCall(PetscLogEventEnd(PD_LOG.force, 0, 0, 0, 0));
  m->forces_by_change++;
  *done = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* Curve quantities: load (applied force, or reaction of a displacement region along its direction),
   mean displacement of the displacement region along the load direction, and the CMOD gauge. Leaves the
   internal force f_int(u) in m->f_work for the drivers' external-work sums; after an IMPL-EX step's
   commit that force comes from the last residual's and the bonds the commit changes (InternalForceByChange). */
PetscErrorCode PDModelMeasure(PDModel *m, Vec u, PetscReal *load, PetscReal *disp, PetscReal *cmod) {
  PetscScalar v;
  PetscBool   done = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (m->keep_force) PetscCall(InternalForceByChange(m, u, m->f_work, &done)); /* decided alike on every rank */
  if (!done) PetscCall(PDModelInternalForce(m, u, m->f_work));
  if (m->scene->region[m->scene->load_regions[0]].kind == PD_REGION_FORCE)
    *load = m->lambda * m->force_magnitude;
  else {
    PetscCall(VecDot(m->f_work, m->load_pattern, &v));
    *load = PetscRealPart(v);
  }
  PetscCall(VecDot(u, m->disp_pattern, &v));
  *disp = PetscRealPart(v);
  *cmod = PD_NAN;
  if (m->scene->has_cmod) {
    PetscCall(VecDot(u, m->cmod_pattern, &v));
    *cmod = PetscRealPart(v);
  }
  PetscFunctionReturn(0);
}

/* x with its ghost entries, in the model's work vector x_local, whose local form's array *xl is (with
   eliminate, constrained entries zeroed: their columns take no part in a product); the tangent products'
   common start, undone by PDModelRestoreProductInput. */
PetscErrorCode PDModelGetProductInput(PDModel *m, Vec x, PetscBool eliminate, PetscScalar **xl, Vec *xloc) {
  PetscFunctionBeginUser;
  if (!m->x_local) PetscCall(VecDuplicate(m->u_local, &m->x_local));
  PetscCall(VecCopy(x, m->x_local));
  PetscCall(VecGhostUpdateBegin(m->x_local, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(m->x_local, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostGetLocalForm(m->x_local, xloc));
  PetscCall(VecGetArray(*xloc, xl));
  for (PetscInt k = 0; eliminate && k < m->bs * m->lat->nlocal; k++)
    if (m->fixed_local[k]) (*xl)[k] = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode PDModelRestoreProductInput(PDModel *m, PetscScalar **xl, Vec *xloc) {
  PetscFunctionBeginUser;
  PetscCall(VecRestoreArray(*xloc, xl));
  PetscCall(VecGhostRestoreLocalForm(m->x_local, xloc));
  PetscFunctionReturn(0);
}

/* y = K x on every owned dof from the bond scalars ka, kb at u (PDModelTangentApplyLocal; u NULL: at rest;
   scaled: ka holds ka / |xi|^2, small kinematics).
   With eliminate, constrained columns take no part: their entries of x count as zero. The displacement
   is gathered only under finite kinematics, where a bond's direction follows it. */
PetscErrorCode PDModelTangentApplyScalars(PDModel *m, Vec u, const PetscReal *ka, const PetscReal *kb, PetscBool scaled,
                                          PetscBool eliminate, Vec x, Vec y) {
  const PetscScalar *ul     = NULL;
  const PetscBool    finite = m->scene->kinematics == PD_KINEMATICS_FINITE ? PETSC_TRUE : PETSC_FALSE;
  PetscScalar       *xl, *yl, *yy;
  Vec                uloc = NULL, xloc, yloc;

  PetscFunctionBeginUser;
  PetscCall(PDModelGetProductInput(m, x, eliminate, &xl, &xloc));
  if (finite && u)
    PetscCall(PDModelScatterToLocal(m, u, &ul, &uloc));
  else if (finite) {
    PetscCall(VecGhostGetLocalForm(m->u_local, &uloc));
    PetscCall(VecZeroEntries(uloc));
    PetscCall(VecGetArrayRead(uloc, &ul));
  }
  PetscCall(VecGhostGetLocalForm(m->f_local, &yloc));
  PetscCall(VecGetArray(yloc, &yl));
  PetscCall(PDModelTangentApplyLocal(m, ul, ka, kb, scaled, xl, yl));
  PetscCall(VecGetArray(y, &yy));
  PetscCall(PetscArraycpy(yy, yl, m->bs * m->lat->nowned)); /* ghost entries are partial sums: dropped */
  PetscCall(VecRestoreArray(y, &yy));
  PetscCall(VecRestoreArray(yloc, &yl));
  PetscCall(VecGhostRestoreLocalForm(m->f_local, &yloc));
  PetscCall(PDModelRestoreProductInput(m, &xl, &xloc));
  if (uloc) PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  PetscFunctionReturn(0);
}

/* y = K x on every dof from the bond scalars at u (recomputed first when refresh is set), or from the
   linearised micromodulus at rest when u is NULL. */
static PetscErrorCode TangentApply(PDModel *m, Vec u, Vec x, Vec y, PetscBool refresh) {
  PetscFunctionBeginUser;
  if (u && refresh && m->ka) {
    const PetscScalar *ul;
    Vec                uloc;
    PetscCall(PDModelScatterToLocal(m, u, &ul, &uloc));
    PetscCall(PDModelTangentScalars(m, ul, m->ka, m->kb, NULL));
    PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  }
  PetscCall(PDModelTangentApplyScalars(m, u, u ? m->ka : NULL, u ? m->kb : NULL, PETSC_FALSE, PETSC_FALSE, x, y));
  PetscFunctionReturn(0);
}

/* y = K(u) x on every dof, constrained ones included (no elimination): the tangent whose bond scalars
   the last PDModelJacobian computed (at the same u), or the linearised micromodulus of a model whose
   tangent is constant. Path following needs the coupling of free and constrained dofs, which the
   assembled matrix drops. */
PetscErrorCode PDModelTangentApply(PDModel *m, Vec u, Vec x, Vec y) {
  PetscFunctionBeginUser;
  PetscCall(TangentApply(m, u, x, y, PETSC_FALSE));
  PetscFunctionReturn(0);
}

/* The same, the bond scalars first recomputed at u when refresh is set. */
PetscErrorCode PDModelTangentApplyAt(PDModel *m, Vec u, Vec x, Vec y, PetscBool refresh) {
  PetscFunctionBeginUser;
  PetscCall(TangentApply(m, u, x, y, refresh));
  PetscFunctionReturn(0);
}

/* y = K_0 x on every dof: the undamaged elastic stiffness in the reference configuration (the linearised
   micromodulus, THEORY.md Eq. 4.13), whatever the bond histories and the kinematics. */
PetscErrorCode PDModelElasticApply(PDModel *m, Vec x, Vec y) {
  PetscFunctionBeginUser;
  PetscCall(TangentApply(m, NULL, x, y, PETSC_FALSE));
  PetscFunctionReturn(0);
}

PetscErrorCode PDModelSteelStress(PDModel *m, Vec u, PetscReal *stress, PetscReal *slip) {
  const PetscScalar *ul;
  Vec                loc;
  PetscReal          mine[2], all[2];

  PetscFunctionBeginUser;
  *stress = *slip = 0;
  if (!m->scene->nbars) PetscFunctionReturn(0);
  PetscCall(PDModelScatterToLocal(m, u, &ul, &loc));
  mine[0] = PDModelSteelStressLocal(m, ul);
  mine[1] = PDModelSlipLocal(m, ul);
  PetscCall(PDModelRestoreLocal(m, &ul, &loc));
  PetscCall(MPIU_Allreduce(mine, all, 2, MPIU_REAL, MPIU_MAX, m->lat->comm));
  *stress = all[0];
  *slip   = all[1];
  PetscFunctionReturn(0);
}

/* The bars' nodal fields at u (PDModelBarFieldsLocal), into vectors of one entry per owned node; slip may be NULL. */
PetscErrorCode PDModelBarFields(PDModel *m, Vec u, Vec stress, Vec plastic, Vec slip) {
  const PetscScalar *ul;
  PetscScalar       *st, *pl, *sl = NULL;
  Vec                loc;

  PetscFunctionBeginUser;
  PetscCall(PDModelScatterToLocal(m, u, &ul, &loc));
  PetscCall(VecGetArray(stress, &st));
  PetscCall(VecGetArray(plastic, &pl));
  if (slip) PetscCall(VecGetArray(slip, &sl));
  PDModelBarFieldsLocal(m, ul, st, pl, sl);
  if (slip) PetscCall(VecRestoreArray(slip, &sl));
  PetscCall(VecRestoreArray(plastic, &pl));
  PetscCall(VecRestoreArray(stress, &st));
  PetscCall(PDModelRestoreLocal(m, &ul, &loc));
  PetscFunctionReturn(0);
}

/* The bond closest to crushing over all ranks (PDModelCrushingLocal): -s / eps_cu, its stretch s and its
   midpoint; of ratios that tie the smallest global bond id, from the lowest rank that holds it (a bond
   with a ghost end is held by two). Off (ratio -PETSC_MAX_REAL, s 0) where no material has -pd_eps_cu. */
PetscErrorCode PDModelCrushing(PDModel *m, Vec u, PetscBool strain_state_at_u, PetscReal *ratio, PetscReal *s_min, PetscReal at[3]) {
  const PetscScalar *th, *ul;
  Vec                loc, uloc;
  PetscReal          mine, top, buf[5] = {0, 0, 0, 0, 0};
  PetscInt64         gid, gmin;
  PetscMPIInt        rank, size, holder, cand;

  PetscFunctionBeginUser;
  *ratio = -PETSC_MAX_REAL;
  *s_min = 0;
  for (PetscInt a = 0; a < 3; a++) at[a] = 0;
  if (!PDSceneHasCrushingStrain(m->scene)) PetscFunctionReturn(0);
  PetscCall(PDModelScatterToLocal(m, u, &ul, &uloc));
  if (!strain_state_at_u) PetscCall(PDModelNodalDilatation(m, ul));
  PetscCall(VecGhostGetLocalForm(m->dilatation, &loc));
  PetscCall(VecGetArrayRead(loc, &th));
  PDModelCrushingLocal(m, ul, th, &mine, &gid, &buf[1], &buf[2]);
  buf[0] = mine;
  PetscCall(VecRestoreArrayRead(loc, &th));
  PetscCall(VecGhostRestoreLocalForm(m->dilatation, &loc));
  PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  PetscCall(MPIU_Allreduce(&mine, &top, 1, MPIU_REAL, MPIU_MAX, m->lat->comm));
  PetscCallMPI(MPI_Comm_rank(m->lat->comm, &rank));
  PetscCallMPI(MPI_Comm_size(m->lat->comm, &size));
  if (mine < top * (1 - PD_CRUSH_TIE)) gid = INT64_MAX;
  PetscCall(MPIU_Allreduce(&gid, &gmin, 1, MPIU_INT64, MPI_MIN, m->lat->comm));
  cand = gid == gmin ? rank : size;
  PetscCall(MPIU_Allreduce(&cand, &holder, 1, MPI_INT, MPI_MIN, m->lat->comm));
  PetscCallMPI(MPI_Bcast(buf, 5, MPIU_REAL, holder, m->lat->comm));
  *ratio = buf[0];
  *s_min = buf[1];
  for (PetscInt a = 0; a < 3; a++) at[a] = buf[2 + a];
  PetscFunctionReturn(0);
}

/* Strain energy stored in the bonds and energy dissipated by damage, summed over ranks (J). */
PetscErrorCode PDModelEnergy(PDModel *m, Vec u, PetscReal *stored, PetscReal *dissipated) {
  const PetscScalar *ul;
  Vec                loc;
  PetscReal          e[2], g[2];

  PetscFunctionBeginUser;
  PetscCall(PDModelScatterToLocal(m, u, &ul, &loc));
  PetscCall(PDModelEnergiesLocal(m, ul, &e[0], &e[1]));
  PetscCall(PDModelRestoreLocal(m, &ul, &loc));
  PetscCall(MPIU_Allreduce(e, g, 2, MPIU_REAL, MPIU_SUM, m->lat->comm));
  *stored     = g[0];
  *dissipated = g[1];
  PetscFunctionReturn(0);
}

/* du . (K(u0) - K(u1)) du, du = u1 - u0, under small kinematics, both tangents with the history the model
   holds (PDModelTangentChangeLocal): the bond scalars are not stored and no product is formed. */
PetscErrorCode PDModelTangentChange(PDModel *m, Vec u0, Vec u1, PetscReal *change) {
  const PetscScalar *ul;
  PetscScalar       *vl;
  Vec                uloc, vloc;
  PetscReal          mine;

  PetscFunctionBeginUser;
  PetscCheck(m->scene->kinematics == PD_KINEMATICS_SMALL, m->lat->comm, PETSC_ERR_SUP,
             "the tangent's change by bonds needs small kinematics");
  PetscCall(PDModelScatterToLocal(m, u0, &ul, &uloc));
  PetscCall(PDModelGetProductInput(m, u1, PETSC_FALSE, &vl, &vloc));
  mine = PDModelTangentChangeLocal(m, ul, vl);
  PetscCall(PDModelRestoreProductInput(m, &vl, &vloc));
  PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  PetscCall(MPIU_Allreduce(&mine, change, 1, MPIU_REAL, MPIU_SUM, m->lat->comm));
  PetscFunctionReturn(0);
}

/* Gershgorin bound on the undamaged elastic stiffness K_0, per dof: row (i, a) holds per bond the block
   (c/|xi|) e e^T on node i's diagonal and its negative in column j, whose entries sum in absolute value to
   2 (c/|xi|) |e_a| sum_b |e_b|. No eigenvalue of M^-1 K_0 (M diagonal) exceeds the largest row sum over its
   dof's mass, constrained dofs eliminated or not (a principal submatrix has smaller rows and eigenvalues).
   Damage, secant and softening slopes only lower bond stiffnesses; finite kinematics raises the tangent
   by a relative amount of the order of the bond stretch. */
PetscErrorCode PDModelStiffnessRowBound(const PDModel *m, Vec row) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscInt   bs  = m->bs;
  PetscScalar     *r;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(row, &r));
  for (PetscInt i = 0; i < lat->nowned; i++) {
    for (PetscInt a = 0; a < bs; a++) r[bs * i + a] = 0;
    for (PetscInt p = bd->inc_start[i]; p < bd->inc_start[i + 1]; p++) {
      const PetscInt   e  = bd->inc_bond[p];
      const PetscReal *xa = &lat->x[3 * bd->a[e]], *xb = &lat->x[3 * bd->b[e]];
      PetscReal        L = 0, sum = 0;
      for (PetscInt a = 0; a < bs; a++) L += (xb[a] - xa[a]) * (xb[a] - xa[a]);
      L = PetscSqrtReal(L);
      for (PetscInt a = 0; a < bs; a++) sum += PetscAbsReal(xb[a] - xa[a]) / L;
      for (PetscInt a = 0; a < bs; a++) r[bs * i + a] += 2 * PDBondStiffness(bd, e) / L * PetscAbsReal(xb[a] - xa[a]) / L * sum;
    }
  }
  PetscCall(VecRestoreArray(row, &r));
  PetscFunctionReturn(0);
}

/* Physical effects the scene calls for (discretisation corrections are not effects). */
PetscInt PDModelEffects(const PDModel *m, const char *names[PD_MAX_EFFECTS]) {
  const PDScene *sc   = m->scene;
  PetscBool      soft = PETSC_FALSE, brk = PETSC_FALSE;
  PetscInt       n = 0;

  for (PetscInt k = 0; k < sc->nmaterials; k++) {
    if (sc->material[k].law != PD_LAW_ELASTIC) brk = PETSC_TRUE;
    if (sc->material[k].law != PD_LAW_ELASTIC && sc->material[k].law != PD_LAW_LINEAR) soft = PETSC_TRUE;
  }
  names[n++] = "elasticity";
  if (soft) names[n++] = "softening_damage";
  if (brk) names[n++] = "bond_breaking";
  if (m->shift) names[n++] = "crushing";                            /* allocated where a material's -pd_fc raises thresholds */
  if (PDSceneHasCrushingStrain(sc)) names[n++] = "crushing_strain"; /* a failure criterion: the run ends where the concrete crushes */
  if (sc->nbars) names[n++] = "steel_plasticity";
  for (PetscInt k = 0; k < sc->nbars; k++)
    if (sc->bar[k].rupture > 0) {
      names[n++] = "steel_rupture";
      break;
    }
  for (PetscInt k = 0; k < sc->nbars; k++)
    if (sc->bar[k].slip) {
      names[n++] = "bond_slip";
      break;
    }
  if (sc->kinematics == PD_KINEMATICS_FINITE) names[n++] = "geometric_nonlinearity";
  if (sc->explicit_mode) names[n++] = "inertia";
  return n;
}
