/* curve.csv: one row per converged step, columns fixed by the stable interface. Each row is appended and
   flushed as the step is accepted, so the file holds every step done even if the process dies. */
#include "pd_io.h"
#include <errno.h>
#include <string.h>

/* (Re)starts the file with its header: when the output is prepared, and when the rows are cleared. */
PetscErrorCode PDCurveStart(PDRecord *rec) {
  char path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  if (rec->rank) PetscFunctionReturn(0);
  if (rec->curve) fclose(rec->curve);
  PetscCall(PetscSNPrintf(path, sizeof path, "%s/curve.csv", rec->dir));
  rec->curve = fopen(path, "w");
  PetscCheck(rec->curve, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "Cannot write %s: %s", path, strerror(errno));
  fprintf(rec->curve,
          "step,lambda,load_N,disp_m,cmod_m,broken_bonds,newton_its,ksp_its,wall_s,external_J,stored_J,dissipated_J,kinetic_J,damped_J,"
          "yielded_segments,steel_stress_Pa,slip_m,strain_min%s\n",
          rec->section ? ",section_steel_N,section_concrete_tension_N,section_concrete_compression_N,section_steel_height_m,"
                         "section_tension_height_m,section_compression_height_m,section_shear_N"
                       : "");
  PetscCheck(fflush(rec->curve) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "Cannot write %s: %s", path, strerror(errno));
  PetscFunctionReturn(0);
}

/* C's fprintf, not PETSc's: PETSc's appends '.' to whole numbers. */
PetscErrorCode PDCurveAppend(PDRecord *rec, const PDCurveRow *r) {
  PetscFunctionBeginUser;
  if (!rec->curve) PetscFunctionReturn(0);
  fprintf(rec->curve,
          "%" PetscInt_FMT ",%.15g,%.15g,%.15g,%.15g,%" PetscInt64_FMT ",%" PetscInt_FMT ",%" PetscInt_FMT
          ",%.4f,%.10g,%.10g,%.10g,%.10g,%.10g,%" PetscInt_FMT ",%.10g,%.10g,%.10g",
          r->step, (double)r->lambda, (double)r->load, (double)r->disp, (double)r->cmod, r->broken_bonds, r->newton_its, r->ksp_its,
          (double)r->wall, (double)r->external, (double)r->stored, (double)r->dissipated, (double)r->kinetic, (double)r->damped, r->yielded,
          (double)r->steel_stress, (double)r->slip, (double)r->strain_min);
  for (PetscInt k = 0; rec->section && k < PD_SECTION_N; k++) fprintf(rec->curve, ",%.10g", (double)r->section[k]);
  fprintf(rec->curve, "\n");
  PetscCheck(fflush(rec->curve) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "Cannot write %s/curve.csv: %s", rec->dir, strerror(errno));
  PetscFunctionReturn(0);
}

PetscErrorCode PDCurveClose(PDRecord *rec) {
  PetscFunctionBeginUser;
  if (rec->curve) {
    const int err = fclose(rec->curve);
    rec->curve    = NULL;
    PetscCheck(err == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "Cannot write %s/curve.csv: %s", rec->dir, strerror(errno));
  }
  PetscFunctionReturn(0);
}
