/* checkpoint.h5: the state of a quasi-static path at an accepted step, so that a run stopped by a time
   limit (SIGTERM) or by a failed step goes on from there with -pd_restart instead of from the start.
   A large 3D beam takes hours per curve; this is what lets it be traced in legs.

   What it holds, through PETSc's HDF5 viewer:
   - the path vectors the driver names (displacement, internal force, last step), in global node order;
   - the bond history, kappa and the limiter level, laid out per owned node and per neighbour in global
     id order (the stiffness rows), and where the driver keeps one (IMPL-EX) the history a step earlier,
     which its next extrapolation needs. That layout depends on the lattice only, not on the partition, so a
     checkpoint written with one rank count is read with any other;
   - the curve rows and run totals, so curve.csv and summary.json cover the whole path;
   - the driver's scalars as named attributes;
   - a fingerprint of the scene: node, bond and dof counts and two sums over the bonds (stiffness
     coefficients and critical stretches), and the path-following constraint. A changed geometry, modulus,
     strength (tensile or compressive), fracture energy, horizon, correction or constraint changes one of them, and the restart is
     refused before any output is written.
   The file is written under a temporary name and renamed once complete. */
#include "pd_io.h"
#include "checkpoint_bonds.h"
#include "kernel.h"
#include <petscviewerhdf5.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#define ROW_FIELDS 16

static const char *const fingerprint_names[] = {"nodes", "bonds", "dofs_per_node", "bond_stiffness_sum", "critical_stretch_sum"};
#define NFINGERPRINT 5

static PetscErrorCode Fingerprint(const PDModel *m, PetscReal fp[NFINGERPRINT]) {
  const PDBonds *bd      = m->bonds;
  PetscReal      mine[2] = {0, 0}, sum[2];

  PetscFunctionBeginUser;
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PDLaw *law = &m->law[bd->material[e]];
    if (!PDBondCountedHere(m->lat, bd, e)) continue;
    mine[0] += PDBondStiffness(bd, e);
    /* the thresholds as built (crushing's rise, m->shift, is history, written with it) and the rise's
       coefficient, so that a leg with another -pd_fc is refused like one with another strength */
    if (law->kind == PD_LAW_SLIP)
      mine[1] += law->slip.tau_max + law->slip.x[3]; /* a link never breaks: sc is infinite */
    else if (law->kind != PD_LAW_ELASTIC)
      mine[1] += PDModelBondThresholds(m, e, law).sc - (m->shift ? m->shift[e] : 0) + law->confine;
    if (bd->seg && bd->seg[e] >= 0) {
      const PDSteel *st = &m->steel[bd->seg_bar[bd->seg[e]]];
      mine[1] += st->sy + st->h + (st->su < PETSC_MAX_REAL ? st->su : 0);
    }
  }
  PetscCall(MPIU_Allreduce(mine, sum, 2, MPIU_REAL, MPI_SUM, m->lat->comm));
  fp[0] = (PetscReal)m->lat->nglobal;
  fp[1] = (PetscReal)bd->nbonds_global;
  fp[2] = (PetscReal)m->bs;
  fp[3] = sum[0];
  fp[4] = sum[1];
  PetscFunctionReturn(0);
}

static const char *const total_names[] = {"steps", "newton_its", "ksp_its", "max_events_per_iteration", "jacobian_assemblies"};
#define NTOTALS 5
/* Whether every rank's values pass (collective). */
static PetscErrorCode AllPass(MPI_Comm comm, PetscBool mine, PetscBool *all) {
  PetscFunctionBeginUser;
  PetscCall(MPIU_Allreduce(&mine, all, 1, MPIU_BOOL, MPI_LAND, comm));
  PetscFunctionReturn(0);
}

