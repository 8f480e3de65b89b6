/* Damage limiter and bond history.

   A bond event is a bond entering the softening branch for the first time (passing s0), passing into
   the next of the -pd_limiter_sublevels parts of that branch, or breaking (passing sc). Within a load
   step the history kappa_n of the last accepted step is fixed and every bond is allowed a level
   (elastic, softening part 1 to K, broken); a bond whose stretch passes the threshold of its level is
   held there (kernel.c: secant beyond it, a positive slope) and becomes a candidate. After each Newton stage the limiter lets the
   max_events most critical candidates (largest stretch over threshold; ties by global bond id) move up
   one level. The decision is global and deterministic: every rank proposes its own best candidates,
   all ranks see the same merged list, so the sequence does not depend on the number of ranks. */
#include "pd_model.h"
#include "kernel.h"
#include "pd_log.h"

typedef struct {
  PetscReal  crit;
  PetscInt64 id;
} Candidate;

static int CompareCandidates(const void *pa, const void *pb) {
  const Candidate *a = (const Candidate *)pa, *b = (const Candidate *)pb;
  if (a->crit != b->crit) return a->crit > b->crit ? -1 : 1;
  return a->id < b->id ? -1 : (a->id > b->id ? 1 : 0);
}

/* Moves the k best of c[0..n-1] (CompareCandidates' order, a total one) to c[0..k-1], in no particular order:
   a quickselect, linear in n on average. Only the k best are read, and sorting every candidate cost n log n
   per limiter stage: in the brittle drop of a large model, where nearly every bond of the tension face is a
   candidate, stack samples found most of a stage there. The set selected is the sort's. */
static void SelectBest(Candidate *c, PetscInt n, PetscInt k) {
  PetscInt lo = 0, hi = n - 1;
  while (lo < hi && k > lo && k <= hi) {
    const PetscInt mid = lo + (hi - lo) / 2;
    Candidate      pivot, t;
    PetscInt       store = lo;
    /* the median of three as the pivot, moved to hi */
    if (CompareCandidates(&c[mid], &c[lo]) < 0) t = c[mid], c[mid] = c[lo], c[lo] = t;
    if (CompareCandidates(&c[hi], &c[lo]) < 0) t = c[hi], c[hi] = c[lo], c[lo] = t;
    if (CompareCandidates(&c[mid], &c[hi]) < 0) t = c[mid], c[mid] = c[hi], c[hi] = t;
    pivot = c[hi];
    for (PetscInt i = lo; i < hi; i++)
      if (CompareCandidates(&c[i], &pivot) < 0) t = c[i], c[i] = c[store], c[store++] = t;
    c[hi] = c[store], c[store] = pivot; /* c[lo..store-1] come before the pivot, c[store+1..hi] after it */
    if (store + 1 == k || store == k) return;
    if (store + 1 < k)
      lo = store + 1;
    else
      hi = store - 1;
  }
}

static int CompareIds(const void *pa, const void *pb) {
  const PetscInt64 a = *(const PetscInt64 *)pa, b = *(const PetscInt64 *)pb;
  return a < b ? -1 : (a > b ? 1 : 0);
}

static PetscReal Threshold(const PDModel *m, PetscInt e) {
  const PDLaw    *law = &m->law[m->bonds->material[e]];
  const PDLawBond t   = PDModelBondThresholds(m, e, law);
  return PDLawNextThreshold(law, &t, m->level[e]);
}

/* A bond moves up one level; the static driver's next residual recomputes only the rows of such bonds
   (model.c PDModelResidual), so they are recorded, up to an eighth of the bonds (beyond that a whole
   evaluation costs about as much). */
static PetscErrorCode Raise(PDModel *m, PetscInt e) {
  PetscFunctionBeginUser;
  m->level[e]++;
  if (!m->track_grants || m->nchanged < 0) PetscFunctionReturn(0);
  if (m->nchanged == m->changed_cap) {
    if (m->changed_cap >= m->bonds->nbonds / 8) {
      m->nchanged = -1;
      PetscFunctionReturn(0);
    }
    m->changed_cap = PetscMax(256, 2 * m->changed_cap);
    PetscCall(PetscRealloc(sizeof(PetscInt) * m->changed_cap, &m->changed));
  }
  m->changed[m->nchanged++] = e;
  PetscFunctionReturn(0);
}

