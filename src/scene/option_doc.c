/* The option schema for people: -help (every option, and what the scene read makes of it) and the
   README's Markdown table (-pd_help_markdown), both from the one table in schema_table.c. */
#include "schema.h"
#include <stdio.h>
#include <string.h>

static void TypeText(const PDOptionSpec *s, PetscBool markdown, char *buf, size_t len) {
  static const char *const names[] = {
      [PD_OPTION_REAL] = "real",           [PD_OPTION_INT] = "integer",         [PD_OPTION_BOOL] = "true/false",
      [PD_OPTION_STRING] = "text",         [PD_OPTION_REALS] = "reals x,y,...", [PD_OPTION_INTS] = "integers i,j,...",
      [PD_OPTION_PREFIX] = "PETSc options"};
  const char *q = markdown ? "`" : "";
  size_t      n;

  snprintf(buf, len, "%s", s->type == PD_OPTION_ENUM ? "" : names[s->type]);
  for (PetscInt i = 0; s->type == PD_OPTION_ENUM && s->values[i]; i++) {
    n = strlen(buf);
    snprintf(buf + n, len - n, "%s%s%s%s", i ? (markdown ? ", " : "|") : "", q, s->values[i], q);
  }
  n = strlen(buf);
  if (s->unit) snprintf(buf + n, len - n, " (%s)", s->unit);
}

static void DefaultText(const PDOptionSpec *s, PetscBool markdown, char *buf, size_t len) {
  if (s->def)
    snprintf(buf, len, markdown ? "`%s`" : "%s", s->def);
  else
    snprintf(buf, len, "%s", s->def_note ? s->def_note : "");
}

/* A Markdown table cell: '|' would end it, '<' and '>' would read as HTML. */
static PetscErrorCode Cell(MPI_Comm comm, const char *text) {
  char buf[1024];
  int  n = 0;

  PetscFunctionBeginUser;
  for (const char *p = text; *p && n < (int)sizeof buf - 8; p++) {
    const char *rep = *p == '|' ? "\\|" : *p == '<' ? "&lt;" : *p == '>' ? "&gt;" : NULL;
    if (rep)
      n += snprintf(buf + n, sizeof buf - n, "%s", rep);
    else
      buf[n++] = *p;
  }
  buf[n] = '\0';
  PetscCall(PetscPrintf(comm, " %s |", buf));
  PetscFunctionReturn(0);
}

static PetscErrorCode FamiliesLine(MPI_Comm comm, PetscBool markdown) {
  const char *q = markdown ? "`" : "";

  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(comm, "K is %s1%s to %s%d%s in %s-pd_materialK_*%s (further materials), ", q, q, q, PD_MAX_MATERIALS - 1, q, q, q));
  PetscCall(PetscPrintf(comm, "%s0%s to %s%d%s in %s-pd_notchK_*%s, ", q, q, q, PD_MAX_NOTCHES - 1, q, q, q));
  PetscCall(PetscPrintf(comm, "%s0%s to %s%d%s in %s-pd_regionK_*%s, ", q, q, q, PD_MAX_REGIONS - 1, q, q, q));
  PetscCall(
      PetscPrintf(comm, "%s0%s to %s%d%s in %s-pd_voidK_*%s; members are numbered without gaps.\n", q, q, q, PD_MAX_VOIDS - 1, q, q, q));
  PetscFunctionReturn(0);
}

PetscErrorCode PDSceneOptionsMarkdown(MPI_Comm comm) {
  PetscFunctionBeginUser;
  PetscCall(FamiliesLine(comm, PETSC_TRUE));
  PetscCall(PetscPrintf(comm, "\n| option | type | default | range | applies to | meaning |\n|---|---|---|---|---|---|\n"));
  for (PetscInt i = 0; i < PDOptionSchemaSize; i++) {
    const PDOptionSpec *s = &PDOptionSchema[i];
    char                pattern[128], names[192] = "", text[512], *tok, *save;
    PDSchemaPattern(s, pattern, sizeof pattern);
    for (tok = strtok_r(pattern, ", ", &save); tok; tok = strtok_r(NULL, ", ", &save)) {
      size_t n = strlen(names);
      snprintf(names + n, sizeof names - n, "%s`%s`", n ? ", " : "", tok);
    }
    PetscCall(PetscPrintf(comm, "| %s |", names));
    TypeText(s, PETSC_TRUE, text, sizeof text);
    PetscCall(Cell(comm, text));
    DefaultText(s, PETSC_TRUE, text, sizeof text);
    PetscCall(Cell(comm, text));
    PetscCall(Cell(comm, s->range ? s->range : ""));
    PetscCall(Cell(comm, PDSchemaWhenText(s->when)));
    PetscCall(Cell(comm, s->help));
    PetscCall(PetscPrintf(comm, "\n"));
  }
  PetscFunctionReturn(0);
}

