/* Explicit reference path: the same scene, bond kernel and laws integrated in time with PETSc TS.

   The state is X = [u; v] per rank, split for TSBASICSYMPLECTIC into "position" (du/dt = v) and
   "momentum" (dv/dt = a(u)); velocity Verlet by default, Euler-Cromer (the thesis's scheme) with
   -ts_basicsymplectic_type 1. The load factor follows the fifth-order smoothstep of THEORY.md Sec. 6 (under
   CMOD control, -pd_explicit_cmod, the servo of servo.c drives it so that the CMOD gauge follows that ramp);
   constrained dofs move with the prescribed motion (their acceleration is lambda''(t) u_ref). Local
   damping -C v is integrated exactly after each step (v *= exp(-C dt / rho)), which keeps the split
   separable. Bond histories rise at every force evaluation: there is no limiter in dynamics. */
#include "explicit.h"
#include "../model/kernel.h"

/* The fifth-order smoothstep from 0 to L over T, then held: its value and first two time derivatives at t
   (the load factor's ramp, and the CMOD gauge's under CMOD control). */
void PDSmoothstep(PetscReal L, PetscReal T, PetscReal t, PetscReal v[3]) {
  const PetscReal g = PetscMin(t / T, 1);
  v[0]              = L * g * g * g * (10 - 15 * g + 6 * g * g);
  v[1]              = t < T ? L / T * 30 * g * g * (1 - g) * (1 - g) : 0;
  v[2]              = t < T ? L / (T * T) * (60 * g - 180 * g * g + 120 * g * g * g) : 0;
}

/* Load factor and its second derivative at time t: the smoothstep ramp, or the servo's under CMOD control. */
static void Ramp(const PDExplicit *c, PetscReal t, PetscReal *lam, PetscReal *lam_tt) {
  PetscReal v[3];
  if (c->servo.on) {
    PDServoAt(&c->servo, t, lam, lam_tt);
    return;
  }
  PDSmoothstep(c->lambda_max, c->t_ramp, t, v);
  *lam    = v[0];
  *lam_tt = v[2];
}

/* Instability check (docs/explicit.md, "Stability check"). An integration past its stable step grows the
   highest-frequency mode by a factor per step: bonds gain stretch fast, and energy appears from nowhere,
   more of it at every step. A crack that bursts open within a stable step also gains stretch fast, but
   moves energy from stored to dissipated and kinetic. So a fast stretch rate (about the cracking strain
   per step) only raises the suspicion, and energy that appears fast confirms it: at two checks in a row
   (PD_CHECK_EVERY steps apart), the excess of held energy over the work grew by more than
   PD_ENERGY_JUMP of the work. The growth, not the excess itself, is what counts: debris that rattles
   after a member's failure lets the balance drift slowly (contact is not smooth, so velocity Verlet does
   not keep the energy there), by a large part of the work over many thousand steps. */
#define PD_CHECK_EVERY 10
#define PD_STRETCH_PER_STEP 1e-4
#define PD_ENERGY_JUMP 0.05

/* Largest stretch gained in one time step over the bonds, from the velocities: ds = (v_b - v_a).xi/|xi|^2 dt. */
static PetscErrorCode MaxStretchPerStep(PDExplicit *c, Vec v, PetscReal *ds) {
  PDModel           *m  = c->m;
  const PDBonds     *bd = m->bonds;
  const PetscInt     bs = m->bs;
  const PetscScalar *vl;
  Vec                loc;
  PetscReal          mx = 0;

  PetscFunctionBeginUser;
  PetscCall(VecCopy(v, c->v_local));
  PetscCall(VecGhostUpdateBegin(c->v_local, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(c->v_local, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostGetLocalForm(c->v_local, &loc));
  PetscCall(VecGetArrayRead(loc, &vl));
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt   i = bd->a[e], j = bd->b[e];
    const PetscReal *xi = &m->lat->x[3 * i], *xj = &m->lat->x[3 * j];
    PetscReal        dot = 0, L2 = 0;
    for (PetscInt a = 0; a < bs; a++) {
      dot += (xj[a] - xi[a]) * PetscRealPart(vl[bs * j + a] - vl[bs * i + a]);
      L2 += (xj[a] - xi[a]) * (xj[a] - xi[a]);
    }
    /* over dx^2 for a bar node's link, much shorter than dx: its stretch is its slip over that length */
    mx = PetscMax(mx, PetscAbsReal(dot) / PetscMax(L2, m->lat->dx * m->lat->dx) * c->dt);
  }
  PetscCall(VecRestoreArrayRead(loc, &vl));
  PetscCall(VecGhostRestoreLocalForm(c->v_local, &loc));
  PetscCall(MPIU_Allreduce(&mx, ds, 1, MPIU_REAL, MPIU_MAX, m->lat->comm));
  PetscFunctionReturn(0);
}

/* The estimate of THEORY.md Eq. 4.6, dt_i = sqrt(2 rho V_i / sum_j coef_ij/|xi_ij|), minimum over nodes; coef
   already holds c, beta, lambda and both volumes. It is 2/sqrt of a bound on the largest eigenvalue of
   M^-1 K (x^T K x <= 2 sum_i x_i^T D_i x_i with D_i the node's diagonal block, whose largest eigenvalue is
   at most its trace), as loose as the Gershgorin bound; reported for comparison. */
static PetscErrorCode Eq46TimeStep(PDModel *m, PetscReal *dt) {
  const PDBonds   *bd  = m->bonds;
  const PDLattice *lat = m->lat;
  PetscReal       *k, dtmin = PETSC_MAX_REAL;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(lat->nowned, &k));
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt i = bd->a[e], j = bd->b[e];
    PetscReal      L = 0;
    for (PetscInt a = 0; a < 3; a++) L += (lat->x[3 * j + a] - lat->x[3 * i + a]) * (lat->x[3 * j + a] - lat->x[3 * i + a]);
    L = PetscSqrtReal(L);
    k[i] += PDBondStiffness(bd, e) / L;
    if (j < lat->nowned) k[j] += PDBondStiffness(bd, e) / L;
  }
  for (PetscInt i = 0; i < lat->nowned; i++)
    if (k[i] > 0) dtmin = PetscMin(dtmin, PetscSqrtReal(2 * PDModelNodeMass(m, i) / k[i]));
  PetscCall(PetscFree(k));
  PetscCall(MPIU_Allreduce(&dtmin, dt, 1, MPIU_REAL, MPIU_MIN, lat->comm));
  PetscFunctionReturn(0);
}