/* Every finite, within [lo, hi] (skip: an entry index modulo stride that may be NaN, or -1). */
static PetscErrorCode VecInRange(Vec x, PetscReal lo, PetscReal hi, PetscInt stride, PetscInt skip, PetscBool *ok) {
  const PetscScalar *a;
  PetscInt           n, start;
  PetscBool          mine = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(x, &n));
  PetscCall(VecGetOwnershipRange(x, &start, NULL));
  PetscCall(VecGetArrayRead(x, &a));
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal v = PetscRealPart(a[i]);
    if (stride > 0 && (start + i) % stride == skip && PetscIsNanReal(v)) continue;
    if (PetscIsInfOrNanReal(v) || v < lo || v > hi) mine = PETSC_FALSE;
  }
  PetscCall(VecRestoreArrayRead(x, &a));
  PetscCall(AllPass(PetscObjectComm((PetscObject)x), mine, ok));
  PetscFunctionReturn(0);
}

/* The values a restart would start from, checked like any other input: counts non-negative, the driver's
   scalars and the path vectors finite, curve rows finite (the CMOD column may be NaN in a scene without a
   gauge), bond histories finite and within [0, PD_KAPPA_MAX], limiter levels whole numbers from 0 to 255.
   bad gets what failed (empty: nothing). */
static PetscErrorCode CheckValues(const PDModel *m, PetscViewer v, PetscInt nvec, const char *const vec_name[], PetscInt nreal,
                                  const char *const real_name[], char *bad, size_t len) {
  MPI_Comm        comm = m->lat->comm;
  PetscInt        total[NTOTALS], nrows;
  PetscBool       ok, has;
  const PetscReal zero = 0;
  Vec             x;

  PetscFunctionBeginUser;
  bad[0] = '\0';
  for (PetscInt k = 0; k < NTOTALS; k++) {
    PetscCall(PetscViewerHDF5ReadAttribute(v, "/", total_names[k], PETSC_INT, NULL, &total[k]));
    if (total[k] < 0) {
      PetscCall(PetscSNPrintf(bad, len, "its %s is %" PetscInt_FMT, total_names[k], total[k]));
      PetscFunctionReturn(0);
    }
  }
  PetscCall(PetscViewerHDF5ReadAttribute(v, "/", "curve_rows", PETSC_INT, NULL, &nrows));
  if (nrows < 0 || nrows > total[0] + 1) {
    PetscCall(PetscSNPrintf(bad, len, "it has %" PetscInt_FMT " curve rows for %" PetscInt_FMT " steps", nrows, total[0]));
    PetscFunctionReturn(0);
  }
  for (PetscInt k = 0; k < nreal; k++) {
    PetscReal r;
    PetscCall(PetscViewerHDF5ReadAttribute(v, "/", real_name[k], PETSC_REAL, &zero, &r));
    if (PetscIsInfOrNanReal(r)) {
      PetscCall(PetscSNPrintf(bad, len, "its %s is %g", real_name[k], (double)r));
      PetscFunctionReturn(0);
    }
  }
  for (PetscInt k = 0; k < nvec; k++) {
    PetscCall(PetscViewerHDF5HasDataset(v, vec_name[k], &has));
    if (!has) {
      PetscCall(PetscSNPrintf(bad, len, "it has no %s", vec_name[k]));
      PetscFunctionReturn(0);
    }
    PetscCall(VecDuplicate(m->f_ref, &x));
    PetscCall(PetscObjectSetName((PetscObject)x, vec_name[k]));
    PetscCall(VecLoad(x, v));
    PetscCall(VecInRange(x, PETSC_MIN_REAL, PETSC_MAX_REAL, 0, -1, &ok));
    PetscCall(VecDestroy(&x));
    if (!ok) {
      PetscCall(PetscSNPrintf(bad, len, "its %s is not finite everywhere", vec_name[k]));
      PetscFunctionReturn(0);
    }
  }
  PetscCall(VecCreateMPI(comm, PETSC_DECIDE, PetscMax(1, nrows) * ROW_FIELDS, &x));
  PetscCall(PetscObjectSetName((PetscObject)x, "curve"));
  PetscCall(VecLoad(x, v));
  PetscCall(VecInRange(x, PETSC_MIN_REAL, PETSC_MAX_REAL, ROW_FIELDS, m->scene->has_cmod ? -1 : 7, &ok));
  PetscCall(VecDestroy(&x));
  if (!ok) {
    PetscCall(PetscSNPrintf(bad, len, "its curve rows are not finite"));
    PetscFunctionReturn(0);
  }
  if (m->scene->nbars) {
    for (PDBondField f = PD_BOND_STEEL_PLASTIC; f <= PD_BOND_STEEL_DISSIPATED; f++) {
      PetscCall(PDBondFieldCheck(m, f, v, &ok));
      if (!ok) {
        PetscCall(PetscSNPrintf(bad, len, "its %s is missing, not finite or out of range", PDBondFieldNames[f]));
        PetscFunctionReturn(0);
      }
    }
  }
  if (!m->softening) PetscFunctionReturn(0);
  PetscCall(PDBondFieldCheck(m, PD_BOND_KAPPA, v, &ok));
  if (!ok) PetscCall(PetscSNPrintf(bad, len, "a bond history (largest stretch) is missing, not finite or outside [0, %g]", PD_KAPPA_MAX));
  if (ok) {
    PetscCall(PDBondFieldCheck(m, PD_BOND_LEVEL, v, &ok));
    if (!ok) PetscCall(PetscSNPrintf(bad, len, "a limiter level is missing or not a whole number from 0 to 255"));
  }
  if (ok && m->shift) { /* crushing's rises: present, finite, not negative */
    PetscCall(PDBondFieldCheck(m, PD_BOND_RISE, v, &ok));
    if (!ok) PetscCall(PetscSNPrintf(bad, len, "its threshold rises (-pd_fc) are missing, not finite or outside [0, %g]", PD_KAPPA_MAX));
  }
  PetscFunctionReturn(0);
}

