/* The explicit path under CMOD control (-pd_explicit_cmod): the load factor is no longer ramped but
   driven by a servo so that the CMOD gauge follows the smoothstep ramp, as a CMOD-controlled test's
   actuator is. Under load-point control a beam whose static path snaps back (the large unnotched ones)
   can only jump, dynamically, from its peak to the far side of the snap; with the gauge's opening
   ramped instead, the load factor falls as the crack runs and the curve follows the static path.

   The servo is a second-order tracking law on the load factor,
     lambda'' = (w^2 (c*(t) - c) + 2 w (c*'(t) - g lambda') + c*''(t)) / g,
   c the gauge's opening, c* its ramp, g the opening per unit load factor of the static elastic body and
   w the servo's circular frequency. Where the body answers quasi-statically (c = g lambda) the tracking
   error obeys e'' + 2 w e' + w^2 e = 0: critically damped. The damping term uses the load factor's own
   rate, not the gauge's, which carries the body's vibrations. w is a fraction (-pd_servo_bandwidth) of
   the body's fundamental frequency, estimated by the Rayleigh quotient of the static deflection, so
   that the body does answer quasi-statically at w. lambda'' is held over each time step and lambda
   integrated exactly with it, so the driven dofs, whose acceleration is lambda'' u_ref, stay at
   lambda u_ref. */
#include "explicit.h"

typedef struct {
  PDModel *m;
  Vec      free; /* 1 on free dofs, 0 on constrained ones */
  Vec      w;
} FreeOperator;

/* y = P_f K P_f x + P_c x: the elastic stiffness on the free dofs, identity on the constrained ones. */
static PetscErrorCode FreeApply(Mat A, Vec x, Vec y) {
  FreeOperator *op;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &op));
  PetscCall(VecPointwiseMult(op->w, x, op->free));
  PetscCall(PDModelElasticApply(op->m, op->w, y));
  PetscCall(VecPointwiseMult(y, y, op->free));
  PetscCall(VecPointwiseMult(op->w, x, op->m->fixed));
  PetscCall(VecAXPY(y, 1, op->w));
  PetscFunctionReturn(0);
}

/* The static elastic answer to lambda = 1 (K u = f_ref on free dofs, u = u_ref on constrained ones), solved
   by CG on the free dofs (options prefix -servo_), gives the gauge's opening per unit load factor and, by
   the Rayleigh quotient of its free part, the fundamental frequency with the driven dofs held. */
