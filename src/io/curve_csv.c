/* curve.csv: one row per converged step, columns fixed by the stable interface. */
#include "pd_io.h"

PetscErrorCode PDCurveWrite(MPI_Comm comm, const PDScene *sc, const PDRecord *rec) {
  FILE *fp;
  char  path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  (void)sc;
  PetscCall(PetscSNPrintf(path, sizeof path, "%s/curve.csv.tmp", rec->dir));
  PetscCall(PetscFOpen(comm, path, "w", &fp));
  PetscCall(PetscFPrintf(
      comm, fp,
      "step,lambda,load_N,disp_m,cmod_m,broken_bonds,newton_its,ksp_its,wall_s,external_J,stored_J,dissipated_J,kinetic_J,damped_J\n"));
  for (PetscInt k = 0; k < rec->nrows; k++) {
    const PDCurveRow *r = &rec->rows[k];
    PetscCall(PetscFPrintf(comm, fp,
                           "%" PetscInt_FMT ",%.15g,%.15g,%.15g,%.15g,%" PetscInt_FMT ",%" PetscInt_FMT ",%" PetscInt_FMT
                           ",%.4f,%.10g,%.10g,%.10g,%.10g,%.10g\n",
                           r->step, (double)r->lambda, (double)r->load, (double)r->disp, (double)r->cmod, r->broken_bonds, r->newton_its,
                           r->ksp_its, (double)r->wall, (double)r->external, (double)r->stored, (double)r->dissipated, (double)r->kinetic,
                           (double)r->damped));
  }
  PetscCall(PetscFClose(comm, fp));
  PetscCall(PDFileCommit(comm, rec->dir, "curve.csv"));
  PetscFunctionReturn(0);
}
