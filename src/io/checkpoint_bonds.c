/* The per-bond quantities of a checkpoint (bond history, crushing's rises, the bar segments' state), each a
   dataset over the incidence entries of the owned nodes in global node order, so that its layout depends
   on the lattice only and a file written on one rank count reads on any other.

   Each is written and read in pieces of PIECE entries by independent hyperslab transfers into a
   contiguous dataset, not through a Vec and VecView. A Vec of the rank's entries costs 8 bytes per entry
   (16 per bond) at the moment of writing, and VecView makes the dataset one chunk, which parallel HDF5
   stages whole on every rank that writes part of it: on two ranks a checkpoint written while the solver's
   preconditioner was built set the run's peak memory (docs/arclength.md, "Long runs in legs"). Files written by VecView
   (one chunk) read the same way. */
#include "checkpoint_bonds.h"
#include "kernel.h"
#include <petscviewerhdf5.h>

#define PIECE 65536

_Static_assert(sizeof(PetscReal) == sizeof(double), "bond datasets are transferred as doubles");

#define PDCallH5(call)                                                                                                                     \
  do {                                                                                                                                     \
    if ((call) < 0) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "HDF5 call failed: %s", #call);                                                \
  } while (0)

const char *const PDBondFieldNames[] = {"kappa",          "level",           "kappa_previous", "threshold_rise", "steel_plastic_stretch",
                                        "steel_ruptured", "steel_dissipated"};

/* Whether the model has the quantity: a history where bonds soften, the previous one where the driver
   keeps it (IMPL-EX), rises under crushing, the steel state where there are bars. */
PetscBool PDBondFieldKept(const PDModel *m, const PetscReal *kappa_prev, PDBondField f) {
  if (f >= PD_BOND_STEEL_PLASTIC) return m->scene->nbars > 0 ? PETSC_TRUE : PETSC_FALSE;
  if (!m->softening) return PETSC_FALSE;
  if (f == PD_BOND_KAPPA_PREVIOUS) return kappa_prev ? PETSC_TRUE : PETSC_FALSE;
  if (f == PD_BOND_RISE) return m->shift ? PETSC_TRUE : PETSC_FALSE;
  return PETSC_TRUE;
}

static PetscReal Value(const PDModel *m, const PetscReal *kappa_prev, PDBondField f, PetscInt e) {
  const PetscInt sg = f >= PD_BOND_STEEL_PLASTIC ? m->bonds->seg[e] : -1;
  switch (f) {
  case PD_BOND_KAPPA:
    return m->kappa[e];
  case PD_BOND_LEVEL:
    return m->level_n[e];
  case PD_BOND_KAPPA_PREVIOUS:
    return kappa_prev[e];
  case PD_BOND_RISE:
    return m->shift[e];
  case PD_BOND_STEEL_PLASTIC:
    return sg >= 0 ? m->sp_n[sg] : 0;
  case PD_BOND_STEEL_RUPTURED:
    return sg >= 0 && m->ruptured_n[sg] ? 1 : 0;
  default:
    return sg >= 0 ? m->dissipated_n[sg] : 0;
  }
}

/* This rank's entries: where they start in the dataset, how many, and the dataset's length. */
static PetscErrorCode Entries(const PDModel *m, PetscInt *start, PetscInt *n, PetscInt *total) {
  PetscLayout map;

  PetscFunctionBeginUser;
  *n = m->bonds->inc_start[m->lat->nowned];
  PetscCall(PetscLayoutCreate(m->lat->comm, &map));
  PetscCall(PetscLayoutSetLocalSize(map, *n));
  PetscCall(PetscLayoutSetUp(map));
  PetscCall(PetscLayoutGetRange(map, start, NULL));
  PetscCall(PetscLayoutGetSize(map, total));
  PetscCall(PetscLayoutDestroy(&map));
  PetscFunctionReturn(0);
}

