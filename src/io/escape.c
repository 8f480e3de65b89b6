/* Text from the user (the scene name, paths, messages) inside JSON, XML and SVG. Bytes that are not UTF-8
   become U+FFFD, so that every output file parses whatever the name holds. */
#include "pd_io.h"
#include <stdio.h>
#include <string.h>

/* Length of the valid UTF-8 sequence at p, or 0. */
static size_t Utf8Length(const unsigned char *p) {
  size_t n = p[0] < 0x80 ? 1 : (p[0] & 0xe0) == 0xc0 ? 2 : (p[0] & 0xf0) == 0xe0 ? 3 : (p[0] & 0xf8) == 0xf0 ? 4 : 0;

  if (n == 2 && p[0] < 0xc2) return 0; /* overlong */
  for (size_t i = 1; i < n; i++)
    if ((p[i] & 0xc0) != 0x80) return 0;
  return n;
}

/* Escapes in into a new string; json: a quoted JSON string, else XML character data and attribute text. */
static PetscErrorCode Escape(const char *in, PetscBool json, char **out) {
  const unsigned char *p   = (const unsigned char *)(in ? in : "");
  size_t               cap = 8 * strlen((const char *)p) + 3, n = 0;
  char                *o;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(cap, &o));
  if (json) o[n++] = '"';
  while (*p) {
    const size_t len = Utf8Length(p);
    if (!len) {
      n += (size_t)snprintf(o + n, cap - n, "%s", json ? "\\ufffd" : "\xef\xbf\xbd");
      p++;
      continue;
    }
    if (len > 1) {
      memcpy(o + n, p, len);
      n += len;
    } else if (json && (*p == '"' || *p == '\\'))
      n += (size_t)snprintf(o + n, cap - n, "\\%c", *p);
    else if (json && *p < 0x20)
      n += (size_t)snprintf(o + n, cap - n, "\\u%04x", *p);
    else if (!json && *p < 0x20 && *p != '\t' && *p != '\n' && *p != '\r')
      n += (size_t)snprintf(o + n, cap - n, "\xef\xbf\xbd");
    else if (!json && (*p == '&' || *p == '<' || *p == '>' || *p == '"' || *p == '\''))
      n += (size_t)snprintf(o + n, cap - n, "%s",
                            *p == '&'   ? "&amp;"
                            : *p == '<' ? "&lt;"
                            : *p == '>' ? "&gt;"
                            : *p == '"' ? "&quot;"
                                        : "&apos;");
    else
      o[n++] = (char)*p;
    p += len;
  }
  if (json) o[n++] = '"';
  o[n] = '\0';
  *out = o;
  PetscFunctionReturn(0);
}

PetscErrorCode PDEscapeJSON(const char *in, char **out) {
  PetscFunctionBeginUser;
  PetscCall(Escape(in, PETSC_TRUE, out));
  PetscFunctionReturn(0);
}

PetscErrorCode PDEscapeXML(const char *in, char **out) {
  PetscFunctionBeginUser;
  PetscCall(Escape(in, PETSC_FALSE, out));
  PetscFunctionReturn(0);
}