/* The file must exist, be HDF5 (its signature, checked here so the message names the option rather than
   an HDF5 call), carry the checkpoint mark, match this scene's fingerprint and hold values a run can go
   on from (CheckValues): the driver names its vectors and scalars. */
PetscErrorCode PDCheckpointValidate(const PDModel *m, const char *path, PetscInt nvec, const char *const vec_name[], PetscInt nreal,
                                    const char *const real_name[]) {
  MPI_Comm    comm = m->lat->comm;
  PetscBool   exists, mark, same;
  PetscMPIInt rank;
  int         hdf5 = 0;
  PetscViewer v;
  PetscReal   fp[NFINGERPRINT], theirs;

  PetscFunctionBeginUser;
  PetscCall(PetscTestFile(path, 'r', &exists));
  PetscCheck(exists, comm, PETSC_ERR_FILE_OPEN, "Option -pd_restart: cannot read '%s'", path);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    static const unsigned char sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
    unsigned char              head[8];
    FILE                      *f = fopen(path, "rb");
    hdf5                         = f && fread(head, 1, 8, f) == 8 && !memcmp(head, sig, 8);
    if (f) fclose(f);
  }
  PetscCallMPI(MPI_Bcast(&hdf5, 1, MPI_INT, 0, comm));
  PetscCheck(hdf5, comm, PETSC_ERR_FILE_READ, "Option -pd_restart: '%s' is not an HDF5 file", path);
  PetscCall(PetscViewerHDF5Open(comm, path, FILE_MODE_READ, &v));
  PetscCall(PetscViewerHDF5HasAttribute(v, "/", "pdimplicit_checkpoint", &mark));
  if (!mark) PetscCall(PetscViewerDestroy(&v));
  PetscCheck(mark, comm, PETSC_ERR_FILE_READ, "Option -pd_restart: '%s' is not a pdimplicit checkpoint", path);
  PetscCall(PetscViewerHDF5HasAttribute(v, "/", "arclength_type", &same)); /* older checkpoints lack it */
  if (same) {
    /* the arc length is measured in the constraint's units (m, or J for dissipation): it cannot change */
    char *type;
    PetscCall(PetscViewerHDF5ReadAttribute(v, "/", "arclength_type", PETSC_STRING, NULL, &type));
    PetscCall(PetscStrcmp(type, PDArcTypes[m->scene->arc_type], &same));
    if (!same) PetscCall(PetscViewerDestroy(&v));
    PetscCheck(same, comm, PETSC_ERR_USER_INPUT, "Option -pd_restart: '%s' followed the path with -pd_arclength_type %s, not %s", path,
               type, PDArcTypes[m->scene->arc_type]);
    PetscCall(PetscFree(type));
  }
  PetscCall(Fingerprint(m, fp));
  for (PetscInt k = 0; k < NFINGERPRINT; k++) {
    PetscReal tol;
    PetscCall(PetscViewerHDF5ReadAttribute(v, "/", fingerprint_names[k], PETSC_REAL, NULL, &theirs));
    /* the sums are reduced in another order on another rank count: round-off, not a different scene */
    tol = k < 3 ? 0 : 1e-9 * PetscAbsReal(fp[k]);
    if (PetscAbsReal(theirs - fp[k]) > tol) PetscCall(PetscViewerDestroy(&v));
    PetscCheck(PetscAbsReal(theirs - fp[k]) <= tol, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_restart: '%s' belongs to another scene: its %s is %.10g, this scene's is %.10g", path, fingerprint_names[k],
               (double)theirs, (double)fp[k]);
  }
  {
    char bad[160];
    PetscCall(CheckValues(m, v, nvec, vec_name, nreal, real_name, bad, sizeof bad));
    PetscCall(PetscViewerDestroy(&v));
    PetscCheck(!bad[0], comm, PETSC_ERR_USER_INPUT, "Option -pd_restart: '%s' cannot be gone on from: %s", path, bad);
  }
  PetscFunctionReturn(0);
}

