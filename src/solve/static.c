/* Quasi-static path under load or displacement control. The load factor lambda scales every prescribed
   displacement and applied force; each increment is solved by SNES (one KSP solve with SNESKSPONLY when
   the model is linear), with the damage limiter granting bond events between Newton stages. Increments
   are cut on failure and grown on easy convergence. */
#include "path.h"

#define PD_MAX_STAGES 1000000
/* freezes and branch changes an increment may take before it counts as failed (path following's budget) */
#define PD_MAX_FLIPS 30
/* share of Newton's absolute tolerance a linear solve stops at (Predict) */
#define PD_KSP_ATOL_SHARE 0.5
/* GMRES restart: no solve of the half-notched beam needs more iterations; PETSc's default restart cut
   into half of them and doubled the Krylov count (docs/solvers.md) */
#define PD_GMRES_RESTART 60

/* GAMG's Galerkin products P^T A P on several ranks (the only matrix triple products pdimplicit makes):
   PETSc's default parallel algorithm keeps intermediate products for a later numeric reuse, and they set the
   peak memory of a whole run, while a hierarchy rebuilt only when stale (pc_refresh.c) seldom reuses them.
   The all-at-once algorithm keeps none, at the same wall time of a whole run (docs/benchmarks/memory.md, rows
   "default" and "Galerkin products kept for reuse"), but its product of the finest level takes several times
   as long as the row-merged one (`nonscalable`, whose intermediates are as large as the default's). Below
   PD_GALERKIN_LEAN_NODES nodes, where those intermediates take a few hundred megabytes, the faster product
   is taken; from there on, where memory limits what a machine can run, the leaner one (docs/solvers.md,
   "What a second rank adds, and GAMG's Galerkin products"). A choice on the command line stands; one rank has no such algorithm and needs
   none. */
#define PD_GALERKIN_LEAN_NODES 100000
static PetscErrorCode ChooseGalerkinProduct(MPI_Comm comm, PetscInt nodes) {
  PetscMPIInt size;
  PetscBool   via, alg;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-matptap_via", &via));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-mat_product_algorithm", &alg));
  if (size > 1 && !via && !alg)
    PetscCall(PetscOptionsSetValue(NULL, "-matptap_via", nodes < PD_GALERKIN_LEAN_NODES ? "nonscalable" : "allatonce"));
  PetscFunctionReturn(0);
}

/* A MUMPS factor of a softening model's tangent detects null pivots (ICNTL(24)) unless the command line
   says otherwise: a crack that frees a fragment (nodes whose bonds to the rest have all broken) leaves the
   tangent singular in the fragment's rigid-body modes, and MUMPS then fixes those modes in the correction
   instead of failing (docs/reinforcement.md, "A factored tangent"). Set only where MUMPS is named, so
   that no option goes unused. */
static PetscErrorCode ChooseNullPivots(const PDModel *m) {
  char      pkg[64] = "";
  PetscBool named, mumps, given;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-pc_factor_mat_solver_type", pkg, sizeof pkg, &named));
  PetscCall(PetscStrcmp(pkg, MATSOLVERMUMPS, &mumps));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-mat_mumps_icntl_24", &given));
  if (m->softening && named && mumps && !given) PetscCall(PetscOptionsSetValue(NULL, "-mat_mumps_icntl_24", "1"));
  PetscFunctionReturn(0);
}

