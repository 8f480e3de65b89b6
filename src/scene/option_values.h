/* Typed option readers that register the option for -help and, on a bad value, stop with a message
   that names the option and the value. Used only inside PetscOptionsBegin/End. */
#pragma once
#include <petscsys.h>

PetscErrorCode PDOptionReal(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, PetscReal *value, PetscBool *set);
/* A real in [0, 1): scatters, fractions of the peak, relative tolerances. */
PetscErrorCode PDOptionFraction(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, PetscReal *value);
PetscErrorCode PDOptionInt(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, PetscInt *value, PetscBool *set);
PetscErrorCode PDOptionBool(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, PetscBool *value, PetscBool *set);
PetscErrorCode PDOptionEnum(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, const char *const *names,
                            PetscInt nnames, PetscInt *value, PetscBool *set);
/* Reads a comma-separated list of reals; *n on input is the capacity, on output the count read. */
PetscErrorCode PDOptionRealArray(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, PetscReal *values, PetscInt *n,
                                 PetscBool *set);
PetscErrorCode PDOptionString(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, char *value, size_t len,
                              PetscBool *set);
