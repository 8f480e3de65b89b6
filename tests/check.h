/* Pass/fail bookkeeping shared by the C unit tests; the closing line is the one CI counts. */
#pragma once
#include <petscsys.h>

static int check_failures = 0, check_passes = 0;

static inline void Check(PetscBool ok, const char *what, double got, double want) {
  PetscPrintf(PETSC_COMM_SELF, "%s %-60s got %.10g want %.10g\n", ok ? "ok  " : "FAIL", what, got, want);
  if (ok)
    check_passes++;
  else
    check_failures++;
}

static inline void CheckRel(const char *what, double got, double want, double tol) {
  Check(PetscAbsReal(got - want) <= tol * PetscAbsReal(want) ? PETSC_TRUE : PETSC_FALSE, what, got, want);
}

static inline int CheckSummary(void) {
  PetscPrintf(PETSC_COMM_SELF, "%d passed, %d failed\n", check_passes, check_failures);
  return check_failures ? 1 : 0;
}
