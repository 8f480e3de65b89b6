/* When to rebuild the preconditioner of the tangent.

   Two policies:
   - a fixed lag across Newton iterations, limiter stages and steps: every sixth assembly for block
     ICC(0) in 3D (PD_ICC_LAG), every third for 2D models (PD_FIXED_LAG). Rebuilt every time, the factor
     took a large share of the half-notched beam's time; short lags took most of it away, longer ones
     gained nothing more while each increment was settled twice. Once an increment's first Newton
     iteration became a limiter stage (docs/design.md, point 42), most assemblies are stages' whose
     linear solves ask little, and a lag of 6 halved the factorisations' time for a few more Krylov
     iterations (docs/benchmarks/solve_profile.md). Rebuilding it only when stale
     gained nothing on the D = 50 mm beams at dx = 5 mm (fewer factors, more Krylov iterations), and on the 2D beams it let
     left-preconditioned GMRES meet its tolerance on a preconditioned residual that no longer measured
     the true one, so that Newton stalled (docs/solvers.md).
   - when stale: 3D models under GAMG (the default from PD_GAMG_MIN_NODES_SOFTENING nodes, or -pc_type gamg), whose set-up (aggregation,
   Galerkin products, eigenvalue estimates) costs several V-cycles. A hierarchy built before the damage still fits the tangent, which damage
   changes in a band of bonds. Each solve is measured in Krylov iterations per decade of residual reduction (its over log10(1/rtol):
   Eisenstat-Walker moves rtol from solve to solve; a solve stopped at the drivers' absolute floor counts the decades from its
   right-hand side down to the floor). The first solve after a rebuild that takes more than one iteration sets the reference (a
   single iteration, under a loose Eisenstat-Walker tolerance, says nothing of the preconditioner, and as a reference it made
   every ordinary solve look stale); a later one that needs more than
     PD_STALE_FACTOR times it plus PD_STALE_SLACK, or that fails, asks for a rebuild at the next
     assembly, and a failed one may be made again at once with a fresh preconditioner.
   docs/solvers.md and docs/benchmarks/pc_refresh.md have the measurements. */
#include "path.h"

#define PD_FIXED_LAG 3
#define PD_ICC_LAG 6
#define PD_STALE_FACTOR 2.0
#define PD_STALE_SLACK 4.0

/* bnorm: the norm of the solve's right-hand side, or NULL to read it from the KSP where it is needed */
static PetscErrorCode Measure(PDPCRefresh *r, KSP ksp, const PetscReal *bnorm, PetscBool *again) {
  PetscInt           its;
  PetscReal          rtol, atol, decades, per_decade;
  KSPConvergedReason reason;
  PetscBool          guess;

  PetscFunctionBeginUser;
  if (again) *again = PETSC_FALSE;
  if (!r->when_stale) PetscFunctionReturn(0);
  PetscCall(KSPGetIterationNumber(ksp, &its));
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  PetscCall(KSPGetTolerances(ksp, &rtol, &atol, NULL, NULL));
  PetscCall(KSPGetInitialGuessNonzero(ksp, &guess));
  /* a solve started from a guess reduced its residual by fewer decades than rtol says: it measures
     nothing, unless it failed */
  if (guess && reason >= 0) PetscFunctionReturn(0);
  decades = -PetscLog10Real(PetscMax(rtol, PETSC_MACHINE_EPSILON));
  if (reason == KSP_CONVERGED_ATOL) { /* stopped at the drivers' floor (a true residual, from a zero guess) */
    PetscReal b = bnorm ? *bnorm : 0;
    if (!bnorm) {
      Vec rhs;
      PetscCall(KSPGetRhs(ksp, &rhs));
      PetscCall(VecNorm(rhs, NORM_2, &b));
    }
    decades = PetscLog10Real(PetscMax(b / atol, 1.0));
  }
  per_decade = its / PetscMax(1.0, decades);
  if (r->measure && its < 2) PetscFunctionReturn(0); /* measures nothing: the next solve sets the reference */
  if (r->measure) {                                  /* the first solve with a fresh preconditioner */
    r->fresh   = per_decade;
    r->measure = PETSC_FALSE;
  } else if (!r->due && (reason < 0 || per_decade > PD_STALE_FACTOR * r->fresh + PD_STALE_SLACK)) {
    PetscCall(
        PetscInfo(ksp, "preconditioner stale: %g iterations per decade against %g when built\n", (double)per_decade, (double)r->fresh));
    PetscCall(PDPCRefreshRequest(r));
    if (again && reason < 0) *again = PETSC_TRUE; /* failed with a kept preconditioner: worth a fresh one */
  }
  PetscFunctionReturn(0);
}

