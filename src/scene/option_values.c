#include "option_values.h"
#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>

/* PETSc's own readers report a bad number without the option's name; these parse the text themselves. */

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

static PetscErrorCode ReadText(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, const char *shown, char *buf,
                               size_t len, PetscBool *set) {
  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(buf, shown, len));
  PetscCall(PetscOptionsString(opt, help, NULL, shown, buf, len, set));
  PetscFunctionReturn(0);
}

PetscErrorCode PDOptionReal(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, PetscReal *value, PetscBool *set) {
  char      shown[64], buf[256];
  PetscBool flg;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(shown, sizeof shown, "%g", (double)*value));
  PetscCall(ReadText(PetscOptionsObject, opt, help, shown, buf, sizeof buf, &flg));
  if (flg) PetscCall(ParseReal(opt, buf, value));
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode PDOptionFraction(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, PetscReal *value) {
  PetscFunctionBeginUser;
  PetscCall(PDOptionReal(PetscOptionsObject, opt, help, value, NULL));
  PetscCheck(*value >= 0 && *value < 1, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: must lie in [0, 1), got %g", opt,
             (double)*value);
  PetscFunctionReturn(0);
}

PetscErrorCode PDOptionInt(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, PetscInt *value, PetscBool *set) {
  char      shown[64], buf[256], *end;
  PetscBool flg;
  long      v;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(shown, sizeof shown, "%" PetscInt_FMT, *value));
  PetscCall(ReadText(PetscOptionsObject, opt, help, shown, buf, sizeof buf, &flg));
  if (flg) {
    errno = 0;
    v     = strtol(buf, &end, 10);
    while (*end && isspace((unsigned char)*end)) end++;
    PetscCheck(end != buf && *end == '\0' && errno == 0 && v >= PETSC_MIN_INT && v <= PETSC_MAX_INT, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option %s: value '%s' is not an integer", opt, buf);
    *value = (PetscInt)v;
  }
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode PDOptionBool(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, PetscBool *value, PetscBool *set) {
  char      buf[64];
  PetscBool flg, t = PETSC_FALSE, f = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(ReadText(PetscOptionsObject, opt, help, *value ? "true" : "false", buf, sizeof buf, &flg));
  if (flg) {
    /* a bare flag (-pd_progress) arrives as an empty string and means true */
    if (!buf[0]) t = PETSC_TRUE;
    for (const char *const *w = (const char *const[]){"true", "yes", "on", "1", NULL}; *w && !t; w++)
      PetscCall(PetscStrcasecmp(buf, *w, &t));
    for (const char *const *w = (const char *const[]){"false", "no", "off", "0", NULL}; *w && !f; w++)
      PetscCall(PetscStrcasecmp(buf, *w, &f));
    PetscCheck(t || f, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: value '%s' is not true or false", opt, buf);
    *value = t ? PETSC_TRUE : PETSC_FALSE;
  }
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode PDOptionEnum(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, const char *const *names,
                            PetscInt nnames, PetscInt *value, PetscBool *set) {
  char      buf[64], choices[512] = "";
  PetscBool flg, match            = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(ReadText(PetscOptionsObject, opt, help, names[*value], buf, sizeof buf, &flg));
  if (flg) {
    for (PetscInt i = 0; i < nnames && !match; i++) {
      PetscCall(PetscStrcasecmp(buf, names[i], &match));
      if (match) *value = i;
    }
    if (!match) {
      for (PetscInt i = 0; i < nnames; i++) {
        PetscCall(PetscStrlcat(choices, names[i], sizeof choices));
        if (i + 1 < nnames) PetscCall(PetscStrlcat(choices, ", ", sizeof choices));
      }
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: unknown value '%s' (expected one of: %s)", opt, buf, choices);
    }
  }
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode PDOptionRealArray(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, PetscReal *values, PetscInt *n,
                                 PetscBool *set) {
  char      buf[1024], shown[512] = "", item[64];
  PetscBool flg;
  PetscInt  cap = *n, count = 0;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < cap; i++) {
    PetscCall(PetscSNPrintf(item, sizeof item, i ? ",%g" : "%g", (double)values[i]));
    PetscCall(PetscStrlcat(shown, item, sizeof shown));
  }
  PetscCall(ReadText(PetscOptionsObject, opt, help, shown, buf, sizeof buf, &flg));
  if (flg) {
    char *p = buf;
    while (p) {
      char *comma = strchr(p, ',');
      if (comma) *comma = '\0';
      PetscCheck(count < cap, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: more than %" PetscInt_FMT " values given", opt, cap);
      PetscCall(ParseReal(opt, p, &values[count]));
      count++;
      p = comma ? comma + 1 : NULL;
    }
    *n = count;
  }
  if (set) *set = flg;
  PetscFunctionReturn(0);
}

PetscErrorCode PDOptionString(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, char *value, size_t len,
                              PetscBool *set) {
  char      buf[PETSC_MAX_PATH_LEN];
  PetscBool flg;

  PetscFunctionBeginUser;
  PetscCall(ReadText(PetscOptionsObject, opt, help, value, buf, sizeof buf, &flg));
  if (flg) {
    PetscCheck(buf[0], PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option %s: needs a value", opt);
    PetscCall(PetscStrncpy(value, buf, len));
  }
  if (set) *set = flg;
  PetscFunctionReturn(0);
}