/* Krylov method and preconditioner for the stiffness, shared with path following. */
PetscErrorCode PDSolverConfigureKSP(PDModel *m, KSP ksp) {
  PC pc;

  PetscFunctionBeginUser;
  /* Non-linear 3D models: block Jacobi with ICC(0) blocks on SBAIJ storage, measured fastest on small
     3D PD stiffnesses; GAMG takes over on 2D and large models (below). Linear 3D models: CG with point
     Jacobi, which needs more iterations than ICC(0) but no triangular solves and no factor, so that one
     solve costs less and half the memory (docs/solvers.md, docs/benchmarks/elastic.md); their matrix is
     assembled once, so ICC(0)'s cheap set-up does not count. Direct factorisations suffer from the
     fill-in of a 3D horizon. The consistent tangent of a softening bond is indefinite: CG and MINRES
     (which needs a positive preconditioner) break down on it with ICC, GMRES does not. */
  PetscCall(KSPSetType(ksp, (m->softening && m->scene->tangent == PD_TANGENT_CONSISTENT) ? KSPGMRES : KSPCG));
  PetscCall(KSPGMRESSetRestart(ksp, PD_GMRES_RESTART));
  PetscCall(KSPGetPC(ksp, &pc));
  /* 2D models and large 3D ones: algebraic multigrid with the rigid-body near-null space; ICC(0) loses
     its grip on long beams, where its Krylov iterations grow by an order of magnitude (docs/solvers.md;
     PDModelDefaultsToGAMG) */
  PetscCall(PCSetType(pc, PDModelDefaultsToGAMG(m) ? PCGAMG : m->linear ? PCJACOBI : PCBJACOBI));
  /* a Krylov solve of a softening model that needs thousands of iterations has stalled (the half-notched beam's
     need a few dozen): give up early, so that the increment is cut or the preconditioner changed
     (SwitchToGAMG) within seconds rather than minutes */
  PetscCall(KSPSetTolerances(ksp, m->linear ? 1e-9 : 1e-6, PETSC_DEFAULT, PETSC_DEFAULT, m->softening ? 2000 : 20000));
  PetscCall(PDInterruptWatchKSP(ksp));
  PetscCall(ChooseGalerkinProduct(PetscObjectComm((PetscObject)ksp), m->lat->nglobal));
  PetscCall(ChooseNullPivots(m));
  PetscFunctionReturn(0);
}

/* GMRES (a softening model's consistent tangent, PDSolverConfigureKSP) with block ICC(0) or GAMG in 3D:
   preconditioned on the right, so that its residual is the true one, which Eisenstat-Walker's tolerance
   is defined on and which Newton's own test measures (the drivers then stop each linear solve once it
   meets that test: Predict, and the path-following corrector; docs/solvers.md "Tolerances"). In its
   flexible form: right-preconditioned GMRES applies the preconditioner once more at the end of each solve
   to map its Krylov combination back, FGMRES keeps the preconditioned vectors and does not, and the
   tangent's solves take two or three iterations each (docs/benchmarks/solve_profile.md, row "GMRES"); a
   side chosen with -ksp_pc_side keeps GMRES, which takes either. A preconditioner chosen on the command
   line keeps PETSc's side unless -ksp_pc_side says otherwise. Called before the KSP reads its options. */