PetscErrorCode PDPCRefreshSolved(PDPCRefresh *r, KSP ksp, PetscBool *again) {
  PetscFunctionBeginUser;
  PetscCall(Measure(r, ksp, NULL, again));
  PetscFunctionReturn(0);
}

/* SNES keeps KSP's pre- and post-solve hooks for Eisenstat-Walker, so under SNES the solve is measured
   from a monitor, which runs after each Newton update (iteration 0 is the start, after no solve). By then
   the residual vector the solve had as its right-hand side holds the new residual: the right-hand side's
   norm is the residual norm the monitor saw one iteration before. */
static PetscErrorCode MonitorSolve(SNES snes, PetscInt it, PetscReal fnorm, void *ctx) {
  PDPCRefresh *r = (PDPCRefresh *)ctx;
  KSP          ksp;

  PetscFunctionBeginUser;
  if (it > 0) {
    PetscCall(SNESGetKSP(snes, &ksp));
    PetscCall(Measure(r, ksp, &r->fnorm, NULL));
  }
  r->fnorm = fnorm;
  PetscFunctionReturn(0);
}

PetscErrorCode PDPCRefreshAttach(const PDModel *m, KSP ksp, SNES snes, PDPCRefresh *r) {
  PC        pc;
  PetscBool gamg, bjacobi;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(r, sizeof *r));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCGAMG, &gamg));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCBJACOBI, &bjacobi));
  r->lag        = m->bs == 3 && bjacobi ? PD_ICC_LAG : PD_FIXED_LAG;
  r->snes       = snes;
  r->when_stale = m->bs == 3 && gamg ? PETSC_TRUE : PETSC_FALSE;
  r->due        = PETSC_TRUE;
  if (!snes) PetscFunctionReturn(0);
  if (r->when_stale) {
    PetscCall(SNESSetLagPreconditioner(snes, -2));
    PetscCall(SNESMonitorSet(snes, MonitorSolve, r, NULL));
  } else
    PetscCall(SNESSetLagPreconditioner(snes, r->lag));
  PetscCall(SNESSetLagPreconditionerPersists(snes, PETSC_TRUE));
  PetscFunctionReturn(0);
}

PetscErrorCode PDPCRefreshAssembled(PDPCRefresh *r, KSP ksp) {
  PetscFunctionBeginUser;
  if (!r->when_stale && r->assemblies++ % r->lag == 0) r->due = PETSC_TRUE;
  if (r->due) r->measure = PETSC_TRUE;
  /* under SNES its lag has already told the KSP; the path-following driver tells it here */
  if (!r->snes) PetscCall(KSPSetReusePreconditioner(ksp, r->due ? PETSC_FALSE : PETSC_TRUE));
  r->due = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode PDPCRefreshRequest(PDPCRefresh *r) {
  PetscFunctionBeginUser;
  r->due        = PETSC_TRUE;
  r->assemblies = 0; /* the fixed lag counts from the rebuild */
  if (r->snes && r->when_stale) PetscCall(SNESSetLagPreconditioner(r->snes, -2));
  PetscFunctionReturn(0);
}

/* A preconditioner whose set-up failed (a zero pivot in a factorisation) must not be kept: PETSc's MUMPS
   interface skips every later numeric factorisation once one has failed, so the next solve stops the run
   with an error, and a lag or an unchanged operator would apply the failed factor again. Reset, the PC is
   built from scratch at the next solve. The failure is read from the PC on every rank (a KSP's reason may
   be set on some ranks only), and the operators, which PCReset drops, are given back. */
PetscErrorCode PDPCForgetFailed(KSP ksp) {
  PC             pc;
  PCFailedReason reason;
  PetscInt       mine, any;
  Mat            A, P;

  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCGetFailedReasonRank(pc, &reason));
  mine = reason != PC_NOERROR;
  PetscCall(MPIU_Allreduce(&mine, &any, 1, MPIU_INT, MPI_MAX, PetscObjectComm((PetscObject)ksp)));
  if (!any) PetscFunctionReturn(0);
  PetscCall(KSPGetOperators(ksp, &A, &P));
  PetscCall(PetscObjectReference((PetscObject)A));
  PetscCall(PetscObjectReference((PetscObject)P));
  PetscCall(PCReset(pc));
  PetscCall(PCSetFailedReason(pc, PC_NOERROR)); /* which PCReset keeps: a PC of another type would report it at every solve */
  PetscCall(KSPSetOperators(ksp, A, P));
  PetscCall(MatDestroy(&A));
  PetscCall(MatDestroy(&P));
  PetscFunctionReturn(0);
}
