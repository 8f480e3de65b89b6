/* Path following (THEORY.md Sec. 5): the load factor lambda becomes an unknown next to u, tied to the
   step by a constraint, so the path can pass limit points and snap-backs. Prescribed displacements
   move with lambda (u_c = lambda u_ref), so the equilibrium equations on free dofs are
   G(u_f, lambda) = f_int(u_f, lambda u_ref) - lambda f_ref = 0 with dG/dlambda = K_fc u_ref - f_ref.
   Each Newton iteration makes two solves with one operator and one preconditioner (bordering):
   K du_I = -G and K du_II = -dG/dlambda; the update is du_I + dlambda v with v = du_II + u_ref, and
   dlambda comes from the linearised constraint. For the constraints linear in (u, lambda) (cmod,
   dissipation) one solve of the tangent bordered by the constraint gives the same update
   (augmented.c); the direction v is then solved for only at the predictor. The constraints:
     cmod         c.(u - u_n) = dl                          (the gauge opens by dl: CMOD control)
     cylindrical  |u - u_n|^2 = dl^2                        (Crisfield; root nearest the last step)
     spherical    |u - u_n|^2 + psi^2 (lambda - lambda_n)^2 = dl^2, psi = |v| of the first step
     dissipation  (f_n.u - f_int(u).u_n) / 2 = dl           (energy released by damage; secant laws)
   The damage limiter grants bond events between converged iterations as under plain control; the arc
   length adapts to the iteration count and is cut on failure. Under -pd_control auto (and always for
   the dissipation constraint, which is singular while nothing dissipates) the region's plain control
   runs until the first bond softens. Newton cycling at the kink of softened bonds (loading beyond their
   largest stretch, secant below it) is settled by freezing their branches (see Step); -pd_unload_at
   turns the path for unloading and reloading (LoadReversal). -pd_arclength_implex replaces the implicit
   history of a step by one extrapolated from the last two (ImplexExtrapolate), where Newton cannot settle
   which bonds load and which unload. */
#include "path.h"
#include "augmented.h"
#include "../model/kernel.h"

/* Load reversal (-pd_unload_at): where a path is, given the accepted step's row. */
typedef struct {
  PetscInt  phase;      /* 0 not yet, 1 unloading, 2 reloading, 3 back on the envelope */
  PetscReal gauge_turn; /* CMOD (else load-point displacement) where the path turned */
} Reversal;

#define NSTATE 16 /* scalars a checkpoint keeps of the driver (state_names below) */
/* IMPL-EX tolerance of the fallback, the error whose peak the tests hold to the implicit one (docs/arclength.md, "The default path") */
#define PD_FALLBACK_IMPLEX 0.01
/* equilibrium tolerance of a step (-pd_arclength_rtol): implicit steps settle the limiter's bonds on it;
   an IMPL-EX step is a secant problem whose error is the extrapolation's, which a looser equilibrium
   hardly changes while its corrector solve stops decades sooner (docs/arclength.md, "Linear tolerances") */
#define PD_ARC_RTOL 1e-7
#define PD_IMPLEX_RTOL 1e-4
static PetscReal EquilibriumRtol(const PDScene *sc, PetscBool implex) {
  return sc->arc_rtol > 0 ? sc->arc_rtol : (implex ? PD_IMPLEX_RTOL : PD_ARC_RTOL);
}
/* how often an IMPL-EX step gives its damaged bonds their sides again before it leaves them free (Step) */
#define PD_IMPLEX_RESIDES 10
/* Krylov tolerance of the predictor's direction where the augmented corrector follows: the direction only
   starts the step and estimates the corrector's Schur complement, and the equilibrium the corrector
   reaches does not depend on it (docs/arclength.md, "Linear tolerances") */
#define PD_DIRECTION_RTOL 1e-4
/* a corrector's linear solve stops once its true residual is this share of Newton's tolerance, as under
   plain control (PD_KSP_ATOL_SHARE in static.c) */
#define PD_CORRECTOR_ATOL_SHARE 0.5
/* the augmented corrector's constraint row is weighted so that a constraint residual of this share of the
   arc length counts as much as a force residual at the floor above */
#define PD_CONSTRAINT_SHARE 1e-3

typedef struct {
  PDModel       *m;
  Mat            J, P; /* the tangent (its product from the bond scalars, or P itself) and the assembled matrix of its preconditioner */
  KSP            ksp;
  PetscReal      rtol, atol;         /* Krylov tolerances of a solve with the tangent: 1e-8 and none, or -ksp_rtol and -ksp_atol */
  PetscBool      matched;            /* linear tolerances matched to Newton's need (none given on the command line) */
  PetscBool      floor_k;            /* and ksp measures the true residual: a corrector's solve stops at Newton's need */
  PetscBool      floor_aug;          /* the same for the augmented corrector's solve */
  PetscReal      rtol_aug, atol_aug; /* the augmented solve's own (-pd_augmented_ksp_rtol, or those of ksp) */
  Vec            u, fint, R, q, duI, v, w, dprev, row;
  Vec            v_n;       /* v at the last accepted step: the guess a restart starts from (-pd_arclength_guess) */
  PetscInt       totals[2]; /* the run's Newton and Krylov iterations at the last accepted step */
  PDAugmented    aug;       /* used for linear constraints unless -pd_arclength_solve bordering */
  PetscBool      augmented;
  PetscReal      lam;
  PetscReal      vnorm;     /* |v|, with v */
  PetscReal      psi2;      /* spherical scaling of lambda */
  PetscBool      have_prev; /* dprev holds the last accepted step */
  PetscInt       its, lits; /* this step */
  PDPCRefresh    refresh;   /* when to rebuild the preconditioner */
  PetscBool      direct;    /* KSPPREONLY: factor at every assembly */
  unsigned char *branch;    /* per-bond branches, frozen once Newton cycles at history kinks */
  /* IMPL-EX (-pd_arclength_implex): bond histories at the last two accepted steps, the one a step uses */
  PetscReal  *kx_n, *kx_prev;
  PetscReal   implex;   /* the damage error per step IMPL-EX adapts to (-pd_arclength_implex, or the fallback's) */
  PetscReal   eq_rtol;  /* equilibrium: |R| below this times |f_int| (-pd_arclength_rtol, or PD_ARC_RTOL / PD_IMPLEX_RTOL) */
  PetscReal   len_prev; /* the last accepted step's length in the units of the next one */
  Vec         xg;       /* IMPL-EX under the augmented corrector: the last step's first correction (-pd_arclength_guess) */
  PetscBool   have_xg;
  PetscInt    rejects;      /* IMPL-EX steps made again shorter since the last accepted one */
  PetscBool   faces;        /* the last IMPL-EX step froze its damaged bonds' sides (PDModelFreezeSides) */
  PetscReal   reject_err;   /* the damage error the last of them would leave if it scaled with the step */
  PetscBool   root_flipped; /* this step is being taken again with the predictor's other root */
  PetscReal   dlam_pred;    /* the load-factor change of the step's predictor */
  PetscReal   dlam_last;    /* the load-factor change of the last accepted step (with dprev: the secant predictor) */
  PetscBool   secant;       /* this step started from the secant predictor */
  PetscBool   secant_off;   /* a step so started failed: the next attempt solves for the direction */
  Reversal    rev;          /* load reversal; while unloading (phase 1) the cmod gauge closes */
  PetscBool   turn;         /* the next predictor goes against the last step (load reversal) */
  const char *why;          /* why the last step failed */
  /* between steps */
  PetscInt  type;            /* constraint, or ARC_LOAD: plain control (the first step, and under auto until softening) */
  PetscReal dl, dl0, dlam;   /* arc length, the first one, load-factor increment under plain control */
  PetscReal peak, peak_sign; /* largest |load| so far and its sign */
  PetscInt  hold;            /* accepted steps left during which the arc length may not grow (-pd_arclength_hold) */
  PetscReal state[NSTATE];   /* the scalars above at the last accepted step, as a checkpoint keeps them */
} Arc;

typedef enum { ARC_LOAD = -1 } ArcPlain; /* plain control: lambda advances by a fixed increment */

/* A solve with the tangent; one that fails with a preconditioner kept from an earlier tangent is made
   again with a fresh one, and a preconditioner whose set-up failed is not kept. */
static PetscErrorCode Solve(Arc *a, Vec b, Vec x) {
  PetscBool again = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(KSPSolve(a->ksp, b, x));
  if (!a->direct) PetscCall(PDPCRefreshSolved(&a->refresh, a->ksp, &again));
  if (again) {
    PetscCall(PDPCRefreshAssembled(&a->refresh, a->ksp));
    PetscCall(KSPSolve(a->ksp, b, x));
    PetscCall(PDPCRefreshSolved(&a->refresh, a->ksp, NULL));
  }
  PetscCall(PDPCForgetFailed(a->ksp));
  PetscFunctionReturn(0);
}