PetscErrorCode PDSolverPreferFlexible(PDModel *m, KSP ksp) {
  PetscFunctionBeginUser;
  if (m->bs == 3 && !m->scene->pc_chosen) {
    PC        pc;
    PetscBool gmres, pcok, side_chosen;
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PetscObjectTypeCompare((PetscObject)ksp, KSPGMRES, &gmres));
    PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &pcok, PCBJACOBI, PCGAMG, ""));
    PetscCall(PetscOptionsHasName(NULL, NULL, "-ksp_pc_side", &side_chosen));
    if (gmres && pcok && !side_chosen) {
      PetscCall(KSPSetType(ksp, KSPFGMRES));
      PetscCall(KSPGMRESSetRestart(ksp, PD_GMRES_RESTART));
    }
    if (gmres && pcok) PetscCall(KSPSetPCSide(ksp, PC_RIGHT));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode ConfigureSolver(PDModel *m, SNES snes, PDPCRefresh *refresh) {
  KSP ksp;

  PetscFunctionBeginUser;
  PetscCall(SNESSetType(snes, m->linear ? SNESKSPONLY : SNESNEWTONLS));
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(PDSolverConfigureKSP(m, ksp));
  PetscCall(PDInterruptWatchSNES(snes));
  /* inexact Newton (Eisenstat-Walker) on non-linear scenes: early iterations need little accuracy; a
     failing increment gives up after 20 iterations and is cut */
  if (!m->linear) {
    PetscCall(SNESKSPSetUseEW(snes, PETSC_TRUE));
    /* Eisenstat-Walker's first choice (linear tolerance from how well the last linear model predicted the
       residual) took fewer Krylov iterations than the default second one on the half-notched beam, with
       the same curve (docs/benchmarks/solve_profile.md) */
    PetscCall(SNESKSPSetParametersEW(snes, 1, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
  }
  if (m->softening) {
    /* full Newton steps: the increment cut is the globalisation. Backtracking on |R| stalled where
       bonds change branch (fifth-notched beam with the bilinear law; the secant tangent, whose direction
       need not descend, near the half-notched peak); full steps trace both with the same peaks and
       times elsewhere (docs/softening.md) */
    SNESLineSearch ls;
    PetscCall(SNESGetLineSearch(snes, &ls));
    PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
  }
  /* equilibrium to 1e-6 of the increment's load residual on non-linear scenes: 1e-8 took more Newton
     iterations for the same curve (docs/benchmarks/solve_profile.md). The secant tangent converges
     linearly: it gets up to 200 iterations per increment. Around a steel bar Newton cycles on the kinks
     of the softening bonds for longer before it settles: bars raise the budget to 60
     (docs/reinforcement.md) */
  PetscCall(SNESSetTolerances(snes, m->force_scale * 1e-10, m->linear ? 1e-8 : 1e-6, 0,
                              m->softening && m->scene->tangent == PD_TANGENT_SECANT ? 200 : (m->scene->nbars ? 60 : 20), -1));
  PetscCall(PDSolverPreferFlexible(m, ksp));
  PetscCall(SNESSetFromOptions(snes));
  /* the preconditioner is rebuilt at a fixed lag or, for 3D models under GAMG, when the Krylov solver
     finds it stale (src/solve/pc_refresh.c), across Newton iterations, limiter stages and increments,
     unless -snes_lag_preconditioner sets the lag */
  if (!m->linear) {
    PetscBool lag;
    PetscCall(PetscOptionsHasName(NULL, NULL, "-snes_lag_preconditioner", &lag));
    if (lag)
      PetscCall(SNESSetLagPreconditionerPersists(snes, PETSC_TRUE));
    else
      PetscCall(PDPCRefreshAttach(m, ksp, snes, refresh));
  }
  PetscFunctionReturn(0);
}

typedef struct {
  PDModel     *m;
  PDPCRefresh *refresh;
} JacobianCtx;

/* The tangent, and the preconditioner's refresh told of the assembly. */
static PetscErrorCode Jacobian(SNES snes, Vec u, Mat J, Mat P, void *ctx) {
  JacobianCtx *c = (JacobianCtx *)ctx;
  KSP          ksp;

  PetscFunctionBeginUser;
  PetscCall(PDModelJacobian(snes, u, J, P, c->m));
  PetscCall(SNESGetKSP(snes, &ksp));
  if (c->refresh->when_stale) PetscCall(PDPCRefreshAssembled(c->refresh, ksp));
  PetscFunctionReturn(0);
}

/* No linear solve needs a residual below the one Newton stops at: where the increment is nearly linear,
   Eisenstat-Walker's tolerance falls far below it in the last iteration, and the Krylov iterations past
   it bought nothing (docs/benchmarks/solve_profile.md). Under inexact Newton with a true-residual norm
   (right preconditioning), each linear solve stops at PD_KSP_ATOL_SHARE of Newton's absolute tolerance
   (Predict); fixed linear tolerances (-snes_ksp_ew false) and a -ksp_atol of the user's are left alone.
   Decided once, after the solver has read its options. */
static PetscErrorCode LinearFloorApplies(SNES snes, PetscBool *applies) {
  KSP       ksp;
  PCSide    side;
  PetscBool ew, chosen;

  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPGetPCSide(ksp, &side));
  PetscCall(SNESKSPGetUseEW(snes, &ew));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-ksp_atol", &chosen));
  *applies = side == PC_RIGHT && ew && !chosen ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* Start of a non-linear increment. The residual at u_n with the new boundary values is the increment's
   load; equilibrium is demanded relative to it (rtol), as SNES's relative test does from that start.
   The last accepted increment, scaled to this one, is then added on the free dofs (a secant predictor):
   on a smooth stretch of the path Newton starts next to the answer, and the absolute tolerance keeps
   the demanded equilibrium that of the plain start, not a stricter one relative to a smaller residual. */
static PetscErrorCode Predict(PDModel *m, SNES snes, PetscReal atol0, PetscBool linear_floor, Vec r, Vec u, Vec du_prev, PetscReal ratio) {
  PetscReal rnorm, atol, rtol, stol;
  PetscInt  maxit;

  PetscFunctionBeginUser;
  PetscCall(PDModelResidual(snes, u, r, m));
  PetscCall(VecNorm(r, NORM_2, &rnorm));
  PetscCall(SNESGetTolerances(snes, &atol, &rtol, &stol, &maxit, NULL));
  atol = PetscMax(atol0, rtol * rnorm);
  PetscCall(SNESSetTolerances(snes, atol, rtol, stol, maxit, -1));
  if (linear_floor) {
    KSP ksp;
    PetscCall(SNESGetKSP(snes, &ksp));
    PetscCall(KSPSetTolerances(ksp, PETSC_DEFAULT, PD_KSP_ATOL_SHARE * atol, PETSC_DEFAULT, PETSC_DEFAULT));
  }
  if (ratio > 0) {
    PetscCall(VecAXPY(u, ratio, du_prev));
    PetscCall(PDModelApplyBoundaryValues(m, m->lambda, u));
  }
  PetscFunctionReturn(0);
}

/* Incomplete Cholesky is not positive for every positive definite matrix: at dx = 50 mm the cantilever's
   block ICC(0) has negative pivots, and CG stops with KSP_DIVERGED_INDEFINITE_PC although the stiffness
   is definite. GMRES needs no positive preconditioner and converges with the same factor, so the run goes
   on with it (once; the summary's solver names it). */
static PetscErrorCode SwitchFromCG(SNES snes, PetscBool *retry) {
  KSP                ksp;
  KSPConvergedReason kr;
  PetscBool          cg;

  PetscFunctionBeginUser;
  *retry = PETSC_FALSE;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPGetConvergedReason(ksp, &kr));
  PetscCall(PetscObjectTypeCompare((PetscObject)ksp, KSPCG, &cg));
  if (!cg || kr != KSP_DIVERGED_INDEFINITE_PC) PetscFunctionReturn(0);
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)ksp), "  CG met an indefinite preconditioner: going on with GMRES\n"));
  PetscCall(KSPSetType(ksp, KSPGMRES));
  PetscCall(KSPGMRESSetRestart(ksp, PD_GMRES_RESTART));
  *retry = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* Block ICC(0) can fail on the consistent tangent of a 3D model below PD_GAMG_MIN_NODES_SOFTENING once softening
   bonds make it indefinite near a load line (options/eccentric_notch_3d.opts: GMRES stalls in the first
   increment, where GAMG converges; docs/solvers.md). The run goes on with algebraic multigrid on AIJ
   storage (once; the summary's solver names it), unless the preconditioner or the storage was chosen on
   the command line. */
static PetscErrorCode SwitchToGAMG(PDModel *m, SNES snes, JacobianCtx *jctx, Mat *J, Mat *P, PetscBool *retry) {
  KSP                ksp;
  PC                 pc;
  KSPConvergedReason kr;
  PetscBool          bjacobi;

  PetscFunctionBeginUser;
  *retry = PETSC_FALSE;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPGetConvergedReason(ksp, &kr));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCBJACOBI, &bjacobi));
  if (!m->softening || !bjacobi || m->scene->pc_chosen || m->scene->mat_type[0] || kr >= 0) PetscFunctionReturn(0);
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)ksp), "  block ICC(0) failed on the tangent (%s): going on with GAMG\n",
                        KSPConvergedReasons[kr]));
  m->gamg_after_icc = PETSC_TRUE;
  PetscCall(PDModelDestroyOperators(J, P));
  PetscCall(PDModelCreateOperators(m, J, P));
  PetscCall(SNESSetJacobian(snes, *J, *P, Jacobian, jctx));
  PetscCall(PCSetType(pc, PCGAMG));
  PetscCall(KSPSetFromOptions(ksp));
  *retry = PETSC_TRUE;
  PetscFunctionReturn(0);
}