static void RowPack(const PDCurveRow *r, PetscScalar *a) {
  const PetscReal v[ROW_FIELDS] = {(PetscReal)r->step,
                                   (PetscReal)r->newton_its,
                                   (PetscReal)r->ksp_its,
                                   (PetscReal)r->broken_bonds,
                                   r->lambda,
                                   r->load,
                                   r->disp,
                                   r->cmod,
                                   r->wall,
                                   r->external,
                                   r->stored,
                                   r->dissipated,
                                   r->kinetic,
                                   r->damped,
                                   (PetscReal)r->yielded,
                                   r->steel_stress};
  for (PetscInt k = 0; k < ROW_FIELDS; k++) a[k] = v[k];
}

static void RowUnpack(const PetscScalar *a, PDCurveRow *r) {
  r->step         = (PetscInt)PetscRealPart(a[0]);
  r->newton_its   = (PetscInt)PetscRealPart(a[1]);
  r->ksp_its      = (PetscInt)PetscRealPart(a[2]);
  r->broken_bonds = (PetscInt64)PetscRealPart(a[3]);
  r->lambda       = PetscRealPart(a[4]);
  r->load         = PetscRealPart(a[5]);
  r->disp         = PetscRealPart(a[6]);
  r->cmod         = PetscRealPart(a[7]);
  r->wall         = PetscRealPart(a[8]);
  r->external     = PetscRealPart(a[9]);
  r->stored       = PetscRealPart(a[10]);
  r->dissipated   = PetscRealPart(a[11]);
  r->kinetic      = PetscRealPart(a[12]);
  r->damped       = PetscRealPart(a[13]);
  r->yielded      = (PetscInt)PetscRealPart(a[14]);
  r->steel_stress = PetscRealPart(a[15]);
}

/* kappa_prev, where the driver keeps one (IMPL-EX), is the history a step earlier; it reads as kappa from a
   file written by a driver that kept none. The rises come first: the levels' thresholds depend on them. */
static PetscErrorCode ReadHistory(PDModel *m, PetscReal *kappa_prev, PetscViewer v) {
  PetscBool has = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (m->shift) PetscCall(PDBondFieldRead(m, NULL, PD_BOND_RISE, v));
  PetscCall(PDBondFieldRead(m, NULL, PD_BOND_KAPPA, v));
  PetscCall(PDBondFieldRead(m, NULL, PD_BOND_LEVEL, v));
  if (kappa_prev) PetscCall(PetscViewerHDF5HasDataset(v, PDBondFieldNames[PD_BOND_KAPPA_PREVIOUS], &has));
  if (has)
    PetscCall(PDBondFieldRead(m, kappa_prev, PD_BOND_KAPPA_PREVIOUS, v));
  else if (kappa_prev)
    for (PetscInt p = 0; p < m->bonds->inc_start[m->lat->nowned]; p++) kappa_prev[m->bonds->inc_bond[p]] = m->kappa[m->bonds->inc_bond[p]];
  PetscCall(PDModelCountDamage(m));
  PetscFunctionReturn(0);
}

