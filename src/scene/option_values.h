/* Typed readers of -pd_ options, used only inside PetscOptionsBegin/End. Each takes the option's
   default, help and range from the schema (schema.h), leaves the value at that default where the
   option does not apply to the scene read so far, registers the option for -help and, on a bad value,
   stops with a message that names the option and the value. */
#pragma once
#include <petscsys.h>
#include "pd_scene.h"

PetscErrorCode PDOptionReal(PetscOptionItems *PetscOptionsObject, PDScene *, const char *opt, PetscReal *value, PetscBool *set);
PetscErrorCode PDOptionInt(PetscOptionItems *PetscOptionsObject, PDScene *, const char *opt, PetscInt *value, PetscBool *set);
PetscErrorCode PDOptionBool(PetscOptionItems *PetscOptionsObject, PDScene *, const char *opt, PetscBool *value, PetscBool *set);
/* *value: the index among the schema's names. */
PetscErrorCode PDOptionEnum(PetscOptionItems *PetscOptionsObject, PDScene *, const char *opt, PetscInt *value, PetscBool *set);
/* Reads a comma-separated list of integers into values[cap]; *n on input is the count of defaults values
   holds, on output the count read. */
PetscErrorCode PDOptionIntArray(PetscOptionItems *PetscOptionsObject, PDScene *, const char *opt, PetscInt *values, PetscInt cap,
                                PetscInt *n, PetscBool *set);
/* Reads a comma-separated list of reals; *n on input is the capacity, on output the count read. */
PetscErrorCode PDOptionRealArray(PetscOptionItems *PetscOptionsObject, PDScene *, const char *opt, PetscReal *values, PetscInt *n,
                                 PetscBool *set);
PetscErrorCode PDOptionString(PetscOptionItems *PetscOptionsObject, PDScene *, const char *opt, char *value, size_t len, PetscBool *set);
