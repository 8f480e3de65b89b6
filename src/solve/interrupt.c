/* Ending a long run on SIGTERM, which batch systems and time limits send before they kill: the path
   loops finish the step under way, write curve, summary and the last fields, and report the run as
   interrupted, so hours of a large beam are not lost with the process. Every rank checks the flag with
   one reduction per step, so all ranks stop after the same step (mpiexec forwards the signal to each
   rank). The handler is installed with sigaction after MPI and PETSc are up: PetscPushSignalHandler
   does not see SIGTERM once Open MPI has taken it (measured: the process died by the signal with the
   PETSc handler pushed). */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include "pd_solve.h"

static volatile sig_atomic_t pd_terminate = 0;

static void OnTerminate(int sig) {
  (void)sig;
  pd_terminate = 1;
}

PetscErrorCode PDInterruptInstall(void) {
  struct sigaction sa;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&sa, sizeof sa));
  sa.sa_handler = OnTerminate;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  PetscCheck(sigaction(SIGTERM, &sa, NULL) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS, "sigaction(SIGTERM) failed");
  PetscFunctionReturn(0);
}

/* Whether any rank has been asked to terminate (collective). */
PetscErrorCode PDInterrupted(MPI_Comm comm, PetscBool *stop) {
  PetscMPIInt mine = pd_terminate, any;

  PetscFunctionBeginUser;
  PetscCall(MPIU_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm));
  *stop = any ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* After an accepted step of a quasi-static path: stop there if asked to, with the status saying so. */
PetscErrorCode PDStopOnSignal(MPI_Comm comm, PDRecord *rec, PetscBool *stop) {
  PetscFunctionBeginUser;
  PetscCall(PDInterrupted(comm, stop));
  if (!*stop) PetscFunctionReturn(0);
  rec->converged = PETSC_FALSE;
  PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "interrupted by SIGTERM after step %" PetscInt_FMT, rec->steps));
  PetscFunctionReturn(0);
}
