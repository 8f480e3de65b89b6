/* The bond loop: internal forces and the tangent scalars. The residual, the Jacobian, the limiter and
   the explicit path all use it. Per bond, the law is evaluated once per rank; rows of the stiffness are
   then gathered from the stored tangent scalars node by node (assembly.c). */
#include "pd_model.h"
#include "kernel.h"
#include "pd_log.h"

/* The largest stretch a bond's law sees at stretch s: its history, raised by s, and held just below the
   threshold the limiter has not yet let it pass (the limit from below). */
static inline PetscReal EffectiveHistory(const PDModel *m, PetscInt e, const PDLaw *law, const PDLawBond *t, PetscReal s, PetscReal *cap) {
  const PetscReal kap = PetscMax(m->kappa[e], s);
  *cap                = PDLawNextThreshold(law, t, m->level[e]);
  return kap >= *cap ? *cap * (1 - 1e-12) : kap;
}

/* Whether bond e's concrete is elastic at stretch s with the history it has, before its own thresholds are
   needed: no softening; compression without bond-slip links, which needs no law (most bonds of a loaded body);
   an elastic law; or stretch and history below every threshold of its material (PDModel onset). */
static inline PetscBool ConcreteElastic(const PDModel *m, PetscInt e, PetscReal s) {
  const unsigned side = m->faces ? m->branch[e] & PD_BRANCH_SIDE : 0; /* a frozen crack side (PD_BRANCH_OPEN) */
  const PDLaw   *law;
  PetscReal      a;
  if (!m->softening || side == PD_BRANCH_CLOSED || (s < 0 && !m->nslip && !side)) return PETSC_TRUE;
  law = &m->law[m->bonds->material[e]];
  a   = PDLawHistoryStretch(law, s);
  return (a < 0 && !side) || law->kind == PD_LAW_ELASTIC || PetscMax(m->kappa[e], a) < m->onset[m->bonds->material[e]] ? PETSC_TRUE
                                                                                                                       : PETSC_FALSE;
}

/* Scalar force g(s) of a bond's concrete and its slope. History kappa_n and the level the limiter allows
   give the effective largest stretch; a bond held below a threshold stays on its current branch.
   Compression is linear elastic whatever the damage (cracks do not interpenetrate). A bar's bond-slip link
   (PD_LAW_SLIP) is the same law in a = |s|: symmetric in the slip, its history the largest |s|, and
   never held by the limiter. */
static inline void ConcreteForce(const PDModel *m, PetscInt e, PetscReal s, PetscReal *g, PetscReal *gp) {
  const PetscReal c = m->bonds->coef[e];
  const PDLaw    *law;
  PetscReal       kap, cap, d, dd, a;

  if (ConcreteElastic(m, e, s)) {
    *g  = c * s;
    *gp = c;
    return;
  }
  law = &m->law[m->bonds->material[e]];
  a   = PDLawHistoryStretch(law, s);
  {
    const PDLawBond tb = PDModelBondThresholds(m, e, law), *t = &tb;
    PetscBool       loading = a >= m->kappa[e] ? PETSC_TRUE : PETSC_FALSE;
    /* below the damage threshold (and below the breaking one, which a coarse bilinear bond can have
       lower): elastic on every branch and at every level, the state of most bonds */
    if (PetscMax(m->kappa[e], a) < PetscMin(t->s0, t->sc)) {
      *g  = c * s;
      *gp = c;
      return;
    }
    kap = EffectiveHistory(m, e, law, t, a, &cap);
    switch (m->branch ? m->branch[e] & PD_BRANCH_MASK : PD_BRANCH_FREE) {
    case PD_BRANCH_SECANT:
      kap     = m->kappa[e];
      loading = PETSC_FALSE;
      break;
    case PD_BRANCH_ENVELOPE:
      kap     = a >= cap ? cap * (1 - 1e-12) : a;
      loading = PETSC_TRUE;
      break;
    case PD_BRANCH_KINK:
      loading = PETSC_FALSE;
      break;
    default:
      break;
    }
    d  = PDLawDamage(law, t, kap, &dd);
    *g = c * (1 - d) * s;
    /* loading on the active branch: consistent slope c((1 - d) - a d'); otherwise the secant */
    if (m->scene->tangent == PD_TANGENT_CONSISTENT && loading && a < cap)
      *gp = c * ((1 - d) - a * dd);
    else
      *gp = c * (1 - d);
  }
}

/* The force of a bar segment at stretch s from its committed state, the consistent slope, and the state
   it leaves. */
static inline void SegmentForce(const PDModel *m, PetscInt sg, PetscReal s, PetscReal *g, PetscReal *gp, PetscReal *sp, PetscBool *rupt) {
  const PetscReal c = m->bonds->seg_coef[sg];
  PDSteelResponse(&m->steel[m->bonds->seg_bar[sg]], s, m->sp_n[sg], m->ruptured_n[sg], g, gp, sp, rupt);
  if (!*rupt) *gp = PetscMax(*gp, m->scene->steel_tangent_floor); /* a yielded segment's slope, floored (-pd_steel_tangent_floor) */
  *g *= c;
  *gp *= c;
}

/* What a segment of length L0 dissipates on its way from the committed state to (sp, rupt): s_y E A L0 per
   unit of plastic stretch, or at a break the elastic energy it held when it broke, at the rupture
   stretch (the step may carry the stretch past it). */
static inline PetscReal SegmentDissipation(const PDModel *m, PetscInt sg, PetscReal L0, PetscReal s, PetscReal sp, PetscBool rupt) {
  const PDSteel *st = &m->steel[m->bonds->seg_bar[sg]];
  return m->bonds->seg_coef[sg] * L0 *
         (rupt && !m->ruptured_n[sg] ? PDSteelStored(st, PetscMin(s, st->su), m->sp_n[sg]) : st->sy * PetscAbsReal(sp - m->sp_n[sg]));
}

/* A bond's force and slope: its concrete's and its bar segment's, if it carries one. */
static inline void BondForce(const PDModel *m, PetscInt e, PetscReal s, PetscReal *g, PetscReal *gp) {
  ConcreteForce(m, e, s, g, gp);
  if (m->bonds->seg && m->bonds->seg[e] >= 0) {
    PetscReal gs, gps, sp;
    PetscBool rupt;
    SegmentForce(m, m->bonds->seg[e], s, &gs, &gps, &sp, &rupt);
    *g += gs;
    *gp += gps;
  }
}