/* Largest eigenvalue of M^-1 K on the free dofs (constrained ones follow the prescribed motion), K the
   undamaged elastic stiffness at rest: velocity Verlet is stable for dt < 2/sqrt(lambda_max). The
   Gershgorin bound (PDModelStiffnessRowBound) is guaranteed but several times too large on the
   Gregoire lattices; power iteration x <- M^-1 K x from a start fixed by the global dof ids (the same on
   any rank count) gives the Rayleigh quotient x^T K x / x^T M x, a lower bound that rises towards
   lambda_max (docs/explicit.md for how close it gets, and the margin the default safety leaves). */
static PetscErrorCode LargestEigenvalue(PDModel *m, Vec mass, PetscReal *eig_est, PetscReal *eig_bound) {
  const PetscInt n = m->bs * m->lat->nowned, its = m->scene->dt_power_its;
  Vec            fr, x, y, w;
  PetscScalar   *xx, xkx, xmx;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(mass, &fr));
  PetscCall(VecDuplicate(mass, &x));
  PetscCall(VecDuplicate(mass, &y));
  PetscCall(VecDuplicate(mass, &w));
  PetscCall(VecCopy(m->fixed, fr)); /* 1 on free dofs, 0 on constrained ones */
  PetscCall(VecScale(fr, -1));
  PetscCall(VecShift(fr, 1));
  PetscCall(PDModelStiffnessRowBound(m, y));
  PetscCall(VecPointwiseDivide(y, y, mass));
  PetscCall(VecPointwiseMult(y, y, fr));
  PetscCall(VecMax(y, NULL, eig_bound));
  PetscCall(VecGetArray(x, &xx));
  for (PetscInt k = 0; k < n; k++) xx[k] = PDUnitFromId(m->bs * (PetscInt64)m->lat->gid_start + k);
  PetscCall(VecRestoreArray(x, &xx));
  PetscCall(VecPointwiseMult(x, x, fr));
  *eig_est = 0;
  for (PetscInt it = 0; it < its; it++) {
    PetscCall(PDModelElasticApply(m, x, y));
    PetscCall(VecPointwiseMult(y, y, fr));
    PetscCall(VecPointwiseMult(w, x, mass));
    PetscCall(VecDot(x, y, &xkx));
    PetscCall(VecDot(x, w, &xmx));
    if (PetscRealPart(xmx) == 0) break; /* no free dof */
    *eig_est = PetscMax(*eig_est, PetscRealPart(xkx) / PetscRealPart(xmx));
    PetscCall(VecPointwiseDivide(x, y, mass));
    PetscCall(VecNormalize(x, NULL));
  }
  PetscCall(VecDestroy(&fr));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&y));
  PetscCall(VecDestroy(&w));
  PetscCheck(*eig_est > 0, m->lat->comm, PETSC_ERR_USER_INPUT, "Explicit path: no free degree of freedom has stiffness");
  PetscFunctionReturn(0);
}

/* Adaptive dynamic relaxation (Kilic and Madenci 2010): fictitious masses m = (1/4) sum_j |K_ij| / sf^2 with
   a unit time step, the Gershgorin bound that keeps central differences stable (sf = -pd_dt_safety);
   K is the elastic bond stiffness, which bounds the secant and consistent tangents of every law. */
static PetscErrorCode AdrMass(PDModel *m, Vec mass) {
  const PetscReal sf = m->scene->dt_safety;
  PetscScalar    *ms;

  PetscFunctionBeginUser;
  PetscCall(PDModelStiffnessRowBound(m, mass));
  PetscCall(VecScale(mass, 1 / (4 * sf * sf)));
  PetscCall(VecGetArray(mass, &ms));
  for (PetscInt k = 0; k < m->bs * m->lat->nowned; k++)
    if (PetscRealPart(ms[k]) == 0) ms[k] = 1; /* a dof without bonds: any mass, it carries no force */
  PetscCall(VecRestoreArray(mass, &ms));
  PetscFunctionReturn(0);
}

