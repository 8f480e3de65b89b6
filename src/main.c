static const char help[] = "pdimplicit: implicit quasi-static bond-based peridynamics for concrete.\n"
                           "Usage: pdimplicit -options_file scene.opts [-pd_* overrides] [PETSc SNES/KSP/PC options]\n"
                           "Every -pd_ option is listed, with its default, by -help.\n";

#include "pd_solve.h"
#include "pd_log.h"

/* Everything a scene can get wrong is found here, before any output exists. */
static PetscErrorCode BuildProblem(MPI_Comm comm, PDScene *sc, PDLattice *lat, PDBonds *bonds, PDModel *model, PDRecord *rec,
                                   PetscBool *dry_run) {
  PetscLogDouble t0, t1;

  PetscFunctionBeginUser;
  PetscCall(PDSceneCreateFromOptions(comm, sc));
  *dry_run = sc->dry_run;
  PetscCall(PDRecordCreate(comm, sc, rec));
  PetscCall(PetscTime(&t0));
  PetscCall(PDLatticeCreate(comm, sc, lat));
  {
    PetscBool keep = PETSC_FALSE; /* per-bond critical stretches need each bond's lambda */
    for (PetscInt k = 0; k < sc->nmaterials; k++)
      if (sc->material[k].law != PD_LAW_ELASTIC && sc->sc_correction) keep = PETSC_TRUE;
    PetscCall(PDBondsCreate(sc, lat, keep, bonds));
  }
  PetscCall(PDModelCreate(sc, lat, bonds, model));
  if (sc->restart[0]) PetscCall(PDCheckpointValidate(model, sc->restart));
  PetscCall(PetscTime(&t1));
  rec->t_setup = t1 - t0;
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  PDScene        sc;
  PDLattice      lat;
  PDBonds        bonds;
  PDModel        model;
  PDRecord       rec;
  PetscLogDouble t0, t1;
  PetscBool      dry_run = PETSC_FALSE, converged;
  MPI_Comm       comm;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  comm = PETSC_COMM_WORLD;
  PetscCall(PDLogRegister());
  PetscCall(PetscLogStagePush(PD_LOG.setup));
  {
    PetscErrorCode ierr;
    /* bad input: one clear line on stderr and a non-zero exit, not a traceback */
    PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
    ierr = BuildProblem(comm, &sc, &lat, &bonds, &model, &rec, &dry_run);
    PetscCall(PetscPopErrorHandler());
    if (ierr) {
      const char *text;
      char       *specific;
      PetscCall(PetscErrorMessage(ierr, &text, &specific));
      PetscCall(PetscFPrintf(comm, PETSC_STDERR, "pdimplicit: error: %s\n", specific && specific[0] ? specific : text));
      PetscCall(PetscLogStagePop());
      PetscCall(PetscFinalize());
      return 2;
    }
  }
  PetscCall(PDSceneView(&sc, PETSC_VIEWER_STDOUT_(comm)));
  PetscCall(PetscPrintf(comm,
                        "  %" PetscInt_FMT " nodes, %" PetscInt_FMT " bonds (%" PetscInt_FMT " cut by notches), %" PetscInt_FMT
                        " constrained dofs, set-up %.3f s\n",
                        lat.nglobal, bonds.nbonds_global, bonds.ncut, model.nconstrained, (double)rec.t_setup));
  {
    const char    *names[5];
    const PetscInt n = PDModelEffects(&model, names);
    PetscCall(PetscPrintf(comm, "  effects:"));
    for (PetscInt k = 0; k < n; k++) PetscCall(PetscPrintf(comm, "%s %s", k ? "," : "", names[k]));
    PetscCall(PetscPrintf(comm, "\n"));
  }
  if (model.nzero_dofs)
    PetscCall(PetscPrintf(comm, "  %" PetscInt_FMT " dofs without stiffness pinned (%" PetscInt_FMT " nodes without any bond)\n",
                          model.nzero_dofs, model.nisolated));
  PetscCall(PDOutputPrepare(comm, &sc, &rec));
  PetscCall(PDInterruptInstall()); /* SIGTERM: finish the step, write what was traced */
  PetscCall(PetscLogStagePop());
  PetscCall(PetscLogStagePush(PD_LOG.solve));
  if (!dry_run)
    PetscCall(sc.failure_search                    ? PDFailureSearchRun(&model, &rec)
              : sc.explicit_mode                   ? PDExplicitRun(&model, &rec)
              : sc.control >= PD_CONTROL_ARCLENGTH ? PDArcLengthRun(&model, &rec)
                                                   : PDStaticRun(&model, &rec));
  else
    PetscCall(PetscStrncpy(rec.status, "dry run: scene built, not solved", sizeof rec.status));
  PetscCall(PetscLogStagePop());
  PetscCall(PetscLogStagePush(PD_LOG.output));
  converged     = dry_run ? PETSC_TRUE : rec.converged;
  rec.converged = converged;
  PetscCall(PetscTime(&t0));
  PetscCall(PDFieldsFinish(&model, &rec));
  PetscCall(PDCurveWrite(comm, &sc, &rec));
  PetscCall(PDCurvePlotWrite(comm, &sc, &rec));
  PetscCall(PetscTime(&t1));
  rec.t_output += t1 - t0;
  PetscCall(PDSummaryWrite(comm, &model, &rec));
  PetscCall(PetscLogStagePop());
  if (sc.explicit_mode)
    PetscCall(PetscPrintf(comm, "  %s: %" PetscInt_FMT " time steps of %.4g s; results in %s\n", rec.status, rec.time_steps, (double)rec.dt,
                          rec.dir));
  else
    PetscCall(PetscPrintf(comm,
                          "  %s: %" PetscInt_FMT " steps, %" PetscInt_FMT " Newton and %" PetscInt_FMT " KSP iterations; results in %s\n",
                          rec.status, rec.steps, rec.newton_its, rec.ksp_its, rec.dir));
  if (!converged) PetscCall(PetscFPrintf(comm, PETSC_STDERR, "pdimplicit: run stopped early: %s\n", rec.status));
  PetscCall(PDRecordDestroy(&rec));
  PetscCall(PDModelDestroy(&model));
  PetscCall(PDBondsDestroy(&bonds));
  PetscCall(PDLatticeDestroy(&lat));
  PetscCall(PetscFinalize());
  return converged ? 0 : 1;
}