/* Residual on free dofs (constrained ones are lifted to lambda u_ref, so theirs is zero) and |f_int|. */
static PetscErrorCode Residual(Arc *a, PetscReal *rnorm, PetscReal *fnorm) {
  PDModel *m = a->m;

  PetscFunctionBeginUser;
  PetscCall(PDModelApplyBoundaryValues(m, a->lam, a->u));
  PetscCall(PDModelInternalForceKeepTangent(m, a->u, a->fint));
  PetscCall(VecNorm(a->fint, NORM_2, fnorm));
  PetscCall(VecWAXPY(a->R, -a->lam, m->f_ref, a->fint));
  PetscCall(VecPointwiseMult(a->w, a->R, m->fixed));
  PetscCall(VecAXPY(a->R, -1, a->w)); /* zero on constrained dofs */
  PetscCall(VecNorm(a->R, NORM_2, rnorm));
  PetscFunctionReturn(0);
}

/* Tangent at u, the preconditioner rebuilt every third assembly, q = -(K u_ref - f_ref) on free dofs, and
   (when asked) the path direction v per unit lambda: K du_II = q, v = du_II + u_ref. */
static PetscErrorCode TangentAndDirection(Arc *a, PetscBool direction, PetscReal rtol, PetscBool *ok) {
  PDModel           *m = a->m;
  PetscInt           n;
  KSPConvergedReason kr;

  PetscFunctionBeginUser;
  *ok = PETSC_TRUE;
  PetscCall(PDModelJacobian(NULL, a->u, a->J, a->P, m));
  /* an iterative solve absorbs a preconditioner kept from an earlier tangent until it goes stale (as under
     plain control); a direct one (preonly) must factor every time */
  if (a->direct)
    PetscCall(KSPSetReusePreconditioner(a->ksp, PETSC_FALSE));
  else
    PetscCall(PDPCRefreshAssembled(&a->refresh, a->ksp));
  PetscCall(KSPSetOperators(a->ksp, a->J, a->P));
  PetscCall(PDModelTangentApply(m, a->u, m->u_ref, a->q));
  PetscCall(VecAXPY(a->q, -1, m->f_ref));
  PetscCall(VecPointwiseMult(a->w, a->q, m->fixed));
  PetscCall(VecAXPY(a->q, -1, a->w));
  PetscCall(VecScale(a->q, -1));
  if (!direction) PetscFunctionReturn(0);
  /* the direction changes little from one solve to the next (damage changes the tangent in a band): the
     last one starts the Krylov solve, whose tolerance stays relative to |q| (KSPConvergedDefaultSetUIRNorm
     in Run), so that the guess saves iterations and not accuracy (-pd_arclength_guess) */
  const PetscBool guess = !a->direct && m->scene->arc_guess ? PETSC_TRUE : PETSC_FALSE;
  if (guess) {
    PetscCall(VecAXPY(a->v, -1, m->u_ref));
    PetscCall(KSPSetInitialGuessNonzero(a->ksp, PETSC_TRUE));
  }
  PetscCall(KSPSetTolerances(a->ksp, rtol, a->atol, PETSC_DEFAULT, PETSC_DEFAULT));
  PetscCall(Solve(a, a->q, a->v));
  PetscCall(KSPSetInitialGuessNonzero(a->ksp, PETSC_FALSE));
  PetscCall(KSPGetIterationNumber(a->ksp, &n));
  PetscCall(KSPGetConvergedReason(a->ksp, &kr));
  a->lits += n;
  /* the last direction can be a bad guess where the tangent has changed much (a crack that has just
     freed a fragment): its residual then exceeds the divergence tolerance relative to |q| at once, and
     the solve stops there, returning the guess. It is solved again from zero */
  if (guess && kr < 0 && kr != KSP_DIVERGED_ITS) {
    PetscCall(PetscInfo(NULL, "arclength: direction from the last one %s; solved again from zero\n", KSPConvergedReasons[kr]));
    PetscCall(VecZeroEntries(a->v));
    PetscCall(Solve(a, a->q, a->v));
    PetscCall(KSPGetIterationNumber(a->ksp, &n));
    PetscCall(KSPGetConvergedReason(a->ksp, &kr));
    a->lits += n;
  }
  PetscCall(VecAXPY(a->v, 1, m->u_ref));
  PetscCall(VecNorm(a->v, NORM_2, &a->vnorm));
  /* a solve that broke down or met a non-finite value leaves no direction (taken as one, a failed solve's
     left-over guess led steps later to a residual that was not finite): the step is cut. One that ran out
     of iterations still gives an approximate direction, which the bordered corrections put right. */
  if ((kr < 0 && kr != KSP_DIVERGED_ITS) || PetscIsInfOrNanReal(a->vnorm)) {
    a->why = kr < 0 ? KSPConvergedReasons[kr] : "direction not finite";
    *ok    = PETSC_FALSE;
  }
  PetscFunctionReturn(0);
}

/* The load-factor change that the linearised constraint asks for, given the iteration's du_I (zero for
   the predictor). Returns PETSC_FALSE when the constraint has no real solution. */
static PetscErrorCode ConstraintUpdate(Arc *a, PDPath *p, PetscInt type, PetscReal dl, PetscBool predictor, PetscReal *dlam,
                                       PetscBool *ok) {
  PDModel    *m = a->m;
  PetscScalar cv, cu;

  PetscFunctionBeginUser;
  *ok = PETSC_TRUE;
  /* w = u - u_n + du_I: where the iterate goes before the lambda correction */
  PetscCall(VecWAXPY(a->w, -1, p->u_n, a->u));
  if (!predictor) PetscCall(VecAXPY(a->w, 1, a->duI));
  switch (type) {
  case ARC_LOAD:
    *dlam = predictor ? dl : 0;
    break;
  case PD_ARC_CMOD:
    PetscCall(VecDot(m->cmod_pattern, a->v, &cv));
    PetscCall(VecDot(m->cmod_pattern, a->w, &cu));
    *ok   = PetscAbsScalar(cv) > 0 ? PETSC_TRUE : PETSC_FALSE;
    *dlam = *ok ? ((a->rev.phase == 1 ? -1 : 1) * dl - PetscRealPart(cu)) / PetscRealPart(cv) : 0;
    break;
  case PD_ARC_CYLINDRICAL:
  case PD_ARC_SPHERICAL: {
    const PetscReal psi2 = type == PD_ARC_SPHERICAL ? a->psi2 : 0, Dl = a->lam - p->lambda_n;
    PetscScalar     vv, vw, ww, vp = 1;
    PetscReal       A, B, C, disc, r1, r2, s1, s2;
    PetscCall(VecDot(a->v, a->v, &vv));
    PetscCall(VecDot(a->v, a->w, &vw));
    PetscCall(VecDot(a->w, a->w, &ww));
    A    = PetscRealPart(vv) + psi2;
    B    = 2 * (PetscRealPart(vw) + psi2 * Dl);
    C    = PetscRealPart(ww) + psi2 * Dl * Dl - dl * dl;
    disc = B * B - 4 * A * C;
    if (disc < 0 && !predictor) {
      /* the corrector's line u + du_I + dlam v misses the constraint's surface (the iterate's residual is
         large against the arc length, as where a crack opens across a bar in one step): take its nearest
         point, the real part of the complex roots (Lam and Morley 1992), and go on; the step ends where
         equilibrium holds, longer than dl by what the log reports. Bounding the miss (to one arc length)
         stopped the small reinforced beam with bond slip at its first crack again. */
      *dlam = -B / (2 * A);
      PetscCall(PetscInfo(NULL, "arclength: the corrector passes %g arc lengths from the constraint: nearest point taken\n",
                          (double)(PetscSqrtReal(dl * dl - disc / (4 * A)) / dl - 1)));
      break;
    }
    if (disc < 0) {
      *ok = PETSC_FALSE;
      break;
    }
    r1 = (-B + PetscSqrtReal(disc)) / (2 * A);
    r2 = (-B - PetscSqrtReal(disc)) / (2 * A);
    /* the root that keeps going the way the path went: predictor by the last step's direction (the
       first step loads), corrector by the angle with the current step */
    if (predictor) {
      if (a->have_prev) PetscCall(VecDot(a->v, a->dprev, &vp));
      if (a->turn) vp = -vp;
      *dlam = PetscRealPart(vp) >= 0 ? PetscMax(r1, r2) : PetscMin(r1, r2);
    } else {
      s1    = PetscRealPart(ww) + r1 * PetscRealPart(vw) + psi2 * (Dl + r1) * Dl;
      s2    = PetscRealPart(ww) + r2 * PetscRealPart(vw) + psi2 * (Dl + r2) * Dl;
      *dlam = s1 >= s2 ? r1 : r2;
    }
  } break;
  case PD_ARC_DISSIPATION: {
    /* g = (f_n.u - f_int(u).u_n)/2 - dl, linearised with d(f_int.u_n) = (K u_n).du */
    PetscScalar fu, fi, wd, wv;
    PetscReal   g;
    /* at the predictor u = u_n, whose internal force is f_n: a->fint may hold a failed attempt's last
       iterate, or nothing after a restart */
    PetscCall(VecDot(p->f_n, a->u, &fu));
    PetscCall(VecDot(predictor ? p->f_n : a->fint, p->u_n, &fi));
    g = 0.5 * PetscRealPart(fu - fi) - dl;
    PetscCall(PDModelTangentApply(m, a->u, p->u_n, a->q));
    PetscCall(VecAYPX(a->q, -1, p->f_n)); /* f_n - K u_n */
    PetscCall(VecDot(a->q, a->duI, &wd));
    PetscCall(VecDot(a->q, a->v, &wv));
    if (predictor) wd = 0;
    *ok   = PetscAbsScalar(wv) > 0 ? PETSC_TRUE : PETSC_FALSE;
    *dlam = *ok ? -(g + 0.5 * PetscRealPart(wd)) / (0.5 * PetscRealPart(wv)) : 0;
  } break;
  }
  PetscFunctionReturn(0);
}

