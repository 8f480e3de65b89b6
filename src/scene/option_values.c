/* Typed readers of -pd_ options, driven by the schema: an option's default, help and range come from
   its entry, it is read only where the entry says it applies, and what was read is recorded for the
   echo in summary.json and for -help. PETSc's own readers report a bad number without the option's
   name; these parse the text themselves. */
#include "option_values.h"
#include "schema.h"
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static PetscErrorCode ParseReal(const char *opt, const char *text, PetscReal *value) {
  char  *end;
  double v;

  PetscFunctionBeginUser;
  while (isspace((unsigned char)*text)) text++;
  errno = 0;
  v     = strtod(text, &end);
  while (end && isspace((unsigned char)*end)) end++;
  PetscCheck(end != text && *end == '\0' && errno == 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: value '%s' is not a number", opt,
             text);
  PetscCheck(PetscIsNormalReal((PetscReal)v) || v == 0.0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: value '%s' is not a finite number", opt, text);
  *value = (PetscReal)v;
  PetscFunctionReturn(0);
}

/* The shortest text that reads back as v. C's snprintf, not PETSc's, which appends '.' to whole numbers. */
static void RealText(char *buf, size_t len, PetscReal v) {
  for (int digits = 6; digits <= 17; digits++) {
    snprintf(buf, len, "%.*g", digits, (double)v);
    if (strtod(buf, NULL) == (double)v) return;
  }
}

/* An option left at a default the model works out later is echoed without a value. */
static PetscErrorCode Record(PDScene *sc, const PDOptionSpec *spec, const char *opt, PDOptionType type, PetscBool set, const char *text) {
  PDOptionValue *v;

  PetscFunctionBeginUser;
  if (spec->later && !set) text = NULL;
  if (sc->noptions % 32 == 0) PetscCall(PetscRealloc(sizeof(PDOptionValue) * (sc->noptions + 32), &sc->options));
  v = &sc->options[sc->noptions++];
  PetscCall(PetscStrncpy(v->name, opt, sizeof v->name));
  v->type = type;
  v->set  = set;
  PetscCall(PetscStrallocpy(text, &v->value));
  PetscFunctionReturn(0);
}

/* Registers the option with PETSc (for -help and -options_left) and returns its text if given. */
static PetscErrorCode ReadText(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, const char *shown, char *buf,
                               size_t len, PetscBool *set) {
  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(buf, shown, len));
  PetscCall(PetscOptionsString(opt, help, NULL, shown, buf, len, set));
  PetscFunctionReturn(0);
}

static PetscErrorCode ParseInt(const char *opt, const char *text, PetscInt *value) {
  char *end;
  long  v;

  PetscFunctionBeginUser;
  errno = 0;
  v     = strtol(text, &end, 10);
  while (*end && isspace((unsigned char)*end)) end++;
  PetscCheck(end != text && *end == '\0' && errno == 0 && v >= PETSC_MIN_INT && v <= PETSC_MAX_INT, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "Option %s: value '%s' is not an integer", opt, text);
  *value = (PetscInt)v;
  PetscFunctionReturn(0);
}

