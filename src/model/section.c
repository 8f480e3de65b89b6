/* A section cut (-pd_section_x): the forces that the bonds crossing a plane normal to x carry, split into
   the bars' and the concrete's in tension and in compression. The plane lies halfway between two node
   columns, so each crossing bond is cut once; by equilibrium of the part before the plane their sum is the
   reaction on that part, and their moment the bending moment there (docs/reinforcement.md, Section forces). */
#include "kernel.h"

PetscErrorCode PDModelSection(PDModel *m, Vec u, PetscReal out[PD_SECTION_N]) {
  const PetscScalar *ul;
  Vec                loc;
  PetscReal          mine[PD_SECTION_N];

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < PD_SECTION_N; k++) out[k] = 0;
  if (!m->scene->has_section) PetscFunctionReturn(0);
  PetscCall(PDModelScatterToLocal(m, u, &ul, &loc));
  PDModelSectionLocal(m, ul, mine);
  PetscCall(PDModelRestoreLocal(m, &ul, &loc));
  PetscCall(MPIU_Allreduce(mine, out, PD_SECTION_N, MPIU_REAL, MPIU_SUM, m->lat->comm));
  /* moments to the heights at which the resultants act (none where nothing acts) */
  out[PD_SECTION_TENSION_Y]     = out[PD_SECTION_TENSION] != 0 ? out[PD_SECTION_TENSION_Y] / out[PD_SECTION_TENSION] : 0;
  out[PD_SECTION_COMPRESSION_Y] = out[PD_SECTION_COMPRESSION] != 0 ? out[PD_SECTION_COMPRESSION_Y] / out[PD_SECTION_COMPRESSION] : 0;
  PetscFunctionReturn(0);
}
