/* curve.svg: the load curve drawn by the program, with the experimental mean and envelope when the
   scene names a data file (columns cmod_mm, load_mean_kN, load_min_kN, load_max_kN). */
#include "pd_io.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 640.0
#define H 440.0
#define ML 70.0
#define MR 20.0
#define MT 30.0
#define MB 55.0

typedef struct {
  PetscInt   n;
  PetscReal *x, *mean, *lo, *hi;
} ExpCurve;

static PetscErrorCode ReadExperiment(const char *file, ExpCurve *ex) {
  FILE    *fp;
  char     line[512];
  PetscInt cap = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(ex, sizeof *ex));
  fp = fopen(file, "r");
  PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "Option -pd_data_file: cannot open '%s'", file);
  while (fgets(line, sizeof line, fp)) {
    double a, b, c, d;
    if (line[0] == '#' || sscanf(line, "%lf,%lf,%lf,%lf", &a, &b, &c, &d) != 4) continue;
    if (ex->n == cap) {
      cap = PetscMax(256, 2 * cap);
      PetscCall(PetscRealloc(sizeof(PetscReal) * cap, &ex->x));
      PetscCall(PetscRealloc(sizeof(PetscReal) * cap, &ex->mean));
      PetscCall(PetscRealloc(sizeof(PetscReal) * cap, &ex->lo));
      PetscCall(PetscRealloc(sizeof(PetscReal) * cap, &ex->hi));
    }
    ex->x[ex->n]    = a;
    ex->mean[ex->n] = b;
    ex->lo[ex->n]   = c;
    ex->hi[ex->n]   = d;
    ex->n++;
  }
  fclose(fp);
  PetscFunctionReturn(0);
}

static PetscReal NiceStep(PetscReal range) {
  const PetscReal raw = range / 5, p = PetscPowReal(10, PetscFloorReal(PetscLog10Real(raw))), f = raw / p;
  return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * p;
}

PetscErrorCode PDCurvePlotWrite(MPI_Comm comm, const PDScene *sc, const PDRecord *rec) {
  PetscMPIInt rank;
  FILE       *fp;
  char        path[PETSC_MAX_PATH_LEN], *title;
  ExpCurve    ex   = {0, NULL, NULL, NULL, NULL};
  PetscReal   xmax = 0, ymax = 0, ymin = 0, sx, sy, step;
  PetscBool   use_cmod = sc->has_cmod;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    if (sc->data_file[0] && use_cmod) PetscCall(ReadExperiment(sc->data_file, &ex));
    for (PetscInt k = 0; k < rec->nrows; k++) {
      const PetscReal x = 1e3 * (use_cmod ? rec->rows[k].cmod : rec->rows[k].disp), y = 1e-3 * rec->rows[k].load;
      if (PetscIsNormalReal(x)) xmax = PetscMax(xmax, x);
      ymax = PetscMax(ymax, y);
      ymin = PetscMin(ymin, y);
    }
    for (PetscInt k = 0; k < ex.n; k++) {
      xmax = PetscMax(xmax, ex.x[k]);
      ymax = PetscMax(ymax, ex.hi[k]);
    }
    if (xmax <= 0) xmax = 1;
    if (ymax <= ymin) ymax = ymin + 1;
    ymax += 0.05 * (ymax - ymin); /* headroom above the peak */
    sx = (W - ML - MR) / xmax;
    sy = (H - MT - MB) / (ymax - ymin);
    PetscCall(PetscSNPrintf(path, sizeof path, "%s/curve.svg.tmp", rec->dir));
    fp = fopen(path, "w");
    PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "Cannot write %s", path);
    fprintf(fp, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" font-family=\"sans-serif\" font-size=\"12\">\n", W,
            H);
    PetscCall(PDEscapeXML(sc->name, &title));
    fprintf(fp, "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n<text x=\"%g\" y=\"18\" text-anchor=\"middle\">%s</text>\n",
            W / 2, title);
    PetscCall(PetscFree(title));
#define PX(v) (ML + (v)*sx)
#define PY(v) (H - MB - ((v)-ymin) * sy)
    step = NiceStep(xmax);
    for (PetscReal t = 0; t <= xmax * (1 + 1e-9); t += step)
      fprintf(fp,
              "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"%.1f\" "
              "text-anchor=\"middle\">%g</text>\n",
              PX(t), PY(ymin), PX(t), PY(ymax), PX(t), PY(ymin) + 16, (double)t);
    step = NiceStep(ymax - ymin);
    for (PetscReal t = step * PetscCeilReal(ymin / step); t <= ymax * (1 + 1e-9); t += step)
      fprintf(fp,
              "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"%.1f\" "
              "text-anchor=\"end\">%g</text>\n",
              PX(0), PY(t), PX(xmax), PY(t), PX(0) - 6, PY(t) + 4, (double)t);
    fprintf(fp, "<rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" fill=\"none\" stroke=\"black\"/>\n", ML, MT, W - ML - MR, H - MT - MB);
    fprintf(fp, "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">%s (mm)</text>\n", (ML + W - MR) / 2, H - 15,
            use_cmod ? "CMOD" : "displacement");
    fprintf(fp, "<text x=\"18\" y=\"%g\" text-anchor=\"middle\" transform=\"rotate(-90 18 %g)\">load (kN)</text>\n", (MT + H - MB) / 2,
            (MT + H - MB) / 2);
    if (ex.n) {
      fprintf(fp, "<polygon fill=\"#9ecae1\" fill-opacity=\"0.5\" stroke=\"none\" points=\"");
      for (PetscInt k = 0; k < ex.n; k++) fprintf(fp, "%.1f,%.1f ", PX(ex.x[k]), PY(ex.hi[k]));
      for (PetscInt k = ex.n - 1; k >= 0; k--) fprintf(fp, "%.1f,%.1f ", PX(ex.x[k]), PY(ex.lo[k]));
      fprintf(fp, "\"/>\n<polyline fill=\"none\" stroke=\"#3182bd\" stroke-dasharray=\"5,3\" points=\"");
      for (PetscInt k = 0; k < ex.n; k++) fprintf(fp, "%.1f,%.1f ", PX(ex.x[k]), PY(ex.mean[k]));
      fprintf(fp, "\"/>\n<text x=\"%g\" y=\"%g\" fill=\"#3182bd\">experiment: mean and envelope</text>\n", W - MR - 230, MT + 36);
    }
    fprintf(fp, "<polyline fill=\"none\" stroke=\"#d62728\" stroke-width=\"2\" points=\"%.1f,%.1f ", PX(0), PY(0));
    for (PetscInt k = 0; k < rec->nrows; k++) {
      const PetscReal x = 1e3 * (use_cmod ? rec->rows[k].cmod : rec->rows[k].disp);
      if (PetscIsNormalReal(x) || x == 0) fprintf(fp, "%.1f,%.1f ", PX(x), PY(1e-3 * rec->rows[k].load));
    }
    fprintf(fp, "\"/>\n<text x=\"%g\" y=\"%g\" fill=\"#d62728\">pdimplicit</text>\n</svg>\n", W - MR - 230, MT + 18);
#undef PX
#undef PY
    fclose(fp);
    PetscCall(PetscFree(ex.x));
    PetscCall(PetscFree(ex.mean));
    PetscCall(PetscFree(ex.lo));
    PetscCall(PetscFree(ex.hi));
  }
  PetscCall(PDFileCommit(comm, rec->dir, "curve.svg"));
  PetscFunctionReturn(0);
}