static PetscErrorCode ParseBool(const char *opt, const char *text, PetscBool *value) {
  PetscBool t = PETSC_FALSE, f = PETSC_FALSE;

  PetscFunctionBeginUser;
  /* a bare flag (-pd_progress) arrives as an empty string and means true */
  if (!text[0]) t = PETSC_TRUE;
  for (const char *const *w = (const char *const[]){"true", "yes", "on", "1", NULL}; *w && !t; w++)
    PetscCall(PetscStrcasecmp(text, *w, &t));
  for (const char *const *w = (const char *const[]){"false", "no", "off", "0", NULL}; *w && !f; w++)
    PetscCall(PetscStrcasecmp(text, *w, &f));
  PetscCheck(t || f, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: value '%s' is not true or false", opt, text);
  *value = t ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

static PetscErrorCode ParseEnum(const char *opt, const char *const *names, const char *text, PetscInt *value) {
  char      choices[512] = "";
  PetscBool match        = PETSC_FALSE;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; names[i] && !match; i++) {
    PetscCall(PetscStrcasecmp(text, names[i], &match));
    if (match) *value = i;
  }
  if (match) PetscFunctionReturn(0);
  for (PetscInt i = 0; names[i]; i++) {
    PetscCall(PetscStrlcat(choices, names[i], sizeof choices));
    if (names[i + 1]) PetscCall(PetscStrlcat(choices, ", ", sizeof choices));
  }
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: unknown value '%s' (expected one of: %s)", opt, text, choices);
}

/* One kind of scalar value: how its text reads (a given value is checked against the entry's range; a
   default is the schema's own, where pi may stand for the number) and how it is shown. */
typedef struct {
  PDOptionType type;
  PetscErrorCode (*parse)(const PDOptionSpec *, const char *opt, const char *text, PetscBool given, void *value);
  void (*show)(const PDOptionSpec *, const void *value, char *buf, size_t len);
} Kind;

static PetscErrorCode RealParse(const PDOptionSpec *s, const char *opt, const char *text, PetscBool given, void *value) {
  PetscReal *v = (PetscReal *)value;

  PetscFunctionBeginUser;
  if (!given && !strcmp(text, "pi"))
    *v = PETSC_PI;
  else
    PetscCall(ParseReal(opt, text, v));
  if (given) PetscCall(PDSchemaCheckRange(s, opt, *v));
  PetscFunctionReturn(0);
}

static void RealShow(const PDOptionSpec *s, const void *value, char *buf, size_t len) {
  (void)s;
  RealText(buf, len, *(const PetscReal *)value);
}

static PetscErrorCode IntParse(const PDOptionSpec *s, const char *opt, const char *text, PetscBool given, void *value) {
  PetscInt *v = (PetscInt *)value;

  PetscFunctionBeginUser;
  PetscCall(ParseInt(opt, text, v));
  if (given) PetscCall(PDSchemaCheckRange(s, opt, (PetscReal)*v));
  PetscFunctionReturn(0);
}

static void IntShow(const PDOptionSpec *s, const void *value, char *buf, size_t len) {
  (void)s;
  snprintf(buf, len, "%" PetscInt_FMT, *(const PetscInt *)value);
}

static PetscErrorCode BoolParse(const PDOptionSpec *s, const char *opt, const char *text, PetscBool given, void *value) {
  (void)s;
  (void)given;
  return ParseBool(opt, text, (PetscBool *)value);
}

static void BoolShow(const PDOptionSpec *s, const void *value, char *buf, size_t len) {
  (void)s;
  snprintf(buf, len, "%s", *(const PetscBool *)value ? "true" : "false");
}

static PetscErrorCode EnumParse(const PDOptionSpec *s, const char *opt, const char *text, PetscBool given, void *value) {
  (void)given;
  return ParseEnum(opt, s->values, text, (PetscInt *)value);
}

static void EnumShow(const PDOptionSpec *s, const void *value, char *buf, size_t len) {
  snprintf(buf, len, "%s", s->values[*(const PetscInt *)value]);
}

static const Kind RealKind = {PD_OPTION_REAL, RealParse, RealShow}, IntKind = {PD_OPTION_INT, IntParse, IntShow},
                  BoolKind = {PD_OPTION_BOOL, BoolParse, BoolShow}, EnumKind = {PD_OPTION_ENUM, EnumParse, EnumShow};

/* Looks the option up, applies its default, and where the option applies to the scene reads it. */
static PetscErrorCode Begin(PDScene *sc, const char *opt, const PDOptionSpec **spec, PetscBool *use_default, PetscBool *active,
                            PetscBool *set) {
  PetscInt k;

  PetscFunctionBeginUser;
  PetscCheck(PDSchemaMatch(opt, spec, &k) == PD_MATCH_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Option %s is missing from the option schema",
             opt);
  /* further materials start from the base material's values instead */
  *use_default = (*spec)->def && !((*spec)->family == PD_FAMILY_MATERIAL && k > 0) ? PETSC_TRUE : PETSC_FALSE;
  *active      = PDSchemaActive(*spec, k, sc);
  if (set) *set = PETSC_FALSE;
  PetscFunctionReturn(0);
}

static PetscErrorCode Read(PetscOptionItems *PetscOptionsObject, PDScene *sc, const char *opt, const Kind *kind, void *value,
                           PetscBool *set) {
  const PDOptionSpec *spec;
  PetscBool           def, active, flg = PETSC_FALSE;
  char                shown[256], buf[256];

  PetscFunctionBeginUser;
  PetscCall(Begin(sc, opt, &spec, &def, &active, set));
  if (def) PetscCall(kind->parse(spec, opt, spec->def, PETSC_FALSE, value));
  if (!active) PetscFunctionReturn(0);
  kind->show(spec, value, shown, sizeof shown);
  PetscCall(ReadText(PetscOptionsObject, opt, spec->help, shown, buf, sizeof buf, &flg));
  if (flg) {
    PetscCall(kind->parse(spec, opt, buf, PETSC_TRUE, value));
    kind->show(spec, value, shown, sizeof shown);
  }
  PetscCall(Record(sc, spec, opt, kind->type, flg, shown));
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode PDOptionReal(PetscOptionItems *PetscOptionsObject, PDScene *sc, const char *opt, PetscReal *value, PetscBool *set) {
  return Read(PetscOptionsObject, sc, opt, &RealKind, value, set);
}

PetscErrorCode PDOptionInt(PetscOptionItems *PetscOptionsObject, PDScene *sc, const char *opt, PetscInt *value, PetscBool *set) {
  return Read(PetscOptionsObject, sc, opt, &IntKind, value, set);
}

PetscErrorCode PDOptionBool(PetscOptionItems *PetscOptionsObject, PDScene *sc, const char *opt, PetscBool *value, PetscBool *set) {
  return Read(PetscOptionsObject, sc, opt, &BoolKind, value, set);
}

PetscErrorCode PDOptionEnum(PetscOptionItems *PetscOptionsObject, PDScene *sc, const char *opt, PetscInt *value, PetscBool *set) {
  return Read(PetscOptionsObject, sc, opt, &EnumKind, value, set);
}

static PetscErrorCode RealsText(const PetscReal *values, PetscInt n, char *buf, size_t len) {
  char item[32];

  PetscFunctionBeginUser;
  buf[0] = '\0';
  for (PetscInt i = 0; i < n; i++) {
    RealText(item, sizeof item, values[i]);
    if (i) PetscCall(PetscStrlcat(buf, ",", len));
    PetscCall(PetscStrlcat(buf, item, len));
  }
  PetscFunctionReturn(0);
}

/* The next item of a comma-separated list, cut off in place; *rest moves past it (NULL after the last). */
static char *NextItem(char **rest) {
  char *item = *rest, *comma = strchr(item, ',');
  if (comma) *comma = '\0';
  *rest = comma ? comma + 1 : NULL;
  return item;
}

PetscErrorCode PDOptionRealArray(PetscOptionItems *PetscOptionsObject, PDScene *sc, const char *opt, PetscReal *values, PetscInt *n,
                                 PetscBool *set) {
  const PDOptionSpec *spec;
  PetscInt            cap = *n, count = 0;
  PetscBool           def, active, flg = PETSC_FALSE;
  char                buf[1024], shown[512];

  PetscFunctionBeginUser;
  PetscCall(Begin(sc, opt, &spec, &def, &active, set));
  if (!active) PetscFunctionReturn(0);
  PetscCall(RealsText(values, cap, shown, sizeof shown));
  PetscCall(ReadText(PetscOptionsObject, opt, spec->help, shown, buf, sizeof buf, &flg));
  if (flg) {
    for (char *rest = buf; rest;) {
      PetscCheck(count < cap, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: more than %" PetscInt_FMT " values given", opt, cap);
      PetscCall(ParseReal(opt, NextItem(&rest), &values[count++]));
    }
    *n = count;
    PetscCall(RealsText(values, count, shown, sizeof shown));
  }
  PetscCall(Record(sc, spec, opt, PD_OPTION_REALS, flg, flg ? shown : NULL));
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

/* A list of integers, each checked against the option's range. */
PetscErrorCode PDOptionIntArray(PetscOptionItems *PetscOptionsObject, PDScene *sc, const char *opt, PetscInt *values, PetscInt cap,
                                PetscInt *n, PetscBool *set) {
  const PDOptionSpec *spec;
  PetscInt            count = 0;
  PetscBool           def, active, flg = PETSC_FALSE;
  char                buf[1024], shown[512] = "", item[32];

  PetscFunctionBeginUser;
  PetscCall(Begin(sc, opt, &spec, &def, &active, set));
  if (!active) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < *n; i++) {
    snprintf(item, sizeof item, "%s%" PetscInt_FMT, i ? "," : "", values[i]);
    PetscCall(PetscStrlcat(shown, item, sizeof shown));
  }
  PetscCall(ReadText(PetscOptionsObject, opt, spec->help, shown, buf, sizeof buf, &flg));
  if (flg) {
    shown[0] = '\0';
    for (char *rest = buf; rest;) {
      PetscCheck(count < cap, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: more than %" PetscInt_FMT " values given", opt, cap);
      PetscCall(ParseInt(opt, NextItem(&rest), &values[count]));
      PetscCall(PDSchemaCheckRange(spec, opt, (PetscReal)values[count]));
      snprintf(item, sizeof item, "%s%" PetscInt_FMT, count ? "," : "", values[count]);
      PetscCall(PetscStrlcat(shown, item, sizeof shown));
      count++;
    }
    *n = count;
  }
  PetscCall(Record(sc, spec, opt, PD_OPTION_INTS, flg, shown)); /* the default too, as the other readers echo theirs */
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode PDOptionString(PetscOptionItems *PetscOptionsObject, PDScene *sc, const char *opt, char *value, size_t len, PetscBool *set) {
  const PDOptionSpec *spec;
  PetscBool           def, active, flg = PETSC_FALSE;
  char                buf[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(Begin(sc, opt, &spec, &def, &active, set));
  if (def) PetscCall(PetscStrncpy(value, spec->def, len));
  if (!active) PetscFunctionReturn(0);
  PetscCall(ReadText(PetscOptionsObject, opt, spec->help, value, buf, sizeof buf, &flg));
  if (flg) {
    PetscCheck(buf[0], PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: needs a value", opt);
    PetscCheck(strlen(buf) < len, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: longer than %d characters", opt, (int)len - 1);
    PetscCall(PetscStrncpy(value, buf, len));
  }
  PetscCall(Record(sc, spec, opt, PD_OPTION_STRING, flg, value[0] ? value : NULL));
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode PDSceneDestroy(PDScene *sc) {
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < sc->noptions; i++) PetscCall(PetscFree(sc->options[i].value));
  PetscCall(PetscFree(sc->options));
  sc->noptions = 0;
  PetscFunctionReturn(0);
}