static PetscBool FieldsDue(const PDScene *sc, PetscInt step, PetscBool last) {
  if (last) return PETSC_TRUE;
  return (sc->fields_every > 0 && step % sc->fields_every == 0) ? PETSC_TRUE : PETSC_FALSE;
}

typedef struct {
  PetscInt  its, lits, stages, max_events;
  PetscBool ok;
  char      why[128];
} StepResult;

/* One load increment: Newton stages until equilibrium holds with no deferred bond event. On a softening
   scene the increment's first Newton iteration is already a limiter stage: bringing the increment to
   equilibrium before the first grant (-pd_limiter_settle_first, the earlier default) settled it twice,
   once before its events and once after, for the same curve (docs/benchmarks/solve_profile.md).
   A bond whose stretch sits at its history switches between the loading slope and the secant from one
   iterate to the next, and Newton can cycle for good (a reinforced beam as its first flexural crack
   opens across the bar's bond-slip links: options/rc_beam_2d.opts). Where full Newton on the consistent
   tangent fails (the secant tangent has no slope to switch: it converges slowly rather than cycles), every
   softened bond is frozen on the branch it is on (branch, nbonds entries), which makes the equations
   smooth, and Newton goes on from where it stopped. Equilibrium on frozen branches is that of the real
   law once every bond lies on the side of its history its branch assumes; bonds on the wrong side
   change branch (PDModelFlipBranches, as path following does: arclength.c Step) and Newton goes on. */