/* Bonds come in runs of one first node (the neighbour search's order). At the start of node i's run the
   row sum acc of the node before is added to out, and i's coordinates xc and values vc (of v) are loaded,
   so that they stay in registers for the run and no bond waits on the store of the one before. */
static inline void RunStart(PetscInt bs, const PetscReal *x, const PetscScalar *v, PetscScalar *out, PetscInt i, PetscInt *cur,
                            PetscReal xc[3], PetscReal vc[3], PetscReal acc[3]) {
  for (PetscInt r = 0; r < bs && *cur >= 0; r++) out[bs * *cur + r] += acc[r];
  *cur = i;
  for (PetscInt r = 0; r < bs; r++) {
    xc[r]  = x[3 * i + r];
    vc[r]  = PetscRealPart(v[bs * i + r]);
    acc[r] = 0;
  }
}

/* Small kinematics: the bond from node c (coordinates xc, values vc) to node j, xi = x_j - xc, its squared
   length, and the projection xi . (v_j - vc), whose quotient by |xi|^2 is the stretch (v = u) or the
   stretch rate along the bond (v = x). */
static inline PetscReal Projection(PetscInt bs, const PetscReal *x, const PetscScalar *v, PetscInt j, const PetscReal xc[3],
                                   const PetscReal vc[3], PetscReal xi[3], PetscReal *L2) {
  PetscReal dot = 0;
  *L2           = 0;
  for (PetscInt r = 0; r < bs; r++) {
    xi[r] = x[3 * j + r] - xc[r];
    *L2 += xi[r] * xi[r];
    dot += xi[r] * (PetscRealPart(v[bs * j + r]) - vc[r]);
  }
  return dot;
}

/* Small kinematics: a bond's force over its length, g(s) / |xi| with s = dot / |xi|^2, and its tangent
   scalar into *ka (if given). The residual's loop and its rows (PDModelInternalForceRows) share it, so
   both evaluate the same expressions in the same order. */
static inline PetscReal SmallForce(const PDModel *m, PetscInt e, PetscReal dot, PetscReal L2, PetscReal *ka) {
  PetscReal g, gp, q;
  BondForce(m, e, dot / L2, &g, &gp);
  q = 1 / PetscSqrtReal(L2);
  if (ka) *ka = gp * q;
  return g * q;
}

/* Small kinematics, as the tangent's product (TangentApplySmall): the stretch needs no square root, so
   the law's evaluation does not wait for one, and 1/|xi| scales the force at the end. */
static inline void InternalForceSmall(PetscInt bs, PDModel *m, const PetscReal *restrict x, const PetscScalar *restrict u,
                                      PetscScalar *restrict f, PetscReal *restrict ka) {
  const PDBonds *bd    = m->bonds;
  PetscInt       cur   = -1;
  PetscReal      xc[3] = {0, 0, 0}, uc[3] = {0, 0, 0}, acc[3] = {0, 0, 0};
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt i = bd->a[e], j = bd->b[e];
    PetscReal      xi[3], L2, dot, g;
    if (i != cur) RunStart(bs, x, u, f, i, &cur, xc, uc, acc);
    dot = Projection(bs, x, u, j, xc, uc, xi, &L2);
    g   = SmallForce(m, e, dot, L2, ka ? &ka[e] : NULL);
    if (m->commit_history) PDModelCommitBond(m, e, dot / L2);
    for (PetscInt r = 0; r < bs; r++) {
      acc[r] -= g * xi[r];
      f[bs * j + r] += g * xi[r];
    }
  }
  for (PetscInt r = 0; r < bs && cur >= 0; r++) f[bs * cur + r] += acc[r];
}

/* Internal forces f at u and, where ka is given, the tangent scalars at u as PDModelTangentScalars
   computes them (without kp): the residual and the tangent of one Newton iteration share the bond
   loop. */
