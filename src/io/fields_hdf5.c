/* fields.h5 through PETSc's HDF5 viewer (node positions once, displacement, damage and on scenes with bars their
   stress, plastic strain and slip per chosen step)
   and fields.xmf, the XDMF index that lets ParaView open them as a point cloud over time. */
#include "pd_io.h"
#include "pd_log.h"
#include <petscviewerhdf5.h>

static PetscErrorCode CreateNodeVec(const PDModel *m, PetscInt bs, Vec *v) {
  PetscFunctionBeginUser;
  PetscCall(VecCreate(m->lat->comm, v));
  PetscCall(VecSetSizes(*v, bs * m->lat->nowned, PETSC_DECIDE));
  PetscCall(VecSetBlockSize(*v, bs));
  PetscCall(VecSetFromOptions(*v));
  PetscFunctionReturn(0);
}

/* The datasets of each step besides displacement (a vector) and damage: those of the bars on scenes with bars
   (PDModelBarFields), slip where a bar has nodes of its own. */
static PetscInt StepScalars(const PDModel *m, const char *names[4]) {
  PetscInt n = 0;
  names[n++] = "damage";
  if (m->scene->nbars) {
    names[n++] = "steel_stress";
    names[n++] = "steel_plastic_strain";
  }
  if (m->lat->nbarnodes) names[n++] = "slip";
  return n;
}