static PetscErrorCode SolveIncrement(PDModel *m, SNES snes, PDPCRefresh *refresh, unsigned char *branch, Vec u, StepResult *res) {
  const PDScene *sc      = m->scene;
  PetscBool      limited = m->softening && !sc->limiter_settle_first ? PETSC_TRUE : PETSC_FALSE;
  PetscInt       maxit, flips = 0;
  PetscReal      atol, rtol, stol;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(res, sizeof *res));
  PetscCall(SNESGetTolerances(snes, &atol, &rtol, &stol, &maxit, NULL));
  for (;;) {
    SNESConvergedReason reason;
    PetscInt            its, lits, ncand, granted;

    PetscCall(SNESSetTolerances(snes, atol, rtol, stol, limited ? PetscMin(sc->limiter_stage_its, maxit) : maxit, -1));
    PetscCall(SNESSolve(snes, NULL, u));
    PetscCall(SNESGetConvergedReason(snes, &reason));
    PetscCall(SNESGetIterationNumber(snes, &its));
    PetscCall(SNESGetLinearSolveIterations(snes, &lits));
    res->its += its;
    res->lits += lits;
    if (PDInterruptSeen()) {
      PetscCall(PetscSNPrintf(res->why, sizeof res->why, "interrupted"));
      break;
    }
    if (reason == SNES_DIVERGED_LINEAR_SOLVE || reason == SNES_DIVERGED_FNORM_NAN) {
      KSP ksp;
      PetscCall(SNESGetKSP(snes, &ksp));
      PetscCall(PDPCForgetFailed(ksp));
    }
    if (reason == SNES_DIVERGED_LINEAR_SOLVE && refresh->when_stale && !refresh->measure) {
      /* a preconditioner kept from an earlier tangent may have lost its grip: Newton goes on from where
         it stopped with a fresh one (once; a fresh one that fails is a failure) */
      PetscCall(PDPCRefreshRequest(refresh));
      continue;
    }
    if (reason == SNES_DIVERGED_FNORM_NAN || reason == SNES_DIVERGED_LINEAR_SOLVE) {
      PetscCall(PetscSNPrintf(res->why, sizeof res->why, "%s", SNESConvergedReasons[reason]));
      break;
    }
    if (m->branch) {
      PetscInt  nflipped, nkink;
      PetscReal fz, fr;
      Vec       r;
      if (reason < 0) {
        PetscCall(PetscSNPrintf(res->why, sizeof res->why, "%s on frozen branches", SNESConvergedReasons[reason]));
        break;
      }
      /* equilibrium on frozen branches: does the real law hold there too? (its residual, with its tangent
         scalars, is then the last one, which a limiter grant's row update starts from) */
      PetscCall(SNESGetFunctionNorm(snes, &fz));
      m->branch         = NULL;
      m->ka_at_residual = PETSC_FALSE;
      PetscCall(SNESGetFunction(snes, &r, NULL, NULL));
      PetscCall(SNESComputeFunction(snes, u, r));
      PetscCall(VecNorm(r, NORM_2, &fr));
      if (fr > PetscMax(atol, fz)) {
        m->branch = branch;
        PetscCall(PDModelFlipBranches(m, u, &nflipped, &nkink));
        PetscCall(PetscInfo(snes,
                            "frozen branches in equilibrium, real law |R| %g: %" PetscInt_FMT " bonds change branch, %" PetscInt_FMT
                            " of them back\n",
                            (double)fr, nflipped, nkink));
        m->ka_at_residual = m->rows_after_grant = PETSC_FALSE;
        if (!nflipped || ++flips > PD_MAX_FLIPS) {
          PetscCall(PetscSNPrintf(res->why, sizeof res->why, "frozen branches do not settle"));
          break;
        }
        continue;
      }
    }
    PetscCall(PDModelGrantEvents(m, u, m->limiter_max, &ncand, &granted));
    m->rows_after_grant = granted && m->track_grants ? PETSC_TRUE : PETSC_FALSE;
    if (granted) {
      res->max_events = PetscMax(res->max_events, granted);
      if (++res->stages > PD_MAX_STAGES) {
        PetscCall(PetscSNPrintf(res->why, sizeof res->why, "more than %d limiter stages", PD_MAX_STAGES));
        break;
      }
      limited = PETSC_TRUE;
      continue;
    }
    if (reason > 0) {
      res->ok = PETSC_TRUE;
      break;
    }
    if (limited && reason == SNES_DIVERGED_MAX_IT) { /* events are settled: finish with full Newton */
      limited = PETSC_FALSE;
      continue;
    }
    if (branch && sc->tangent == PD_TANGENT_CONSISTENT && flips < PD_MAX_FLIPS &&
        (reason == SNES_DIVERGED_MAX_IT || reason == SNES_DIVERGED_DTOL || reason == SNES_DIVERGED_LINE_SEARCH)) {
      PetscInt nfrozen;
      PetscCall(PDModelFreezeBranches(m, u, branch, &nfrozen));
      PetscCall(PetscInfo(snes, "Newton failed (%s): %" PetscInt_FMT " softened bonds frozen on their branch\n",
                          SNESConvergedReasons[reason], nfrozen));
      m->ka_at_residual = m->rows_after_grant = PETSC_FALSE;
      limited                                 = PETSC_FALSE; /* the frozen solve is full Newton */
      flips++;
      if (nfrozen) continue;
      m->branch = NULL;
    }
    PetscCall(PetscSNPrintf(res->why, sizeof res->why, "%s", SNESConvergedReasons[reason]));
    break;
  }
  m->branch = NULL; /* the next increment, or this one again, starts on the real law */
  PetscCall(SNESSetTolerances(snes, atol, rtol, stol, maxit, -1));
  PetscFunctionReturn(0);
}

