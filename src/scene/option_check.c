/* Input errors in the -pd_ options themselves: names outside the schema (reported with the closest valid
   name), family indices out of range, options the scene does not use, and family members after a gap.
   PETSc keeps a used flag per option; the scene's readers set it for every option they read. */
#include "schema.h"
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Edit distance (insertions, deletions, substitutions), letters compared without case. */
static PetscInt Distance(const char *a, const char *b) {
  const size_t la = strlen(a), lb = strlen(b);
  PetscInt     row[128];

  if (la >= 127 || lb >= 127) return PETSC_MAX_INT;
  for (size_t j = 0; j <= lb; j++) row[j] = (PetscInt)j;
  for (size_t i = 1; i <= la; i++) {
    PetscInt diag = row[0];
    row[0]        = (PetscInt)i;
    for (size_t j = 1; j <= lb; j++) {
      const PetscInt up = row[j], sub = diag + (tolower((unsigned char)a[i - 1]) != tolower((unsigned char)b[j - 1]));
      row[j] = PetscMin(PetscMin(up + 1, row[j - 1] + 1), sub);
      diag   = up;
    }
  }
  return row[lb];
}

/* The valid name closest to the given one; family members keep the given index where it is valid. */
static void Closest(const char *given, char *best, size_t len) {
  PetscInt    k = -1, bestd = PETSC_MAX_INT;
  const char *digit = given;
  char        cand[96];

  while (*digit && !isdigit((unsigned char)*digit)) digit++;
  if (*digit) k = (PetscInt)atoi(digit);
  best[0] = '\0';
  for (PetscInt i = 0; i < PDOptionSchemaSize; i++) {
    const PDOptionSpec *s = &PDOptionSchema[i];
    if (s->type == PD_OPTION_PREFIX) continue;
    for (int pass = 0; pass < 2; pass++) {
      PetscInt first, last, d;
      if (s->family == PD_FAMILY_NONE || (pass == 0 && s->base)) {
        if (pass == 1 && s->family == PD_FAMILY_NONE) break;
        PDSchemaInstance(s, 0, cand, sizeof cand);
      } else if (pass == 1) {
        PDSchemaFamily(s->family, NULL, NULL, NULL, &first, &last);
        PDSchemaInstance(s, k >= first && k <= last ? k : first, cand, sizeof cand);
      } else
        continue;
      d = Distance(given, cand);
      if (d < bestd) {
        bestd = d;
        snprintf(best, len, "%s", cand);
      }
    }
  }
}

static void IndexMessage(const char *given, const PDOptionSpec *s, char *msg, size_t len) {
  const char *prefix, *nouns;
  PetscInt    first, last;

  PDSchemaFamily(s->family, &prefix, NULL, &nouns, &first, &last);
  snprintf(msg, len, "Option %s: %s are numbered %d to %d (%s%d to %s%d)%s", given, nouns, (int)first, (int)last, prefix, (int)first,
           prefix, (int)last, s->family == PD_FAMILY_MATERIAL ? "; the base material's options are -pd_E, -pd_law, ..." : "");
}

/* A name outside the schema, or a family index out of range. */
static void NameMessage(const char *given, const PDScene *sc, char *msg, size_t len) {
  const PDOptionSpec *s;
  PetscInt            k;
  char                best[96];

  (void)sc;
  switch (PDSchemaMatch(given, &s, &k)) {
  case PD_MATCH_OK:
    break;
  case PD_MATCH_INDEX:
    IndexMessage(given, s, msg, len);
    break;
  case PD_MATCH_NONE:
    Closest(given, best, sizeof best);
    snprintf(msg, len, "Option %s: no such option; did you mean %s? (-help lists every -pd_ option)", given, best);
    break;
  }
}

/* Runs check on every -pd_ option not used so far, in the order given; the first message is the error. */
static PetscErrorCode CheckLeft(void (*check)(const char *given, const PDScene *, char *msg, size_t len), const PDScene *sc) {
  PetscInt N;
  char   **names, **values, msg[512] = "";

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsLeftGet(NULL, &N, &names, &values));
  for (PetscInt i = 0; i < N && !msg[0]; i++) {
    char given[256];
    if (strncasecmp(names[i], "pd_", 3)) continue;
    snprintf(given, sizeof given, "-%s", names[i]);
    check(given, sc, msg, sizeof msg);
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &N, &names, &values));
  PetscCheck(!msg[0], PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s", msg);
  PetscFunctionReturn(0);
}

PetscErrorCode PDOptionsCheckNames(void) {
  PetscFunctionBeginUser;
  PetscCall(CheckLeft(NameMessage, NULL));
  PetscFunctionReturn(0);
}

/* Why an option the scene left unread is not used; options of a PETSc object are read by it later. */
static void UnusedMessage(const char *given, const PDScene *sc, char *msg, size_t len) {
  const PDOptionSpec *s;
  PetscInt            k, n;
  const char         *prefix, *noun, *nouns;
  char                what[96];

  if (PDSchemaMatch(given, &s, &k) != PD_MATCH_OK) return; /* PDOptionsCheckNames reports these */
  if (s->type == PD_OPTION_PREFIX && PDSchemaActive(s, k, sc)) return;
  n = s->family == PD_FAMILY_NONE ? 0 : PDSchemaFamilyCount(s->family, sc);
  if (s->family != PD_FAMILY_NONE && k >= n && !(s->family == PD_FAMILY_MATERIAL && k == 0)) {
    PDSchemaFamily(s->family, &prefix, &noun, &nouns, NULL, NULL);
    if (s->family == PD_FAMILY_REGION || s->family == PD_FAMILY_VOID || s->family == PD_FAMILY_NOFAIL)
      snprintf(what, sizeof what, "%s%d_box or %s%d_cylinder", prefix, (int)n, prefix, (int)n);
    else if (s->family == PD_FAMILY_BAR)
      snprintf(what, sizeof what, "%s%d_line", prefix, (int)n);
    else
      snprintf(what, sizeof what, "%s%d_box", prefix, (int)n);
    if (k == n)
      snprintf(msg, len, "Option %s: %s %d has no %s", given, noun, (int)k, what);
    else
      snprintf(msg, len, "Option %s: there is no %s %d (%s), and %s are numbered without gaps, so %s %d is not read", given, noun, (int)n,
               what, nouns, noun, (int)k);
  } else if (!PDSchemaActive(s, k, sc))
    snprintf(msg, len, "Option %s is not used by this scene: it applies to %s", given, PDSchemaWhenText(s->when));
  else
    snprintf(msg, len, "Option %s is not used by this scene", given);
}

PetscErrorCode PDOptionsCheckUnused(const PDScene *sc) {
  PetscFunctionBeginUser;
  PetscCall(CheckLeft(UnusedMessage, sc));
  PetscFunctionReturn(0);
}
