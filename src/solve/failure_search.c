/* Failure load of a load-controlled scene (Ness 2019, Sec. 3.5 and 4.3): each trial ramps the load to a
   test value with the smoothstep, holds it with damping, and is judged converged (carried) or failed by
   one of three criteria; a geometric bisection T = sqrt(L U) narrows [L, U] between the largest load
   carried and the smallest that failed. Every trial starts from the undamaged body at rest. */
#include "explicit.h"

typedef struct {
  const PDScene *sc;
  PetscBool     *loaded;     /* [nowned] node carries applied force */
  PetscReal      nloaded;    /* global count */
  PetscReal      vmean_peak; /* largest mean loaded-node speed in the trial */
  PetscInt       window;     /* checks (every tenth step) in the damage criterion's window */
  PetscInt       still;      /* consecutive checks with damage still */
  PetscInt       aligned;    /* consecutive checks, once still, with velocity along the load */
  PetscInt64     broken_prev;
  PetscInt       verdict; /* 0 undecided, 1 converged, -1 failed */
  char           why[96];
} Judge;

/* Mean speed of the loaded nodes (Ness Eq. 3.11) and mean out-of-balance over applied force at them
   (Eq. 3.13, from the last force evaluation). */
static PetscErrorCode LoadedNodeMeans(PDExplicit *c, Judge *jd, Vec v, PetscReal *vmean, PetscReal *fratio) {
  PDModel           *m  = c->m;
  const PetscInt     bs = m->bs;
  const PetscScalar *vv, *F, *f;
  PetscReal          loc[2] = {0, 0}, glob[2];

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(v, &vv));
  PetscCall(VecGetArrayRead(c->f_ext, &F));
  PetscCall(VecGetArrayRead(c->f_int, &f));
  for (PetscInt i = 0; i < m->lat->nowned; i++) {
    PetscReal sv = 0, sr = 0, sf = 0;
    if (!jd->loaded[i]) continue;
    for (PetscInt a = 0; a < bs; a++) {
      sv += PetscRealPart(vv[bs * i + a] * vv[bs * i + a]);
      sr += PetscRealPart((F[bs * i + a] - f[bs * i + a]) * (F[bs * i + a] - f[bs * i + a]));
      sf += PetscRealPart(F[bs * i + a] * F[bs * i + a]);
    }
    loc[0] += PetscSqrtReal(sv);
    loc[1] += sf > 0 ? PetscSqrtReal(sr / sf) : 0;
  }
  PetscCall(VecRestoreArrayRead(c->f_int, &f));
  PetscCall(VecRestoreArrayRead(c->f_ext, &F));
  PetscCall(VecRestoreArrayRead(v, &vv));
  PetscCall(MPIU_Allreduce(loc, glob, 2, MPIU_REAL, MPIU_SUM, m->lat->comm));
  *vmean  = glob[0] / jd->nloaded;
  *fratio = glob[1] / jd->nloaded;
  PetscFunctionReturn(0);
}

/* Judges a trial every tenth step once the load is held. Velocity decay: converged when the mean
   loaded-node speed falls below vtol times its peak. Force decay: converged when the mean out-of-balance
   ratio falls below ftol. Bond damage (Ness Alg. 2): once the broken-bond fraction has grown less than
   dtol per step for a window, failed if the loaded nodes keep moving along the load for another window,
   converged when they come to rest (velocity decay); the rest test is made whichever way they move, since
   a damped body can creep to rest along the load. Undecided at the end of the hold counts as failed. */
