/* The parts of reading a scene, in the order PDSceneCreateFromOptions calls them (each may depend on
   what the earlier ones read). Used only inside PetscOptionsBegin/End. */
#pragma once
#include "pd_scene.h"

/* Materials, notches, node regions, voids and no-fail zones (-pd_materialK_*, -pd_notchK_*, -pd_regionK_*,
   -pd_voidK_*, -pd_nofailK_*). */
PetscErrorCode PDSceneReadParts(PetscOptionItems *PetscOptionsObject, PDScene *);
/* Steel bars (-pd_barK_*). */
PetscErrorCode PDSceneReadBars(PetscOptionItems *PetscOptionsObject, PDScene *);
/* Control, path following, the explicit path, the failure search, the damage limiter, checkpoints. */
PetscErrorCode PDSceneReadSolution(PetscOptionItems *PetscOptionsObject, MPI_Comm, PDScene *);
