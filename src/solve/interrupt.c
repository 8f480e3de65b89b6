/* Ending a long run on SIGTERM, SIGINT or SIGHUP (a batch system's time limit, Ctrl-C, a closed
   terminal): the path loops stop, write curve, summary and the fields of the last accepted step, and
   report the run as interrupted, so hours of a large beam are not lost with the process. A step under
   way is abandoned: its Newton and Krylov iterations look for the signal too (PDInterruptWatchKSP and
   PDInterruptWatchSNES), since one step of a large 3D beam can take minutes. A second signal of the same
   kind ends the process at once (the handler is reset after the first). Every rank checks the flag with
   one reduction per step and per watched iteration, so all ranks stop at the same place (mpiexec
   forwards the signal to each rank). The handlers are installed with sigaction after MPI and PETSc are
   up: PetscPushSignalHandler does not see SIGTERM once Open MPI has taken it (measured: the process died
   by the signal with the PETSc handler pushed). */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include "pd_solve.h"

static volatile sig_atomic_t pd_signal = 0; /* the signal received on this rank, 0: none */
static int                   pd_seen   = 0; /* the signal any rank received, once PDInterrupted has seen one */

static void OnSignal(int sig) {
  pd_signal = sig;
}

PetscErrorCode PDInterruptInstall(void) {
  const int        sigs[] = {SIGTERM, SIGINT, SIGHUP};
  struct sigaction sa;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&sa, sizeof sa));
  sa.sa_handler = OnSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART | SA_RESETHAND;
  for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++)
    PetscCheck(sigaction(sigs[i], &sa, NULL) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS, "sigaction(%d) failed", sigs[i]);
  PetscFunctionReturn(0);
}

/* Whether any rank has been asked to stop (collective). */
PetscErrorCode PDInterrupted(MPI_Comm comm, PetscBool *stop) {
  PetscMPIInt mine = pd_signal, any;

  PetscFunctionBeginUser;
  PetscCall(MPIU_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm));
  if (any) pd_seen = any;
  *stop = any ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscBool PDInterruptSeen(void) {
  return pd_seen ? PETSC_TRUE : PETSC_FALSE;
}

/* Krylov iterations look for a signal at the first and every PD_WATCH_EVERY-th iteration: one small
   reduction beside the solver's own. Stopped, the solve reports KSP_DIVERGED_ITS (3.18 has no reason of
   its own for it) and the driver, seeing PDInterruptSeen, ends the run instead of cutting the step. */
#define PD_WATCH_EVERY 10

static PetscErrorCode KSPConvergedOrInterrupted(KSP ksp, PetscInt it, PetscReal rnorm, KSPConvergedReason *reason, void *ctx) {
  PetscBool stop;

  PetscFunctionBeginUser;
  PetscCall(KSPConvergedDefault(ksp, it, rnorm, reason, ctx));
  if (*reason || (it != 1 && it % PD_WATCH_EVERY)) PetscFunctionReturn(0);
  PetscCall(PDInterrupted(PetscObjectComm((PetscObject)ksp), &stop));
  if (stop) *reason = KSP_DIVERGED_ITS;
  PetscFunctionReturn(0);
}

/* Newton iterations look for a signal at every iteration that has not converged. */
static PetscErrorCode SNESConvergedOrInterrupted(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                                                 SNESConvergedReason *reason, void *ctx) {
  PetscBool stop;

  PetscFunctionBeginUser;
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, ctx));
  if (*reason > 0 || it == 0) PetscFunctionReturn(0);
  PetscCall(PDInterrupted(PetscObjectComm((PetscObject)snes), &stop));
  if (stop) *reason = SNES_DIVERGED_MAX_IT;
  PetscFunctionReturn(0);
}

PetscErrorCode PDInterruptWatchKSP(KSP ksp) {
  void *ctx;

  PetscFunctionBeginUser;
  PetscCall(KSPConvergedDefaultCreate(&ctx));
  PetscCall(KSPSetConvergenceTest(ksp, KSPConvergedOrInterrupted, ctx, KSPConvergedDefaultDestroy));
  PetscFunctionReturn(0);
}

PetscErrorCode PDInterruptWatchSNES(SNES snes) {
  PetscFunctionBeginUser;
  PetscCall(SNESSetConvergenceTest(snes, SNESConvergedOrInterrupted, NULL, NULL));
  PetscFunctionReturn(0);
}

/* After a step that did not finish: stop if a signal cut it short, with the status saying so. */
PetscErrorCode PDStopInsideStep(PDRecord *rec, PetscBool *stop) {
  PetscFunctionBeginUser;
  *stop = PDInterruptSeen();
  if (!*stop) PetscFunctionReturn(0);
  rec->converged = PETSC_FALSE;
  PetscCall(PetscSNPrintf(rec->status, sizeof rec->status,
                          "interrupted by %s during step %" PetscInt_FMT " (the curve ends at step %" PetscInt_FMT ")", PDInterruptSignal(),
                          rec->steps + 1, rec->steps));
  PetscFunctionReturn(0);
}

const char *PDInterruptSignal(void) {
  return pd_seen == SIGINT ? "SIGINT" : pd_seen == SIGHUP ? "SIGHUP" : "SIGTERM";
}

/* After an accepted step of a quasi-static path: stop there if asked to, with the status saying so. */
PetscErrorCode PDStopOnSignal(MPI_Comm comm, PDRecord *rec, PetscBool *stop) {
  PetscFunctionBeginUser;
  PetscCall(PDInterrupted(comm, stop));
  if (!*stop) PetscFunctionReturn(0);
  rec->converged = PETSC_FALSE;
  PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "interrupted by %s after step %" PetscInt_FMT, PDInterruptSignal(), rec->steps));
  PetscFunctionReturn(0);
}