static PetscErrorCode Judge_Monitor(PDExplicit *c, PetscInt step, PetscReal t, Vec v, PetscBool *stop) {
  Judge    *jd = (Judge *)c->monitor_ctx;
  PDModel  *m  = c->m;
  PetscReal vmean, fratio;

  PetscFunctionBeginUser;
  (void)step;
  PetscCall(LoadedNodeMeans(c, jd, v, &vmean, &fratio));
  jd->vmean_peak = PetscMax(jd->vmean_peak, vmean);
  if (t < c->t_ramp) PetscFunctionReturn(0);
  switch (jd->sc->failure_criterion) {
  case PD_FAILURE_VELOCITY:
    if (vmean <= jd->sc->failure_vtol * jd->vmean_peak) {
      jd->verdict = 1;
      PetscCall(
          PetscSNPrintf(jd->why, sizeof jd->why, "loaded nodes at rest (%.3g of their peak speed)", (double)(vmean / jd->vmean_peak)));
    }
    break;
  case PD_FAILURE_FORCE:
    if (fratio <= jd->sc->failure_ftol) {
      jd->verdict = 1;
      PetscCall(PetscSNPrintf(jd->why, sizeof jd->why, "out-of-balance %.3g of the applied force", (double)fratio));
    }
    break;
  case PD_FAILURE_DAMAGE: {
    PetscScalar vb;
    PetscReal   rate;
    PetscCall(PDModelCountDamage(m));
    rate            = (PetscReal)(m->broken - jd->broken_prev) / (PetscReal)m->bonds->nbonds_global / 10;
    jd->broken_prev = m->broken;
    jd->still       = rate < jd->sc->failure_dtol ? jd->still + 1 : 0;
    if (jd->still < jd->window) break;
    if (vmean <= jd->sc->failure_vtol * jd->vmean_peak) {
      jd->verdict = 1;
      PetscCall(PetscSNPrintf(jd->why, sizeof jd->why, "damage still, loaded nodes at rest (%.3g of their peak speed)",
                              (double)(vmean / jd->vmean_peak)));
      break;
    }
    PetscCall(VecDot(v, m->f_ref, &vb));
    jd->aligned = PetscRealPart(vb) * c->lambda_max > 0 ? jd->aligned + 1 : 0;
    if (jd->aligned >= jd->window) {
      jd->verdict = -1;
      PetscCall(PetscSNPrintf(jd->why, sizeof jd->why,
                              "loaded nodes kept moving along the load (%" PetscInt64_FMT " bonds broken, %" PetscInt64_FMT " softening)",
                              m->broken, m->softening_bonds));
    }
  } break;
  }
  if (jd->verdict) *stop = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode PDFailureSearchRun(PDModel *m, PDRecord *rec) {
  const PDScene  *sc   = m->scene;
  MPI_Comm        comm = m->lat->comm;
  PDExplicit      c;
  Judge           jd;
  PDCurveRow     *best  = NULL;
  PetscInt        nbest = 0, total_steps = 0;
  const PetscReal P = m->force_magnitude; /* total applied force at load factor 1 (N) */
  PetscReal       L = sc->failure_bracket[0] > 0 ? sc->failure_bracket[0] : 0.5 * P * sc->lambda_max;
  PetscReal       U = sc->failure_bracket[1] > 0 ? sc->failure_bracket[1] : 2 * P * sc->lambda_max;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&jd, sizeof jd));
  jd.sc = sc;
  PetscCall(PetscCalloc1(PetscMax(1, m->lat->nowned), &jd.loaded));
  {
    const PetscScalar *fr;
    PetscReal          n = 0;
    PetscCall(VecGetArrayRead(m->f_ref, &fr));
    for (PetscInt i = 0; i < m->lat->nowned; i++)
      for (PetscInt a = 0; a < m->bs; a++)
        if (PetscRealPart(fr[m->bs * i + a]) != 0) jd.loaded[i] = PETSC_TRUE;
    for (PetscInt i = 0; i < m->lat->nowned; i++) n += jd.loaded[i] ? 1 : 0;
    PetscCall(VecRestoreArrayRead(m->f_ref, &fr));
    PetscCall(MPIU_Allreduce(&n, &jd.nloaded, 1, MPIU_REAL, MPIU_SUM, comm));
  }
  PetscCall(PDExplicitCreate(m, rec, &c));
  c.monitor     = Judge_Monitor;
  c.monitor_ctx = &jd;
  jd.window     = PetscMax(1, (PetscInt)((sc->failure_window > 0 ? sc->failure_window : 0.25 * c.t_ramp) / (10 * c.dt)));
  PetscCall(PetscPrintf(
      comm, "  failure search (%s criterion): bracket %.1f to %.1f N, tolerance %g, trials of %" PetscInt_FMT " steps at most\n",
      PDFailureCriteria[sc->failure_criterion], (double)L, (double)U, (double)sc->failure_tol, c.nsteps));
  rec->converged = PETSC_TRUE;
  while ((U - L) / L > sc->failure_tol && rec->ntrials < (PetscInt)(sizeof rec->trial / sizeof rec->trial[0])) {
    const PetscReal T = PetscSqrtReal(L * U);
    const PetscInt  k = rec->ntrials++;
    jd.vmean_peak     = 0;
    jd.still = jd.aligned = jd.broken_prev = 0;
    jd.verdict                             = 0;
    PetscCall(PDExplicitSolve(&c, T / P));
    total_steps += rec->time_steps;
    if (c.interrupted) { /* the trial under way is not judged */
      rec->ntrials--;
      break;
    }
    PetscCheck(
        !c.blew_up, comm, PETSC_ERR_NOT_CONVERGED,
        "Failure search: trial at %.1f N became unstable (stretch %.3g in one step, energy of %.3g of the work appeared in ten steps); "
        "lower -pd_dt_safety",
        (double)T, (double)c.ds_peak, (double)c.jump);
    if (!jd.verdict && c.crushed) { /* -pd_eps_cu: the concrete crushed under the trial load */
      jd.verdict = -1;
      PetscCall(PetscSNPrintf(jd.why, sizeof jd.why, "crushed: a bond's stretch %.4g at time step %" PetscInt_FMT,
                              (double)rec->rows[rec->nrows - 1].strain_min, rec->rows[rec->nrows - 1].step));
    }
    if (!jd.verdict) {
      jd.verdict = -1;
      PetscCall(PetscSNPrintf(jd.why, sizeof jd.why, "undecided at the end of the hold (%g s)", (double)c.t_end));
    }
    rec->trial[k].load    = T;
    rec->trial[k].verdict = jd.verdict;
    rec->trial[k].steps   = rec->time_steps;
    PetscCall(PetscStrncpy(rec->trial[k].why, jd.why, sizeof rec->trial[k].why));
    PetscCall(PetscPrintf(comm, "  trial %" PetscInt_FMT ": %.1f N %s after %" PetscInt_FMT " steps: %s\n", k + 1, (double)T,
                          jd.verdict > 0 ? "carried" : "failed", rec->time_steps, jd.why));
    {
      Vec u;
      PetscCall(VecGetSubVector(c.X, c.is_u, &u));
      PetscCall(PDFieldsWrite(m, rec, k + 1, u)); /* one field group per trial: the damage each load left */
      PetscCall(VecRestoreSubVector(c.X, c.is_u, &u));
    }
    if (jd.verdict > 0) {
      L = rec->fail_lower = T;
      /* the curve reports the largest load carried */
      PetscCall(PetscFree(best));
      PetscCall(PetscMalloc1(PetscMax(1, rec->nrows), &best));
      PetscCall(PetscArraycpy(best, rec->rows, rec->nrows));
      nbest = rec->nrows;
    } else
      U = rec->fail_upper = T;
  }
  if (best) { /* the curve of the largest load carried */
    PetscCall(PDRecordClearRows(rec));
    for (PetscInt r = 0; r < nbest; r++) PetscCall(PDRecordAddRow(rec, &best[r]));
  }
  rec->time_steps = total_steps;
  rec->steps      = rec->ntrials;
  if (c.interrupted) {
    rec->converged = PETSC_FALSE;
    PetscCall(PetscSNPrintf(rec->status, sizeof rec->status,
                            "interrupted by %s after %" PetscInt_FMT " trials: failure load between %.1f and %.1f N so far",
                            PDInterruptSignal(), rec->ntrials, (double)L, (double)U));
  } else if (rec->fail_lower > 0 && rec->fail_upper > 0)
    PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "completed: failure load between %.1f and %.1f N (%" PetscInt_FMT " trials)",
                            (double)rec->fail_lower, (double)rec->fail_upper, rec->ntrials));
  else {
    rec->converged = PETSC_FALSE;
    PetscCall(PetscSNPrintf(rec->status, sizeof rec->status,
                            "failure search open: every trial %s; widen -pd_failure_bracket (now %.1f to %.1f N)",
                            rec->fail_upper > 0 ? "failed" : "carried its load",
                            (double)sc->failure_bracket[0] > 0 ? (double)sc->failure_bracket[0] : (double)(0.5 * P * sc->lambda_max),
                            (double)(sc->failure_bracket[1] > 0 ? sc->failure_bracket[1] : 2 * P * sc->lambda_max)));
  }
  PetscCall(PetscSNPrintf(rec->solver, sizeof rec->solver, "TS %s", "basicsymplectic"));
  PetscCall(PetscFree(best));
  PetscCall(PetscFree(jd.loaded));
  PetscCall(PDExplicitDestroy(&c));
  PetscFunctionReturn(0);
}
