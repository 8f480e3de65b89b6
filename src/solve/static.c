/* Quasi-static path under load or displacement control: one SNES solve per load step. An elastic
   model with small kinematics is linear, so each step is a single KSP solve (SNESKSPONLY). */
#include "pd_solve.h"

static PetscErrorCode ConfigureSolver(PDModel *m, SNES snes)
{
  KSP ksp;
  PC  pc;

  PetscFunctionBeginUser;
  PetscCall(SNESSetType(snes, m->linear ? SNESKSPONLY : SNESNEWTONLS));
  PetscCall(SNESGetKSP(snes, &ksp));
  /* CG + block Jacobi with ICC(0) blocks on SBAIJ storage: measured fastest on the PD stiffness
     (docs/benchmarks/elastic.md); direct factorisations suffer from the fill-in of a 3D horizon and
     GAMG's set-up costs more than it saves on these matrices. */
  PetscCall(KSPSetType(ksp, KSPCG));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCBJACOBI));
  PetscCall(KSPSetTolerances(ksp, 1e-9, PETSC_DEFAULT, PETSC_DEFAULT, 20000));
  PetscCall(SNESSetTolerances(snes, PETSC_DEFAULT, 1e-8, PETSC_DEFAULT, 50, PETSC_DEFAULT));
  PetscCall(SNESSetFromOptions(snes));
  PetscFunctionReturn(0);
}

static PetscBool FieldsDue(const PDScene *sc, PetscInt step, PetscBool last)
{
  if (last) return PETSC_TRUE;
  return (sc->fields_every > 0 && step % sc->fields_every == 0) ? PETSC_TRUE : PETSC_FALSE;
}

PetscErrorCode PDStaticRun(PDModel *m, PDRecord *rec)
{
  const PDScene *sc = m->scene;
  MPI_Comm       comm = m->lat->comm;
  SNES           snes;
  Mat            J;
  Vec            u, r;

  PetscFunctionBeginUser;
  PetscCall(PDModelCreateMatrix(m, &J));
  PetscCall(VecDuplicate(m->f_ref, &u));
  PetscCall(VecDuplicate(m->f_ref, &r));
  PetscCall(VecZeroEntries(u));
  PetscCall(SNESCreate(comm, &snes));
  PetscCall(SNESSetFunction(snes, r, PDModelResidual, m));
  PetscCall(SNESSetJacobian(snes, J, J, PDModelJacobian, m));
  PetscCall(ConfigureSolver(m, snes));
  rec->converged = PETSC_TRUE;
  PetscCall(PetscStrncpy(rec->status, "completed", sizeof rec->status));
  for (PetscInt step = 1; step <= sc->steps; step++) {
    SNESConvergedReason reason;
    PDCurveRow          row;
    PetscInt            its, lits;
    PetscLogDouble      t0, t1, now;
    PetscReal           asm0 = m->t_assembly;

    PetscCall(PDModelApplyBoundaryValues(m, (PetscReal)step / sc->steps, u));
    PetscCall(PetscTime(&t0));
    PetscCall(SNESSolve(snes, NULL, u));
    PetscCall(PetscTime(&t1));
    rec->t_solve += (t1 - t0) - (m->t_assembly - asm0);
    PetscCall(SNESGetConvergedReason(snes, &reason));
    PetscCall(SNESGetIterationNumber(snes, &its));
    PetscCall(SNESGetLinearSolveIterations(snes, &lits));
    rec->newton_its += its;
    rec->ksp_its += lits;
    if (reason < 0) {
      rec->converged = PETSC_FALSE;
      PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "diverged at step %" PetscInt_FMT ": %s", step, SNESConvergedReasons[reason]));
      PetscCall(PetscPrintf(comm, "pdimplicit: %s\n", rec->status));
      break;
    }
    rec->steps = step;
    PetscCall(PetscTime(&now));
    row.step         = step;
    row.lambda       = m->lambda;
    row.newton_its   = its;
    row.ksp_its      = lits;
    row.broken_bonds = 0;
    row.wall         = now - rec->t_start;
    PetscCall(PDModelMeasure(m, u, &row.load, &row.disp, &row.cmod));
    PetscCall(PDRecordAddRow(rec, &row));
    PetscCall(PDProgress(comm, sc, &row, sc->steps));
    if (FieldsDue(sc, step, step == sc->steps)) PetscCall(PDFieldsWrite(m, rec, step, u));
  }
  {
    MatInfo     info;
    KSP         ksp;
    PC          pc;
    SNESType    st;
    KSPType     kt;
    PCType      pt;
    PetscCall(MatGetInfo(J, MAT_GLOBAL_SUM, &info));
    rec->matrix_nonzeros = info.nz_allocated;
    PetscCall(SNESGetType(snes, &st));
    PetscCall(SNESGetKSP(snes, &ksp));
    PetscCall(KSPGetType(ksp, &kt));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCGetType(pc, &pt));
    PetscCall(PetscSNPrintf(rec->solver, sizeof rec->solver, "%s/%s/%s", st, kt, pt));
  }
  PetscCall(SNESDestroy(&snes));
  PetscCall(MatDestroy(&J));
  PetscCall(VecDestroy(&u));
  PetscCall(VecDestroy(&r));
  PetscFunctionReturn(0);
}
