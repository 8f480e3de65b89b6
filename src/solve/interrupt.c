/* Ending a long run on SIGTERM, SIGINT or SIGHUP (a batch system's time limit, Ctrl-C, a closed
   terminal): the path loops finish the step under way, write curve, summary and the last fields, and
   report the run as interrupted, so hours of a large beam are not lost with the process. A second
   signal of the same kind ends the process at once (the handler is reset after the first). Every rank
   checks the flag with one reduction per step, so all ranks stop after the same step (mpiexec forwards
   the signal to each rank). The handlers are installed with sigaction after MPI and PETSc are up:
   PetscPushSignalHandler does not see SIGTERM once Open MPI has taken it (measured: the process died by
   the signal with the PETSc handler pushed). */
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