PetscErrorCode PDStaticRun(PDModel *m, PDRecord *rec) {
  const PDScene *sc   = m->scene;
  MPI_Comm       comm = m->lat->comm;
  SNES           snes;
  Mat            J, P; /* the tangent (its product from the bond scalars, or P itself) and the assembled matrix of its preconditioner */
  Vec            u, r;
  PDPath         path;
  PetscReal      lambda_n = 0, dl = sc->lambda_max / sc->steps, dl_prev = 0, atol0, peak = 0;
  PetscInt       step         = 0;
  PetscBool      takeover     = PETSC_FALSE;
  PetscBool      linear_floor = PETSC_FALSE; /* linear solves stop at Newton's tolerance (LinearFloorApplies) */
  PDPCRefresh    refresh      = {0};
  unsigned char *branch       = NULL; /* frozen branches where Newton cycles (SolveIncrement) */
  JacobianCtx    jctx         = {m, &refresh};

  PetscFunctionBeginUser;
  PetscCall(PDModelCreateOperators(m, &J, &P));
  if (m->softening) PetscCall(PetscMalloc1(PetscMax(1, m->bonds->nbonds), &branch)); /* on every rank: freezing is collective */
  PetscCall(VecDuplicate(m->f_ref, &u));
  PetscCall(VecDuplicate(m->f_ref, &r));
  PetscCall(PDPathCreate(m, &path));
  PetscCall(SNESCreate(comm, &snes));
  PetscCall(SNESSetFunction(snes, r, PDModelResidual, m));
  PetscCall(SNESSetJacobian(snes, J, P, Jacobian, &jctx));
  PetscCall(ConfigureSolver(m, snes, &refresh));
  PetscCall(SNESGetTolerances(snes, &atol0, NULL, NULL, NULL, NULL));
  PetscCall(LinearFloorApplies(snes, &linear_floor));
  /* Newton asks for the tangent where it has just evaluated the residual, and nothing changes the bonds'
     history or levels inside a SNES solve: one bond loop gives both (PDModelResidual) */
  m->ka_with_residual = sc->tangent_with_residual && m->ka && !m->kp && !m->commit_history ? PETSC_TRUE : PETSC_FALSE;
  /* and after a limiter grant, where SNES evaluates the residual again at the same displacement, only the
     rows of the bonds the grant changed are recomputed (model.c PDModelResidual) */
  m->track_grants = m->ka_with_residual && m->softening && sc->residual_rows ? PETSC_TRUE : PETSC_FALSE;
  rec->converged  = PETSC_TRUE;
  PetscCall(PetscStrncpy(rec->status, "completed", sizeof rec->status));
  dl = PetscMin(dl, sc->dlambda_max);
  while (lambda_n < sc->lambda_max * (1 - 1e-12)) {
    const PetscReal lam = PetscMin(lambda_n + dl, sc->lambda_max);
    StepResult      res;
    PDCurveRow      row;
    PetscLogDouble  t0, t1;
    PetscReal       asm0 = m->t_assembly;
    PetscBool       stop = PETSC_FALSE;

    PetscCall(VecCopy(path.u_n, u));
    PetscCall(PDModelApplyBoundaryValues(m, lam, u));
    PetscCall(PetscTime(&t0));
    if (!m->linear)
      PetscCall(Predict(m, snes, atol0, linear_floor, r, u, path.du, sc->predictor && dl_prev > 0 ? (lam - lambda_n) / dl_prev : 0));
    PetscCall(SolveIncrement(m, snes, &refresh, branch, u, &res));
    PetscCall(PetscTime(&t1));
    rec->t_solve += (t1 - t0) - (m->t_assembly - asm0);
    rec->newton_its += res.its;
    rec->ksp_its += res.lits;
    if (!res.ok) {
      PetscBool stop, retry;
      PetscCall(PDModelRestoreLevels(m));
      PetscCall(PDStopInsideStep(rec, &stop));
      if (stop) break;
      PetscCall(SwitchFromCG(snes, &retry));
      if (retry) continue; /* the same increment again, now with GMRES */
      PetscCall(SwitchToGAMG(m, snes, &jctx, &J, &P, &retry));
      if (retry) continue; /* and with GAMG */
      if (!m->linear && dl * 0.5 < sc->dlambda_min && m->softening && sc->control_fallback && path.step > 0) {
        /* past a limit point, or where bonds snap, plain control has no equilibrium to find: path
           following goes on from the last accepted step */
        takeover = PETSC_TRUE;
        PetscCall(PetscSNPrintf(rec->fallback_why, sizeof rec->fallback_why,
                                "%s control found no equilibrium past load factor %g (%s; increment %g at its floor)",
                                sc->control == PD_CONTROL_FORCE ? "load" : "displacement", (double)lambda_n, res.why, (double)dl));
        rec->fallback_step   = path.step;
        rec->fallback_lambda = lambda_n;
        break;
      }
      if (m->linear || dl * 0.5 < sc->dlambda_min) {
        rec->converged = PETSC_FALSE;
        PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "diverged at load factor %g (%s); increment %g at its floor", (double)lam,
                                res.why, (double)dl));
        break;
      }
      dl *= 0.5;
      PetscCall(PetscInfo(NULL, "increment to %g failed (%s): cut to %g\n", (double)lam, res.why, (double)dl));
      continue;
    }
    dl_prev = lam - lambda_n; /* the increment itself is path.du once accepted */
    PetscCall(PDPathAccept(m, rec, &path, u, lam, res.its, res.lits, &row));
    lambda_n                = lam;
    step                    = path.step;
    rec->max_events_per_its = PetscMax(rec->max_events_per_its, res.max_events);
    peak                    = PetscMax(peak, PetscAbsReal(row.load));
    /* separation, the criterion of path following, which this path may hand over to: judged where bonds soften */
    PetscCall(PDPathStopCriteria(sc, rec, &row, peak, m->softening, &stop));
    if (lambda_n >= sc->lambda_max * (1 - 1e-12)) stop = PETSC_TRUE;
    if (!stop) PetscCall(PDStopOnSignal(comm, rec, &stop));
    PetscCall(PDProgress(comm, sc, &row, stop));
    if (FieldsDue(sc, step, stop)) PetscCall(PDFieldsWrite(m, rec, step, u));
    if (stop) break;
    /* an increment that converged without trouble lets the next one grow back after cuts; easy ones
       (no bond events, few iterations) grow faster */
    if (res.stages == 0 && res.its <= 3)
      dl = PetscMin(2 * dl, sc->dlambda_max);
    else if (res.its <= 12)
      dl = PetscMin(1.25 * dl, sc->dlambda_max);
  }
  if (!rec->converged && rec->steps > 0 && (!rec->nfield_steps || rec->field_steps[rec->nfield_steps - 1] != rec->steps))
    PetscCall(PDFieldsWrite(m, rec, rec->steps, path.u_n));
  {
    MatInfo  info;
    KSP      ksp;
    PC       pc;
    SNESType st;
    KSPType  kt;
    PCType   pt;
    PetscCall(MatGetInfo(P, MAT_GLOBAL_SUM, &info));
    rec->matrix_nonzeros = info.nz_allocated;
    PetscCall(SNESGetType(snes, &st));
    PetscCall(SNESGetKSP(snes, &ksp));
    PetscCall(KSPGetType(ksp, &kt));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCGetType(pc, &pt));
    PetscCall(PetscSNPrintf(rec->solver, sizeof rec->solver, "%s/%s/%s", st, kt, pt));
  }
  m->ka_with_residual = m->ka_at_residual = m->track_grants = m->rows_after_grant = PETSC_FALSE;
  PetscCall(VecDestroy(&m->ka_u));
  PetscCall(VecDestroy(&m->r_last));
  PetscCall(SNESDestroy(&snes));
  PetscCall(PetscFree(branch));
  PetscCall(PDModelDestroyOperators(&J, &P));
  PetscCall(VecDestroy(&u));
  PetscCall(VecDestroy(&r));
  if (takeover) PetscCall(PDArcLengthTakeOver(m, rec, &path, dl_prev));
  PetscCall(PDPathDestroy(&path));
  PetscFunctionReturn(0);
}
