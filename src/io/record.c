/* The run record (curve rows, counters, timings) and the output directory. curve.csv grows row by row;
   every other file is written under a temporary name and renamed once complete, so a reader never sees
   half a file. */
#include "pd_io.h"
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

PetscErrorCode PDRecordCreate(MPI_Comm comm, const PDScene *sc, PDRecord *rec) {
  PetscLogDouble t;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(rec, sizeof *rec));
  rec->comm = comm;
  PetscCallMPI(MPI_Comm_rank(comm, &rec->rank));
  PetscCall(PetscStrncpy(rec->dir, sc->output_dir, sizeof rec->dir));
  rec->section = sc->has_section;
  PetscCall(PetscTime(&t));
  rec->t_start = t;
  PetscFunctionReturn(0);
}

PetscErrorCode PDRecordAddRow(PDRecord *rec, const PDCurveRow *row) {
  PetscFunctionBeginUser;
  if (rec->nrows == rec->capacity) {
    rec->capacity = PetscMax(64, 2 * rec->capacity);
    PetscCall(PetscRealloc(sizeof(PDCurveRow) * rec->capacity, &rec->rows));
  }
  rec->rows[rec->nrows++] = *row;
  PetscCall(PDCurveAppend(rec, row));
  PetscFunctionReturn(0);
}

/* The status of a run that stopped because a bond reached its material's ultimate compressive strain at
   the step of row (-pd_eps_cu): a failure found, not a failed run. */
