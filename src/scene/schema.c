/* Looking options up in the schema: names and families, when an option applies, ranges. */
#include "schema.h"
#include <ctype.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

static const struct {
  const char *prefix, *noun, *nouns;
  PetscInt    first, last;
} Families[] = {
    [PD_FAMILY_NONE]     = {"", "", "", 0, 0},
    [PD_FAMILY_MATERIAL] = {"-pd_material", "material", "materials", 1, PD_MAX_MATERIALS - 1},
    [PD_FAMILY_NOTCH]    = {"-pd_notch", "notch", "notches", 0, PD_MAX_NOTCHES - 1},
    [PD_FAMILY_REGION]   = {"-pd_region", "region", "regions", 0, PD_MAX_REGIONS - 1},
    [PD_FAMILY_VOID]     = {"-pd_void", "void", "voids", 0, PD_MAX_VOIDS - 1},
    [PD_FAMILY_BAR]      = {"-pd_bar", "bar", "bars", 0, PD_MAX_BARS - 1},
    [PD_FAMILY_NOFAIL]   = {"-pd_nofail", "no-fail zone", "no-fail zones", 0, PD_MAX_NOFAIL - 1},
    [PD_FAMILY_PLATE]    = {"-pd_plate", "plate", "plates", 0, PD_MAX_MATERIALS - 2},
};

void PDSchemaFamily(PDOptionFamily f, const char **prefix, const char **noun, const char **nouns, PetscInt *first, PetscInt *last) {
  if (prefix) *prefix = Families[f].prefix;
  if (noun) *noun = Families[f].noun;
  if (nouns) *nouns = Families[f].nouns;
  if (first) *first = Families[f].first;
  if (last) *last = Families[f].last;
}

/* A family member's index: digits right after the prefix, without leading zeros; *rest after them. */
static PetscBool ParseIndex(const char *name, const char *prefix, PetscInt *k, const char **rest) {
  const size_t n = strlen(prefix);
  const char  *p = name + n;

  if (strncasecmp(name, prefix, n) || !isdigit((unsigned char)*p) || (p[0] == '0' && isdigit((unsigned char)p[1]))) return PETSC_FALSE;
  *k = 0;
  for (; isdigit((unsigned char)*p) && *k < 100000; p++) *k = 10 * *k + (*p - '0');
  *rest = p;
  return PETSC_TRUE;
}

PDOptionMatch PDSchemaMatch(const char *name, const PDOptionSpec **spec, PetscInt *index) {
  char          full[256];
  PDOptionMatch found = PD_MATCH_NONE;

  snprintf(full, sizeof full, "%s%s", name[0] == '-' ? "" : "-", name);
  *spec  = NULL;
  *index = 0;
  for (PetscInt i = 0; i < PDOptionSchemaSize; i++) {
    const PDOptionSpec *s = &PDOptionSchema[i];
    const char         *rest;
    PetscInt            k;
    if (s->family == PD_FAMILY_NONE) {
      const size_t n = strlen(s->name);
      if (s->type == PD_OPTION_PREFIX ? !strncasecmp(full, s->name, n) && full[n] : !strcasecmp(full, s->name)) {
        *spec = s;
        return PD_MATCH_OK;
      }
      continue;
    }
    if (s->base && !strncasecmp(full, "-pd", 3) && !strcasecmp(full + 3, s->name)) {
      *spec = s;
      return PD_MATCH_OK;
    }
    if (ParseIndex(full, Families[s->family].prefix, &k, &rest) && !strcasecmp(rest, s->name)) {
      *spec  = s;
      *index = k;
      if (k >= Families[s->family].first && k <= Families[s->family].last) return PD_MATCH_OK;
      found = PD_MATCH_INDEX;
    }
  }
  return found;
}

void PDSchemaInstance(const PDOptionSpec *s, PetscInt index, char *buf, size_t len) {
  if (s->family == PD_FAMILY_NONE)
    snprintf(buf, len, "%s", s->name);
  else if (s->family == PD_FAMILY_MATERIAL && index == 0)
    snprintf(buf, len, "-pd%s", s->name);
  else
    snprintf(buf, len, "%s%d%s", Families[s->family].prefix, (int)index, s->name);
}