static PetscErrorCode WriteBarFields(PDModel *m, PDRecord *rec, PetscInt step, Vec u) {
  const char *names[4];
  Vec         v[3] = {NULL, NULL, NULL};
  char        name[64];
  PetscInt    n = StepScalars(m, names) - 1;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < n; k++) PetscCall(CreateNodeVec(m, 1, &v[k]));
  PetscCall(PDModelBarFields(m, u, v[0], v[1], v[2]));
  for (PetscInt k = 0; k < n; k++) {
    PetscCall(PetscSNPrintf(name, sizeof name, "%s_%06" PetscInt_FMT, names[k + 1], step));
    PetscCall(PetscObjectSetName((PetscObject)v[k], name));
    PetscCall(VecView(v[k], rec->h5));
    PetscCall(VecDestroy(&v[k]));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode PDFieldsWrite(PDModel *m, PDRecord *rec, PetscInt step, Vec u) {
  const PDLattice   *lat = m->lat;
  Vec                v3, d;
  PetscScalar       *a;
  const PetscScalar *uu;
  char               name[64];
  PetscLogDouble     t0, t1;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PD_LOG.fields, 0, 0, 0, 0));
  PetscCall(PetscTime(&t0));
  PetscCall(CreateNodeVec(m, 3, &v3));
  if (!rec->h5) {
    char path[PETSC_MAX_PATH_LEN];
    PetscCall(PetscSNPrintf(path, sizeof path, "%s/fields.h5.tmp", rec->dir));
    PetscCall(PetscViewerHDF5Open(lat->comm, path, FILE_MODE_WRITE, &rec->h5));
    PetscCall(PetscViewerHDF5PushGroup(rec->h5, "/fields"));
    PetscCall(VecGetArray(v3, &a));
    for (PetscInt i = 0; i < 3 * lat->nowned; i++) a[i] = lat->x[i];
    PetscCall(VecRestoreArray(v3, &a));
    PetscCall(PetscObjectSetName((PetscObject)v3, "coordinates"));
    PetscCall(VecView(v3, rec->h5));
  }
  /* displacement padded to three components so 2D and 3D files read alike */
  PetscCall(VecGetArray(v3, &a));
  PetscCall(VecGetArrayRead(u, &uu));
  for (PetscInt i = 0; i < lat->nowned; i++)
    for (PetscInt c = 0; c < 3; c++) a[3 * i + c] = c < m->bs ? uu[m->bs * i + c] : 0;
  PetscCall(VecRestoreArrayRead(u, &uu));
  PetscCall(VecRestoreArray(v3, &a));
  PetscCall(PetscSNPrintf(name, sizeof name, "displacement_%06" PetscInt_FMT, step));
  PetscCall(PetscObjectSetName((PetscObject)v3, name));
  PetscCall(VecView(v3, rec->h5));
  PetscCall(CreateNodeVec(m, 1, &d));
  PetscCall(PDModelNodalDamage(m, d));
  PetscCall(PetscSNPrintf(name, sizeof name, "damage_%06" PetscInt_FMT, step));
  PetscCall(PetscObjectSetName((PetscObject)d, name));
  PetscCall(VecView(d, rec->h5));
  PetscCall(VecDestroy(&d));
  PetscCall(VecDestroy(&v3));
  if (m->scene->nbars) PetscCall(WriteBarFields(m, rec, step, u));
  PetscCall(PetscRealloc(sizeof(PetscInt) * (rec->nfield_steps + 1), &rec->field_steps));
  rec->field_steps[rec->nfield_steps++] = step;
  PetscCall(PetscTime(&t1));
  rec->t_output += t1 - t0;
  PetscCall(PetscLogEventEnd(PD_LOG.fields, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode PDFieldsFinish(PDModel *m, PDRecord *rec) {
  MPI_Comm    comm = m->lat->comm;
  FILE       *fp;
  char        path[PETSC_MAX_PATH_LEN], *name;
  PetscInt    N = m->lat->nglobal;
  const char *scalars[4];
  PetscInt    nscalar = StepScalars(m, scalars);

  PetscFunctionBeginUser;
  if (!rec->h5) PetscFunctionReturn(0); /* no step converged: no fields */
  PetscCall(PetscViewerHDF5PopGroup(rec->h5));
  PetscCall(PetscViewerDestroy(&rec->h5));
  PetscCall(PetscSNPrintf(path, sizeof path, "%s/fields.xmf.tmp", rec->dir));
  PetscCall(PetscFOpen(comm, path, "w", &fp));
  PetscCall(PetscFPrintf(comm, fp, "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"));
  PetscCall(PDEscapeXML(m->scene->name, &name));
  PetscCall(PetscFPrintf(comm, fp, "  <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n", name));
  PetscCall(PetscFree(name));
  for (PetscInt k = 0; k < rec->nfield_steps; k++) {
    const PetscInt s = rec->field_steps[k];
    PetscCall(PetscFPrintf(
        comm, fp, "   <Grid Name=\"step_%06" PetscInt_FMT "\" GridType=\"Uniform\">\n    <Time Value=\"%" PetscInt_FMT "\"/>\n", s, s));
    PetscCall(PetscFPrintf(
        comm, fp, "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%" PetscInt_FMT "\" NodesPerElement=\"1\"/>\n", N));
    PetscCall(PetscFPrintf(comm, fp,
                           "    <Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"%" PetscInt_FMT
                           " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">fields.h5:/fields/coordinates</DataItem></Geometry>\n",
                           N));
    PetscCall(
        PetscFPrintf(comm, fp,
                     "    <Attribute Name=\"displacement\" AttributeType=\"Vector\" Center=\"Node\"><DataItem Dimensions=\"%" PetscInt_FMT
                     " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">fields.h5:/fields/displacement_%06" PetscInt_FMT
                     "</DataItem></Attribute>\n",
                     N, s));
    for (PetscInt a = 0; a < nscalar; a++)
      PetscCall(PetscFPrintf(comm, fp,
                             "    <Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Node\"><DataItem Dimensions=\"%" PetscInt_FMT
                             "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">fields.h5:/fields/%s_%06" PetscInt_FMT
                             "</DataItem></Attribute>\n",
                             scalars[a], N, scalars[a], s));
    PetscCall(PetscFPrintf(comm, fp, "   </Grid>\n"));
  }
  PetscCall(PetscFPrintf(comm, fp, "  </Grid>\n </Domain>\n</Xdmf>\n"));
  PetscCall(PetscFClose(comm, fp));
  PetscCall(PDFileCommit(comm, rec->dir, "fields.h5"));
  PetscCall(PDFileCommit(comm, rec->dir, "fields.xmf"));
  PetscFunctionReturn(0);
}