/* Text wrapped at 100 columns after an indent of six. */
static PetscErrorCode Wrapped(MPI_Comm comm, const char *text) {
  const char *p = text;

  PetscFunctionBeginUser;
  while (*p) {
    size_t n = strlen(p);
    if (n > 94) {
      n = 94;
      while (n > 0 && p[n] != ' ') n--;
      if (!n) n = 94;
    }
    PetscCall(PetscPrintf(comm, "      %.*s\n", (int)n, p));
    p += n;
    while (*p == ' ') p++;
  }
  PetscFunctionReturn(0);
}

/* What the scene makes of an option: the values it read, per member of a family. */
static PetscErrorCode SceneUse(const PDOptionSpec *s, const PDScene *sc, char *buf, size_t len) {
  PetscInt n = 0;

  PetscFunctionBeginUser;
  buf[0] = '\0';
  if (!sc) PetscFunctionReturn(0);
  if (s->type == PD_OPTION_PREFIX) {
    snprintf(buf, len, "%s", PDSchemaActive(s, 0, sc) ? "applies" : "does not apply");
    PetscFunctionReturn(0);
  }
  for (PetscInt i = 0; i < sc->noptions; i++) {
    const PDOptionValue *v = &sc->options[i];
    const PDOptionSpec  *t;
    PetscInt             k;
    size_t               m = strlen(buf);
    if (PDSchemaMatch(v->name, &t, &k) != PD_MATCH_OK || t != s) continue;
    snprintf(buf + m, len - m, "%s", n++ ? "; " : "reads it: ");
    m = strlen(buf);
    if (v->value)
      snprintf(buf + m, len - m, "%s = %s%s", v->name, v->value, v->set ? "" : " (default)");
    else
      snprintf(buf + m, len - m, "%s %s", v->name, s->later ? "(default, worked out by the model)" : "(not given)");
  }
  if (!n) snprintf(buf, len, "does not use it");
  PetscFunctionReturn(0);
}

PetscErrorCode PDSceneOptionsHelp(MPI_Comm comm, const PDScene *sc, const char *note) {
  PetscFunctionBeginUser;
  PetscCall(
      PetscPrintf(comm, "\npdimplicit scene options: every -pd_ option, its type (unit), default and range, where it applies, and\n"));
  PetscCall(PetscPrintf(comm, "what this scene makes of it. An option given where it does not apply is an input error.\n"));
  PetscCall(FamiliesLine(comm, PETSC_FALSE));
  if (sc)
    PetscCall(PetscPrintf(comm, "Scene read: %s\n", sc->name));
  else
    PetscCall(PetscPrintf(comm, "No scene read: %s\n", note ? note : "no options"));
  for (PetscInt i = 0; i < PDOptionSchemaSize; i++) {
    const PDOptionSpec *s = &PDOptionSchema[i];
    char                pattern[128], type[256], def[256], use[4096], line[4352];
    PDSchemaPattern(s, pattern, sizeof pattern);
    TypeText(s, PETSC_FALSE, type, sizeof type);
    DefaultText(s, PETSC_FALSE, def, sizeof def);
    PetscCall(PetscPrintf(comm, "\n  %s <%s>%s%s%s%s\n", pattern, type, def[0] ? " default: " : "", def, s->range ? " range: " : "",
                          s->range ? s->range : ""));
    PetscCall(Wrapped(comm, s->help));
    PetscCall(SceneUse(s, sc, use, sizeof use));
    PetscCall(PetscSNPrintf(line, sizeof line, "Applies to %s%s%s", PDSchemaWhenText(s->when), sc ? ". This scene " : "", use));
    PetscCall(Wrapped(comm, line));
  }
  PetscFunctionReturn(0);
}
