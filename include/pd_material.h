/* Material: micromodulus and influence functions (THEORY.md Sec. 1), bond laws (Sec. 3). */
#pragma once
#include "pd_scene.h"

PetscReal PDMicromodulus(const PDScene *, PetscReal E);
PetscReal PDInfluenceValue(PDInfluence, PetscReal len, PetscReal horizon);