PetscErrorCode PDModelInternalForceLocal(PDModel *m, const PetscScalar *u, PetscScalar *f, PetscReal *ka, PetscReal *kb) {
  const PDBonds   *bd        = m->bonds;
  const PDLattice *lat       = m->lat;
  const PetscInt   bs        = m->bs;
  const PetscBool  geometric = m->scene->kinematics == PD_KINEMATICS_FINITE;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PD_LOG.force, 0, 0, 0, 0));
  PetscCall(PetscArrayzero(f, bs * lat->nlocal));
  if (!geometric) {
    if (bs == 3)
      InternalForceSmall(3, m, lat->x, u, f, ka); /* kb is NULL under small kinematics */
    else
      InternalForceSmall(bs, m, lat->x, u, f, ka);
    PetscCall(PetscLogFlops(30.0 * bd->nbonds));
    PetscCall(PetscLogEventEnd(PD_LOG.force, 0, 0, 0, 0));
    PetscFunctionReturn(0);
  }
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt i = bd->a[e], j = bd->b[e];
    PetscReal      dir[3], L0, L, s, q, g, gp;
    BondState(m->scene, bs, &lat->x[3 * i], &lat->x[3 * j], &u[bs * i], &u[bs * j], dir, &L0, &L, &s, &q);
    BondForce(m, e, s, &g, &gp);
    if (ka) {
      ka[e] = gp * q - (geometric ? g / L : 0);
      if (kb) kb[e] = geometric ? g / L : 0;
    }
    if (m->commit_history) PDModelCommitBond(m, e, s);
    for (PetscInt a = 0; a < bs; a++) {
      f[bs * i + a] -= g * dir[a];
      f[bs * j + a] += g * dir[a];
    }
  }
  PetscCall(PetscLogFlops(30.0 * bd->nbonds));
  PetscCall(PetscLogEventEnd(PD_LOG.force, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* Where each node's contributions lie in the bond arrays: its run (the bonds it starts, contiguous) and
   the bonds that end at it, in bond order. Not usable if a node starts two runs (the rows below then
   could not follow the whole loop's order). */
static PetscErrorCode RowIndexSetUp(PDModel *m) {
  const PDBonds   *bd = m->bonds;
  const PetscInt   n  = m->lat->nlocal;
  PDModelRowIndex *ix = &m->rows;
  PetscInt        *fill;

  PetscFunctionBeginUser;
  ix->usable = PETSC_TRUE;
  PetscCall(PetscCalloc4(n, &ix->run_start, n, &ix->run_end, n + 1, &ix->end_off, PetscMax(1, bd->nbonds), &ix->end_bond));
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt i = bd->a[e];
    if (e == 0 || bd->a[e - 1] != i) {
      if (ix->run_end[i] > 0) ix->usable = PETSC_FALSE; /* a second run */
      ix->run_start[i] = e;
    }
    ix->run_end[i] = e + 1;
    ix->end_off[bd->b[e] + 1]++;
  }
  for (PetscInt k = 0; k < n; k++) ix->end_off[k + 1] += ix->end_off[k];
  PetscCall(PetscCalloc1(n, &fill));
  for (PetscInt e = 0; e < bd->nbonds; e++) ix->end_bond[ix->end_off[bd->b[e]] + fill[bd->b[e]]++] = e;
  PetscCall(PetscFree(fill));
  ix->ready = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode PDModelRowIndexDestroy(PDModel *m) {
  PDModelRowIndex *ix = &m->rows;

  PetscFunctionBeginUser;
  PetscCall(PetscFree4(ix->run_start, ix->run_end, ix->end_off, ix->end_bond));
  ix->ready = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* Whether this rank's rows can be recomputed alone (PDModelInternalForceRows): small kinematics, and a
   run per node. The index is built at the first call. */
PetscErrorCode PDModelRowsUsable(PDModel *m, PetscBool *usable) {
  PetscFunctionBeginUser;
  *usable = PETSC_FALSE;
  if (m->scene->kinematics == PD_KINEMATICS_FINITE) PetscFunctionReturn(0);
  if (!m->rows.ready) PetscCall(RowIndexSetUp(m));
  *usable = m->rows.usable;
  PetscFunctionReturn(0);
}

/* Rows rows[0..n) of PDModelInternalForceLocal's f under small kinematics, into fr[bs k + r], with ka of
   every bond they touch, where PDModelRowsUsable says so. Each row is summed as the whole loop sums it:
   the contributions of the bonds ending at the node in bond order, its own run's sum where the run ends.
   So the rows equal the whole loop's to the last bit, and a residual after a limiter grant recomputes
   only the rows of the bonds it changed (model.c PDModelResidual). */
PetscErrorCode PDModelInternalForceRows(PDModel *m, const PetscScalar *u, PetscInt n, const PetscInt *rows, PetscScalar *fr,
                                        PetscReal *ka) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscInt   bs  = m->bs;

  PetscFunctionBeginUser;
  PetscCheck(m->rows.ready && m->rows.usable, PETSC_COMM_SELF, PETSC_ERR_PLIB, "rows recomputed without a usable row index");
  PetscCall(PetscLogEventBegin(PD_LOG.force, 0, 0, 0, 0));
  for (PetscInt k = 0; k < n; k++) {
    const PetscInt i = rows[k], e0 = m->rows.run_start[i], e1 = m->rows.run_end[i];
    PetscReal      xc[3] = {0, 0, 0}, uc[3] = {0, 0, 0}, acc[3] = {0, 0, 0}, f[3] = {0, 0, 0};
    PetscBool      pending = e1 > e0 ? PETSC_TRUE : PETSC_FALSE;
    for (PetscInt r = 0; r < bs; r++) {
      xc[r] = lat->x[3 * i + r];
      uc[r] = PetscRealPart(u[bs * i + r]);
    }
    for (PetscInt e = e0; e < e1; e++) { /* the run's sum, as the whole loop forms it */
      PetscReal xi[3], L2, dot, g;
      dot = Projection(bs, lat->x, u, bd->b[e], xc, uc, xi, &L2);
      g   = SmallForce(m, e, dot, L2, ka ? &ka[e] : NULL);
      for (PetscInt r = 0; r < bs; r++) acc[r] -= g * xi[r];
    }
    for (PetscInt t = m->rows.end_off[i]; t < m->rows.end_off[i + 1]; t++) {
      const PetscInt e = m->rows.end_bond[t], a = bd->a[e];
      PetscReal      xa[3] = {0, 0, 0}, ua[3] = {0, 0, 0}, xi[3], L2, dot, g;
      if (pending && e >= e1) {
        for (PetscInt r = 0; r < bs; r++) f[r] += acc[r];
        pending = PETSC_FALSE;
      }
      for (PetscInt r = 0; r < bs; r++) {
        xa[r] = lat->x[3 * a + r];
        ua[r] = PetscRealPart(u[bs * a + r]);
      }
      dot = Projection(bs, lat->x, u, i, xa, ua, xi, &L2);
      g   = SmallForce(m, e, dot, L2, ka ? &ka[e] : NULL);
      for (PetscInt r = 0; r < bs; r++) f[r] += g * xi[r];
    }
    if (pending)
      for (PetscInt r = 0; r < bs; r++) f[r] += acc[r];
    for (PetscInt r = 0; r < bs; r++) fr[bs * k + r] = f[r];
  }
  PetscCall(PetscLogEventEnd(PD_LOG.force, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* Small kinematics: bond e's force over its length at the local displacements u (SmallForce), and its xi. */
PetscReal PDModelBondForceSmall(const PDModel *m, const PetscScalar *u, PetscInt e, PetscReal xi[3]) {
  const PDLattice *lat   = m->lat;
  const PetscInt   i     = m->bonds->a[e];
  PetscReal        xc[3] = {0, 0, 0}, uc[3] = {0, 0, 0}, L2, dot;
  for (PetscInt r = 0; r < m->bs; r++) {
    xc[r] = lat->x[3 * i + r];
    uc[r] = PetscRealPart(u[m->bs * i + r]);
  }
  dot = Projection(m->bs, lat->x, u, m->bonds->b[e], xc, uc, xi, &L2);
  return SmallForce(m, e, dot, L2, NULL);
}

/* Adds to the owned rows of f (the internal force with the bonds' forces over their lengths g_old) the change of
   the n bonds' forces to what they are now, at the local displacements u: the whole loop's force with the new
   history, to round-off (the sums run in another order). */
void PDModelForceChangeLocal(const PDModel *m, const PetscScalar *u, PetscInt n, const PetscInt *bonds, const PetscReal *g_old,
                             PetscScalar *f) {
  const PetscInt nowned = m->lat->nowned, bs = m->bs;
  for (PetscInt k = 0; k < n; k++) {
    const PetscInt  e = bonds[k], i = m->bonds->a[e], j = m->bonds->b[e];
    PetscReal       xi[3];
    const PetscReal dg = PDModelBondForceSmall(m, u, e, xi) - g_old[k];
    for (PetscInt r = 0; r < bs; r++) {
      if (i < nowned) f[bs * i + r] -= dg * xi[r];
      if (j < nowned) f[bs * j + r] += dg * xi[r];
    }
  }
}

/* Energy of bond e of concrete at stretch s, reference length L0: stored c (1 - d) s^2 |xi| / 2 (c s^2 |xi| / 2
   in compression) and dissipated c |xi| (W(kappa) - (1 - d) kappa^2 / 2), W the law's envelope work. The |xi|
   turns the stretch integral into work for the standard stretch (ds = e.deta / |xi|); with the modified
   stretch it is the small-strain value. */
static inline void ConcreteEnergy(const PDModel *m, PetscInt e, PetscReal s, PetscReal L0, PetscReal *es, PetscReal *ed) {
  const PetscReal c = m->bonds->coef[e];
  if (!m->softening || m->law[m->bonds->material[e]].kind == PD_LAW_ELASTIC) {
    *es += 0.5 * c * s * s * L0;
    return;
  }
  {
    const PDLaw    *law = &m->law[m->bonds->material[e]];
    const PetscReal a   = PDLawHistoryStretch(law, s);
    if (PetscMax(m->kappa[e], a) < m->onset[m->bonds->material[e]]) { /* undamaged, W(kappa) = kappa^2 / 2: nothing dissipated */
      *es += 0.5 * c * s * s * L0;
      return;
    }
    const PDLawBond tb = PDModelBondThresholds(m, e, law), *t = &tb;
    PetscReal       cap, dd, kap = EffectiveHistory(m, e, law, t, PetscMax(a, 0), &cap);
    PetscReal       d = PDLawDamage(law, t, kap, &dd);
    *es += 0.5 * c * (a < 0 ? 1 : 1 - d) * s * s * L0;
    *ed += c * L0 * (PDLawEnvelopeWork(law, t, kap) - 0.5 * (1 - d) * kap * kap);
  }
}

/* Energy of the bonds this rank counts (ConcreteEnergy, and a bar segment's stored and dissipated work). */
PetscErrorCode PDModelEnergiesLocal(PDModel *m, const PetscScalar *u, PetscReal *stored, PetscReal *dissipated) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  PetscReal        es = 0, ed = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PD_LOG.energy, 0, 0, 0, 0));
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt i = bd->a[e], j = bd->b[e];
    PetscReal      dir[3], L0, L, s, q;
    if (!PDBondCountedHere(lat, bd, e)) continue;
    BondState(m->scene, m->bs, &lat->x[3 * i], &lat->x[3 * j], &u[m->bs * i], &u[m->bs * j], dir, &L0, &L, &s, &q);
    if (bd->seg && bd->seg[e] >= 0) {
      const PetscInt sg = bd->seg[e];
      const PDSteel *st = &m->steel[bd->seg_bar[sg]];
      PetscReal      g, gp, sp;
      PetscBool      rupt;
      SegmentForce(m, sg, s, &g, &gp, &sp, &rupt);
      if (!rupt) es += bd->seg_coef[sg] * L0 * PDSteelStored(st, s, sp);
      ed += m->dissipated_n[sg] + SegmentDissipation(m, sg, L0, s, sp, rupt);
    }
    ConcreteEnergy(m, e, s, L0, &es, &ed);
  }
  *stored     = es;
  *dissipated = ed;
  PetscCall(PetscLogEventEnd(PD_LOG.energy, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* The same sums over bonds e0 .. e0 + n - 1 at their stretches s (PDModelBondStretches), added to *es and *ed,
   for a model without bar segments: the history commit takes the energies of the state it commits in its
   own loop over the stretches. */
void PDModelBondEnergies(const PDModel *m, PetscInt e0, PetscInt n, const PetscReal *s, PetscReal *es, PetscReal *ed) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  for (PetscInt k = 0; k < n; k++) {
    const PetscInt e = e0 + k;
    if (!PDBondCountedHere(lat, bd, e)) continue;
    ConcreteEnergy(m, e, s[k], PetscSqrtReal(PDBondLength2(m->bs, lat->x, bd->a[e], bd->b[e])), es, ed);
  }
}

/* Tangent scalars of each bond: block = ka e e^T + kb I, ka = g' q - g/|y|, kb = g/|y| (THEORY.md Sec. 4);
   kb is NULL under small kinematics, where it is zero.
   With kp, also the ka of the preconditioning matrix: a softening slope g' < 0 replaced by the secant g/s,
   which is positive, so that matrix stays definite where the tangent is not (-pd_pc_matrix secant). */
PetscErrorCode PDModelTangentScalars(PDModel *m, const PetscScalar *u, PetscReal *ka, PetscReal *kb, PetscReal *kp) {
  const PDBonds   *bd        = m->bonds;
  const PDLattice *lat       = m->lat;
  const PetscInt   bs        = m->bs;
  const PetscBool  geometric = m->scene->kinematics == PD_KINEMATICS_FINITE;

  PetscFunctionBeginUser;
  if (ka == m->ka) m->ka_at_residual = PETSC_FALSE;
  PetscCall(PetscLogEventBegin(PD_LOG.tangent, 0, 0, 0, 0));
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt i = bd->a[e], j = bd->b[e];
    PetscReal      dir[3], L0, L, s, q, g, gp;
    BondState(m->scene, bs, &lat->x[3 * i], &lat->x[3 * j], &u[bs * i], &u[bs * j], dir, &L0, &L, &s, &q);
    BondForce(m, e, s, &g, &gp);
    ka[e] = gp * q - (geometric ? g / L : 0);
    if (kb) kb[e] = geometric ? g / L : 0;
    if (kp) kp[e] = gp < 0 && s != 0 ? ka[e] + (g / s - gp) * q : ka[e]; /* g / s > 0: a bond-slip link's fall has s < 0 too */
  }
  PetscCall(PetscLogEventEnd(PD_LOG.tangent, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* Small kinematics: y += K x from the tangent scalars ka (NULL: the elastic ones; scaled: ka / |xi|^2,
   which spares the loop its division). The loops of the
   product, the residual and the stretches are inline functions of the dofs per node, called with a
   literal 3 in 3D: Krylov solves and multigrid's finest smoother spend most of their time in the product,
   and a loop over a count known only at run time keeps the compiler from unrolling it. Both copies
   evaluate the same expressions in the same order. */
static inline void TangentApplySmall(PetscInt bs, PetscBool scaled, const PDBonds *bd, const PetscReal *restrict x,
                                     const PetscReal *restrict ka, const PetscScalar *restrict v, PetscScalar *restrict y) {
  const PetscInt *restrict a = bd->a, *restrict b = bd->b;
  PetscInt  cur   = -1;
  PetscReal xc[3] = {0, 0, 0}, vc[3] = {0, 0, 0}, acc[3] = {0, 0, 0};
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt i = a[e], j = b[e];
    PetscReal      xi[3], L2, dot, t;
    if (i != cur) RunStart(bs, x, v, y, i, &cur, xc, vc, acc);
    dot = Projection(bs, x, v, j, xc, vc, xi, &L2);
    t   = scaled ? ka[e] * dot : (ka ? ka[e] : PDBondStiffness(bd, e) / PetscSqrtReal(L2)) * dot / L2;
    for (PetscInt r = 0; r < bs; r++) {
      acc[r] -= t * xi[r];
      y[bs * j + r] += t * xi[r];
    }
  }
  for (PetscInt r = 0; r < bs && cur >= 0; r++) y[bs * cur + r] += acc[r];
}

/* y = K x from the bond scalars, on every dof (no elimination of constrained ones): per bond the block
   B = ka e e^T + kb I acts on x_j - x_i, +B on node j and -B on node i (ka NULL: the linearised
   micromodulus; kb NULL: small kinematics). Under small kinematics B = ka xi xi^T / |xi|^2 needs neither
   u (which may be NULL) nor a square root, and a node's row is summed over its run of bonds (RunStart).
   This is the Krylov solves' operator (tangent_product.c). */
PetscErrorCode PDModelTangentApplyLocal(PDModel *m, const PetscScalar *u, const PetscReal *ka, const PetscReal *kb, PetscBool scaled,
                                        const PetscScalar *x, PetscScalar *y) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscInt   bs  = m->bs;

  PetscFunctionBeginUser;
  PetscCall(PetscArrayzero(y, bs * lat->nlocal));
  if (m->scene->kinematics == PD_KINEMATICS_SMALL) {
    if (bs == 3 && scaled)
      TangentApplySmall(3, PETSC_TRUE, bd, lat->x, ka, x, y);
    else if (bs == 3)
      TangentApplySmall(3, PETSC_FALSE, bd, lat->x, ka, x, y);
    else
      TangentApplySmall(bs, scaled, bd, lat->x, ka, x, y);
    PetscCall(PetscLogFlops((bs == 3 ? 25.0 : 18.0) * bd->nbonds));
    PetscFunctionReturn(0);
  }
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt i = bd->a[e], j = bd->b[e];
    PetscReal      dir[3], L0, L, s, q, d[3] = {0, 0, 0}, ed = 0;
    BondState(m->scene, bs, &lat->x[3 * i], &lat->x[3 * j], &u[bs * i], &u[bs * j], dir, &L0, &L, &s, &q);
    const PetscReal a = ka ? ka[e] : PDBondStiffness(bd, e) / L0, b = kb ? kb[e] : 0;
    for (PetscInt r = 0; r < bs; r++) {
      d[r] = PetscRealPart(x[bs * j + r] - x[bs * i + r]);
      ed += dir[r] * d[r];
    }
    for (PetscInt r = 0; r < bs; r++) {
      const PetscReal t = a * ed * dir[r] + b * d[r];
      y[bs * i + r] -= t;
      y[bs * j + r] += t;
    }
  }
  PetscFunctionReturn(0);
}

/* One bond's stretch at the local displacements u, for the limiter, the history update, the branches and
   the crushing criterion: evaluated where it is read rather than kept per bond. Under small kinematics
   BondState's stretch without the length it has no use for. A bond-slip link's history is its largest
   |s|, so its users see |s|. */
PetscReal PDModelBondStretch(const PDModel *m, const PetscScalar *u, PetscInt e) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscInt   bs = m->bs, a = bd->a[e];
  PetscReal        s;

  if (m->scene->kinematics == PD_KINEMATICS_SMALL) {
    PetscReal xa[3] = {0, 0, 0}, ua[3] = {0, 0, 0}, xi[3], L2;
    for (PetscInt r = 0; r < bs; r++) {
      xa[r] = lat->x[3 * a + r];
      ua[r] = PetscRealPart(u[bs * a + r]);
    }
    s = Projection(bs, lat->x, u, bd->b[e], xa, ua, xi, &L2) / L2;
  } else {
    PetscReal dir[3], L0, L, q;
    BondState(m->scene, bs, &lat->x[3 * a], &lat->x[3 * bd->b[e]], &u[bs * a], &u[bs * bd->b[e]], dir, &L0, &L, &s, &q);
  }
  return m->law[bd->material[e]].kind == PD_LAW_SLIP ? PetscAbsReal(s) : s;
}

/* Small kinematics: the stretches of bonds e0 .. e0 + n - 1, a run of one first node at a time (RunStart). */
static inline void StretchesSmall(PetscInt bs, const PDBonds *bd, const PetscReal *restrict x, const PetscScalar *restrict u, PetscInt e0,
                                  PetscInt n, PetscReal *restrict s) {
  PetscInt  cur   = -1;
  PetscReal xc[3] = {0, 0, 0}, uc[3] = {0, 0, 0};
  for (PetscInt k = 0; k < n; k++) {
    const PetscInt e = e0 + k, i = bd->a[e];
    PetscReal      xi[3], L2, dot;
    if (i != cur) {
      cur = i;
      for (PetscInt r = 0; r < bs; r++) {
        xc[r] = x[3 * i + r];
        uc[r] = PetscRealPart(u[bs * i + r]);
      }
    }
    dot  = Projection(bs, x, u, bd->b[e], xc, uc, xi, &L2);
    s[k] = dot / L2;
  }
}

/* The stretches of bonds e0 .. e0 + n - 1 (n at most PD_STRETCH_BLOCK) at the local displacements u, as
   PDModelBondStretch gives them one by one, to the last bit: the loops over every bond that read stretches
   (the limiter, the history commit, IMPL-EX's error) take them a block at a time, in a loop that keeps each
   node's values in registers for its run of bonds and that the compiler unrolls in 3D. */
void PDModelBondStretches(const PDModel *m, const PetscScalar *u, PetscInt e0, PetscInt n, PetscReal *s) {
  const PDBonds *bd = m->bonds;
  if (m->scene->kinematics != PD_KINEMATICS_SMALL) {
    for (PetscInt k = 0; k < n; k++) s[k] = PDModelBondStretch(m, u, e0 + k);
    return;
  }
  if (m->bs == 3)
    StretchesSmall(3, bd, m->lat->x, u, e0, n, s);
  else
    StretchesSmall(m->bs, bd, m->lat->x, u, e0, n, s);
  for (PetscInt k = 0; m->nslip && k < n; k++)
    if (m->law[bd->material[e0 + k]].kind == PD_LAW_SLIP) s[k] = PetscAbsReal(s[k]);
}

/* Whether bond e's slope is c at stretch s with the history it has: its concrete elastic before its own
   thresholds are needed (ConcreteElastic), and no bar segment. */
static inline PetscBool SlopeElastic(const PDModel *m, PetscInt e, PetscReal s) {
  return (!m->bonds->seg || m->bonds->seg[e] < 0) && ConcreteElastic(m, e, s) ? PETSC_TRUE : PETSC_FALSE;
}

/* A bar segment's share of the end-slope term of a step from stretch s0 to s1 (PDModelTangentChangeBlock): 12 times
   its exact work over the step less the trapezoid's, so that the step's work is exact for the steel. Its force
   bends where the step meets the yield surface, and the cubic of the end slopes, which suits the concrete's
   smooth laws, puts the kink's corner in the wrong place (a segment that yields in a long step was given
   several times the work it took). The work is what the history commit books for the step (SegmentForce's
   return mapping from the committed state, SegmentDissipation): the change of the stored energy plus the
   dissipated. */
static inline PetscReal SegmentStepTerm(const PDModel *m, PetscInt sg, PetscReal L0, PetscReal s0, PetscReal s1) {
  const PDSteel  *st = &m->steel[m->bonds->seg_bar[sg]];
  const PetscReal c = m->bonds->seg_coef[sg], sp0 = m->sp_n[sg];
  PetscReal       g0, g1, gp, sp1;
  PetscBool       rupt;

  if (m->ruptured_n[sg]) return 0;
  g0 = c * (s0 - sp0);
  SegmentForce(m, sg, s1, &g1, &gp, &sp1, &rupt);
  const PetscReal work =
      c * L0 * ((rupt ? 0 : PDSteelStored(st, s1, sp1)) - PDSteelStored(st, s0, sp0)) + SegmentDissipation(m, sg, L0, s1, sp1, rupt);
  return 12 * (work - 0.5 * L0 * (g0 + g1) * (s1 - s0));
}

/* Small kinematics: adds to *sum, bond by bond in bond order, the part of du . (K(u0) - K(u1)) du, du = u1 - u0,
   of the bonds e0 .. e0 + n - 1 this rank counts, both tangents with the history the model holds (the
   end-slope term of an accepted step's work, path.c). s1 are the bonds' stretches at u1 and s0 at u0
   (PDModelBondStretches). Per bond it is (k(u0) - k(u1)) (xi . (du_j - du_i))^2 / |xi|^2, k the tangent
   scalar; it is zero for a bond whose slope is c in both states, most of them, whose law is not evaluated.
   s0 NULL says that the history is the one committed at u0 (the history commit's case): a bond whose
   history lies below its material's onset by more than the commit's margin had its stretch at u0 below it
   as well, so its slope at u0 is c without the stretch, which is then formed only for the other bonds. */
void PDModelTangentChangeBlock(const PDModel *m, const PetscScalar *u0, const PetscScalar *u1, PetscInt e0, PetscInt n, const PetscReal *s0,
                               const PetscReal *s1, PetscReal *sum) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscInt   bs  = m->bs;
  for (PetscInt k = 0; k < n; k++) {
    const PetscInt  e = e0 + k, i = bd->a[e], j = bd->b[e];
    const PetscBool elastic1 = SlopeElastic(m, e, s1[k]);
    PetscReal       xi[3], L2 = 0, d0 = 0, d1 = 0, dd, g, gp0, gp1;
    if (elastic1 && (s0 ? SlopeElastic(m, e, s0[k]) : m->kappa[e] < m->onset[bd->material[e]] * (1 - 1e-12))) continue;
    if (!PDBondCountedHere(lat, bd, e)) continue;
    for (PetscInt r = 0; r < bs; r++) {
      xi[r] = lat->x[3 * j + r] - lat->x[3 * i + r];
      L2 += xi[r] * xi[r];
      d0 += xi[r] * PetscRealPart(u0[bs * j + r] - u0[bs * i + r]);
      d1 += xi[r] * PetscRealPart(u1[bs * j + r] - u1[bs * i + r]);
    }
    if (!s0 && elastic1 && SlopeElastic(m, e, d0 / L2)) continue;
    ConcreteForce(m, e, d0 / L2, &g, &gp0);
    ConcreteForce(m, e, d1 / L2, &g, &gp1);
    dd = d1 - d0;
    *sum += (gp0 - gp1) / PetscSqrtReal(L2) * dd * dd / L2;
    if (bd->seg && bd->seg[e] >= 0) *sum += SegmentStepTerm(m, bd->seg[e], PetscSqrtReal(L2), d0 / L2, d1 / L2);
  }
}

/* The same sum over every bond this rank counts (PDModelTangentChangeBlock), a block of stretches at a time. */
PetscReal PDModelTangentChangeLocal(const PDModel *m, const PetscScalar *u0, const PetscScalar *u1) {
  PetscReal sum = 0;
  for (PetscInt e0 = 0; e0 < m->bonds->nbonds; e0 += PD_STRETCH_BLOCK) {
    const PetscInt n = PetscMin(PD_STRETCH_BLOCK, m->bonds->nbonds - e0);
    PetscReal      s0[PD_STRETCH_BLOCK], s1[PD_STRETCH_BLOCK];
    PDModelBondStretches(m, u0, e0, n, s0);
    PDModelBondStretches(m, u1, e0, n, s1);
    PDModelTangentChangeBlock(m, u0, u1, e0, n, s0, s1, &sum);
  }
  return sum;
}

/* Commits one bond's state at stretch s: the largest stretch of its concrete (the explicit path, which has
   no limiter, commits at every force evaluation) and its bar segment's plastic stretch and rupture. */
void PDModelCommitBond(PDModel *m, PetscInt e, PetscReal s) {
  if (m->softening) m->kappa[e] = PetscMax(m->kappa[e], PDLawHistoryStretch(&m->law[m->bonds->material[e]], s));
  if (m->bonds->seg && m->bonds->seg[e] >= 0) PDModelCommitSegment(m, m->bonds->seg[e], s);
}

void PDModelCommitSegment(PDModel *m, PetscInt sg, PetscReal s) {
  const PDBonds   *bd = m->bonds;
  const PetscInt   e  = bd->seg_bond[sg];
  const PetscReal *xa = &m->lat->x[3 * bd->a[e]], *xb = &m->lat->x[3 * bd->b[e]];
  PetscReal        g, gp, sp, L0 = 0;
  PetscBool        rupt;

  for (PetscInt a = 0; a < 3; a++) L0 += (xb[a] - xa[a]) * (xb[a] - xa[a]);
  L0 = PetscSqrtReal(L0);
  SegmentForce(m, sg, s, &g, &gp, &sp, &rupt);
  m->dissipated_n[sg] += SegmentDissipation(m, sg, L0, s, sp, rupt);
  m->sp_n[sg]       = sp;
  m->ruptured_n[sg] = rupt;
}

/* Stress of bar segment sg at the local displacements u: its force over its bar's area (Pa). */
static PetscReal SegmentStress(const PDModel *m, const PetscScalar *u, PetscInt sg) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscInt   e = bd->seg_bond[sg], i = bd->a[e], j = bd->b[e];
  PetscReal        dir[3], L0, L, s, q, g, gp, sp;
  PetscBool        rupt;
  BondState(m->scene, m->bs, &lat->x[3 * i], &lat->x[3 * j], &u[m->bs * i], &u[m->bs * j], dir, &L0, &L, &s, &q);
  SegmentForce(m, sg, s, &g, &gp, &sp, &rupt);
  return g / PDBarArea(&m->scene->bar[bd->seg_bar[sg]]);
}