PetscErrorCode PDCrushedStatus(const PDScene *sc, PDRecord *rec, const PDCurveRow *row) {
  const PetscReal *x = row->crush_at;

  PetscFunctionBeginUser;
  if (sc->dim == 3)
    PetscCall(PetscSNPrintf(rec->status, sizeof rec->status,
                            "crushed: a bond's stretch %.4g reached -pd_eps_cu %.4g at (%.4g, %.4g, %.4g) m, at step %" PetscInt_FMT
                            ", load %.4g N",
                            (double)row->strain_min, (double)(-row->strain_min / row->crush_ratio), (double)x[0], (double)x[1],
                            (double)x[2], row->step, (double)row->load));
  else
    PetscCall(PetscSNPrintf(
        rec->status, sizeof rec->status,
        "crushed: a bond's stretch %.4g reached -pd_eps_cu %.4g at (%.4g, %.4g) m, at step %" PetscInt_FMT ", load %.4g N",
        (double)row->strain_min, (double)(-row->strain_min / row->crush_ratio), (double)x[0], (double)x[1], row->step, (double)row->load));
  rec->converged = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode PDRecordClearRows(PDRecord *rec) {
  PetscFunctionBeginUser;
  rec->nrows = 0;
  if (rec->curve) PetscCall(PDCurveStart(rec));
  PetscFunctionReturn(0);
}

PetscErrorCode PDRecordDestroy(PDRecord *rec) {
  PetscFunctionBeginUser;
  PetscCall(PDCurveClose(rec));
  PetscCall(PetscFree(rec->rows));
  PetscCall(PetscFree(rec->field_steps));
  PetscCall(PetscViewerDestroy(&rec->h5));
  PetscFunctionReturn(0);
}

/* Why the directory cannot take the output, or NULL: it exists and is a writable directory, or its
   nearest existing ancestor is one (it will be created there). */
static const char *OutputProblem(const char *dir, char *where, size_t len) {
  struct stat st;
  char       *slash;

  snprintf(where, len, "%s", dir);
  while (stat(where, &st)) {
    if (errno != ENOENT && errno != ENOTDIR) return "not accessible";
    slash = strrchr(where, '/');
    while (slash && slash > where && slash[1] == '\0') { /* a trailing '/' */
      *slash = '\0';
      slash  = strrchr(where, '/');
    }
    if (!slash)
      snprintf(where, len, ".");
    else if (slash == where)
      slash[1] = '\0';
    else
      *slash = '\0';
  }
  if (!S_ISDIR(st.st_mode)) return "not a directory";
  if (access(where, W_OK | X_OK)) return "not writable";
  return NULL;
}

#define PD_OUTPUT_DIR_MAX 200 /* leaves room for "/checkpoint.h5.tmp" below the limit met */

PetscErrorCode PDOutputCheck(MPI_Comm comm, const PDScene *sc) {
  PetscMPIInt rank;
  char        msg[PETSC_MAX_PATH_LEN + 64] = "";

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    char        where[PETSC_MAX_PATH_LEN];
    const char *why = OutputProblem(sc->output_dir, where, sizeof where);
    if (why) snprintf(msg, sizeof msg, "'%s' is %s", where, why);
  }
  PetscCallMPI(MPI_Bcast(msg, (PetscMPIInt)sizeof msg, MPI_CHAR, 0, comm));
  PetscCheck(!msg[0], comm, PETSC_ERR_USER_INPUT, "Option -pd_output_dir: cannot write to '%s': %s", sc->output_dir, msg);
  /* the MPI-IO layer under HDF5 aborted the process (a glibc buffer check) on file paths from about 240
     characters: longer output directories are refused here, before the run rather than after it */
  PetscCheck(strlen(sc->output_dir) <= PD_OUTPUT_DIR_MAX, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_output_dir: the path has %zu characters, at most %d are accepted (HDF5's parallel I/O fails on longer ones)",
             strlen(sc->output_dir), PD_OUTPUT_DIR_MAX);
  PetscFunctionReturn(0);
}

/* mkdir -p on rank 0; every rank learns the outcome. */
PetscErrorCode PDOutputPrepare(MPI_Comm comm, const PDScene *sc, PDRecord *rec) {
  int err = 0;

  PetscFunctionBeginUser;
  (void)sc;
  if (rec->rank == 0) {
    char path[PETSC_MAX_PATH_LEN];
    PetscCall(PetscStrncpy(path, rec->dir, sizeof path));
    for (char *p = path + 1; *p && !err; p++)
      if (*p == '/') {
        *p = '\0';
        if (mkdir(path, 0755) && errno != EEXIST) err = errno;
        *p = '/';
      }
    if (!err && mkdir(path, 0755) && errno != EEXIST) err = errno;
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_OPEN, "Option -pd_output_dir: cannot create '%s': %s", rec->dir, strerror(err));
  PetscCall(PDCurveStart(rec));
  PetscFunctionReturn(0);
}

PetscErrorCode PDOutputDiscardTemporary(PDRecord *rec) {
  static const char *const names[] = {"curve.svg", "summary.json", "fields.h5", "fields.xmf", "checkpoint.h5"};

  PetscFunctionBeginUser;
  PetscCall(PetscViewerDestroy(&rec->h5));
  if (rec->rank) PetscFunctionReturn(0);
  for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
    char path[PETSC_MAX_PATH_LEN];
    PetscCall(PetscSNPrintf(path, sizeof path, "%s/%s.tmp", rec->dir, names[i]));
    (void)unlink(path);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode PDFileCommit(MPI_Comm comm, const char *dir, const char *name) {
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    char tmp[PETSC_MAX_PATH_LEN], fin[PETSC_MAX_PATH_LEN];
    PetscCall(PetscSNPrintf(tmp, sizeof tmp, "%s/%s.tmp", dir, name));
    PetscCall(PetscSNPrintf(fin, sizeof fin, "%s/%s", dir, name));
    if (rename(tmp, fin)) err = errno;
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "Cannot rename %s/%s.tmp: %s", dir, name, strerror(err));
  PetscFunctionReturn(0);
}

/* One line on stderr, rewritten in place on a terminal. */
PetscErrorCode PDProgress(MPI_Comm comm, const PDScene *sc, const PDCurveRow *row, PetscBool last) {
  PetscFunctionBeginUser;
  if (!sc->progress) PetscFunctionReturn(0);
  PetscCall(PetscFPrintf(comm, PETSC_STDERR,
                         "\r[%s] step %" PetscInt_FMT "  lambda %.4f/%.4g  load %.5g N  disp %.4g m  cmod %.4g m  broken %" PetscInt64_FMT
                         "  newton %" PetscInt_FMT "  %.1f s   %s",
                         sc->name, row->step, (double)row->lambda, (double)sc->lambda_max, (double)row->load, (double)row->disp,
                         (double)row->cmod, row->broken_bonds, row->newton_its, (double)row->wall, last ? "\n" : ""));
  PetscFunctionReturn(0);
}
