static const char help[] = "pdimplicit: implicit quasi-static bond-based peridynamics for concrete.\n"
                           "Usage: pdimplicit -options_file scene.opts [-pd_* overrides] [PETSc SNES/KSP/PC options]\n"
                           "Every -pd_ option is listed below, with its type, default and range, and whether the scene uses it.\n";

#define _POSIX_C_SOURCE 200809L
#include "pd_solve.h"
#include "pd_log.h"
#include <stdio.h>
#include <time.h>

/* Exit statuses: the run completed (or separated), bad input (nothing written), the run failed or stopped early. */
enum { PD_EXIT_OK = 0, PD_EXIT_FAILED = 1, PD_EXIT_BAD_INPUT = 2 };

typedef struct {
  MPI_Comm  comm;
  PDScene   sc;
  PDLattice lat;
  PDBonds   bonds;
  PDModel   model;
  PDRecord  rec;
} Run;

static void ErrorText(PetscErrorCode ierr, char *buf, size_t len) {
  const char *text     = NULL;
  char       *specific = NULL;

  if (PetscErrorMessage(ierr, &text, &specific)) specific = NULL;
  snprintf(buf, len, "%s", specific && specific[0] ? specific : text ? text : "unknown error");
}

/* Everything a scene can get wrong is found here, before any output exists. */
static PetscErrorCode BuildProblem(Run *r) {
  PetscLogDouble t0, t1;
  PetscBool      keep = PETSC_FALSE; /* per-bond critical stretches need each bond's lambda */

  PetscFunctionBeginUser;
  PetscCall(PDSceneCreateFromOptions(r->comm, &r->sc));
  PetscCall(PDOutputCheck(r->comm, &r->sc));
  PetscCall(PDRecordCreate(r->comm, &r->sc, &r->rec));
  PetscCall(PetscTime(&t0));
  PetscCall(PDLatticeCreate(r->comm, &r->sc, &r->lat));
  for (PetscInt k = 0; k < r->sc.nmaterials; k++)
    if (r->sc.material[k].law != PD_LAW_ELASTIC && r->sc.sc_correction) keep = PETSC_TRUE;
  PetscCall(PDBondsCreate(&r->sc, &r->lat, keep, &r->bonds));
  PetscCall(PDModelCreate(&r->sc, &r->lat, &r->bonds, &r->model));
  if (r->sc.restart[0]) PetscCall(PDArcLengthValidateRestart(&r->model, r->sc.restart));
  if (r->sc.explicit_mode || r->sc.failure_search) PetscCall(PDExplicitPlan(&r->model, &r->rec));
  PetscCall(PetscTime(&t1));
  r->rec.t_setup = t1 - t0;
  PetscFunctionReturn(0);
}

/* Runs a stage with PETSc errors returned, not traced back: an error is one line on stderr (from every
   rank of comm). */