/* Largest |stress| of the bar segments this rank holds. */
PetscReal PDModelSteelStressLocal(PDModel *m, const PetscScalar *u) {
  PetscReal smax = 0;
  for (PetscInt sg = 0; sg < m->bonds->nseg; sg++) smax = PetscMax(smax, PetscAbsReal(SegmentStress(m, u, sg)));
  return smax;
}

/* Sums over the bonds that cross the plane x = sc->section_x (m->section_bonds: this rank's, each counted
   once), of the force the part beyond the plane exerts through them on the part before it (small kinematics,
   the bond law's force along the bond): sum[PD_SECTION_STEEL] the bar segments' x-component, sum[PD_SECTION_TENSION] and
   [PD_SECTION_COMPRESSION] the concrete's positive and negative x-components, sum[PD_SECTION_SHEAR] the
   vertical component of all, and into the three heights' slots the x-components times the height at which
   the bond crosses the plane (moments, divided by the forces once summed over the ranks). Vertical is
   the last axis: y in 2D, z in 3D, as the scenes' beams stand. */
void PDModelSectionLocal(PDModel *m, const PetscScalar *u, PetscReal sum[PD_SECTION_N]) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  const PetscReal  X   = m->scene->section_x;
  const PetscInt   v   = m->bs - 1; /* the vertical axis */
  for (PetscInt k = 0; k < PD_SECTION_N; k++) sum[k] = 0;
  for (PetscInt c = 0; c < m->nsection; c++) {
    const PetscInt   e = m->section_bonds[c], i = bd->a[e], j = bd->b[e];
    const PetscReal *xi = &lat->x[3 * i], *xj = &lat->x[3 * j];
    PetscReal        dir[3], L0, L, s, q, gc, gp, gs = 0, side, y;
    BondState(m->scene, m->bs, xi, xj, &u[m->bs * i], &u[m->bs * j], dir, &L0, &L, &s, &q);
    ConcreteForce(m, e, s, &gc, &gp);
    if (bd->seg && bd->seg[e] >= 0) {
      PetscReal sp;
      PetscBool rupt;
      SegmentForce(m, bd->seg[e], s, &gs, &gp, &sp, &rupt);
    }
    side = xj[0] > xi[0] ? 1 : -1; /* dir along the bond from the part before the plane to the part beyond */
    y    = xi[v] + (X - xi[0]) / (xj[0] - xi[0]) * (xj[v] - xi[v]);
    sum[PD_SECTION_STEEL] += side * gs * dir[0];
    sum[PD_SECTION_STEEL_Y] += side * gs * dir[0] * y;
    if (gc * dir[0] * side > 0) {
      sum[PD_SECTION_TENSION] += side * gc * dir[0];
      sum[PD_SECTION_TENSION_Y] += side * gc * dir[0] * y;
    } else {
      sum[PD_SECTION_COMPRESSION] += side * gc * dir[0];
      sum[PD_SECTION_COMPRESSION_Y] += side * gc * dir[0] * y;
    }
    sum[PD_SECTION_SHEAR] += side * (gc + gs) * dir[v];
  }
}