/* Columns of the rows kept apart from them, so that the rows of checkpoints written without them still
   read: the largest slip (scenes with bond slip), the bond strain closest to crushing (-pd_eps_cu) and the
   section's forces (-pd_section_x, PD_SECTION_N values a row). */
typedef enum { COLUMN_SLIP, COLUMN_STRAIN_MIN, COLUMN_SECTION, COLUMN_N } RowColumn;
static const char *const column_names[] = {"curve_slip", "curve_strain_min", "curve_section"};

static const size_t   column_offset[] = {offsetof(PDCurveRow, slip), offsetof(PDCurveRow, strain_min), offsetof(PDCurveRow, section)};
static const PetscInt column_width[]  = {1, 1, PD_SECTION_N};

/* Value k of column c in a row. */
static inline PetscReal *ColumnValue(PDCurveRow *row, RowColumn c, PetscInt k) {
  return (PetscReal *)((char *)row + column_offset[c]) + k;
}

static PetscErrorCode WriteRowColumn(MPI_Comm comm, const PDRecord *rec, RowColumn c, PetscViewer v) {
  const PetscInt w = column_width[c];
  Vec            S;
  PetscScalar   *a;
  PetscInt       lo, hi;

  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(comm, PETSC_DECIDE, PetscMax(1, rec->nrows) * w, &S));
  PetscCall(PetscObjectSetName((PetscObject)S, column_names[c]));
  PetscCall(VecGetOwnershipRange(S, &lo, &hi));
  PetscCall(VecGetArray(S, &a));
  for (PetscInt r = lo; r < hi; r++) a[r - lo] = r / w < rec->nrows ? *ColumnValue(&rec->rows[r / w], c, r % w) : 0;
  PetscCall(VecRestoreArray(S, &a));
  PetscCall(VecView(S, v));
  PetscCall(VecDestroy(&S));
  PetscFunctionReturn(0);
}