/* The corrector of a linear constraint in one augmented solve (augmented.c), given a->R = -G. The
   constraint row c (on free dofs) and its lambda coefficient c.u_ref border the tangent; lambda is scaled
   by |v| so that both unknowns are displacements, and the Schur complement c.v / |v| comes from the
   predictor's direction v. */
static PetscErrorCode AugmentedUpdate(Arc *a, PDPath *p, PetscInt type, PetscReal dl, PetscReal fres, PetscReal *dlam, PetscInt *its,
                                      KSPConvergedReason *kr, PetscBool *ok) {
  PDModel        *m = a->m;
  PetscScalar     cu, cl, cv;
  PetscReal       rhs, t, weight;
  PetscBool       again;
  const PetscReal vnorm = a->vnorm;

  PetscFunctionBeginUser;
  PetscCall(VecWAXPY(a->w, -1, p->u_n, a->u));
  if (type == PD_ARC_CMOD) {
    PetscCall(VecCopy(m->cmod_pattern, a->row));
    PetscCall(VecDot(a->row, a->w, &cu));
    rhs = (a->rev.phase == 1 ? -1 : 1) * dl - PetscRealPart(cu);
  } else { /* dissipation, linearised as in ConstraintUpdate: d g = (f_n - K u_n).du / 2 */
    PetscScalar fu, fi;
    PetscCall(VecDot(p->f_n, a->u, &fu));
    PetscCall(VecDot(a->fint, p->u_n, &fi));
    rhs = -(0.5 * PetscRealPart(fu - fi) - dl);
    PetscCall(PDModelTangentApply(m, a->u, p->u_n, a->row));
    PetscCall(VecAYPX(a->row, -1, p->f_n));
    PetscCall(VecScale(a->row, 0.5));
  }
  /* the row in force units: the Krylov residual mixes it with the force rows, and a constraint residual
     of PD_CONSTRAINT_SHARE of the arc length weighs as much as the force residual fres the solve may leave
     (the preconditioner's Schur estimate is weighted with it, so the preconditioned operator is the same) */
  weight = dl != 0 ? fres / (PD_CONSTRAINT_SHARE * PetscAbsReal(dl)) : 1;
  PetscCall(VecScale(a->row, weight));
  rhs *= weight;
  PetscCall(VecDot(a->row, m->u_ref, &cl));
  PetscCall(VecDot(a->row, a->v, &cv));
  PetscCall(VecPointwiseMult(a->w, a->row, m->fixed));
  PetscCall(VecAXPY(a->row, -1, a->w)); /* free dofs: the constrained ones move with lambda, in cl */
  *ok   = PetscAbsScalar(cv) > 0 && vnorm > 0 ? PETSC_TRUE : PETSC_FALSE;
  *its  = 0;
  *kr   = KSP_CONVERGED_ITS;
  *dlam = 0;
  if (!*ok) PetscFunctionReturn(0);
  /* K du - q dlambda = -G with q from TangentAndDirection; the column is -q / |v| */
  PetscCall(VecAXPBY(a->w, -1 / vnorm, 0, a->q));
  PetscCall(PDAugmentedSolve(&a->aug, a->w, a->row, PetscRealPart(cl) / vnorm, PetscRealPart(cv) / vnorm, a->R, rhs, a->duI, &t, its, kr));
  PetscCall(PDPCRefreshSolved(&a->refresh, a->aug.ksp, &again));
  if (again) { /* failed with a kept preconditioner: once more with a fresh one */
    PetscCall(PDPCRefreshAssembled(&a->refresh, a->ksp));
    PetscCall(
        PDAugmentedSolve(&a->aug, a->w, a->row, PetscRealPart(cl) / vnorm, PetscRealPart(cv) / vnorm, a->R, rhs, a->duI, &t, its, kr));
    PetscCall(PDPCRefreshSolved(&a->refresh, a->aug.ksp, NULL));
  }
  *dlam = t / vnorm;
  PetscFunctionReturn(0);
}

/* IMPL-EX (Oliver, Huespe and Cante 2008): a step uses the bond histories extrapolated linearly from the
   last two accepted steps, kappa~ = kappa_n + r (kappa_n - kappa_n-1) with r the ratio of the step lengths,
   every bond on its secant at kappa~. The step's equations then have no softening branch and no kink at
   the history (only the switch to compression), and their matrix is the secant one, definite: Newton
   takes one or two iterations and cannot cycle. The real history follows the solution when the step is
   accepted; how far it lands from the extrapolation is the step's error, which sets the next arc length. */
static PetscErrorCode ImplexExtrapolate(Arc *a, PetscReal r) {
  PDModel *m = a->m;

  PetscFunctionBeginUser;
  for (PetscInt e = 0; e < m->bonds->nbonds; e++) {
    m->kappa[e]  = a->kx_n[e] + r * (a->kx_n[e] - a->kx_prev[e]);
    a->branch[e] = PD_BRANCH_SECANT;
  }
  m->branch = a->branch;
  PetscFunctionReturn(0);
}

/* The error of an IMPL-EX step that reached u: the largest difference between the damage of the real
   history, max(kappa_n, s(u)), and of the extrapolated one the step used (the softening laws lose most of
   their force just past s0, so a difference in stretch would say little). Where the model keeps the last
   residual's force (m->keep_force), the bonds whose force the real history changes are noted with their
   force on the step's secant, so that the accepted step's measurement updates only theirs: a bond whose
   two histories are equal, or both below its material's onset (elastic either way), keeps its force. */
static PetscErrorCode ImplexError(Arc *a, PetscReal *err) {
  PDModel           *m    = a->m;
  PetscReal          mine = 0, dd;
  const PetscScalar *ul;
  Vec                uloc;

  PetscFunctionBeginUser;
  PetscCall(PDModelScatterToLocal(m, a->u, &ul, &uloc));
  m->nfchange = 0;
  m->branch   = a->branch; /* the step's secants, for the noted forces */
  for (PetscInt e0 = 0; e0 < m->bonds->nbonds; e0 += PD_STRETCH_BLOCK) {
    const PetscInt n = PetscMin(PD_STRETCH_BLOCK, m->bonds->nbonds - e0);
    PetscReal      s[PD_STRETCH_BLOCK];
    PDModelBondStretches(m, ul, e0, n, s);
    for (PetscInt k = 0; k < n; k++) {
      const PetscInt  e   = e0 + k;
      const PDLaw    *law = &m->law[m->bonds->material[e]];
      const PetscReal kr  = PetscMax(a->kx_n[e], s[k]);
      if (law->kind == PD_LAW_ELASTIC || kr == m->kappa[e]) continue;
      if (m->keep_force && PetscMax(kr, m->kappa[e]) >= m->onset[m->bonds->material[e]]) PetscCall(PDModelNoteForceChange(m, ul, e));
      {
        const PDLawBond t = PDModelBondThresholds(m, e, law);
        mine              = PetscMax(mine, PetscAbsReal(PDLawDamage(law, &t, kr, &dd) - PDLawDamage(law, &t, m->kappa[e], &dd)));
      }
    }
  }
  m->branch        = NULL;
  m->fchange_ready = m->keep_force;
  PetscCall(PDModelRestoreLocal(m, &ul, &uloc));
  PetscCall(MPIU_Allreduce(&mine, err, 1, MPIU_REAL, MPIU_MAX, m->lat->comm));
  PetscFunctionReturn(0);
}