/* The slip of owned bar node i (bar node q, PD_BAR_NODE): its displacement along the bar less that of the node it
   shadows, or on an embedded bar of its anchor along it (the same layer: local too). */
static PetscReal BarNodeSlip(const PDModel *m, const PetscScalar *u, PetscInt i, PetscInt q) {
  const PDLattice *lat = m->lat;
  const PDBar     *b   = &m->scene->bar[lat->bn_bar[q]];
  const PetscInt c = PDLatticeLocalIndex(lat, b->embedded ? lat->bn_gid[q + PD_BAR_ANCHOR_ALONG] : PDLatticeGid(lat, &lat->bn_ijk[3 * q]));
  PetscReal      s = 0;
  for (PetscInt a = 0; a < m->bs; a++) s += b->dir[0][a] * PetscRealPart(u[m->bs * i + a] - u[m->bs * c + a]);
  return s;
}

/* Largest |slip| of the owned bar nodes (BarNodeSlip). */
PetscReal PDModelSlipLocal(PDModel *m, const PetscScalar *u) {
  const PDLattice *lat  = m->lat;
  PetscReal        smax = 0;
  for (PetscInt i = 0; lat->barnode && i < lat->nowned; i++) {
    const PetscInt q = lat->barnode[i];
    if (q >= 0 && lat->bn_role[q] == PD_BAR_NODE) smax = PetscMax(smax, PetscAbsReal(BarNodeSlip(m, u, i, q)));
  }
  return smax;
}

