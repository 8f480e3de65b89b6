/* The schema of every -pd_ option: name, type, unit, default, range, when the option applies, help.
   One table (schema_table.c) drives the option readers (option_values.c), the checks for unknown and
   unused options (option_check.c), -help and the README's option table (option_doc.c). */
#pragma once
#include "pd_scene.h"

/* Indexed options: -pd_materialK_*, -pd_notchK_*, -pd_regionK_*, -pd_voidK_*, -pd_barK_*, -pd_nofailK_*, -pd_plateK_*. */
typedef enum {
  PD_FAMILY_NONE,
  PD_FAMILY_MATERIAL,
  PD_FAMILY_NOTCH,
  PD_FAMILY_REGION,
  PD_FAMILY_VOID,
  PD_FAMILY_BAR,
  PD_FAMILY_NOFAIL,
  PD_FAMILY_PLATE
} PDOptionFamily;

/* When an option applies; an option given where it does not is an input error. */
typedef enum {
  PD_WHEN_ALWAYS,
  PD_WHEN_2D,
  PD_WHEN_FINITE,
  PD_WHEN_BILINEAR,
  PD_WHEN_ZACCARIOTTO,
  PD_WHEN_TRILINEAR,
  PD_WHEN_NONLINEAR,
  PD_WHEN_CYLINDER,
  PD_WHEN_DISPLACEMENT,
  PD_WHEN_FORCE,
  PD_WHEN_IMPLICIT,
  PD_WHEN_CONTROL,  /* implicit under load or displacement control (not path following) */
  PD_WHEN_FALLBACK, /* the same, on a scene with damage */
  PD_WHEN_EXPLICIT,
  PD_WHEN_PATH,     /* path following: chosen, or plain control's fallback on a scene with damage */
  PD_WHEN_PATH_RUN, /* path following chosen (-pd_control arclength or auto) */
  PD_WHEN_PATH_LINEAR,
  PD_WHEN_AUGMENTED,
  PD_WHEN_UNLOAD,
  PD_WHEN_FAILURE_SEARCH,
  PD_WHEN_SLIP /* a bar with bond slip */
} PDOptionWhen;

typedef struct {
  const char        *name; /* the option; in a family what follows the index ("_E") */
  PDOptionFamily     family;
  PetscBool          base; /* material family: also the base material's option, -pd<name> */
  PDOptionType       type;
  const char        *unit;     /* SI unit, or NULL */
  const char        *def;      /* literal default, read like a given value; NULL: def_note says */
  const char        *def_note; /* a default the scene works out, in words; or "required" */
  PetscBool          later;    /* that default is known only once the model is built */
  const char        *range;    /* interval the value must lie in, e.g. "(0, inf)", "[0, 1)"; NULL: any */
  const char *const *values;   /* names of an enum, NULL-terminated */
  PDOptionWhen       when;
  const char        *help;
} PDOptionSpec;

extern const PDOptionSpec PDOptionSchema[];
extern const PetscInt     PDOptionSchemaSize;

typedef enum { PD_MATCH_NONE, PD_MATCH_OK, PD_MATCH_INDEX } PDOptionMatch;

/* The entry an option name (leading '-' optional, any case, as PETSc compares names) belongs to, and
   its family index (0 for the base material and for options outside families). PD_MATCH_INDEX: the
   name fits a family entry but the index lies outside the family's range. */
PDOptionMatch PDSchemaMatch(const char *name, const PDOptionSpec **spec, PetscInt *index);
/* Whether the scene read so far uses the option; a family member is used only once it exists. */
PetscBool PDSchemaActive(const PDOptionSpec *, PetscInt index, const PDScene *);
/* Members of a family the scene defines (1 for options outside families). */
PetscInt    PDSchemaFamilyCount(PDOptionFamily, const PDScene *);
const char *PDSchemaWhenText(PDOptionWhen);
/* The family's prefix ("-pd_region"), the words for one member and several, and the indices allowed. */
void PDSchemaFamily(PDOptionFamily, const char **prefix, const char **noun, const char **nouns, PetscInt *first, PetscInt *last);
/* The option's name for one index ("-pd_region2_box", "-pd_E"), and as a pattern ("-pd_regionK_box"). */
void PDSchemaInstance(const PDOptionSpec *, PetscInt index, char *buf, size_t len);
void PDSchemaPattern(const PDOptionSpec *, char *buf, size_t len);
/* Checks value against the entry's range; the message names the option. */
PetscErrorCode PDSchemaCheckRange(const PDOptionSpec *, const char *opt, PetscReal value);
/* Input errors in the options as given (before the scene is read): names outside the schema, family
   indices out of range. After the scene is read: options it does not use, family members after a gap. */
PetscErrorCode PDOptionsCheckNames(void);
PetscErrorCode PDOptionsCheckUnused(const PDScene *);