/* ADR damping from the local stiffness estimate k_i = -(R_i - R_i,prev) / (m_i (u_i - u_i,prev)) between
   two force evaluations (R the out-of-balance force): c = 2 sqrt(sum u_i^2 k_i / sum u_i^2), the critical
   damping of the mode the displacement is made of; 0 when the estimate is not positive, at most 2. */
static PetscErrorCode AdrDamping(PDExplicit *c, Vec u, const PetscScalar *f, const PetscScalar *fx, const PetscScalar *ms) {
  PDModel           *m = c->m;
  const PetscScalar *uu, *F;
  PetscScalar       *rp, *up;
  PetscReal          loc[2] = {0, 0}, glob[2];

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(u, &uu));
  PetscCall(VecGetArrayRead(c->f_ext, &F));
  PetscCall(VecGetArray(c->adr_r, &rp));
  PetscCall(VecGetArray(c->adr_u, &up));
  for (PetscInt k = 0; k < m->bs * m->lat->nowned; k++) {
    const PetscReal r = PetscRealPart(F[k] - f[k]), du = PetscRealPart(uu[k] - up[k]);
    if (PetscRealPart(fx[k]) == 0 && du != 0) {
      loc[0] += PetscRealPart(uu[k] * uu[k]) * -(r - PetscRealPart(rp[k])) / (PetscRealPart(ms[k]) * du);
      loc[1] += PetscRealPart(uu[k] * uu[k]);
    }
    rp[k] = r;
    up[k] = uu[k];
  }
  PetscCall(VecRestoreArray(c->adr_u, &up));
  PetscCall(VecRestoreArray(c->adr_r, &rp));
  PetscCall(VecRestoreArrayRead(c->f_ext, &F));
  PetscCall(VecRestoreArrayRead(u, &uu));
  PetscCall(MPIU_Allreduce(loc, glob, 2, MPIU_REAL, MPIU_SUM, m->lat->comm));
  c->adr_c = (glob[0] > 0 && glob[1] > 0) ? PetscMin(2, 2 * PetscSqrtReal(glob[0] / glob[1])) : 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode RHSPosition(TS ts, PetscReal t, Vec v, Vec dudt, void *ctx) {
  PetscFunctionBeginUser;
  (void)ts;
  (void)t;
  (void)ctx;
  PetscCall(VecCopy(v, dudt));
  PetscFunctionReturn(0);
}

/* a = (lambda f_ref - f_int(u)) / (rho V) on free dofs, lambda'' u_ref on constrained ones. */
static PetscErrorCode RHSMomentum(TS ts, PetscReal t, Vec u, Vec dvdt, void *ctx) {
  PDExplicit        *c = (PDExplicit *)ctx;
  PDModel           *m = c->m;
  PetscReal          lam, lam_tt;
  PetscScalar       *a, *F;
  const PetscScalar *f, *fr, *ur, *fx, *ms;

  PetscFunctionBeginUser;
  (void)ts;
  Ramp(c, t, &lam, &lam_tt);
  m->lambda = lam;
  PetscCall(PDModelInternalForce(m, u, c->f_int));
  PetscCall(VecGetArray(dvdt, &a));
  PetscCall(VecGetArray(c->f_ext, &F));
  PetscCall(VecGetArrayRead(c->f_int, &f));
  PetscCall(VecGetArrayRead(m->f_ref, &fr));
  PetscCall(VecGetArrayRead(m->u_ref, &ur));
  PetscCall(VecGetArrayRead(m->fixed, &fx));
  PetscCall(VecGetArrayRead(c->mass, &ms));
  for (PetscInt k = 0; k < m->bs * m->lat->nowned; k++) {
    if (PetscRealPart(fx[k]) != 0) {
      a[k] = lam_tt * ur[k];
      F[k] = ms[k] * a[k] + f[k]; /* the reaction that drives the dof */
    } else {
      F[k] = lam * fr[k];
      a[k] = (F[k] - f[k]) / ms[k];
    }
  }
  PetscCall(VecRestoreArray(c->f_ext, &F));
  if (m->scene->adr) PetscCall(AdrDamping(c, u, f, fx, ms));
  PetscCall(VecRestoreArrayRead(c->mass, &ms));
  PetscCall(VecRestoreArrayRead(m->fixed, &fx));
  PetscCall(VecRestoreArrayRead(m->u_ref, &ur));
  PetscCall(VecRestoreArrayRead(m->f_ref, &fr));
  PetscCall(VecRestoreArrayRead(c->f_int, &f));
  PetscCall(VecRestoreArray(dvdt, &a));
  PetscFunctionReturn(0);
}

/* External work of the step: dW = F.(u_n+1 - u_n), F the applied forces lambda f_ref on free dofs and the
   reactions m lambda'' u_ref + f_int on driven ones, as the last force evaluation saw them. Velocity
   Verlet in PETSc is drift-kick-drift with that evaluation at the half step, so this midpoint rule is
   the integrator's own work and the balance closes to round-off on smooth problems; for schemes with
   other stage layouts it is first-order accurate. */