/* Per owned node, for the fields: the stress of its bar segment with the largest |stress| (signed, Pa), the
   largest committed plastic strain of its segments, and a bar node's slip (BarNodeSlip); 0 where a node has
   none. slip may be NULL. */
void PDModelBarFieldsLocal(PDModel *m, const PetscScalar *u, PetscScalar *stress, PetscScalar *plastic, PetscScalar *slip) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  for (PetscInt i = 0; i < lat->nowned; i++) {
    const PetscInt q = lat->barnode ? lat->barnode[i] : -1;
    stress[i] = plastic[i] = 0;
    if (slip) slip[i] = q >= 0 && lat->bn_role[q] == PD_BAR_NODE ? BarNodeSlip(m, u, i, q) : 0;
  }
  for (PetscInt sg = 0; sg < bd->nseg; sg++) {
    const PetscInt  e = bd->seg_bond[sg], end[2] = {bd->a[e], bd->b[e]};
    const PetscReal sigma = SegmentStress(m, u, sg);
    for (PetscInt k = 0; k < 2; k++) {
      if (end[k] >= lat->nowned) continue;
      if (PetscAbsReal(sigma) > PetscAbsReal(PetscRealPart(stress[end[k]]))) stress[end[k]] = sigma;
      plastic[end[k]] = PetscMax(PetscRealPart(plastic[end[k]]), PetscAbsReal(m->sp_n[sg]));
    }
  }
}