/* The bonds whose stretch at u reaches the threshold of their allowed level, in bond order, with their
   criticality s / threshold (>= 1). */
typedef struct {
  PetscInt  *bond, n, cap;
  PetscReal *crit;
} Held;

static PetscErrorCode HeldAdd(Held *h, PetscInt e, PetscReal crit) {
  PetscFunctionBeginUser;
  if (h->n == h->cap) {
    h->cap = PetscMax(64, 2 * h->cap);
    PetscCall(PetscRealloc(sizeof(PetscInt) * h->cap, &h->bond));
    PetscCall(PetscRealloc(sizeof(PetscReal) * h->cap, &h->crit));
  }
  h->bond[h->n]   = e;
  h->crit[h->n++] = crit;
  PetscFunctionReturn(0);
}

PetscErrorCode PDModelGrantEvents(PDModel *m, Vec u, PetscInt max_events, PetscInt *ncandidates, PetscInt *granted) {
  const PDBonds     *bd   = m->bonds;
  const PDLattice   *lat  = m->lat;
  MPI_Comm           comm = lat->comm;
  const PetscScalar *ul;
  Vec                uloc;
  Held               held = {NULL, 0, 0, NULL};
  Candidate         *mine, *all = NULL;
  PetscInt64        *ids   = NULL;
  PetscInt           nmine = 0, nlocal_cand = 0, ntake, nall = 0, nparts = 0, parts;
  PetscMPIInt        size, nsend, *counts, *displs;

  PetscFunctionBeginUser;
  *ncandidates = *granted = 0;
  if (!m->softening) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(PD_LOG.limiter, 0, 0, 0, 0));
  /* A bond passing from one part of its softening branch to the next (-pd_limiter_sublevels) neither
     enters softening nor breaks: it goes on at once, one part per stage, and only the other events are
     counted and capped */
  PetscCall(PDModelScatterToLocal(m, u, &ul, &uloc));
  for (PetscInt e0 = 0; e0 < bd->nbonds; e0 += PD_STRETCH_BLOCK) {
    const PetscInt n = PetscMin(PD_STRETCH_BLOCK, bd->nbonds - e0);
    PetscReal      s[PD_STRETCH_BLOCK];
    PDModelBondStretches(m, ul, e0, n, s);
    for (PetscInt k = 0; k < n; k++) {
      const PetscInt e   = e0 + k;
      const PDLaw   *law = &m->law[bd->material[e]];
      PetscReal      crit;
      if (law->kind == PD_LAW_ELASTIC) continue;      /* no threshold: its onset is PETSC_MAX_REAL */
      if (s[k] < m->onset[bd->material[e]]) continue; /* below every threshold of its material */
      crit = s[k] / Threshold(m, e);
      if (crit < 1) continue;
      if (law->kind != PD_LAW_LINEAR && m->level[e] >= PD_BOND_SOFTENING && m->level[e] < law->sublevels) {
        PetscCall(Raise(m, e));
        if (PDBondCountedHere(lat, bd, e)) nparts++;
      } else {
        PetscCall(HeldAdd(&held, e, crit));
        nlocal_cand++;
      }
    }
  }
  PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  PetscCall(MPIU_Allreduce(&nparts, &parts, 1, MPIU_INT, MPI_SUM, comm));
  PetscCall(PetscMalloc1(PetscMax(1, nlocal_cand), &mine));
  for (PetscInt k = 0; k < held.n; k++) {
    if (PDBondCountedHere(lat, bd, held.bond[k])) {
      mine[nmine].crit = held.crit[k];
      mine[nmine].id   = PDBondGlobalId(lat, bd, held.bond[k]);
      nmine++;
    }
  }
  PetscCall(MPIU_Allreduce(&nmine, ncandidates, 1, MPIU_INT, MPI_SUM, comm));
  if (*ncandidates == 0) {
    /* only parts went on */
  } else if (max_events == 0 || *ncandidates <= max_events) {
    /* every candidate goes: each rank decides its own copies alike, no exchange needed */
    for (PetscInt k = 0; k < held.n; k++) PetscCall(Raise(m, held.bond[k]));
    *granted = *ncandidates;
  } else {
    /* each rank's best max_events cover the global best max_events */
    ntake = PetscMin(nmine, max_events);
    SelectBest(mine, nmine, ntake);
    PetscCallMPI(MPI_Comm_size(comm, &size));
    PetscCall(PetscMalloc2(size, &counts, size, &displs));
    nsend = (PetscMPIInt)(ntake * (PetscInt)sizeof(Candidate));
    PetscCallMPI(MPI_Allgather(&nsend, 1, MPI_INT, counts, 1, MPI_INT, comm));
    displs[0] = 0;
    for (PetscMPIInt r = 1; r < size; r++) displs[r] = displs[r - 1] + counts[r - 1];
    nall = (displs[size - 1] + counts[size - 1]) / (PetscInt)sizeof(Candidate);
    PetscCall(PetscMalloc2(nall, &all, max_events, &ids));
    PetscCallMPI(MPI_Allgatherv(mine, nsend, MPI_BYTE, all, counts, displs, MPI_BYTE, comm));
    SelectBest(all, nall, max_events);
    for (PetscInt k = 0; k < max_events; k++) ids[k] = all[k].id;
    qsort(ids, (size_t)max_events, sizeof(PetscInt64), CompareIds);
    for (PetscInt k = 0; k < held.n; k++) {
      const PetscInt64 id = PDBondGlobalId(lat, bd, held.bond[k]);
      if (bsearch(&id, ids, (size_t)max_events, sizeof(PetscInt64), CompareIds)) PetscCall(Raise(m, held.bond[k]));
    }
    *granted = max_events;
    PetscCall(PetscFree2(all, ids));
    PetscCall(PetscFree2(counts, displs));
  }
  *ncandidates += parts;
  *granted += parts;
  PetscCall(PetscFree(mine));
  PetscCall(PetscFree(held.bond));
  PetscCall(PetscFree(held.crit));
  PetscCall(PetscLogEventEnd(PD_LOG.limiter, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* A bond is softened when its history lies on the softening branch (s0 < kappa_n < sc): only then does
   its force have a kink at kappa_n (below s0 envelope and secant coincide). */
static PetscBool Softened(const PDModel *m, PetscInt e) {
  const PDLaw    *law = &m->law[m->bonds->material[e]];
  const PDLawBond tb = PDModelBondThresholds(m, e, law), *t = &tb;
  return law->kind != PD_LAW_ELASTIC && law->kind != PD_LAW_LINEAR && m->kappa[e] > t->s0 && m->kappa[e] < t->sc ? PETSC_TRUE : PETSC_FALSE;
}

/* Adds bond e to the broken (count[0]) or softening (count[1]) bonds by its committed history, if this rank
   counts it. A history below its material's onset is neither, whatever the bond's own thresholds. */
static inline void CountBond(const PDModel *m, PetscInt e, PetscInt64 count[3]) {
  const PDBonds *bd  = m->bonds;
  const PDLaw   *law = &m->law[bd->material[e]];
  if (m->kappa[e] < m->onset[bd->material[e]] || law->kind == PD_LAW_ELASTIC || law->kind == PD_LAW_SLIP ||
      !PDBondCountedHere(m->lat, bd, e))
    return;
  if (m->kappa[e] >= PDModelBondThresholds(m, e, law).sc)
    count[0]++;
  else if (Softened(m, e))
    count[1]++;
}

/* The global counts from this rank's bond counts (CountBond) and its yielded bar segments. */
static PetscErrorCode CountsFinish(PDModel *m, PetscInt64 count[3]) {
  const PDBonds *bd = m->bonds;
  PetscInt64     total[3];

  PetscFunctionBeginUser;
  for (PetscInt sg = 0; sg < bd->nseg; sg++)
    if ((m->sp_n[sg] != 0 || m->ruptured_n[sg]) && PDBondCountedHere(m->lat, bd, bd->seg_bond[sg])) count[2]++;
  PetscCall(MPIU_Allreduce(count, total, 3, MPIU_INT64, MPI_SUM, m->lat->comm));
  m->broken          = total[0];
  m->softening_bonds = total[1];
  m->yielded         = (PetscInt)total[2];
  PetscFunctionReturn(0);
}

/* Broken and softening bonds (global, each bond counted once) from the committed history. */
PetscErrorCode PDModelCountDamage(PDModel *m) {
  PetscInt64 count[3] = {0, 0, 0}; /* broken, softening, yielded bar segments */

  PetscFunctionBeginUser;
  if (!m->softening && !m->scene->nbars) PetscFunctionReturn(0);
  for (PetscInt e = 0; m->softening && e < m->bonds->nbonds; e++) CountBond(m, e, count);
  PetscCall(CountsFinish(m, count));
  PetscFunctionReturn(0);
}

/* Commits the state u: each bond's largest stretch (held below the threshold its level has not passed),
   the limiter's levels, the bar segments' plastic state, the crushing's threshold rise, the damage counts;
   with energy, the stored and dissipated energy at u with the committed history (PDModelEnergy), which a
   model without bar segments and crushing sums in the same loop over the stretches. With change, also the
   end-slope term du . (K(u0) - K(u)) du of the step from u0 (at load factor lambda0) to u, both tangents
   with the history before the commit (PDModelTangentChange, small kinematics), which is the one committed
   at u0; a softening model takes it in the same loop, from the stretches at u the commit reads. The
   tangent scalars kept from the last residual belong to the history before: they are not reused. */
PetscErrorCode PDModelCommitHistory(PDModel *m, Vec u, PetscReal energy[2], Vec u0, PetscReal lambda0, PetscReal *change) {
  const PDBonds     *bd       = m->bonds;
  const PetscBool    fuse     = energy && m->softening && !bd->nseg_global && !m->shift ? PETSC_TRUE : PETSC_FALSE;
  const PetscBool    fuse_c   = change && m->softening ? PETSC_TRUE : PETSC_FALSE;
  PetscInt64         count[3] = {0, 0, 0};
  PetscReal          local[2] = {0, 0}, csum = 0;
  const PetscScalar *ul;
  const PetscScalar *u0l = NULL;
  Vec                uloc, u0loc;

  PetscFunctionBeginUser;
  m->ka_at_residual = PETSC_FALSE;
  if (change && !fuse_c) { /* before the history moves */
    const PetscReal lam = m->lambda;
    m->lambda           = lambda0; /* u0's constrained values */
    PetscCall(PDModelTangentChange(m, u0, u, change));
    m->lambda = lam;
  }
  /* decided alike on every rank (global counts): the branches below make different collective calls */
  if (!m->softening && !bd->nseg_global && !m->dilatation) { /* no history, no bars, no crushing: nothing to commit or read */
    if (energy) PetscCall(PDModelEnergy(m, u, &energy[0], &energy[1]));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscLogEventBegin(PD_LOG.history, 0, 0, 0, 0));
  PetscCall(PDModelScatterToLocal(m, u, &ul, &uloc));
  if (fuse_c) {
    PetscCheck(m->scene->kinematics == PD_KINEMATICS_SMALL, m->lat->comm, PETSC_ERR_SUP,
               "the tangent's change by bonds needs small kinematics");
    PetscCall(PDModelScatterSecondToLocal(m, u0, lambda0, &u0l, &u0loc));
  }
  if (m->dilatation) PetscCall(PDModelNodalDilatation(m, ul)); /* the strain state, from the same local values */
  for (PetscInt e0 = 0; m->softening && e0 < bd->nbonds; e0 += PD_STRETCH_BLOCK) {
    const PetscInt n = PetscMin(PD_STRETCH_BLOCK, bd->nbonds - e0);
    PetscReal      s[PD_STRETCH_BLOCK];
    PDModelBondStretches(m, ul, e0, n, s);
    if (fuse_c) PDModelTangentChangeBlock(m, u0l, ul, e0, n, NULL, s, &csum); /* the history is u0's commit */
    for (PetscInt k = 0; k < n; k++) {
      const PetscInt  e   = e0 + k;
      const PetscReal cap = s[k] < m->onset[bd->material[e]] * (1 - 1e-12) ? PETSC_MAX_REAL : Threshold(m, e);
      m->kappa[e]         = PetscMax(m->kappa[e], PetscMin(s[k], cap * (1 - 1e-12)));
      m->level_n[e]       = m->level[e];
      CountBond(m, e, count); /* the crushing's rise below leaves these counts as they are: it raises bonds below s0 only */
    }
    if (fuse) PDModelBondEnergies(m, e0, n, s, &local[0], &local[1]);
  }
  if (fuse_c) PetscCall(PDModelRestoreSecondLocal(m, &u0l, &u0loc));
  for (PetscInt sg = 0; sg < bd->nseg; sg++) PDModelCommitSegment(m, sg, PDModelBondStretch(m, ul, bd->seg_bond[sg]));
  PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  PetscCall(PDModelConfine(m));
  PetscCall(CountsFinish(m, count));
  PetscCall(PetscLogEventEnd(PD_LOG.history, 0, 0, 0, 0));
  if (fuse_c) PetscCall(MPIU_Allreduce(&csum, change, 1, MPIU_REAL, MPIU_SUM, m->lat->comm));
  if (fuse)
    PetscCall(MPIU_Allreduce(local, energy, 2, MPIU_REAL, MPIU_SUM, m->lat->comm));
  else if (energy)
    PetscCall(PDModelEnergy(m, u, &energy[0], &energy[1]));
  PetscFunctionReturn(0);
}

/* Freezes every softened bond on the branch its stretch at u lies on; the others stay free. */
PetscErrorCode PDModelFreezeBranches(PDModel *m, Vec u, unsigned char *branch, PetscInt *nfrozen) {
  const PetscScalar *ul;
  Vec                uloc;
  PetscInt           mine = 0;

  PetscFunctionBeginUser;
  m->branch = NULL;
  PetscCall(PDModelScatterToLocal(m, u, &ul, &uloc));
  for (PetscInt e = 0; e < m->bonds->nbonds; e++) {
    branch[e] = PD_BRANCH_FREE;
    if (!Softened(m, e)) continue;
    branch[e] = PDModelBondStretch(m, ul, e) >= m->kappa[e] ? PD_BRANCH_ENVELOPE : PD_BRANCH_SECANT;
    if (PDBondCountedHere(m->lat, m->bonds, e)) mine++;
  }
  PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  PetscCall(MPIU_Allreduce(&mine, nfrozen, 1, MPIU_INT, MPI_SUM, m->lat->comm));
  m->branch = branch;
  PetscFunctionReturn(0);
}

/* Moves frozen bonds whose stretch at u lies on the other side of their history to that side's branch:
   an envelope bond unloading below kappa_n goes secant, a secant bond stretched past kappa_n loads. A
   bond that has to flip back (its equilibrium lies at its kink: on the secant it loads, on the envelope
   it unloads) goes to PD_BRANCH_KINK instead, the real law with the secant slope, so that a band of such
   bonds cannot swap branches in a cycle. */
PetscErrorCode PDModelFlipBranches(PDModel *m, Vec u, PetscInt *nflipped, PetscInt *nkink) {
  unsigned char     *branch  = m->branch;
  PetscInt           mine[2] = {0, 0}, total[2];
  const PetscScalar *ul;
  Vec                uloc;

  PetscFunctionBeginUser;
  PetscCheck(branch, m->lat->comm, PETSC_ERR_ORDER, "no frozen branches to flip");
  PetscCall(PDModelScatterToLocal(m, u, &ul, &uloc));
  for (PetscInt e = 0; e < m->bonds->nbonds; e++) {
    const PDBranch b = (PDBranch)(branch[e] & PD_BRANCH_MASK);
    PetscReal      s, k;
    PetscBool      back;
    if (b != PD_BRANCH_SECANT && b != PD_BRANCH_ENVELOPE) continue;
    s = PDModelBondStretch(m, ul, e);
    k = m->kappa[e];
    if (!((b == PD_BRANCH_SECANT && s > k) || (b == PD_BRANCH_ENVELOPE && s < k))) continue;
    back = branch[e] & PD_BRANCH_FLIPPED ? PETSC_TRUE : PETSC_FALSE;
    branch[e] =
        back ? PD_BRANCH_KINK : (unsigned char)((b == PD_BRANCH_SECANT ? PD_BRANCH_ENVELOPE : PD_BRANCH_SECANT) | PD_BRANCH_FLIPPED);
    if (PDBondCountedHere(m->lat, m->bonds, e)) mine[back]++;
  }
  PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  PetscCall(MPIU_Allreduce(mine, total, 2, MPIU_INT, MPI_SUM, m->lat->comm));
  *nflipped = total[0] + total[1];
  *nkink    = total[1];
  PetscFunctionReturn(0);
}

/* Freezes every damaged bond of the frozen branches on the side of zero stretch it has at u (PD_BRANCH_OPEN,
   PD_BRANCH_CLOSED); a bond-slip link, symmetric in its slip, has no such kink. */
PetscErrorCode PDModelFreezeSides(PDModel *m, Vec u, PetscInt *nfrozen) {
  unsigned char     *branch = m->branch;
  const PetscScalar *ul;
  Vec                uloc;
  PetscInt           mine = 0;

  PetscFunctionBeginUser;
  PetscCheck(branch, m->lat->comm, PETSC_ERR_ORDER, "no frozen branches to give sides");
  PetscCall(PDModelScatterToLocal(m, u, &ul, &uloc));
  for (PetscInt e = 0; e < m->bonds->nbonds; e++) {
    const PDLaw    *law = &m->law[m->bonds->material[e]];
    const PDLawBond tb  = PDModelBondThresholds(m, e, law);
    if (law->kind == PD_LAW_ELASTIC || law->kind == PD_LAW_SLIP || m->kappa[e] <= tb.s0) continue;
    branch[e] = (unsigned char)((branch[e] & ~PD_BRANCH_SIDE) | (PDModelBondStretch(m, ul, e) < 0 ? PD_BRANCH_CLOSED : PD_BRANCH_OPEN));
    if (PDBondCountedHere(m->lat, m->bonds, e)) mine++;
  }
  PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  PetscCall(MPIU_Allreduce(&mine, nfrozen, 1, MPIU_INT, MPI_SUM, m->lat->comm));
  m->faces    = PETSC_TRUE;
  m->nchanged = -1; /* forces changed without a record: the next residual runs the whole loop */
  PetscFunctionReturn(0);
}

/* Back to the real law's side for every bond: the sides stay in branch, out of force, until a new freeze
   overwrites them or the next IMPL-EX step's extrapolation clears them. */
PetscErrorCode PDModelFreeSides(PDModel *m) {
  PetscFunctionBeginUser;
  m->faces    = PETSC_FALSE;
  m->nchanged = -1;
  PetscFunctionReturn(0);
}

PetscErrorCode PDModelRestoreLevels(PDModel *m) {
  PetscFunctionBeginUser;
  if (m->softening) PetscCall(PetscArraycpy(m->level, m->level_n, m->bonds->nbonds));
  m->nchanged = -1; /* levels changed without a record: the next residual runs the whole loop */
  PetscFunctionReturn(0);
}

/* Nodal damage: the mean damage of a node's concrete bonds (0 intact, 1 all broken); a bar node's links and
   ties are no concrete and its damage is 0. */
PetscErrorCode PDModelNodalDamage(PDModel *m, Vec damage) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  PetscScalar     *d;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(damage, &d));
  for (PetscInt i = 0; i < m->lat->nowned; i++) {
    PetscInt  n   = 0;
    PetscReal sum = 0;
    for (PetscInt p = bd->inc_start[i]; p < bd->inc_start[i + 1]; p++) {
      const PetscInt e = bd->inc_bond[p];
      if (lat->barnode && (lat->barnode[bd->a[e]] >= 0 || lat->barnode[bd->b[e]] >= 0)) continue;
      sum += PDModelBondDamage(m, e);
      n++;
    }
    if (lat->barnode && lat->barnode[i] >= 0) n = 1;
    d[i] = m->lat->hollow[i] ? PD_NAN : (n ? sum / n : 1); /* a void's nodes are no material: NaN, which viewers blank */
  }
  PetscCall(VecRestoreArray(damage, &d));
  PetscFunctionReturn(0);
}