static PetscErrorCode AddExternalWork(PDExplicit *c, Vec u) {
  PetscScalar dw;

  PetscFunctionBeginUser;
  PetscCall(VecAYPX(c->u_prev, -1, u)); /* u_n+1 - u_n */
  PetscCall(VecDot(c->f_ext, c->u_prev, &dw));
  c->w_ext += PetscRealPart(dw);
  PetscCall(VecCopy(u, c->u_prev));
  PetscFunctionReturn(0);
}

/* Kinetic energy and the energy damping has removed so far (J), summed over ranks. */
static PetscErrorCode KineticAndDamped(PDExplicit *c, Vec X, PetscReal *kinetic, PetscReal *damped) {
  const PDModel     *m = c->m;
  Vec                v;
  const PetscScalar *vv, *ms;
  PetscReal          mine[2] = {0, c->w_damp}, sum[2];

  PetscFunctionBeginUser;
  PetscCall(VecGetSubVector(X, c->is_v, &v));
  PetscCall(VecGetArrayRead(v, &vv));
  PetscCall(VecGetArrayRead(c->mass, &ms));
  for (PetscInt k = 0; k < m->bs * m->lat->nowned; k++) mine[0] += 0.5 * PetscRealPart(ms[k]) * PetscRealPart(vv[k] * vv[k]);
  PetscCall(VecRestoreArrayRead(c->mass, &ms));
  PetscCall(VecRestoreArrayRead(v, &vv));
  PetscCall(VecRestoreSubVector(X, c->is_v, &v));
  PetscCall(MPIU_Allreduce(mine, sum, 2, MPIU_REAL, MPIU_SUM, m->lat->comm));
  *kinetic = sum[0];
  *damped  = sum[1];
  PetscFunctionReturn(0);
}

/* Energy held (stored, dissipated, kinetic, damped) less the work done (J), and the larger of the two. */
static PetscErrorCode EnergyExcess(PDExplicit *c, Vec X, PetscReal *excess, PetscReal *scale) {
  Vec       u;
  PetscReal stored, dissipated, kinetic, damped, held;

  PetscFunctionBeginUser;
  PetscCall(KineticAndDamped(c, X, &kinetic, &damped));
  PetscCall(VecGetSubVector(X, c->is_u, &u));
  PetscCall(PDModelEnergy(c->m, u, &stored, &dissipated));
  PetscCall(VecRestoreSubVector(X, c->is_u, &u));
  held    = stored + dissipated + kinetic + damped;
  *excess = held - c->w_ext;
  *scale  = PetscMax(PetscMax(c->w_ext, held), PETSC_SMALL);
  PetscFunctionReturn(0);
}