/* Whether local node i has a constrained dof (a support, or a load by prescribed displacement). */
static inline PetscBool NodeHeld(const PDModel *m, PetscInt i) {
  for (PetscInt r = 0; r < m->bs; r++)
    if (m->fixed_local[m->bs * i + r]) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* The bond of this rank closest to crushing, from the bond stretches s and the nodes' dilatations theta
   (ghosted): the largest -s / eps_cu over the bonds of materials with an ultimate compressive strain
   (-pd_eps_cu), its stretch and its midpoint. Only a bond whose two nodes are compressed counts (theta < 0):
   a bond across a crack shortens as the crack's faces slide past each other, without crushing anything,
   and its nodes dilate with the crack's opening. Left out too (docs/reinforcement.md, Failure mode): the
   bonds of no-fail zones, plates, bars' links and anchor ties, whose material is none of the scene's, and the bonds of a
   node held by a support or a prescribed displacement, since in the layer next to a face so held a
   bond-based lattice strains well beyond the body's mean. Of ratios equal to PD_CRUSH_TIE the bond of the
   smallest global id (*gid): a symmetric body has many such, whose order the solver's round-off would
   decide, and any rank count should name the same. *ratio stays -PETSC_MAX_REAL where no bond counts. */
void PDModelCrushingLocal(PDModel *m, const PetscScalar *u, const PetscScalar *theta, PetscReal *ratio, PetscInt64 *gid, PetscReal *s_min,
                          PetscReal at[3]) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  *ratio               = -PETSC_MAX_REAL;
  *gid                 = INT64_MAX;
  *s_min               = 0;
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt i = bd->a[e], j = bd->b[e], k = bd->material[e];
    PetscReal      r, s;
    PetscInt64     id;
    if (k >= PD_MAX_MATERIALS || m->scene->material[k].eps_cu <= 0) continue;
    if (PetscRealPart(theta[i]) >= 0 || PetscRealPart(theta[j]) >= 0 || NodeHeld(m, i) || NodeHeld(m, j)) continue;
    s = PDModelBondStretch(m, u, e);
    if (s >= 0) continue;
    r = -s / m->scene->material[k].eps_cu;
    if (r < *ratio * (1 - PD_CRUSH_TIE)) continue;
    id = PDBondGlobalId(lat, bd, e);
    if (r <= *ratio * (1 + PD_CRUSH_TIE) && id >= *gid) continue;
    *ratio = r;
    *gid   = id;
    *s_min = s;
    for (PetscInt a = 0; a < 3; a++) at[a] = 0.5 * (lat->x[3 * i + a] + lat->x[3 * j + a]);
  }
}

/* Bond damage with the committed history, for output. */
PetscReal PDModelBondDamage(const PDModel *m, PetscInt e) {
  const PDLaw *law;
  PetscReal    dd;
  if (!m->softening) return 0;
  law = &m->law[m->bonds->material[e]];
  {
    const PDLawBond t = PDModelBondThresholds(m, e, law);
    return PDLawDamage(law, &t, m->kappa[e], &dd);
  }
}