PetscErrorCode PDServoSetUp(PDModel *m, Vec mass, PetscReal target, PetscReal t_ramp, PDServo *s) {
  MPI_Comm           comm = m->lat->comm;
  PetscInt           n    = m->bs * m->lat->nowned;
  FreeOperator       op;
  Mat                A;
  KSP                ksp;
  Vec                b, x, y;
  PetscScalar        xkx, xmx, g;
  KSPConvergedReason reason;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(s, sizeof *s));
  s->on     = PETSC_TRUE;
  s->target = target;
  s->t_ramp = t_ramp;
  op.m      = m;
  PetscCall(VecDuplicate(mass, &op.free));
  PetscCall(VecDuplicate(mass, &op.w));
  PetscCall(VecDuplicate(mass, &b));
  PetscCall(VecDuplicate(mass, &x));
  PetscCall(VecDuplicate(mass, &y));
  PetscCall(VecCopy(m->fixed, op.free));
  PetscCall(VecScale(op.free, -1));
  PetscCall(VecShift(op.free, 1));
  PetscCall(MatCreateShell(comm, n, n, PETSC_DETERMINE, PETSC_DETERMINE, &op, &A));
  PetscCall(MatShellSetOperation(A, MATOP_MULT, (void (*)(void))FreeApply));
  PetscCall(MatSetOption(A, MAT_SYMMETRIC, PETSC_TRUE));
  /* b = P_f (f_ref - K u_ref) */
  PetscCall(PDModelElasticApply(m, m->u_ref, b));
  PetscCall(VecAYPX(b, -1, m->f_ref));
  PetscCall(VecPointwiseMult(b, b, op.free));
  PetscCall(KSPCreate(comm, &ksp));
  PetscCall(KSPSetOptionsPrefix(ksp, "servo_"));
  PetscCall(KSPSetOperators(ksp, A, A));
  PetscCall(KSPSetType(ksp, KSPCG));
  {
    PC pc;
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCSetType(pc, PCNONE));
  }
  PetscCall(KSPSetTolerances(ksp, 1e-8, PETSC_DEFAULT, PETSC_DEFAULT, 100000));
  PetscCall(KSPSetFromOptions(ksp));
  PetscCall(KSPSolve(ksp, b, x));
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  PetscCall(KSPGetIterationNumber(ksp, &s->ksp_its));
  PetscCheck(reason > 0, comm, PETSC_ERR_NOT_CONVERGED,
             "-pd_explicit_cmod: the static elastic solve for the servo's gain did not converge (%s)", KSPConvergedReasons[reason]);
  PetscCall(FreeApply(A, x, y));
  PetscCall(VecDot(x, y, &xkx));
  PetscCall(VecPointwiseMult(y, x, mass));
  PetscCall(VecDot(x, y, &xmx));
  PetscCall(VecAXPY(x, 1, m->u_ref)); /* the whole static displacement */
  PetscCall(VecDot(x, m->cmod_pattern, &g));
  s->gain = PetscRealPart(g);
  PetscCheck(s->gain > 0 && PetscRealPart(xmx) > 0, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_explicit_cmod: the CMOD gauge does not open under the load (%g m per unit load factor)", (double)s->gain);
  s->omega1 = PetscSqrtReal(PetscRealPart(xkx) / PetscRealPart(xmx));
  s->omega  = m->scene->servo_bandwidth * s->omega1;
  PetscCall(KSPDestroy(&ksp));
  PetscCall(MatDestroy(&A));
  PetscCall(VecDestroy(&op.free));
  PetscCall(VecDestroy(&op.w));
  PetscCall(VecDestroy(&b));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&y));
  PetscFunctionReturn(0);
}

/* The load factor and its second derivative at time t within the current step. */
void PDServoAt(const PDServo *s, PetscReal t, PetscReal *lam, PetscReal *lam_tt) {
  const PetscReal h = t - s->t0;
  *lam              = s->lam + s->lam_t * h + 0.5 * s->lam_tt * h * h;
  *lam_tt           = s->lam_tt;
}

/* After a step ending at t with displacement u: the load factor advanced to t, the gauge read, and the
   acceleration of the load factor for the next step. */
PetscErrorCode PDServoUpdate(PDServo *s, const PDModel *m, PetscReal t, Vec u) {
  const PetscReal h = t - s->t0;
  PetscScalar     c;
  PetscReal       cs[3], g, w;

  PetscFunctionBeginUser;
  s->lam += s->lam_t * h + 0.5 * s->lam_tt * h * h;
  s->lam_t += s->lam_tt * h;
  s->t0 = t;
  PetscCall(VecDot(u, m->cmod_pattern, &c));
  PDSmoothstep(s->target, s->t_ramp, t, cs); /* the gauge's target opening and its rates */
  /* the gain of the damaged body: its secant opening per unit load factor, no less than the elastic one */
  g         = s->lam > 0 ? PetscMax(s->gain, PetscRealPart(c) / s->lam) : s->gain;
  w         = s->omega * PetscSqrtReal(s->gain / g);
  s->lam_tt = (w * w * (cs[0] - PetscRealPart(c)) + 2 * w * (cs[1] - g * s->lam_t) + cs[2]) / g;
  PetscFunctionReturn(0);
}

/* Back to rest at time 0. */
void PDServoReset(PDServo *s) {
  s->t0 = s->lam = s->lam_t = s->lam_tt = 0;
}