/* Whether a step starts from the last one (-pd_arclength_predictor secant): an IMPL-EX step under the
   augmented corrector, with a last step to scale and a direction solved for earlier (its Schur estimate),
   not while a load reversal turns the path, and not again for a step that failed from it (Run takes it
   again at the same length from the tangent predictor before it cuts it). */
static PetscBool SecantPredictor(const Arc *a, PetscInt type, PetscBool aug) {
  return a->m->scene->arc_secant && !a->secant_off && a->kx_n && aug && type != ARC_LOAD && a->have_prev && a->len_prev > 0 &&
                 a->vnorm > 0 && !a->turn && a->rev.phase != 1 && a->rev.phase != 2
             ? PETSC_TRUE
             : PETSC_FALSE;
}

/* One step of length dl: predictor along v, then bordered Newton corrections until equilibrium holds,
   the constraint is met and the limiter has no event left. */
static PetscErrorCode Step(Arc *a, PDPath *p, PetscInt type, PetscReal dl, PetscInt *max_events, PetscBool *ok) {
  PDModel        *m     = a->m;
  const PetscInt  maxit = 25;
  PetscReal       dlam, rnorm = PETSC_MAX_REAL, fnorm, damp = 1;
  PetscBool       fine;
  PetscInt        resides = 0;
  const PetscBool aug     = a->augmented && (type == PD_ARC_CMOD || type == PD_ARC_DISSIPATION) ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  *ok               = PETSC_FALSE;
  a->its            = 0;
  a->lits           = 0;
  m->ka_at_residual = PETSC_FALSE; /* the last residual's tangent scalars had the history of the step before */
  a->faces          = PETSC_FALSE;
  if (a->kx_n) PetscCall(ImplexExtrapolate(a, a->len_prev > 0 ? dl / a->len_prev : 0));
  PetscCall(VecCopy(p->u_n, a->u));
  a->lam    = p->lambda_n;
  a->secant = SecantPredictor(a, type, aug);
  if (a->secant) {
    /* an IMPL-EX step is a linear problem (secant, its damage fixed by the extrapolation), which the
       augmented corrector solves for u and lambda together: a direction solve would only start it. The
       last step, scaled to this one's length, starts it instead; the Schur estimate of the corrector's
       preconditioner stays that of the last direction solved for (docs/arclength.md, "The secant predictor") */
    const PetscReal r = dl / a->len_prev;
    dlam              = r * a->dlam_last;
    PetscCall(VecAXPY(a->u, r, a->dprev));
  } else {
    PetscCall(PDModelApplyBoundaryValues(m, a->lam, a->u));
    PetscCall(TangentAndDirection(a, PETSC_TRUE, aug && a->matched ? PetscMax(a->rtol, PD_DIRECTION_RTOL) : a->rtol, &fine));
    if (!fine) PetscFunctionReturn(0);
    PetscCall(ConstraintUpdate(a, p, type, dl, PETSC_TRUE, &dlam, &fine));
    a->why = "no predictor meets the constraint";
    if (!fine) PetscFunctionReturn(0);
    PetscCall(VecAXPY(a->u, dlam, a->v));
  }
  a->lam += dlam;
  a->dlam_pred = dlam;
  /* the iteration budget restarts whenever the limiter grants events: settling a band of bonds that
     soften together takes many grants, each a small perturbation Newton absorbs in a few iterations */
  for (PetscInt k = 0, stages = 0, rises = 0, flips = 0, damped = 0; k < maxit; k++) {
    PetscInt           n, ncand, granted;
    KSPConvergedReason kr;
    PetscReal          tol, rprev = rnorm;
    PetscCall(Residual(a, &rnorm, &fnorm));
    /* a bond whose stretch sits at its history flips between the loading branch (consistent slope) and
       unloading (secant) from one iterate to the next, and Newton can cycle between two states. After
       the residual has risen twice, every softened bond is frozen on its current branch, which makes
       the equations smooth; if it still rises, updates are halved */
    if (k > 0 && rnorm > rprev && ++rises == 2) {
      PetscInt nfrozen;
      if (!m->branch && a->branch) {
        PetscCall(PDModelFreezeBranches(m, a->u, a->branch, &nfrozen));
        PetscCall(PetscInfo(NULL, "arclength: Newton cycles at |R| %g: %" PetscInt_FMT " softened bonds frozen on their branch\n",
                            (double)rnorm, nfrozen));
        PetscCall(Residual(a, &rnorm, &fnorm));
        rises = 0;
      } else if (a->kx_n && !m->faces && !resides) {
        /* IMPL-EX's secant has one kink left, a damaged bond's at zero stretch, where the faces of a sliding
           crack close and open from one iterate to the next: each takes the side it had at the last step */
        PetscCall(PDModelFreezeSides(m, p->u_n, &nfrozen));
        PetscCall(PetscInfo(NULL,
                            "arclength: Newton cycles at |R| %g: %" PetscInt_FMT " damaged bonds frozen on their side of zero stretch\n",
                            (double)rnorm, nfrozen));
        a->faces = PETSC_TRUE;
        PetscCall(Residual(a, &rnorm, &fnorm));
        rises = 0;
      } else {
        damp = 0.5;
        PetscCall(PetscInfo(NULL, "arclength: Newton cycles at |R| %g: updates halved for the rest of the step\n", (double)rnorm));
      }
    }
    a->why = "residual not finite";
    if (PetscIsInfOrNanReal(rnorm)) PetscFunctionReturn(0);
    tol = a->eq_rtol * fnorm + 1e-12 * m->force_scale;
    PetscCall(PetscInfo(NULL, "arclength iteration %" PetscInt_FMT ": |R| %g, tolerance %g, lambda %.10g\n", k, (double)rnorm, (double)tol,
                        (double)a->lam));
    if (rnorm <= tol && m->branch && !a->kx_n) {
      /* equilibrium on frozen branches: it holds for the real law once every bond is on the side of its
         history its branch assumes; otherwise the bonds on the wrong side change branch and Newton goes on */
      PetscInt  nflipped, nkink;
      PetscReal rfree;
      m->branch = NULL;
      PetscCall(Residual(a, &rfree, &fnorm));
      if (rfree > tol) {
        /* a bond that has to flip back has its equilibrium at its kink and is held there (PDModelFlipBranches),
           so a band of such bonds cannot swap branches in a cycle */
        m->branch = a->branch;
        PetscCall(PDModelFlipBranches(m, a->u, &nflipped, &nkink));
        PetscCall(PetscInfo(NULL,
                            "arclength: frozen branches in equilibrium, real law |R| %g: %" PetscInt_FMT
                            " bonds change branch, %" PetscInt_FMT " of them back (held at their kink)\n",
                            (double)rfree, nflipped, nkink));
        a->why = "frozen branches do not settle";
        if (!nflipped || ++flips > 30) PetscFunctionReturn(0);
        k     = 0;
        rises = 0;
        PetscCall(Residual(a, &rnorm, &fnorm));
      } else
        rnorm = rfree;
    }
    if (rnorm <= tol && a->kx_n) { /* IMPL-EX: the secant step is the step; no limiter */
      PetscBool settled = PETSC_TRUE;
      if (m->faces) { /* frozen sides in force (PDModelFreezeSides) */
        /* equilibrium on frozen sides holds for the real law once every bond lies on the side it was given;
           otherwise each takes the side it is on and Newton goes on (an active set) */
        PetscReal rfree;
        PetscCall(PDModelFreeSides(m));
        PetscCall(Residual(a, &rfree, &fnorm));
        if (rfree > tol && ++resides <= PD_IMPLEX_RESIDES) {
          PetscInt nfrozen;
          PetscCall(PDModelFreezeSides(m, a->u, &nfrozen));
          PetscCall(PetscInfo(NULL,
                              "arclength: frozen sides in equilibrium, real law |R| %g: %" PetscInt_FMT " damaged bonds frozen again\n",
                              (double)rfree, nfrozen));
          settled = PETSC_FALSE;
          k       = 0;
          rises   = 0;
          PetscCall(Residual(a, &rnorm, &fnorm));
        } else if (rfree > tol) {
          settled = PETSC_FALSE; /* the sides cycle: the real law with halved updates, as before the freeze */
          damp    = 0.5;
          rnorm   = rfree;
        } else
          rnorm = rfree;
      }
      if (settled) {
        *ok = PETSC_TRUE;
        PetscFunctionReturn(0);
      }
    }
    if (rnorm <= tol) {
      PetscCall(PDModelGrantEvents(m, a->u, m->limiter_max, &ncand, &granted));
      PetscCall(PetscInfo(NULL, "arclength: %" PetscInt_FMT " of %" PetscInt_FMT " bond events granted\n", granted, ncand));
      *max_events = PetscMax(*max_events, granted);
      if (!granted) {
        *ok = PETSC_TRUE;
        PetscFunctionReturn(0);
      }
      a->why = "more than 100,000 limiter stages";
      if (++stages > 100000) PetscFunctionReturn(0);
      k      = 0; /* a new stage: full Newton steps again */
      rises  = 0;
      damp   = 1;
      damped = 0;
      PetscCall(Residual(a, &rnorm, &fnorm));
    }
    /* -pd_arclength_halved_its: halved updates that have not settled by then are taken to cycle, and the
       step is cut rather than left to spend its budget (docs/arclength.md, "Where this is not enough") */
    a->why = "Newton cycles with halved updates";
    if (damp < 1 && m->scene->arc_halved_its > 0 && ++damped > m->scene->arc_halved_its) PetscFunctionReturn(0);
    /* plain control (dlambda = 0) and the augmented solve need no direction */
    PetscCall(TangentAndDirection(a, type != ARC_LOAD && !aug, a->rtol, &fine));
    if (!fine) PetscFunctionReturn(0);
    PetscCall(VecScale(a->R, -1));
    if (aug) {
      /* an IMPL-EX step's first correction takes up the forces its extrapolated damage releases, which move
         along the crack from one step to the next much as the damage does: the last step's, scaled by the
         ratio of the step lengths, starts the solve (as the last direction starts the direction's) */
      const PetscBool first = a->xg && k == 0 ? PETSC_TRUE : PETSC_FALSE;
      if (first && a->have_xg && a->len_prev > 0) {
        PetscCall(VecAXPBY(a->aug.x, dl / a->len_prev, 0, a->xg));
        PetscCall(KSPSetInitialGuessNonzero(a->aug.ksp, PETSC_TRUE));
      }
      PetscCall(KSPSetTolerances(a->aug.ksp, a->rtol_aug, a->floor_aug ? PD_CORRECTOR_ATOL_SHARE * tol : a->atol_aug, PETSC_DEFAULT,
                                 PETSC_DEFAULT));
      PetscCall(AugmentedUpdate(a, p, type, dl, PD_CORRECTOR_ATOL_SHARE * tol, &dlam, &n, &kr, &fine));
      PetscCall(KSPSetInitialGuessNonzero(a->aug.ksp, PETSC_FALSE));
      if (first && kr > 0) {
        PetscCall(VecCopy(a->aug.x, a->xg));
        a->have_xg = PETSC_TRUE;
      }
    } else {
      PetscCall(KSPSetTolerances(a->ksp, a->rtol, a->floor_k ? PD_CORRECTOR_ATOL_SHARE * tol : a->atol, PETSC_DEFAULT, PETSC_DEFAULT));
      PetscCall(Solve(a, a->R, a->duI));
      PetscCall(KSPGetIterationNumber(a->ksp, &n));
      PetscCall(KSPGetConvergedReason(a->ksp, &kr));
    }
    a->lits += n;
    a->its++;
    a->why = KSPConvergedReasons[kr];
    if (kr < 0) {
      /* the augmented solve's factor is that of the tangent's KSP, whose failure its shell PC does not pass on */
      if (aug) PetscCall(PDPCForgetFailed(a->ksp));
      PetscFunctionReturn(0);
    }
    if (!aug) PetscCall(ConstraintUpdate(a, p, type, dl, PETSC_FALSE, &dlam, &fine));
    a->why = "the constraint has no real root";
    if (!fine) PetscFunctionReturn(0);
    /* bordering's v carries u_ref; the augmented du is on free dofs only */
    PetscCall(VecAXPY(a->u, damp, a->duI));
    PetscCall(VecAXPY(a->u, damp * dlam, aug ? a->m->u_ref : a->v));
    a->lam += damp * dlam;
  }
  a->why = "Newton iterations exhausted";
  PetscFunctionReturn(0);
}