void PDSchemaPattern(const PDOptionSpec *s, char *buf, size_t len) {
  if (s->family == PD_FAMILY_NONE)
    snprintf(buf, len, "%s%s", s->name, s->type == PD_OPTION_PREFIX ? "*" : "");
  else if (s->base)
    snprintf(buf, len, "-pd%s, %sK%s", s->name, Families[s->family].prefix, s->name);
  else
    snprintf(buf, len, "%sK%s", Families[s->family].prefix, s->name);
}

const char *PDSchemaWhenText(PDOptionWhen w) {
  switch (w) {
  case PD_WHEN_ALWAYS:
    return "every scene";
  case PD_WHEN_2D:
    return "2D models (-pd_model plane_stress or plane_strain)";
  case PD_WHEN_FINITE:
    return "finite kinematics (-pd_kinematics finite)";
  case PD_WHEN_BILINEAR:
    return "the bilinear law (-pd_law or -pd_materialK_law bilinear)";
  case PD_WHEN_ZACCARIOTTO:
    return "the bilinear law in the zaccariotto form (_bilinear_form)";
  case PD_WHEN_TRILINEAR:
    return "the trilinear law (-pd_law or -pd_materialK_law trilinear)";
  case PD_WHEN_NONLINEAR:
    return "the non-linear law (-pd_law or -pd_materialK_law nonlinear)";
  case PD_WHEN_CYLINDER:
    return "cylinders (-pd_regionK_cylinder, -pd_voidK_cylinder)";
  case PD_WHEN_DISPLACEMENT:
    return "displacement regions (-pd_regionK_kind displacement)";
  case PD_WHEN_FORCE:
    return "force regions (-pd_regionK_kind force)";
  case PD_WHEN_IMPLICIT:
    return "the implicit path (-pd_mode implicit)";
  case PD_WHEN_CONTROL:
    return "load or displacement control (-pd_control displacement or force, implicit)";
  case PD_WHEN_FALLBACK:
    return "load or displacement control on a scene with damage (a law other than elastic, or bond slip)";
  case PD_WHEN_EXPLICIT:
    return "the explicit path (-pd_mode explicit)";
  case PD_WHEN_PATH:
    return "path following (-pd_control arclength or auto, or the fallback of load or displacement control on a scene with damage)";
  case PD_WHEN_PATH_RUN:
    return "path following chosen (-pd_control arclength or auto, implicit)";
  case PD_WHEN_PATH_LINEAR:
    return "path following under the cmod or dissipation constraint";
  case PD_WHEN_AUGMENTED:
    return "path following under the cmod or dissipation constraint with -pd_arclength_solve augmented";
  case PD_WHEN_UNLOAD:
    return "path following with -pd_unload_at";
  case PD_WHEN_FAILURE_SEARCH:
    return "the failure search (-pd_failure_search)";
  case PD_WHEN_SLIP:
    return "bars with bond slip (-pd_barK_bond slip)";
  }
  return "";
}

PetscInt PDSchemaFamilyCount(PDOptionFamily f, const PDScene *sc) {
  switch (f) {
  case PD_FAMILY_MATERIAL:
    return sc->nmaterials;
  case PD_FAMILY_NOTCH:
    return sc->nnotches;
  case PD_FAMILY_REGION:
    return sc->nregions;
  case PD_FAMILY_VOID:
    return sc->nvoids;
  case PD_FAMILY_BAR:
    return sc->nbars;
  case PD_FAMILY_NOFAIL:
    return sc->nnofail;
  case PD_FAMILY_PLATE:
    return sc->nplates;
  default:
    return 1;
  }
}