/* After each step: external work, damping, a curve row every stride steps, the stop and stability checks. */
static PetscErrorCode PostStep(TS ts) {
  PDExplicit *c;
  PDModel    *m;
  Vec         X, u, v;
  PetscInt    step;
  PetscReal   t, norm, ds = 0, jump = 0;

  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &c));
  m = c->m;
  PetscCall(TSGetSolution(ts, &X));
  PetscCall(TSGetStepNumber(ts, &step));
  PetscCall(TSGetTime(ts, &t));
  PetscCall(VecGetSubVector(X, c->is_v, &v));
  PetscCall(VecNorm(v, NORM_INFINITY, &norm));
  c->v_peak = PetscMax(c->v_peak, norm);
  /* the stretch-rate check costs a bond loop: every tenth step, and whenever a velocity is not finite */
  if (step % PD_CHECK_EVERY == 0 && !PetscIsInfOrNanReal(norm)) PetscCall(MaxStretchPerStep(c, v, &ds));
  PetscCall(VecRestoreSubVector(X, c->is_v, &v));
  c->ds_peak = PetscMax(c->ds_peak, ds);
  if (!PetscIsInfOrNanReal(norm) && ds > PD_STRETCH_PER_STEP) {
    PetscReal excess = 0, scale = 1;
    PetscCall(EnergyExcess(c, X, &excess, &scale));
    if (c->excess_step == step - PD_CHECK_EVERY) jump = (excess - c->excess) / scale;
    c->excess      = excess;
    c->excess_step = step;
  }
  if (PetscIsInfOrNanReal(norm) || jump > PD_ENERGY_JUMP) {
    c->blew_up = PETSC_TRUE;
    c->jump    = PetscIsInfOrNanReal(norm) ? PETSC_INFINITY : jump;
    PetscCall(TSSetConvergedReason(ts, TS_DIVERGED_NONLINEAR_SOLVE));
    PetscFunctionReturn(0);
  }
  if (c->monitor && step % PD_CHECK_EVERY == 0) { /* reads f_int, the last force evaluation's */
    PetscBool stop = PETSC_FALSE;
    PetscCall(VecGetSubVector(X, c->is_v, &v));
    PetscCall(c->monitor(c, step, t, v, &stop));
    PetscCall(VecRestoreSubVector(X, c->is_v, &v));
    if (stop) c->stopped = PETSC_TRUE;
  }
  PetscCall(VecGetSubVector(X, c->is_u, &u));
  PetscCall(AddExternalWork(c, u));
  if (c->servo.on) PetscCall(PDServoUpdate(&c->servo, m, t, u));
  if (m->shift && step % PD_CHECK_EVERY == 0) { /* crushing: thresholds follow the compression, every tenth step like the check above */
    PetscCall(PDModelStrainState(m, u));
    PetscCall(PDModelConfine(m));
  }
  PetscCall(VecRestoreSubVector(X, c->is_u, &u));
  if (m->scene->damping > 0 || m->scene->adr) { /* free dofs only: constrained ones follow the prescribed motion */
    PetscScalar       *vv;
    const PetscScalar *fx, *ms;
    PetscReal          wd = 0;
    PetscCall(VecGetSubVector(X, c->is_v, &v));
    PetscCall(VecGetArray(v, &vv));
    PetscCall(VecGetArrayRead(m->fixed, &fx));
    PetscCall(VecGetArrayRead(c->mass, &ms));
    for (PetscInt k = 0; k < m->bs * m->lat->nowned; k++)
      if (PetscRealPart(fx[k]) == 0) {
        const PetscReal decay =
            PetscExpReal(-(m->scene->adr ? c->adr_c : m->scene->damping * m->lat->cell_volume / PetscRealPart(ms[k])) * c->dt);
        wd += 0.5 * PetscRealPart(ms[k]) * PetscRealPart(vv[k] * vv[k]) * (1 - decay * decay);
        vv[k] *= decay;
      }
    c->w_damp += wd; /* summed over ranks at the rows */
    PetscCall(VecRestoreArrayRead(c->mass, &ms));
    PetscCall(VecRestoreArrayRead(m->fixed, &fx));
    PetscCall(VecRestoreArray(v, &vv));
    PetscCall(VecRestoreSubVector(X, c->is_v, &v));
  }
  if (step % c->stride == 0 || t >= c->t_end - 0.5 * c->dt || c->stopped) { /* every stride steps, and the last */
    PDCurveRow     row;
    PetscLogDouble now;
    PetscReal      lam, lam_tt;
    Ramp(c, t, &lam, &lam_tt);
    m->lambda = lam;
    PetscCall(KineticAndDamped(c, X, &row.kinetic, &row.damped));
    c->ke_max    = PetscMax(c->ke_max, row.kinetic);
    row.external = c->w_ext;
    PetscCall(VecGetSubVector(X, c->is_u, &u));
    PetscCall(PDModelCountDamage(m));
    PetscCall(PetscTime(&now));
    row.step         = step;
    row.lambda       = lam;
    row.newton_its   = 0;
    row.ksp_its      = 0;
    row.broken_bonds = m->broken;
    row.yielded      = m->yielded;
    row.wall         = now - c->rec->t_start;
    PetscCall(PDModelMeasure(m, u, &row.load, &row.disp, &row.cmod));
    PetscCall(PDModelEnergy(m, u, &row.stored, &row.dissipated));
    PetscCall(PDModelSteelStress(m, u, &row.steel_stress, &row.slip));
    PetscCall(PDModelCrushing(m, u, PETSC_FALSE, &row.crush_ratio, &row.strain_min, row.crush_at));
    PetscCall(PDModelSection(m, u, row.section));
    PetscCall(PDRecordAddRow(c->rec, &row));
    c->rec->steps = step;
    if (m->scene->stop_cmod > 0 && row.cmod >= m->scene->stop_cmod) c->stopped = c->cmod_reached = PETSC_TRUE;
    if (row.crush_ratio >= 1) c->stopped = c->crushed = PETSC_TRUE;
    if (!c->stopped) {
      PetscCall(PDInterrupted(m->lat->comm, &c->interrupted));
      c->stopped = c->interrupted;
    }
    PetscCall(PDProgress(m->lat->comm, m->scene, &row, c->stopped));
    if (c->cmod_reached || c->crushed || c->interrupted) PetscCall(PDFieldsWrite(m, c->rec, step, u));
    PetscCall(VecRestoreSubVector(X, c->is_u, &u));
  }
  if (c->stopped) PetscCall(TSSetConvergedReason(ts, TS_CONVERGED_USER));
  PetscFunctionReturn(0);
}

/* Nodal masses: rho V per dof, or dynamic relaxation's fictitious ones.
   A bar node (bond slip) carries the steel of its share of the bar, a few per cent of a lattice node's
   mass, on the stiff start of the bond-slip law: its own frequency would set the stable step, half the
   concrete's on options/rc_beam_2d.opts. Its mass is raised to what keeps its Gershgorin bound (row sum
   of the elastic stiffness over the mass) at the lattice's largest, so the concrete sets the step
   (selective mass scaling, as explicit codes use for quasi-static runs); the mass added is reported. */