/* The measure of a finished step in the constraint's units, to start the arc length from. */
static PetscErrorCode StepLength(Arc *a, PDPath *p, Vec u_prev, PetscReal lam_prev, const PDCurveRow *row, PetscReal d_prev, PetscInt type,
                                 PetscReal *dl) {
  PDModel    *m = a->m;
  PetscScalar t;

  PetscFunctionBeginUser;
  PetscCall(VecWAXPY(a->w, -1, u_prev, p->u_n));
  switch (type) {
  case PD_ARC_CMOD:
    PetscCall(VecDot(m->cmod_pattern, a->w, &t));
    *dl = PetscRealPart(t);
    break;
  case PD_ARC_CYLINDRICAL:
    PetscCall(VecNorm(a->w, NORM_2, dl));
    break;
  case PD_ARC_SPHERICAL:
    PetscCall(VecNorm(a->w, NORM_2, dl));
    *dl = PetscSqrtReal(*dl * *dl + a->psi2 * (p->lambda_n - lam_prev) * (p->lambda_n - lam_prev));
    break;
  default: /* dissipation: what the step released, at least a hundredth of the stored energy */
    *dl = PetscMax(row->dissipated - d_prev, 1e-2 * row->stored);
    break;
  }
  PetscFunctionReturn(0);
}

/* Unload once the load has fallen to unload_at of the peak (before the peak the load is the peak), load
   again at reload_at, back on the envelope once the gauge (or the load point) passes where the path
   turned. The turning steps go against the last step's direction; while unloading, which is elastic and
   nearly linear, the arc length is aimed at reload_at from the last step's load rate instead of past it
   (into reversed bending). */
static PetscErrorCode LoadReversal(Arc *a, const PDRecord *rec, const PDCurveRow *row, PetscReal peak, PetscReal peak_sign, PetscReal len,
                                   PetscReal dl0, PetscReal *dl) {
  const PDScene  *sc    = a->m->scene;
  Reversal       *rev   = &a->rev;
  const PetscReal f     = peak_sign * row->load / peak; /* negative once unloading overshoots */
  const PetscReal gauge = sc->has_cmod ? row->cmod : row->disp;

  PetscFunctionBeginUser;
  if (rev->phase == 1 && f > sc->reload_at && rec->nrows > 1) {
    const PetscReal rate = PetscAbsReal(row->load - rec->rows[rec->nrows - 2].load) / len;
    if (rate > 0) *dl = PetscMin(*dl, PetscMax(1e-3 * dl0, 1.05 * (f - sc->reload_at) * peak / rate));
  }
  if ((rev->phase == 0 && f < sc->unload_at) || (rev->phase == 1 && f <= sc->reload_at)) {
    a->turn = PETSC_TRUE;
    if (rev->phase++ == 0) rev->gauge_turn = gauge;
    PetscCall(PetscInfo(NULL, "load reversal at %.6e N: %s\n", (double)row->load, rev->phase == 1 ? "unloading" : "reloading"));
  } else if (rev->phase == 2 && gauge > rev->gauge_turn)
    rev->phase = 3;
  PetscFunctionReturn(0);
}

/* Checkpoints (-pd_checkpoint_every, -pd_restart; src/io/checkpoint.c): the path vectors and the scalars
   of the driver at an accepted step. A restart builds its preconditioner afresh where the run that wrote
   the checkpoint had a lagged one; both solve to the same tolerance, and the restarted path retraces the
   other to round-off (measured 6e-12 of the peak load on the 2D half-notched beam). */
static const char *const state_names[] = {"step",           "lambda",           "external_work",   "control",
                                          "arc_length",     "arc_length_first", "load_increment",  "peak",
                                          "peak_sign",      "spherical_psi2",   "have_previous",   "turn",
                                          "reversal_phase", "reversal_gauge",   "arc_length_hold", "implex_previous_length"};
_Static_assert(sizeof state_names / sizeof state_names[0] == NSTATE, "one name per checkpointed scalar");
/* the direction of the last accepted step starts the next step's Krylov iterations (-pd_arclength_guess):
   kept, so that a restart starts from the same guess */
static const char *const state_vec_names[] = {"displacement", "internal_force", "last_step", "direction"};
#define NSTATE_VECS 4

PetscErrorCode PDArcLengthValidateRestart(const PDModel *m, const char *path) {
  PetscFunctionBeginUser;
  PetscCall(PDCheckpointValidate(m, path, NSTATE_VECS, state_vec_names, NSTATE, state_names));
  PetscFunctionReturn(0);
}

static void PackState(Arc *a, const PDPath *p) {
  const PetscReal v[NSTATE] = {(PetscReal)p->step,
                               p->lambda_n,
                               p->w_ext,
                               (PetscReal)a->type,
                               a->dl,
                               a->dl0,
                               a->dlam,
                               a->peak,
                               a->peak_sign,
                               a->psi2,
                               (PetscReal)a->have_prev,
                               (PetscReal)a->turn,
                               (PetscReal)a->rev.phase,
                               a->rev.gauge_turn,
                               (PetscReal)a->hold,
                               a->len_prev};
  PetscArraycpy(a->state, v, NSTATE);
}