static PetscErrorCode Stage(PetscErrorCode (*stage)(Run *), Run *r, MPI_Comm comm, char *msg, size_t len, PetscErrorCode *ierr) {
  PetscFunctionBeginUser;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  *ierr = stage(r);
  PetscCall(PetscPopErrorHandler());
  msg[0] = '\0';
  if (*ierr) {
    ErrorText(*ierr, msg, len);
    PetscCall(PetscFPrintf(comm, PETSC_STDERR, "pdimplicit: error: %s\n", msg));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Silent(MPI_Comm comm, const char format[], ...) {
  (void)comm;
  (void)format;
  return 0;
}

/* -help: the scene is read for what it uses (its errors are shown, not fatal); nothing is built or written.
   PETSc's own per-option lines are silenced while it is read: the schema's listing replaces them. */
static PetscErrorCode Help(MPI_Comm comm) {
  PetscErrorCode (*print)(MPI_Comm, const char[], ...) = PetscHelpPrintf;
  PDScene        sc;
  PetscErrorCode ierr;
  char           note[1024] = "";

  PetscFunctionBeginUser;
  PetscHelpPrintf = Silent;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = PDSceneCreateFromOptions(comm, &sc);
  PetscCall(PetscPopErrorHandler());
  PetscHelpPrintf = print;
  if (ierr) ErrorText(ierr, note, sizeof note);
  PetscCall(PDSceneOptionsHelp(comm, ierr ? NULL : &sc, note));
  PetscCall(PDSceneDestroy(&sc));
  PetscFunctionReturn(0);
}

/* After an error in the solve: whether every rank has failed, so that they can still report together.
   A barrier on a communicator of its own (no other message can match it), given a minute; a rank that
   failed alone is not waited for. */
static PetscBool AllFailed(MPI_Comm agree) {
  const struct timespec tick = {0, 10000000};
  MPI_Request           req;
  int                   done = 0;

  if (MPI_Ibarrier(agree, &req) != MPI_SUCCESS) return PETSC_FALSE;
  for (int i = 0; i < 6000; i++) {
    if (MPI_Test(&req, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS || done) break;
    nanosleep(&tick, NULL);
  }
  return done ? PETSC_TRUE : PETSC_FALSE;
}

static PetscErrorCode Describe(Run *r) {
  const char    *names[PD_MAX_EFFECTS];
  const PetscInt n = PDModelEffects(&r->model, names);

  PetscFunctionBeginUser;
  PetscCall(PDSceneView(&r->sc, PETSC_VIEWER_STDOUT_(r->comm)));
  PetscCall(PetscPrintf(r->comm,
                        "  %" PetscInt_FMT " nodes, %" PetscInt64_FMT " bonds (%" PetscInt_FMT " cut by notches), %" PetscInt_FMT
                        " constrained dofs, set-up %.3f s\n",
                        r->lat.nglobal - r->lat.nunused, r->bonds.nbonds_global, r->bonds.ncut, r->model.nconstrained,
                        (double)r->rec.t_setup));
  PetscCall(PetscPrintf(r->comm, "  effects:"));
  for (PetscInt k = 0; k < n; k++) PetscCall(PetscPrintf(r->comm, "%s %s", k ? "," : "", names[k]));
  PetscCall(PetscPrintf(r->comm, "\n"));
  if (r->lat.nvoid) PetscCall(PetscPrintf(r->comm, "  %" PetscInt_FMT " lattice nodes in voids (no bonds, pinned)\n", r->lat.nvoid));
  if (r->model.nzero_dofs)
    PetscCall(PetscPrintf(r->comm, "  %" PetscInt_FMT " dofs without stiffness pinned (%" PetscInt_FMT " nodes without any bond)\n",
                          r->model.nzero_dofs, r->model.nisolated));
  PetscFunctionReturn(0);
}

/* The path the scene asks for; a signal that came before the first step stops it there. */
static PetscErrorCode Solve(Run *r) {
  PDRecord *rec = &r->rec;
  PetscBool stop;

  PetscFunctionBeginUser;
  PetscCall(PDOutputPrepare(r->comm, &r->sc, rec));
  PetscCall(PDInterrupted(r->comm, &stop));
  if (stop) {
    rec->converged = PETSC_FALSE;
    PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "interrupted by %s before the first step", PDInterruptSignal()));
  } else if (r->sc.dry_run) {
    rec->converged = PETSC_TRUE;
    PetscCall(PetscStrncpy(rec->status, "dry run: scene built, not solved", sizeof rec->status));
  } else
    PetscCall(r->sc.failure_search                    ? PDFailureSearchRun(&r->model, rec)
              : r->sc.explicit_mode                   ? PDExplicitRun(&r->model, rec)
              : r->sc.control >= PD_CONTROL_ARCLENGTH ? PDArcLengthRun(&r->model, rec)
                                                      : PDStaticRun(&r->model, rec));
  PetscFunctionReturn(0);
}

/* Fields, curve, plot and summary, at every stop. */
static PetscErrorCode Report(Run *r) {
  PDRecord      *rec = &r->rec;
  PetscLogDouble t0, t1;

  PetscFunctionBeginUser;
  PetscCall(PetscTime(&t0));
  PetscCall(PDFieldsFinish(&r->model, rec));
  PetscCall(PDCurveClose(rec));
  PetscCall(PDCurvePlotWrite(r->comm, &r->sc, rec));
  PetscCall(PetscTime(&t1));
  rec->t_output += t1 - t0;
  PetscCall(PDSummaryWrite(r->comm, &r->model, rec));
  if (r->sc.explicit_mode)
    PetscCall(PetscPrintf(r->comm, "  %s: %" PetscInt_FMT " time steps of %.4g s; results in %s\n", rec->status, rec->time_steps,
                          (double)rec->dt, rec->dir));
  else
    PetscCall(PetscPrintf(r->comm,
                          "  %s: %" PetscInt_FMT " steps, %" PetscInt_FMT " Newton and %" PetscInt_FMT " KSP iterations; results in %s\n",
                          rec->status, rec->steps, rec->newton_its, rec->ksp_its, rec->dir));
  if (!rec->converged) PetscCall(PetscFPrintf(r->comm, PETSC_STDERR, "pdimplicit: run stopped early: %s\n", rec->status));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  Run            r;
  PetscBool      markdown = PETSC_FALSE, help_asked = PETSC_FALSE, ok;
  MPI_Comm       agree;
  PetscErrorCode ierr, ierr_report;
  char           msg[1024];

  if (PetscInitialize(&argc, &argv, NULL, help)) return PD_EXIT_BAD_INPUT; /* e.g. a missing options file, which PETSc reports */
  r.comm = PETSC_COMM_WORLD;
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-pd_help_markdown", &markdown, NULL));
  PetscCall(PetscOptionsHasHelp(NULL, &help_asked));
  if (markdown || help_asked) {
    PetscCall(markdown ? PDSceneOptionsMarkdown(r.comm) : Help(r.comm));
    PetscCall(PetscFinalize());
    return PD_EXIT_OK;
  }
  /* bad input: one clear line on stderr and exit status 2, not a traceback, and nothing written */
  PetscCall(PDLogRegister());
  PetscCall(PetscLogStagePush(PD_LOG.setup));
  PetscCall(Stage(BuildProblem, &r, r.comm, msg, sizeof msg, &ierr));
  PetscCall(PetscLogStagePop());
  if (ierr) {
    PetscCall(PDSceneDestroy(&r.sc));
    PetscCall(PetscFinalize());
    return PD_EXIT_BAD_INPUT;
  }
  PetscCall(Describe(&r));
  PetscCall(PDInterruptInstall()); /* SIGTERM, SIGINT, SIGHUP: finish the step, write what was traced */
  PetscCallMPI(MPI_Comm_dup(r.comm, &agree));
  /* a failed run: where every rank failed the summary says so; a rank that fails alone cannot report */
  PetscCall(PetscLogStagePush(PD_LOG.solve));
  PetscCall(Stage(Solve, &r, PETSC_COMM_SELF, msg, sizeof msg, &ierr));
  PetscCall(PetscLogStagePop());
  if (ierr) {
    if (!AllFailed(agree)) MPI_Abort(r.comm, PD_EXIT_FAILED);
    r.rec.converged = PETSC_FALSE;
    PetscCall(PetscSNPrintf(r.rec.status, sizeof r.rec.status, "failed: %s", msg));
  }
  PetscCall(PetscLogStagePush(PD_LOG.output));
  PetscCall(Stage(Report, &r, r.comm, msg, sizeof msg, &ierr_report));
  PetscCall(PetscLogStagePop());
  PetscCall(PDOutputDiscardTemporary(&r.rec));
  ok = !ierr && !ierr_report && r.rec.converged ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PDRecordDestroy(&r.rec));
  PetscCall(PDModelDestroy(&r.model));
  PetscCall(PDBondsDestroy(&r.bonds));
  PetscCall(PDLatticeDestroy(&r.lat));
  PetscCall(PDSceneDestroy(&r.sc));
  PetscCallMPI(MPI_Comm_free(&agree));
  PetscCall(PetscFinalize());
  return ok ? PD_EXIT_OK : PD_EXIT_FAILED;
}