static PetscErrorCode Mass(PDModel *m, Vec mass, PetscReal *added) {
  const PDLattice   *lat = m->lat;
  const PetscInt     bs  = m->bs;
  PetscScalar       *ms;
  const PetscScalar *rb, *fx;
  Vec                row;
  PetscReal          gmax = 0, mine = 0;

  PetscFunctionBeginUser;
  *added = 0;
  if (m->scene->adr) {
    PetscCall(AdrMass(m, mass));
    PetscFunctionReturn(0);
  }
  PetscCall(VecGetArray(mass, &ms));
  for (PetscInt k = 0; k < bs * lat->nowned; k++) ms[k] = PDModelNodeMass(m, k / bs);
  PetscCall(VecRestoreArray(mass, &ms));
  if (!lat->barnode || !m->scene->bar_mass_scaling) PetscFunctionReturn(0);
  PetscCall(VecDuplicate(mass, &row));
  PetscCall(PDModelStiffnessRowBound(m, row));
  PetscCall(VecGetArray(mass, &ms));
  PetscCall(VecGetArrayRead(row, &rb));
  PetscCall(VecGetArrayRead(m->fixed, &fx));
  for (PetscInt k = 0; k < bs * lat->nowned; k++)
    if (lat->barnode[k / bs] < 0 && PetscRealPart(fx[k]) == 0) gmax = PetscMax(gmax, PetscRealPart(rb[k] / ms[k]));
  PetscCall(MPIU_Allreduce(MPI_IN_PLACE, &gmax, 1, MPIU_REAL, MPIU_MAX, lat->comm));
  for (PetscInt i = 0; gmax > 0 && i < lat->nowned; i++) {
    PetscReal need = 0;
    if (lat->barnode[i] < 0) continue;
    for (PetscInt a = 0; a < bs; a++) need = PetscMax(need, PetscRealPart(rb[bs * i + a]) / gmax);
    if (need <= PetscRealPart(ms[bs * i])) continue;
    mine += need - PetscRealPart(ms[bs * i]);
    for (PetscInt a = 0; a < bs; a++) ms[bs * i + a] = need;
  }
  PetscCall(VecRestoreArrayRead(m->fixed, &fx));
  PetscCall(VecRestoreArrayRead(row, &rb));
  PetscCall(VecRestoreArray(mass, &ms));
  PetscCall(VecDestroy(&row));
  PetscCall(MPIU_Allreduce(&mine, added, 1, MPIU_REAL, MPIU_SUM, lat->comm));
  PetscFunctionReturn(0);
}

/* Ramp and hold durations and the step count for the time step dt. The default ramp is a duration, 18,000
   stable steps (20,000 steps at the default safety 0.9): a smaller safety factor takes more steps over the
   same loading, not a faster load. Dynamic relaxation counts its unit steps. */
static void Durations(const PDScene *sc, PetscReal dt, PetscReal dt_stable, PetscReal *t_ramp, PetscReal *t_end, PetscReal *nsteps) {
  *t_ramp = sc->ramp_time > 0 ? sc->ramp_time : sc->adr ? 20000 : 18000 * dt_stable;
  /* a failure search trial holds its load, by default as long as the ramp took */
  *t_end  = *t_ramp + (sc->failure_search && sc->hold_time == 0 ? *t_ramp : sc->hold_time);
  *nsteps = PetscCeilReal(*t_end / dt);
}

/* The stable time step and the step count, before anything is written (in the record, for the run and
   its summary): a ramp, hold or safety factor whose step count no integer holds is bad input, not a
   failure found once the output exists. */
PetscErrorCode PDExplicitPlan(PDModel *m, PDRecord *rec) {
  const PDScene *sc = m->scene;
  Vec            mass;
  PetscReal      t_ramp, t_end, nsteps;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(m->f_ref, &mass));
  PetscCall(Mass(m, mass, &rec->bar_mass_added));
  PetscCall(LargestEigenvalue(m, mass, &rec->eig_est, &rec->eig_bound));
  PetscCall(VecDestroy(&mass));
  PetscCall(Eq46TimeStep(m, &rec->dt_eq46));
  rec->dt_stable = 2 / PetscSqrtReal(rec->eig_est);
  rec->dt        = sc->adr ? 1 : sc->dt_safety * rec->dt_stable; /* dynamic relaxation counts time in steps */
  Durations(sc, rec->dt, rec->dt_stable, &t_ramp, &t_end, &nsteps);
  PetscCheck(nsteps < (PetscReal)PETSC_MAX_INT - 2, m->lat->comm, PETSC_ERR_USER_INPUT,
             "-pd_ramp_time %g s, -pd_hold_time %g s and -pd_dt_safety %g need %g time steps of %g %s: more than an integer counts",
             (double)t_ramp, (double)(t_end - t_ramp), (double)sc->dt_safety, (double)nsteps, (double)rec->dt, sc->adr ? "steps" : "s");
  PetscFunctionReturn(0);
}