/* A vector of the file, whole on every rank. */
static PetscErrorCode ReadToAll(MPI_Comm comm, PetscViewer v, const char *name, PetscInt n, Vec *all) {
  Vec        R;
  VecScatter toall;

  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(comm, PETSC_DECIDE, n, &R));
  PetscCall(PetscObjectSetName((PetscObject)R, name));
  PetscCall(VecLoad(R, v));
  PetscCall(VecScatterCreateToAll(R, &toall, all));
  PetscCall(VecScatterBegin(toall, R, *all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(toall, R, *all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterDestroy(&toall));
  PetscCall(VecDestroy(&R));
  PetscFunctionReturn(0);
}

/* Curve rows: every rank holds all of them; the file holds them once. */
static PetscErrorCode WriteRows(MPI_Comm comm, const PDRecord *rec, PetscViewer v) {
  Vec          R;
  PetscScalar *a;
  PetscInt     lo, hi;

  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(comm, PETSC_DECIDE, PetscMax(1, rec->nrows) * ROW_FIELDS, &R));
  PetscCall(PetscObjectSetName((PetscObject)R, "curve"));
  PetscCall(VecGetOwnershipRange(R, &lo, &hi));
  PetscCall(VecGetArray(R, &a));
  for (PetscInt r = 0; r < rec->nrows; r++) {
    PetscScalar row[ROW_FIELDS];
    RowPack(&rec->rows[r], row);
    for (PetscInt k = 0; k < ROW_FIELDS; k++) {
      const PetscInt i = r * ROW_FIELDS + k;
      if (i >= lo && i < hi) a[i - lo] = row[k];
    }
  }
  PetscCall(VecRestoreArray(R, &a));
  PetscCall(VecView(R, v));
  PetscCall(VecDestroy(&R));
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadRows(MPI_Comm comm, PDRecord *rec, PetscInt nrows, PetscBool slip, PetscViewer v) {
  Vec                all, col[COLUMN_N] = {NULL, NULL, NULL};
  const PetscScalar *a, *c[COLUMN_N]    = {NULL, NULL, NULL};
  PetscBool          has;

  PetscFunctionBeginUser;
  PetscCall(ReadToAll(comm, v, "curve", PetscMax(1, nrows) * ROW_FIELDS, &all));
  if (slip) PetscCall(ReadToAll(comm, v, column_names[COLUMN_SLIP], PetscMax(1, nrows), &col[COLUMN_SLIP]));
  for (RowColumn k = COLUMN_STRAIN_MIN; k < COLUMN_N; k++) { /* (not in files from before they existed) */
    PetscCall(PetscViewerHDF5HasDataset(v, column_names[k], &has));
    if (has && (k != COLUMN_SECTION || rec->section))
      PetscCall(ReadToAll(comm, v, column_names[k], PetscMax(1, nrows) * column_width[k], &col[k]));
  }
  PetscCall(VecGetArrayRead(all, &a));
  for (PetscInt k = 0; k < COLUMN_N; k++)
    if (col[k]) PetscCall(VecGetArrayRead(col[k], &c[k]));
  PetscCall(PDRecordClearRows(rec));
  for (PetscInt r = 0; r < nrows; r++) {
    PDCurveRow row = {0};
    RowUnpack(a + r * ROW_FIELDS, &row);
    for (RowColumn k = COLUMN_SLIP; k < COLUMN_N; k++)
      for (PetscInt q = 0; c[k] && q < column_width[k]; q++) *ColumnValue(&row, k, q) = PetscRealPart(c[k][r * column_width[k] + q]);
    PetscCall(PDRecordAddRow(rec, &row));
  }
  PetscCall(VecRestoreArrayRead(all, &a));
  for (PetscInt k = 0; k < COLUMN_N; k++) {
    if (col[k]) PetscCall(VecRestoreArrayRead(col[k], &c[k]));
    PetscCall(VecDestroy(&col[k]));
  }
  PetscCall(VecDestroy(&all));
  PetscFunctionReturn(0);
}

/* Run totals kept with the rows; the driver's own scalars follow them as attributes of the root group. */
static PetscErrorCode Totals(PDModel *m, PDRecord *rec, PetscViewer v, PetscBool write) {
  PetscInt *t[NTOTALS] = {&rec->steps, &rec->newton_its, &rec->ksp_its, &rec->max_events_per_its, &m->jacobian_assemblies};

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < NTOTALS; k++) {
    if (write)
      PetscCall(PetscViewerHDF5WriteAttribute(v, "/", total_names[k], PETSC_INT, t[k]));
    else
      PetscCall(PetscViewerHDF5ReadAttribute(v, "/", total_names[k], PETSC_INT, NULL, t[k]));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode PDCheckpointWrite(PDModel *m, PDRecord *rec, PetscInt nvec, const Vec vec[], const char *const vec_name[], PetscInt nreal,
                                 const char *const real_name[], const PetscReal real[], const PetscReal *kappa_prev) {
  MPI_Comm       comm = m->lat->comm;
  PetscViewer    v;
  char           path[PETSC_MAX_PATH_LEN];
  PetscReal      fp[NFINGERPRINT];
  const PetscInt mark = 1, nrows = rec->nrows;
  PetscLogDouble t0, t1;

  PetscFunctionBeginUser;
  PetscCall(PetscTime(&t0));
  PetscCall(Fingerprint(m, fp));
  PetscCall(PetscSNPrintf(path, sizeof path, "%s/checkpoint.h5.tmp", rec->dir));
  PetscCall(PetscViewerHDF5Open(comm, path, FILE_MODE_WRITE, &v));
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "pdimplicit_checkpoint", PETSC_INT, &mark));
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "scene", PETSC_STRING, m->scene->name));
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "arclength_type", PETSC_STRING, PDArcTypes[m->scene->arc_type]));
  for (PetscInt k = 0; k < NFINGERPRINT; k++) PetscCall(PetscViewerHDF5WriteAttribute(v, "/", fingerprint_names[k], PETSC_REAL, &fp[k]));
  PetscCall(PetscViewerHDF5WriteAttribute(v, "/", "curve_rows", PETSC_INT, &nrows));
  PetscCall(Totals(m, rec, v, PETSC_TRUE));
  for (PetscInt k = 0; k < nreal; k++) PetscCall(PetscViewerHDF5WriteAttribute(v, "/", real_name[k], PETSC_REAL, &real[k]));
  PetscCall(WriteRows(comm, rec, v));
  if (m->lat->nbarnodes) PetscCall(WriteRowColumn(comm, rec, COLUMN_SLIP, v));
  if (PDSceneHasCrushingStrain(m->scene)) PetscCall(WriteRowColumn(comm, rec, COLUMN_STRAIN_MIN, v));
  if (rec->section) PetscCall(WriteRowColumn(comm, rec, COLUMN_SECTION, v));
  for (PDBondField f = PD_BOND_KAPPA; f <= PD_BOND_STEEL_DISSIPATED; f++)
    if (PDBondFieldKept(m, kappa_prev, f)) PetscCall(PDBondFieldWrite(m, kappa_prev, f, v));
  for (PetscInt k = 0; k < nvec; k++) {
    PetscCall(PetscObjectSetName((PetscObject)vec[k], vec_name[k]));
    PetscCall(VecView(vec[k], v));
  }
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(PDFileCommit(comm, rec->dir, "checkpoint.h5"));
  PetscCall(PetscTime(&t1));
  rec->t_output += t1 - t0;
  PetscFunctionReturn(0);
}

