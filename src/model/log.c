/* Log stages and events (include/pd_log.h): one class, so that -log_view groups pdimplicit's events and
   -log_exclude can hide them. */
#include "pd_log.h"

PDLog PD_LOG;

PetscErrorCode PDLogRegister(void) {
  static PetscBool registered = PETSC_FALSE;
  PetscClassId     id;

  PetscFunctionBeginUser;
  if (registered) PetscFunctionReturn(0);
  registered = PETSC_TRUE;
  PetscCall(PetscClassIdRegister("pdimplicit", &id));
  PetscCall(PetscLogStageRegister("PD set-up", &PD_LOG.setup));
  PetscCall(PetscLogStageRegister("PD solve", &PD_LOG.solve));
  PetscCall(PetscLogStageRegister("PD output", &PD_LOG.output));
  PetscCall(PetscLogEventRegister("PDBondForce", id, &PD_LOG.force));
  PetscCall(PetscLogEventRegister("PDBondTangent", id, &PD_LOG.tangent));
  PetscCall(PetscLogEventRegister("PDAssembly", id, &PD_LOG.assembly));
  PetscCall(PetscLogEventRegister("PDTangentProduct", id, &PD_LOG.product));
  PetscCall(PetscLogEventRegister("PDLimiter", id, &PD_LOG.limiter));
  PetscCall(PetscLogEventRegister("PDHistory", id, &PD_LOG.history));
  PetscCall(PetscLogEventRegister("PDEnergy", id, &PD_LOG.energy));
  PetscCall(PetscLogEventRegister("PDFieldsWrite", id, &PD_LOG.fields));
  PetscFunctionReturn(0);
}