PetscErrorCode PDExplicitCreate(PDModel *m, PDRecord *rec, PDExplicit *c) {
  const PDScene *sc   = m->scene;
  MPI_Comm       comm = m->lat->comm;
  PetscInt       n    = m->bs * m->lat->nowned, rstart;
  PetscReal      nsteps;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(c, sizeof *c));
  c->m   = m;
  c->rec = rec;
  /* dynamics has no limiter: every level is open, and histories rise with each force evaluation */
  for (PetscInt e = 0; m->softening && e < m->bonds->nbonds; e++) m->level[e] = m->level_n[e] = PD_BOND_LEVEL_OPEN;
  m->commit_history = m->softening || m->scene->nbars ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(VecDuplicate(m->f_ref, &c->mass));
  PetscCall(VecDuplicate(m->f_ref, &c->f_int));
  PetscCall(VecDuplicate(m->f_ref, &c->u_prev));
  PetscCall(VecDuplicate(m->f_ref, &c->f_ext));
  PetscCall(Mass(m, c->mass, &rec->bar_mass_added));
  if (sc->adr) {
    PetscCall(VecDuplicate(m->f_ref, &c->adr_r));
    PetscCall(VecDuplicate(m->f_ref, &c->adr_u));
  }
  if (rec->eig_est == 0) PetscCall(PDExplicitPlan(m, rec));
  c->eig_est   = rec->eig_est;
  c->eig_bound = rec->eig_bound;
  c->dt_stable = rec->dt_stable;
  c->dt        = rec->dt;
  Durations(sc, c->dt, c->dt_stable, &c->t_ramp, &c->t_end, &nsteps);
  c->nsteps = (PetscInt)nsteps;
  c->stride = sc->out_stride > 0 ? sc->out_stride : PetscMax(1, c->nsteps / 400);
  PetscCall(PetscPrintf(comm,
                        "  explicit: largest eigenvalue of M^-1 K %.4g 1/s^2 (%" PetscInt_FMT
                        " power iterations), Gershgorin bound %.4g 1/s^2; stable step %.4g %s (Gershgorin %.4g %s, Eq. 4.6 %.4g s)\n",
                        (double)c->eig_est, sc->dt_power_its, (double)c->eig_bound, (double)c->dt_stable, sc->adr ? "steps" : "s",
                        (double)(2 / PetscSqrtReal(c->eig_bound)), sc->adr ? "steps" : "s", (double)rec->dt_eq46));
  if (sc->adr)
    PetscCall(PetscPrintf(
        comm, "  explicit: adaptive dynamic relaxation, unit steps, masses at %g of the Gershgorin bound, ramp %" PetscInt_FMT " steps\n",
        (double)sc->dt_safety, (PetscInt)c->t_ramp));
  else
    PetscCall(PetscPrintf(comm, "  explicit: step %.4g s (safety %g of the stable step), ramp %.4g s, %" PetscInt_FMT " steps\n",
                          (double)c->dt, (double)sc->dt_safety, (double)c->t_ramp, c->nsteps));
  if (sc->explicit_cmod > 0) {
    PetscCall(PDServoSetUp(m, c->mass, sc->explicit_cmod, c->t_ramp, &c->servo));
    rec->servo_gain   = c->servo.gain;
    rec->servo_omega1 = c->servo.omega1;
    rec->servo_its    = c->servo.ksp_its;
    PetscCall(PetscPrintf(comm,
                          "  explicit: CMOD control to %g m, %g m of CMOD per unit load factor (static, %" PetscInt_FMT
                          " CG iterations), fundamental frequency %.4g 1/s, servo at %.4g 1/s\n",
                          (double)sc->explicit_cmod, (double)c->servo.gain, c->servo.ksp_its, (double)c->servo.omega1,
                          (double)c->servo.omega));
  }
  PetscCall(VecDuplicate(m->u_local, &c->v_local));
  PetscCall(VecCreateMPI(comm, 2 * n, PETSC_DETERMINE, &c->X));
  PetscCall(VecGetOwnershipRange(c->X, &rstart, NULL));
  PetscCall(ISCreateStride(comm, n, rstart, 1, &c->is_u));
  PetscCall(ISCreateStride(comm, n, rstart + n, 1, &c->is_v));

  PetscCall(TSCreate(comm, &c->ts));
  PetscCall(TSSetApplicationContext(c->ts, c));
  PetscCall(TSSetType(c->ts, TSBASICSYMPLECTIC));
  PetscCall(TSBasicSymplecticSetType(c->ts, TSBASICSYMPLECTICVELVERLET));
  PetscCall(TSRHSSplitSetIS(c->ts, "position", c->is_u));
  PetscCall(TSRHSSplitSetIS(c->ts, "momentum", c->is_v));
  PetscCall(TSRHSSplitSetRHSFunction(c->ts, "position", NULL, RHSPosition, c));
  PetscCall(TSRHSSplitSetRHSFunction(c->ts, "momentum", NULL, RHSMomentum, c));
  PetscCall(TSSetExactFinalTime(c->ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSetPostStep(c->ts, PostStep));
  PetscCall(TSSetTimeStep(c->ts, c->dt));
  PetscCall(TSSetMaxTime(c->ts, c->t_end));
  PetscCall(TSSetMaxSteps(c->ts, c->nsteps + 1));
  PetscCall(TSSetFromOptions(c->ts));
  PetscFunctionReturn(0);
}

/* Integrates from rest with the load factor ramped to lambda_max, bond histories cleared: each failure
   search trial starts from the undamaged body. */