/* Reads what PDCheckpointWrite wrote (the file was validated before the run started). The rows' wall
   clock goes on from the last one. */
PetscErrorCode PDCheckpointRead(PDModel *m, PDRecord *rec, const char *path, PetscInt nvec, Vec vec[], const char *const vec_name[],
                                PetscInt nreal, const char *const real_name[], PetscReal real[], PetscReal *kappa_prev) {
  MPI_Comm        comm = m->lat->comm;
  PetscViewer     v;
  PetscInt        nrows;
  const PetscReal zero = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5Open(comm, path, FILE_MODE_READ, &v));
  PetscCall(PetscViewerHDF5ReadAttribute(v, "/", "curve_rows", PETSC_INT, NULL, &nrows));
  PetscCall(Totals(m, rec, v, PETSC_FALSE));
  /* a scalar the file lacks (written before the driver kept it) reads as 0 */
  for (PetscInt k = 0; k < nreal; k++) PetscCall(PetscViewerHDF5ReadAttribute(v, "/", real_name[k], PETSC_REAL, &zero, &real[k]));
  PetscCall(ReadRows(comm, rec, nrows, m->lat->nbarnodes > 0 ? PETSC_TRUE : PETSC_FALSE, v));
  if (m->softening) PetscCall(ReadHistory(m, kappa_prev, v));
  if (m->scene->nbars) {
    for (PDBondField f = PD_BOND_STEEL_PLASTIC; f <= PD_BOND_STEEL_DISSIPATED; f++) PetscCall(PDBondFieldRead(m, NULL, f, v));
    PetscCall(PDModelCountDamage(m));
  }
  for (PetscInt k = 0; k < nvec; k++) {
    PetscCall(PetscObjectSetName((PetscObject)vec[k], vec_name[k]));
    PetscCall(VecLoad(vec[k], v));
  }
  PetscCall(PetscViewerDestroy(&v));
  if (rec->nrows) rec->t_start -= rec->rows[rec->nrows - 1].wall;
  PetscCall(PetscStrncpy(rec->restart_from, path, sizeof rec->restart_from));
  rec->restart_step = rec->steps;
  PetscFunctionReturn(0);
}