/* count entries from offset, from or to buf */
static PetscErrorCode Transfer(hid_t dset, PetscBool write, PetscInt offset, PetscInt count, PetscReal *buf) {
  hsize_t off = (hsize_t)offset, cnt = (hsize_t)count;
  hid_t   fs, ms;

  PetscFunctionBeginUser;
  PDCallH5(fs = H5Dget_space(dset));
  PDCallH5(ms = H5Screate_simple(1, &cnt, NULL));
  PDCallH5(H5Sselect_hyperslab(fs, H5S_SELECT_SET, &off, NULL, &cnt, NULL));
  if (write)
    PDCallH5(H5Dwrite(dset, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, buf));
  else
    PDCallH5(H5Dread(dset, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, buf));
  PDCallH5(H5Sclose(ms));
  PDCallH5(H5Sclose(fs));
  PetscFunctionReturn(0);
}

PetscErrorCode PDBondFieldWrite(const PDModel *m, const PetscReal *kappa_prev, PDBondField f, PetscViewer v) {
  const PetscInt *inc = m->bonds->inc_bond;
  PetscInt        start, n, total;
  hid_t           file, group, space, dset;
  hsize_t         dim;
  PetscReal      *buf;

  PetscFunctionBeginUser;
  PetscCall(Entries(m, &start, &n, &total));
  dim = (hsize_t)total;
  PetscCall(PetscViewerHDF5OpenGroup(v, NULL, &file, &group));
  PDCallH5(space = H5Screate_simple(1, &dim, NULL));
  PDCallH5(dset = H5Dcreate2(group, PDBondFieldNames[f], H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  PetscCall(PetscMalloc1(PIECE, &buf));
  for (PetscInt p0 = 0; p0 < n; p0 += PIECE) {
    const PetscInt c = PetscMin(PIECE, n - p0);
    for (PetscInt i = 0; i < c; i++) buf[i] = Value(m, kappa_prev, f, inc[p0 + i]);
    PetscCall(Transfer(dset, PETSC_TRUE, start + p0, c, buf));
  }
  PetscCall(PetscFree(buf));
  PDCallH5(H5Dclose(dset));
  PDCallH5(H5Sclose(space));
  PDCallH5(H5Gclose(group));
  PetscFunctionReturn(0);
}

typedef PetscErrorCode (*PieceUse)(const PDModel *, PDBondField, PetscInt p0, PetscInt n, const PetscReal *val, void *ctx);

/* Reads this rank's entries of the dataset piece by piece and hands each piece to use. *sized is false
   (on every rank) where the dataset is missing or its length is not the model's. */
static PetscErrorCode ForPieces(const PDModel *m, PDBondField f, PetscViewer v, PieceUse use, void *ctx, PetscBool *sized) {
  PetscInt  start, n, total;
  hid_t     file, group, dset, space;
  hsize_t   dim = 0;
  PetscBool has;

  PetscFunctionBeginUser;
  PetscCall(Entries(m, &start, &n, &total));
  PetscCall(PetscViewerHDF5HasDataset(v, PDBondFieldNames[f], &has));
  *sized = PETSC_FALSE;
  if (!has) PetscFunctionReturn(0);
  PetscCall(PetscViewerHDF5OpenGroup(v, NULL, &file, &group));
  PDCallH5(dset = H5Dopen2(group, PDBondFieldNames[f], H5P_DEFAULT));
  PDCallH5(space = H5Dget_space(dset));
  if (H5Sget_simple_extent_ndims(space) == 1) PDCallH5(H5Sget_simple_extent_dims(space, &dim, NULL));
  PDCallH5(H5Sclose(space));
  *sized = dim == (hsize_t)total ? PETSC_TRUE : PETSC_FALSE; /* the same on every rank: one file */
  if (*sized) {
    PetscReal *buf;
    PetscCall(PetscMalloc1(PIECE, &buf));
    for (PetscInt p0 = 0; p0 < n; p0 += PIECE) {
      const PetscInt c = PetscMin(PIECE, n - p0);
      PetscCall(Transfer(dset, PETSC_FALSE, start + p0, c, buf));
      PetscCall(use(m, f, p0, c, buf, ctx));
    }
    PetscCall(PetscFree(buf));
  }
  PDCallH5(H5Dclose(dset));
  PDCallH5(H5Gclose(group));
  PetscFunctionReturn(0);
}

/* Every value finite and inside the quantity's range; levels whole numbers. */
static PetscErrorCode CheckPiece(const PDModel *m, PDBondField f, PetscInt p0, PetscInt n, const PetscReal *val, void *ctx) {
  PetscBool *ok = (PetscBool *)ctx;
  PetscReal  lo = 0, hi = PD_KAPPA_MAX;

  PetscFunctionBeginUser;
  (void)m;
  (void)p0;
  if (f == PD_BOND_LEVEL) hi = 255;
  if (f == PD_BOND_STEEL_PLASTIC || f == PD_BOND_STEEL_RUPTURED) lo = -PD_KAPPA_MAX;
  if (f == PD_BOND_STEEL_RUPTURED) hi = 1;
  for (PetscInt i = 0; i < n; i++)
    if (PetscIsInfOrNanReal(val[i]) || val[i] < lo || val[i] > hi || (f == PD_BOND_LEVEL && val[i] != PetscFloorReal(val[i])))
      *ok = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* Present, of the model's length, and every value in range (collective). */
PetscErrorCode PDBondFieldCheck(const PDModel *m, PDBondField f, PetscViewer v, PetscBool *ok) {
  PetscBool mine = PETSC_TRUE, sized;

  PetscFunctionBeginUser;
  PetscCall(ForPieces(m, f, v, CheckPiece, &mine, &sized));
  PetscCall(MPIU_Allreduce(&mine, ok, 1, MPIU_BOOL, MPI_LAND, m->lat->comm));
  if (!sized) *ok = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* Every bond has an owned end, so every bond is read; a bond with both ends owned is read twice, equal
   (a rise is set, not added). The steel state goes to the bond's segment. */
static PetscErrorCode ReadPiece(const PDModel *mc, PDBondField f, PetscInt p0, PetscInt n, const PetscReal *val, void *ctx) {
  PDModel        *m          = (PDModel *)mc; /* the model ReadBondField was given */
  PetscReal      *kappa_prev = (PetscReal *)ctx;
  const PDBonds  *bd         = m->bonds;
  const PetscInt *inc        = bd->inc_bond + p0;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < n; i++) {
    const PetscInt  e = inc[i], sg = f >= PD_BOND_STEEL_PLASTIC ? bd->seg[e] : -1;
    const PetscReal r = val[i];
    if (f == PD_BOND_KAPPA)
      m->kappa[e] = r;
    else if (f == PD_BOND_LEVEL) {
      const PDLaw    *law = &m->law[bd->material[e]];
      const PDLawBond t   = PDModelBondThresholds(m, e, law);
      /* at least the level its history has passed (kappa is read first): a leg may run with other
         -pd_limiter_sublevels */
      m->level[e] = m->level_n[e] = (unsigned char)PetscMin(PetscMax((PetscInt)r, PDLawLevelOf(law, &t, m->kappa[e])), law->sublevels + 1);
    } else if (f == PD_BOND_KAPPA_PREVIOUS)
      kappa_prev[e] = r;
    else if (f == PD_BOND_RISE)
      m->shift[e] = r;
    else if (sg < 0)
      continue;
    else if (f == PD_BOND_STEEL_PLASTIC)
      m->sp_n[sg] = r;
    else if (f == PD_BOND_STEEL_RUPTURED)
      m->ruptured_n[sg] = r > 0.5 ? PETSC_TRUE : PETSC_FALSE;
    else
      m->dissipated_n[sg] = r;
  }
  PetscFunctionReturn(0);
}

/* kappa_prev: where f is PD_BOND_KAPPA_PREVIOUS, the driver's array it goes to. The file was checked
   (PDBondFieldCheck) before the run. */
PetscErrorCode PDBondFieldRead(PDModel *m, PetscReal *kappa_prev, PDBondField f, PetscViewer v) {
  PetscBool sized;

  PetscFunctionBeginUser;
  PetscCall(ForPieces(m, f, v, ReadPiece, kappa_prev, &sized));
  PetscCheck(sized, m->lat->comm, PETSC_ERR_FILE_UNEXPECTED, "checkpoint: %s is missing or of another length", PDBondFieldNames[f]);
  PetscFunctionReturn(0);
}