PetscErrorCode PDExplicitSolve(PDExplicit *c, PetscReal lambda_max) {
  PDModel *m = c->m;

  PetscFunctionBeginUser;
  c->lambda_max = lambda_max;
  c->ke_max = c->v_peak = c->ds_peak = c->w_ext = c->w_damp = 0;
  c->stopped = c->cmod_reached = c->crushed = c->blew_up = c->interrupted = PETSC_FALSE;
  PDServoReset(&c->servo);
  if (m->softening) PetscCall(PetscArrayzero(m->kappa, m->bonds->nbonds));
  PDModelResetThresholds(m); /* a trial's rises under compression (-pd_fc) are history too */
  if (m->scene->nbars) {
    PetscCall(PetscArrayzero(m->sp_n, m->bonds->nseg));
    PetscCall(PetscArrayzero(m->ruptured_n, m->bonds->nseg));
    PetscCall(PetscArrayzero(m->dissipated_n, m->bonds->nseg));
  }
  m->broken = 0;
  PetscCall(PDRecordClearRows(c->rec));
  PetscCall(VecZeroEntries(c->X));
  PetscCall(VecZeroEntries(c->u_prev));
  PetscCall(VecZeroEntries(c->f_ext));
  c->adr_c = 0;
  if (c->adr_r) {
    PetscCall(VecZeroEntries(c->adr_r));
    PetscCall(VecZeroEntries(c->adr_u));
  }
  PetscCall(TSSetTime(c->ts, 0));
  PetscCall(TSSetStepNumber(c->ts, 0));
  PetscCall(TSSetTimeStep(c->ts, c->dt));
  PetscCall(TSSetConvergedReason(c->ts, TS_CONVERGED_ITERATING));
  PetscCall(TSSolve(c->ts, c->X));
  PetscCall(TSGetConvergedReason(c->ts, &c->reason));
  PetscCall(TSGetStepNumber(c->ts, &c->rec->time_steps));
  c->rec->ke_max  = c->ke_max;
  c->rec->v_peak  = c->v_peak;
  c->rec->ds_peak = c->ds_peak;
  PetscFunctionReturn(0);
}

PetscErrorCode PDExplicitDestroy(PDExplicit *c) {
  PetscFunctionBeginUser;
  PetscCall(TSDestroy(&c->ts));
  PetscCall(ISDestroy(&c->is_u));
  PetscCall(ISDestroy(&c->is_v));
  PetscCall(VecDestroy(&c->X));
  PetscCall(VecDestroy(&c->mass));
  PetscCall(VecDestroy(&c->f_int));
  PetscCall(VecDestroy(&c->v_local));
  PetscCall(VecDestroy(&c->u_prev));
  PetscCall(VecDestroy(&c->f_ext));
  PetscCall(VecDestroy(&c->adr_r));
  PetscCall(VecDestroy(&c->adr_u));
  PetscFunctionReturn(0);
}

/* Status of an integration that did not blow up and was not stopped by a monitor. */
PetscErrorCode PDExplicitStatus(PDExplicit *c) {
  PDRecord *rec = c->rec;

  PetscFunctionBeginUser;
  rec->converged = PETSC_TRUE;
  if (c->blew_up) {
    rec->converged = PETSC_FALSE;
    PetscCall(PetscSNPrintf(rec->status, sizeof rec->status,
                            "unstable: a bond gained a stretch of %.3g in one step, and energy of %.3g of the work appeared in %d steps, "
                            "by time step %" PetscInt_FMT " (time step %.3g s, %.3g of the stable step)",
                            (double)c->ds_peak, (double)c->jump, PD_CHECK_EVERY, rec->time_steps, (double)c->dt,
                            (double)c->m->scene->dt_safety));
  } else if (c->cmod_reached)
    PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "completed: CMOD reached %g m", (double)c->m->scene->stop_cmod));
  else if (c->crushed)
    PetscCall(PDCrushedStatus(c->m->scene, rec, &rec->rows[rec->nrows - 1]));
  else if (c->interrupted) {
    rec->converged = PETSC_FALSE;
    PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "interrupted by %s after time step %" PetscInt_FMT, PDInterruptSignal(),
                            rec->time_steps));
  } else if (c->reason < 0) {
    rec->converged = PETSC_FALSE;
    PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "time integration stopped: %s", TSConvergedReasons[c->reason]));
  } else
    PetscCall(PetscStrncpy(rec->status, "completed", sizeof rec->status));
  PetscCall(PetscSNPrintf(rec->solver, sizeof rec->solver, "TS %s", "basicsymplectic"));
  PetscFunctionReturn(0);
}

PetscErrorCode PDExplicitRun(PDModel *m, PDRecord *rec) {
  PDExplicit c;

  PetscFunctionBeginUser;
  PetscCall(PDExplicitCreate(m, rec, &c));
  PetscCall(PDExplicitSolve(&c, m->scene->lambda_max));
  PetscCall(PDExplicitStatus(&c));
  if (rec->converged && !c.cmod_reached && !c.crushed) { /* (an interrupted run wrote its fields when it stopped) */
    Vec u;
    PetscCall(VecGetSubVector(c.X, c.is_u, &u));
    PetscCall(PDFieldsWrite(m, rec, rec->time_steps, u));
    PetscCall(VecRestoreSubVector(c.X, c.is_u, &u));
  }
  PetscCall(PDExplicitDestroy(&c));
  PetscFunctionReturn(0);
}