static void UnpackState(Arc *a, PDPath *p) {
  const PetscReal *v = a->state;
  p->step            = (PetscInt)v[0];
  p->lambda_n        = v[1];
  p->w_ext           = v[2];
  a->type            = (PetscInt)v[3];
  a->dl              = v[4];
  a->dl0             = v[5];
  a->dlam            = v[6];
  a->peak            = v[7];
  a->peak_sign       = v[8];
  a->psi2            = v[9];
  a->have_prev       = v[10] != 0 ? PETSC_TRUE : PETSC_FALSE;
  a->turn            = v[11] != 0 ? PETSC_TRUE : PETSC_FALSE;
  a->rev.phase       = (PetscInt)v[12];
  a->rev.gauge_turn  = v[13];
  a->hold            = (PetscInt)v[14];
  a->len_prev        = v[15];
}

/* What a checkpoint keeps of the last accepted step besides the path: the driver's scalars, the direction
   and the run's totals. */
static PetscErrorCode KeepAccepted(Arc *a, const PDPath *p, const PDRecord *rec) {
  PetscFunctionBeginUser;
  PackState(a, p);
  PetscCall(VecCopy(a->v, a->v_n));
  a->totals[0] = rec->newton_its;
  a->totals[1] = rec->ksp_its;
  PetscFunctionReturn(0);
}

/* The totals kept are those of the last accepted step: a step interrupted part-way is made again, whole, by
   the run that goes on from the checkpoint. */