PetscBool PDSchemaActive(const PDOptionSpec *s, PetscInt k, const PDScene *sc) {
  const PetscBool   implicit = sc->explicit_mode ? PETSC_FALSE : PETSC_TRUE;
  const PetscBool   chosen   = implicit && sc->control >= PD_CONTROL_ARCLENGTH ? PETSC_TRUE : PETSC_FALSE;
  const PetscBool   path     = chosen || (implicit && sc->control_fallback && PDSceneHasDamage(sc)) ? PETSC_TRUE : PETSC_FALSE;
  const PetscBool   linear   = path && (sc->arc_type == PD_ARC_CMOD || sc->arc_type == PD_ARC_DISSIPATION) ? PETSC_TRUE : PETSC_FALSE;
  const PDMaterial *mat      = &sc->material[s->family == PD_FAMILY_MATERIAL ? k : 0];
  const PDRegion   *reg      = &sc->region[s->family == PD_FAMILY_REGION ? k : 0];
  const PDGeometry *shape    = s->family == PD_FAMILY_VOID && k >= 0 && k < PD_MAX_VOIDS      ? &sc->voids[k].where
                               : s->family == PD_FAMILY_NOFAIL && k >= 0 && k < PD_MAX_NOFAIL ? &sc->nofail[k].where
                                                                                              : &reg->where;

  if (s->family != PD_FAMILY_NONE && (k < 0 || k >= PDSchemaFamilyCount(s->family, sc))) return PETSC_FALSE;
  switch (s->when) {
  case PD_WHEN_ALWAYS:
    return PETSC_TRUE;
  case PD_WHEN_2D:
    return sc->dim == 2 ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_FINITE:
    return sc->kinematics == PD_KINEMATICS_FINITE ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_BILINEAR:
    return mat->law == PD_LAW_BILINEAR ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_ZACCARIOTTO:
    return mat->law == PD_LAW_BILINEAR && !mat->bobaru ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_TRILINEAR:
    return mat->law == PD_LAW_TRILINEAR ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_NONLINEAR:
    return mat->law == PD_LAW_NONLINEAR ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_CYLINDER:
    return shape->shape == PD_SHAPE_CYLINDER ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_DISPLACEMENT:
    return reg->kind == PD_REGION_DISPLACEMENT ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_FORCE:
    return reg->kind == PD_REGION_FORCE ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_IMPLICIT:
    return implicit;
  case PD_WHEN_CONTROL:
    return implicit && !chosen ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_FALLBACK:
    return implicit && !chosen && PDSceneHasDamage(sc) ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_EXPLICIT:
    return sc->explicit_mode;
  case PD_WHEN_PATH:
    return path;
  case PD_WHEN_PATH_RUN:
    return chosen;
  case PD_WHEN_PATH_LINEAR:
    return linear;
  case PD_WHEN_AUGMENTED:
    return linear && sc->arc_augmented ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_UNLOAD:
    return path && sc->unload_at > 0 ? PETSC_TRUE : PETSC_FALSE;
  case PD_WHEN_FAILURE_SEARCH:
    return sc->failure_search;
  case PD_WHEN_SLIP:
    return s->family == PD_FAMILY_BAR && sc->bar[k].slip ? PETSC_TRUE : PETSC_FALSE;
  }
  return PETSC_FALSE;
}

PetscErrorCode PDSchemaCheckRange(const PDOptionSpec *s, const char *opt, PetscReal v) {
  char   open, close, what[96];
  double lo, hi;

  PetscFunctionBeginUser;
  if (!s->range) PetscFunctionReturn(0);
  PetscCheck(sscanf(s->range, " %c %lf , %lf %c", &open, &lo, &hi, &close) == 4, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Option %s: the schema's range '%s' does not read as an interval", opt, s->range);
  if ((open == '(' ? v > lo : v >= lo) && (close == ')' ? v < hi : v <= hi)) PetscFunctionReturn(0);
  if (PetscIsInfReal((PetscReal)hi) && lo == 0)
    snprintf(what, sizeof what, "must be %s", open == '(' ? "positive" : "non-negative");
  else if (PetscIsInfReal((PetscReal)hi))
    snprintf(what, sizeof what, "must be %s %g", open == '(' ? "above" : "at least", lo);
  else
    snprintf(what, sizeof what, "must lie in %s", s->range);
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: %s, got %g", opt, what, (double)v);
}
