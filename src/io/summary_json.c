/* summary.json: what ran, what it cost and how it ended. */
#include "pd_io.h"
#include <sys/resource.h>

static PetscErrorCode PeakMemory(MPI_Comm comm, PetscReal *total)
{
  struct rusage ru;
  PetscReal     mine;

  PetscFunctionBeginUser;
  getrusage(RUSAGE_SELF, &ru);
  mine = (PetscReal)ru.ru_maxrss * 1024.0; /* kilobytes on Linux */
  PetscCall(MPIU_Allreduce(&mine, total, 1, MPIU_REAL, MPI_SUM, comm));
  PetscFunctionReturn(0);
}

/* Physical effects the scene calls for; discretisation corrections are listed apart. */
static PetscErrorCode WriteEffects(MPI_Comm comm, FILE *fp, const PDScene *sc)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFPrintf(comm, fp, "  \"effects\": [\"elasticity\"%s],\n", sc->kinematics == PD_KINEMATICS_FINITE ? ", \"geometric_nonlinearity\"" : ""));
  PetscCall(PetscFPrintf(comm, fp, "  \"corrections\": [%s%s%s],\n", sc->partial_volume ? "\"partial_volume\"" : "",
                         sc->partial_volume && sc->surface_correction ? ", " : "", sc->surface_correction ? "\"surface_correction\"" : ""));
  PetscFunctionReturn(0);
}

static void JsonReal(char *buf, size_t len, PetscReal v)
{
  if (PetscIsInfOrNanReal(v)) PetscSNPrintf(buf, len, "null");
  else PetscSNPrintf(buf, len, "%.10g", (double)v);
}

PetscErrorCode PDSummaryWrite(MPI_Comm comm, const PDModel *m, const PDRecord *rec)
{
  const PDScene *sc = m->scene;
  FILE          *fp;
  char           path[PETSC_MAX_PATH_LEN], peak[32], dpeak[32], fin[32];
  PetscMPIInt    size;
  PetscReal      pk = PETSC_MIN_REAL, dpk = PD_NAN, last = PD_NAN, mem, wall;
  PetscLogDouble now;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  for (PetscInt k = 0; k < rec->nrows; k++)
    if (rec->rows[k].load > pk) {
      pk  = rec->rows[k].load;
      dpk = rec->rows[k].disp;
    }
  if (!rec->nrows) pk = PD_NAN;
  else last = rec->rows[rec->nrows - 1].load;
  JsonReal(peak, sizeof peak, pk);
  JsonReal(dpeak, sizeof dpeak, dpk);
  JsonReal(fin, sizeof fin, last);
  PetscCall(PeakMemory(comm, &mem));
  PetscCall(PetscTime(&now));
  wall = now - rec->t_start;
  PetscCall(PetscSNPrintf(path, sizeof path, "%s/summary.json.tmp", rec->dir));
  PetscCall(PetscFOpen(comm, path, "w", &fp));
  PetscCall(PetscFPrintf(comm, fp, "{\n  \"scene\": \"%s\",\n  \"mode\": \"implicit\",\n  \"ranks\": %d,\n", sc->name, size));
  PetscCall(PetscFPrintf(comm, fp, "  \"nodes\": %" PetscInt_FMT ",\n  \"bonds\": %" PetscInt_FMT ",\n  \"dofs\": %" PetscInt_FMT ",\n", m->lat->nglobal,
                         m->bonds->nbonds_global, m->lat->nglobal * m->bs));
  PetscCall(WriteEffects(comm, fp, sc));
  PetscCall(PetscFPrintf(comm, fp, "  \"dx_m\": %.10g,\n  \"horizon_ratio\": %.10g,\n  \"influence\": \"%s\",\n  \"kinematics\": \"%s\",\n", (double)sc->dx,
                         (double)sc->horizon_ratio, PDInfluences[sc->influence], PDKinematicsNames[sc->kinematics]));
  PetscCall(PetscFPrintf(comm, fp, "  \"bonds_cut_by_notches\": %" PetscInt_FMT ",\n  \"surface_correction_range\": [%.6g, %.6g],\n", m->bonds->ncut,
                         (double)m->bonds->lambda_min, (double)m->bonds->lambda_max));
  PetscCall(PetscFPrintf(comm, fp, "  \"constrained_dofs\": %" PetscInt_FMT ",\n  \"zero_stiffness_dofs_pinned\": %" PetscInt_FMT ",\n  \"isolated_nodes\": %" PetscInt_FMT ",\n", m->nconstrained, m->nzero_dofs, m->nisolated));
  PetscCall(PetscFPrintf(comm, fp, "  \"solver\": \"%s\",\n  \"linear\": %s,\n  \"jacobian_assemblies\": %" PetscInt_FMT ",\n", rec->solver,
                         m->linear ? "true" : "false", m->jacobian_assemblies));
  PetscCall(PetscFPrintf(comm, fp, "  \"steps\": %" PetscInt_FMT ",\n  \"newton_its\": %" PetscInt_FMT ",\n  \"ksp_its\": %" PetscInt_FMT ",\n", rec->steps,
                         rec->newton_its, rec->ksp_its));
  PetscCall(PetscFPrintf(comm, fp, "  \"peak_load_N\": %s,\n  \"disp_at_peak_m\": %s,\n  \"final_load_N\": %s,\n", peak, dpeak, fin));
  PetscCall(PetscFPrintf(comm, fp, "  \"wall_s\": %.4f,\n", (double)wall));
  PetscCall(PetscFPrintf(comm, fp, "  \"timings\": {\"setup\": %.4f, \"assembly\": %.4f, \"solve\": %.4f, \"output\": %.4f},\n", (double)rec->t_setup,
                         (double)m->t_assembly, (double)rec->t_solve, (double)rec->t_output));
  PetscCall(PetscFPrintf(comm, fp, "  \"memory\": {\"history_bytes\": %" PetscInt64_FMT ", \"matrix_nonzeros\": %.0f, \"peak_rss_bytes\": %.0f},\n", m->history_bytes,
                         (double)rec->matrix_nonzeros, (double)mem));
  PetscCall(PetscFPrintf(comm, fp, "  \"converged\": %s,\n  \"status\": \"%s\"\n}\n", rec->converged ? "true" : "false", rec->status));
  PetscCall(PetscFClose(comm, fp));
  PetscCall(PDFileCommit(comm, rec->dir, "summary.json"));
  PetscFunctionReturn(0);
}