static PetscErrorCode WriteCheckpoint(Arc *a, PDPath *p, PDRecord *rec) {
  const Vec vec[NSTATE_VECS] = {p->u_n, p->f_n, a->dprev, a->v_n};
  PDRecord  at               = *rec;

  PetscFunctionBeginUser;
  at.newton_its = a->totals[0];
  at.ksp_its    = a->totals[1];
  PetscCall(PDCheckpointWrite(a->m, &at, NSTATE_VECS, vec, state_vec_names, NSTATE, state_names, a->state, a->kx_prev));
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadCheckpoint(Arc *a, PDPath *p, PDRecord *rec) {
  PDModel *m                = a->m;
  Vec      vec[NSTATE_VECS] = {p->u_n, p->f_n, a->dprev, a->v_n};

  PetscFunctionBeginUser;
  PetscCall(PDCheckpointRead(m, rec, m->scene->restart, NSTATE_VECS, vec, state_vec_names, NSTATE, state_names, a->state, a->kx_prev));
  UnpackState(a, p);
  PetscCall(VecCopy(a->v_n, a->v));
  PetscCall(VecNorm(a->v, NORM_2, &a->vnorm));
  /* the last step's load-factor change, as the run that wrote the checkpoint had it (the curve's rows are
     stored exactly) */
  if (rec->nrows > 1) a->dlam_last = rec->rows[rec->nrows - 1].lambda - rec->rows[rec->nrows - 2].lambda;
  m->lambda = p->lambda_n;
  PetscCall(PDPCRefreshRequest(&a->refresh)); /* a fresh preconditioner, as the run that wrote it had at its start */
  PetscCall(PetscInfo(NULL, "path following goes on from %s at step %" PetscInt_FMT ", load factor %g\n", m->scene->restart, p->step,
                      (double)p->lambda_n));
  PetscFunctionReturn(0);
}

/* Plain control found no equilibrium past its last accepted step (PDStaticRun): path following goes on
   from that step with the scene's constraint. The first arc length is the last step's in the constraint's
   units; the reference that bounds growth and cuts is that of a full increment (-pd_dlambda_max), scaled
   from it, since plain control has cut its last increments short by then. The spherical constraint's
   scaling comes from the same step (there is no elastic first step to take it from). */
static PetscErrorCode TakeOver(Arc *a, PDPath *p, const PDPath *from, PetscReal dlam_last, PDRecord *rec) {
  PDModel       *m  = a->m;
  const PDScene *sc = m->scene;
  PetscReal      dunorm;

  PetscFunctionBeginUser;
  PetscCall(VecCopy(from->u_n, p->u_n));
  PetscCall(VecCopy(from->f_n, p->f_n));
  PetscCall(VecCopy(from->du, a->dprev));
  p->lambda_n  = from->lambda_n;
  a->dlam_last = dlam_last;
  p->w_ext     = from->w_ext;
  p->step      = from->step;
  m->lambda    = p->lambda_n;
  a->have_prev = PETSC_TRUE;
  for (PetscInt k = 0; k < rec->nrows; k++)
    if (PetscAbsReal(rec->rows[k].load) > a->peak) {
      a->peak      = PetscAbsReal(rec->rows[k].load);
      a->peak_sign = rec->rows[k].load < 0 ? -1 : 1;
    }
  PetscCall(VecNorm(from->du, NORM_2, &dunorm));
  a->psi2 = dunorm * dunorm / (dlam_last * dlam_last);
  a->type = sc->arc_type;
  PetscCall(VecWAXPY(a->w, -1, from->du, from->u_n)); /* u at the step before */
  PetscCall(VecCopy(a->w, a->u));
  PetscCall(StepLength(a, p, a->u, p->lambda_n - dlam_last, &rec->rows[rec->nrows - 1],
                       rec->nrows > 1 ? rec->rows[rec->nrows - 2].dissipated : 0, a->type, &a->dl));
  PetscCheck(a->dl > 0, m->lat->comm, PETSC_ERR_NOT_CONVERGED,
             "path following cannot start from step %" PetscInt_FMT ": its last step measures %g in the %s constraint", p->step,
             (double)a->dl, PDArcTypes[a->type]);
  a->dl0 = a->dl * PetscMax(1, sc->dlambda_max / dlam_last);
  if (sc->arc_initial > 0) a->dl = a->dl0 = sc->arc_initial;
  PetscCall(PetscPrintf(m->lat->comm, "  path following (%s) from step %" PetscInt_FMT ", load factor %g: %s\n", PDArcTypes[a->type],
                        p->step, (double)p->lambda_n, rec->fallback_why));
  PetscFunctionReturn(0);
}

/* IMPL-EX from the committed histories (kx_n, and kx_prev unless a checkpoint gave it): no limiter, every
   threshold is open, as on the explicit path. A restart has the history a step earlier from its
   checkpoint (one written without IMPL-EX: the same history, no extrapolation). */
static PetscErrorCode StartImplex(Arc *a, PetscReal tol, PetscBool have_prev) {
  PDModel *m = a->m;

  PetscFunctionBeginUser;
  a->implex  = tol;
  a->eq_rtol = EquilibriumRtol(m->scene, PETSC_TRUE);
  if (a->augmented && m->scene->arc_guess && !a->xg) PetscCall(VecDuplicate(a->aug.x, &a->xg));
  for (PetscInt e = 0; e < m->bonds->nbonds; e++) {
    m->level[e] = m->level_n[e] = PD_BOND_LEVEL_OPEN;
    a->kx_n[e]                  = m->kappa[e];
    if (!have_prev) a->kx_prev[e] = m->kappa[e];
  }
  /* an accepted step's force with the real history: the last residual's, updated at the bonds ImplexError
     notes, where the commit changes nothing else (no bar segments, bond slip or crushing's threshold rise);
     the residual's displacement and load factor are those its tangent scalars keep (ka_u, ka_lambda) */
  {
    const PetscBool mine = m->ka_with_residual && m->scene->kinematics == PD_KINEMATICS_SMALL && !m->bonds->nseg_global && !m->nslip &&
                                   !m->shift && !m->dilatation
                               ? PETSC_TRUE
                               : PETSC_FALSE;
    PetscCall(MPIU_Allreduce(&mine, &m->keep_force, 1, MPIU_BOOL, MPI_LAND, m->lat->comm)); /* decided alike on every rank */
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Run(PDModel *m, PDRecord *rec, const PDPath *from, PetscReal dlam_last) {
  const PDScene *sc   = m->scene;
  MPI_Comm       comm = m->lat->comm;
  Arc            a;
  PDPath         path;
  Vec            u_prev;
  PC             pc;
  PetscReal      lam_prev = 0, d_prev = 0;
  const PetscInt maxsteps = 20 * sc->steps;
  PetscBool      early;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&a, sizeof a));
  a.m         = m;
  a.type      = ARC_LOAD;
  a.dlam      = sc->lambda_max / sc->steps;
  a.peak_sign = 1;
  a.eq_rtol   = EquilibriumRtol(sc, PETSC_FALSE);
  /* what summary.json reports */
  rec->arc_rtol    = a.eq_rtol;
  rec->implex_rtol = EquilibriumRtol(sc, PETSC_TRUE);
  PetscCall(PDModelCreateOperators(m, &a.J, &a.P));
  /* within a step nothing changes the bonds' history, levels or branches between a residual and the tangent
     that follows it without a new residual (grants, frozen and flipped branches evaluate one): the tangent
     scalars come from the residual's loop, as under plain control */
  m->ka_with_residual = sc->tangent_with_residual && m->ka && !m->kp && !m->commit_history ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(VecDuplicate(m->f_ref, &a.u));
  PetscCall(VecDuplicate(m->f_ref, &u_prev));
  {
    Vec *work[] = {&a.fint, &a.R, &a.q, &a.duI, &a.v, &a.v_n, &a.w, &a.dprev, &a.row};
    for (size_t k = 0; k < sizeof work / sizeof work[0]; k++) PetscCall(VecDuplicate(m->f_ref, work[k]));
  }
  PetscCall(PDPathCreate(m, &path));
  if (m->softening) PetscCall(PetscMalloc1(PetscMax(1, m->bonds->nbonds), &a.branch));
  if (m->softening && sc->arc_implex > 0) PetscCall(PetscMalloc1(m->bonds->nbonds, &a.kx_n));
  if (a.kx_n) PetscCall(PetscMalloc1(m->bonds->nbonds, &a.kx_prev));
  PetscCall(KSPCreate(comm, &a.ksp));
  PetscCall(PDSolverConfigureKSP(m, a.ksp));
  PetscCall(PDSolverPreferFlexible(m, a.ksp));
  PetscCall(KSPSetTolerances(a.ksp, 1e-8, PETSC_DEFAULT, PETSC_DEFAULT, 20000));
  PetscCall(KSPSetFromOptions(a.ksp));
  PetscCall(KSPGetTolerances(a.ksp, &a.rtol, &a.atol, NULL, NULL));
  PetscCall(KSPConvergedDefaultSetUIRNorm(a.ksp));
  PetscCall(KSPGetPC(a.ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)a.ksp, KSPPREONLY, &a.direct));
  PetscCall(PDPCRefreshAttach(m, a.ksp, NULL, &a.refresh));
  /* a direct solver makes the second solve a pair of triangular solves: bordering costs nothing more */
  a.augmented =
      sc->arc_augmented && !a.direct && (sc->arc_type == PD_ARC_CMOD || sc->arc_type == PD_ARC_DISSIPATION) ? PETSC_TRUE : PETSC_FALSE;
  if (a.augmented) PetscCall(PDAugmentedCreate(a.J, a.ksp, &a.aug));
  /* linear tolerances matched to Newton's need, unless the command line set them (docs/arclength.md,
     "Linear tolerances") */
  {
    PetscBool   chosen = PETSC_FALSE, has;
    PCSide      side;
    const char *names[] = {"-ksp_rtol", "-ksp_atol", "-pd_augmented_ksp_rtol", "-pd_augmented_ksp_atol"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
      PetscCall(PetscOptionsHasName(NULL, NULL, names[k], &has));
      chosen = chosen || has ? PETSC_TRUE : PETSC_FALSE;
    }
    a.matched = !chosen && !a.direct ? PETSC_TRUE : PETSC_FALSE;
    PetscCall(KSPGetPCSide(a.ksp, &side));
    a.floor_k = a.matched && side == PC_RIGHT ? PETSC_TRUE : PETSC_FALSE;
    if (a.augmented) {
      PetscCall(KSPGetTolerances(a.aug.ksp, &a.rtol_aug, &a.atol_aug, NULL, NULL));
      PetscCall(KSPGetPCSide(a.aug.ksp, &side));
      a.floor_aug = a.matched && side == PC_RIGHT ? PETSC_TRUE : PETSC_FALSE;
    }
  }
  if (sc->restart[0])
    PetscCall(ReadCheckpoint(&a, &path, rec));
  else if (from)
    PetscCall(TakeOver(&a, &path, from, dlam_last, rec));
  if (a.kx_n) PetscCall(StartImplex(&a, sc->arc_implex, sc->restart[0] ? PETSC_TRUE : PETSC_FALSE));
  PetscCall(KeepAccepted(&a, &path, rec));
  rec->converged = PETSC_TRUE;
  PetscCall(PetscStrncpy(rec->status, "completed", sizeof rec->status));
  while (path.step < maxsteps) {
    PDCurveRow row;
    PetscInt   max_events  = 0;
    PetscReal  implex_err  = 0;
    PetscBool  insensitive = PETSC_FALSE;
    PetscBool  ok, stop = PETSC_FALSE;
    PetscReal  len = a.type == ARC_LOAD ? PetscMin(a.dlam, sc->lambda_max - path.lambda_n) : a.dl;

    PetscCall(Step(&a, &path, a.type, len, &max_events, &ok));
    m->branch = NULL; /* a step ends with the real law */
    m->faces  = PETSC_FALSE;
    if (ok || a.root_flipped) a.turn = PETSC_FALSE; /* a failed retry on the other root goes back to the first, unchecked */
    rec->newton_its += a.its;
    rec->ksp_its += a.lits;
    if (!ok) {
      PetscCall(PetscInfo(NULL, "arclength: step %" PetscInt_FMT " cut at %s %g after %" PetscInt_FMT " Newton iterations: %s\n",
                          path.step + 1, a.type == ARC_LOAD ? "increment" : "arc length", (double)len, a.its, a.why));
      PetscCall(PDModelRestoreLevels(m));
      if (a.kx_n) PetscCall(PetscArraycpy(m->kappa, a.kx_n, m->bonds->nbonds));
      PetscCall(PDStopInsideStep(rec, &stop));
      if (stop) break;
      if (a.secant) { /* before the step is cut, the same length from the tangent predictor */
        a.secant_off = PETSC_TRUE;
        continue;
      }
      if (from && !a.kx_n && a.type != ARC_LOAD && a.dl * 0.5 < 1e-6 * a.dl0) {
        /* the fallback goes on: where Newton cannot settle which softened bonds load and which unload (a
           whole ligament at its peak stress), IMPL-EX needs no such decision */
        PetscCall(PetscMalloc1(m->bonds->nbonds, &a.kx_n));
        PetscCall(PetscMalloc1(m->bonds->nbonds, &a.kx_prev));
        PetscCall(StartImplex(&a, PD_FALLBACK_IMPLEX, PETSC_FALSE));
        a.dl                      = a.dl0;
        a.len_prev                = 0;
        rec->fallback_implex_step = path.step;
        PetscCall(PetscPrintf(
            comm, "  IMPL-EX (damage error %g per step) from step %" PetscInt_FMT ": implicit path following found no equilibrium (%s)\n",
            (double)a.implex, path.step, a.why));
        continue;
      }
      if (a.type == ARC_LOAD ? a.dlam * 0.5 < sc->dlambda_min : a.dl * 0.5 < 1e-6 * a.dl0) {
        rec->converged = PETSC_FALSE;
        PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "diverged at load factor %g: %s %g at its floor (%s)",
                                (double)path.lambda_n, a.type == ARC_LOAD ? "increment" : "arc length",
                                (double)(a.type == ARC_LOAD ? a.dlam : a.dl), a.why));
        break;
      }
      if (a.type == ARC_LOAD)
        a.dlam *= 0.5;
      else {
        a.dl *= 0.5;
        a.hold = sc->arc_hold;
      }
      continue;
    }
    if (a.kx_n) {
      PetscCall(ImplexError(&a, &implex_err));
      PetscCall(PetscInfo(NULL, "implex: step %" PetscInt_FMT " damage extrapolated to within %g\n", path.step + 1, (double)implex_err));
      PetscCall(PetscArraycpy(m->kappa, a.kx_n, m->bonds->nbonds)); /* the real history follows from the step's start */
      /* a shorter step helps where damage runs ahead of the extrapolation within the step; where the real
         history of the last step left its state out of balance (the error stays as the step shrinks: the
         unnotched D = 200 mm beam at 0.064 for ten halvings) it does not, and the step is taken. So is a
         step once a cut left its error above twice what it would have been had the error scaled with the
         step (as an extrapolation's error does, at least): further cuts would only add solves (the
         unnotched D = 400 mm beam after its peak, each step cut three times to a quarter while its error
         fell from about 1 to a half) */
      insensitive = a.rejects > 0 && implex_err > 2 * a.reject_err ? PETSC_TRUE : PETSC_FALSE;
      if (a.type != ARC_LOAD && implex_err > 2 * a.implex && a.rejects < 3 && !insensitive && a.dl * 0.5 >= 1e-6 * a.dl0) {
        const PetscReal cut = PetscMax(0.25, PetscSqrtReal(a.implex / implex_err));
        a.dl *= cut;
        a.hold       = sc->arc_hold;
        a.reject_err = cut * implex_err;
        a.rejects++;
        continue;
      }
      a.rejects = 0;
    }
    d_prev = rec->nrows ? rec->rows[rec->nrows - 1].dissipated : 0; /* the energy of u_n, from its curve row */
    if ((a.type == PD_ARC_CYLINDRICAL || a.type == PD_ARC_SPHERICAL) && a.dlam_pred < 0 && a.lam < path.lambda_n && sc->unload_at <= 0 &&
        !a.root_flipped) {
      /* at a limit point the path can turn back onto elastic unloading, which a displacement-norm
         constraint cannot tell from a snap-back (the small reinforced beam after its bar yields: the load
         fell back to zero and the run ended as separated). A step whose predictor lowered the load
         factor, and that lowers it and dissipates nothing, is taken again once with the predictor's
         other root. */
      PetscReal stored, dis;
      PetscCall(PDModelEnergy(m, a.u, &stored, &dis));
      if (dis <= d_prev + 1e-9 * PetscAbsReal(d_prev)) {
        PetscCall(
            PetscInfo(NULL, "arclength: step %" PetscInt_FMT " unloads elastically: taken again with the other root\n", path.step + 1));
        PetscCall(PDModelRestoreLevels(m));
        a.turn = a.root_flipped = PETSC_TRUE;
        continue;
      }
    }
    a.root_flipped = PETSC_FALSE;
    a.secant_off   = PETSC_FALSE;
    if (path.step == 0) a.psi2 = a.vnorm * a.vnorm; /* spherical scaling from the first, elastic, direction */
    PetscCall(VecCopy(path.u_n, u_prev));
    lam_prev = path.lambda_n;
    if (insensitive) rec->implex_insensitive++;
    if (a.faces) rec->implex_faces++;
    PetscCall(PDPathAccept(m, rec, &path, a.u, a.lam, a.its, a.lits, &row));
    if (a.kx_n) { /* the histories move on by a step: the oldest buffer takes the new one */
      PetscReal *t = a.kx_prev;
      a.kx_prev    = a.kx_n;
      a.kx_n       = t;
      PetscCall(PetscArraycpy(a.kx_n, m->kappa, m->bonds->nbonds));
    }
    rec->max_events_per_its = PetscMax(rec->max_events_per_its, max_events);
    PetscCall(VecWAXPY(a.dprev, -1, u_prev, path.u_n));
    a.dlam_last = path.lambda_n - lam_prev;
    a.have_prev = PETSC_TRUE;
    /* the first step sets the arc length; under auto (and for the dissipation constraint) plain control
       hands over once a bond softens */
    if (a.type == ARC_LOAD &&
        ((sc->control == PD_CONTROL_ARCLENGTH && sc->arc_type != PD_ARC_DISSIPATION) || m->softening_bonds > 0 || m->broken > 0)) {
      a.type = sc->arc_type;
      PetscCall(StepLength(&a, &path, u_prev, lam_prev, &row, d_prev, a.type, &a.dl));
      if (sc->arc_initial > 0) a.dl = sc->arc_initial;
      a.dl0 = a.dl;
      PetscCall(
          PetscInfo(NULL, "path following (%s) from step %" PetscInt_FMT ", arc length %g\n", PDArcTypes[a.type], path.step, (double)a.dl));
    } else if (a.type != ARC_LOAD) { /* aim at arc_target_its Newton iterations, within [dl0 / 1000, growth dl0] */
      const PetscReal cap = sc->arc_growth;
      PetscReal       f   = PetscSqrtReal((PetscReal)sc->arc_target_its / PetscMax(1, a.its));
      /* IMPL-EX aims at its extrapolation error instead, which is second order in the step where histories
         change smoothly */
      if (a.kx_n) f = implex_err > 0 ? PetscSqrtReal(a.implex / implex_err) : 2;
      if (a.hold > 0) { /* after a cut: no growth for -pd_arclength_hold steps */
        f = PetscMin(f, 1);
        a.hold--;
      }
      a.dl = PetscMax(1e-3 * a.dl0, PetscMin(cap * a.dl0, a.dl * PetscMax(0.5, PetscMin(2, f))));
    } else if (a.its <= 3)
      a.dlam = PetscMin(2 * a.dlam, sc->dlambda_max);
    if (a.kx_n) { /* the step just made, measured as the next one will be, for the extrapolation ratio */
      if (a.type == ARC_LOAD)
        a.len_prev = path.lambda_n - lam_prev;
      else
        PetscCall(StepLength(&a, &path, u_prev, lam_prev, &row, d_prev, a.type, &a.len_prev));
    }
    if (PetscAbsReal(row.load) > a.peak) {
      a.peak      = PetscAbsReal(row.load);
      a.peak_sign = row.load < 0 ? -1 : 1;
    }
    if (sc->unload_at > 0 && a.type != ARC_LOAD) PetscCall(LoadReversal(&a, rec, &row, a.peak, a.peak_sign, len, a.dl0, &a.dl));
    PetscCall(KeepAccepted(&a, &path, rec));
    /* no separation while a load reversal unloads and reloads */
    PetscCall(PDPathStopCriteria(sc, rec, &row, a.peak, a.rev.phase != 1 && a.rev.phase != 2 ? PETSC_TRUE : PETSC_FALSE, &stop));
    if (!stop && path.lambda_n >= sc->lambda_max * (1 - 1e-12)) stop = PETSC_TRUE;
    if (!stop) PetscCall(PDStopOnSignal(comm, rec, &stop));
    PetscCall(PDProgress(comm, sc, &row, stop));
    if (stop || (sc->fields_every > 0 && path.step % sc->fields_every == 0)) PetscCall(PDFieldsWrite(m, rec, path.step, path.u_n));
    if (!stop && sc->checkpoint_every > 0 && path.step % sc->checkpoint_every == 0) PetscCall(WriteCheckpoint(&a, &path, rec));
    if (stop) break;
  }
  if (path.step >= maxsteps) {
    rec->converged = PETSC_FALSE;
    PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "stopped after %" PetscInt_FMT " steps (20 times -pd_steps)", path.step));
  }
  early = !rec->converged && path.step > 0 ? PETSC_TRUE : PETSC_FALSE;
  if (early && (!rec->nfield_steps || rec->field_steps[rec->nfield_steps - 1] != path.step))
    PetscCall(PDFieldsWrite(m, rec, path.step, path.u_n));
  /* a run that stops early can go on from where it stopped; with -pd_checkpoint_every a finished one too
     (to trace further with another stop criterion) */
  if (early || (sc->checkpoint_every > 0 && path.step > 0)) PetscCall(WriteCheckpoint(&a, &path, rec));
  {
    KSPType kt;
    PCType  pt;
    char    plain[sizeof rec->solver];
    PetscCall(KSPGetType(a.ksp, &kt));
    PetscCall(PCGetType(pc, &pt));
    PetscCall(PetscStrncpy(plain, rec->solver, sizeof plain)); /* the solver of plain control before a take-over */
    PetscCall(PetscSNPrintf(rec->solver, sizeof rec->solver, "%s%sarclength(%s, %s)/%s/%s", from ? plain : "", from ? ", then " : "",
                            PDArcTypes[sc->arc_type], a.augmented ? "augmented" : "bordering", kt, pt));
  }
  PetscCall(VecDestroy(&a.xg));
  if (a.augmented) PetscCall(PDAugmentedDestroy(&a.aug));
  PetscCall(KSPDestroy(&a.ksp));
  PetscCall(PDModelDestroyOperators(&a.J, &a.P));
  {
    Vec *work[] = {&a.u, &a.fint, &a.R, &a.q, &a.duI, &a.v, &a.v_n, &a.w, &a.dprev, &a.row, &u_prev};
    for (size_t k = 0; k < sizeof work / sizeof work[0]; k++) PetscCall(VecDestroy(work[k]));
  }
  PetscCall(PDPathDestroy(&path));
  m->ka_with_residual = m->ka_at_residual = PETSC_FALSE;
  m->keep_force = m->fchange_ready = m->f_last_valid = PETSC_FALSE;
  PetscCall(PetscFree(a.branch));
  PetscCall(PetscFree(a.kx_n));
  PetscCall(PetscFree(a.kx_prev));
  PetscFunctionReturn(0);
}

PetscErrorCode PDArcLengthRun(PDModel *m, PDRecord *rec) {
  PetscFunctionBeginUser;
  PetscCall(Run(m, rec, NULL, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode PDArcLengthTakeOver(PDModel *m, PDRecord *rec, const PDPath *from, PetscReal dlam_last) {
  PetscFunctionBeginUser;
  PetscCall(Run(m, rec, from, dlam_last));
  PetscFunctionReturn(0);
}
