/* Reads a scene from the PETSc options database and validates it before anything is built. Every
   option is read through the schema (schema.h); options given but not used are input errors. */
#include "pd_scene.h"
#include "option_values.h"
#include "scene_read.h"
#include "schema.h"
#include <petscviewer.h>
#include <string.h>

const char *const PDModelKinds[]          = {"3d", "plane_stress", "plane_strain", NULL};
const char *const PDInfluences[]          = {"constant", "conical", "quartic", NULL};
const char *const PDKinematicsNames[]     = {"small", "finite", NULL};
const char *const PDCalibrationNames[]    = {"continuum", "stencil", NULL};
const char *const PDLawNames[]            = {"elastic", "linear", "bilinear", "trilinear", "nonlinear", NULL};
const char *const PDStretchNames[]        = {"exact", "modified", NULL};
const char *const PDControlNames[]        = {"displacement", "force", "arclength", "auto", NULL};
const char *const PDArcTypes[]            = {"spherical", "cylindrical", "cmod", "dissipation", NULL};
const char *const PDTangentNames[]        = {"consistent", "secant", NULL};
const char *const PDPCMatrixNames[]       = {"tangent", "secant", NULL};
const char *const PDTangentProductNames[] = {"bonds", "matrix", NULL};
const char *const PDShapes[]              = {"box", "cylinder", NULL};
const char *const PDRegionKinds[]         = {"support", "displacement", "force", "monitor", NULL};
const char *const PDFailureCriteria[]     = {"damage", "velocity", "force", NULL};
const char *const PDModes[]               = {"implicit", "explicit", NULL};
const char *const PDMatTypes[]            = {"sbaij", "baij", "aij", NULL};

/* The name becomes a directory under output/: it must stay one path component there. */
static PetscErrorCode CheckName(const char *name) {
  PetscFunctionBeginUser;
  for (const char *p = name; *p; p++) {
    PetscCheck(*p != '/' && *p != '\\', PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option -pd_name: '%s' holds a path separator", name);
    PetscCheck((unsigned char)*p >= 0x20 && *p != 0x7f, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option -pd_name: holds a control character");
  }
  PetscCheck(!strstr(name, ".."), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option -pd_name: '%s' holds '..'", name);
  PetscCheck(strcmp(name, "."), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Option -pd_name: '.' names no directory of its own");
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadBody(PetscOptionItems *PetscOptionsObject, MPI_Comm comm, PDScene *sc) {
  PetscInt  model = PD_MODEL_3D, n;
  PetscReal dom[6];
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_model", &model, NULL));
  sc->model = (PDModelKind)model;
  sc->dim   = sc->model == PD_MODEL_3D ? 3 : 2;
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_thickness", &sc->thickness, NULL));
  n = 2 * sc->dim;
  PetscCall(PetscArrayzero(dom, 6));
  PetscCall(PDOptionRealArray(PetscOptionsObject, sc, "-pd_domain", dom, &n, &set));
  PetscCheck(set, comm, PETSC_ERR_USER_INPUT, "Option -pd_domain is required: give a scene with -options_file scene.opts");
  PetscCheck(n == 2 * sc->dim, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_domain: expected %" PetscInt_FMT " numbers for a %" PetscInt_FMT "D model, got %" PetscInt_FMT, 2 * sc->dim,
             sc->dim, n);
  for (PetscInt a = 0; a < 3; a++) {
    sc->domain[a]     = a < sc->dim ? dom[a] : 0;
    sc->domain[3 + a] = a < sc->dim ? dom[sc->dim + a] : 0;
    PetscCheck(a >= sc->dim || sc->domain[3 + a] > sc->domain[a], comm, PETSC_ERR_USER_INPUT,
               "Option -pd_domain: upper corner must exceed lower corner along %c", (char)('x' + a));
  }
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_dx", &sc->dx, &set));
  PetscCheck(set, comm, PETSC_ERR_USER_INPUT, "Option -pd_dx is required");
  for (PetscInt a = 0; a < sc->dim; a++)
    PetscCheck(sc->dx <= sc->domain[3 + a] - sc->domain[a] + 1e-12, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_dx: %g exceeds the domain size along %c", (double)sc->dx, (char)('x' + a));
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadDiscretisation(PetscOptionItems *PetscOptionsObject, PDScene *sc) {
  PetscInt v = 0;

  PetscFunctionBeginUser;
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_horizon_ratio", &sc->horizon_ratio, NULL));
  {
    /* a horizon past the body's longest side bonds every node to every other: no local model is left,
       and the stencil of lattice offsets would outgrow memory */
    PetscReal side = 0;
    for (PetscInt a = 0; a < sc->dim; a++) side = PetscMax(side, sc->domain[3 + a] - sc->domain[a]);
    PetscCheck(sc->horizon_ratio * sc->dx <= side, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
               "Option -pd_horizon_ratio: %g makes the horizon %g m, longer than the body's longest side %g m", (double)sc->horizon_ratio,
               (double)(sc->horizon_ratio * sc->dx), (double)side);
  }
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_influence", &v, NULL));
  sc->influence = (PDInfluence)v;
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_partial_volume", &sc->partial_volume, NULL));
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_surface_correction", &sc->surface_correction, NULL));
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_sc_notch_surface", &sc->notch_surface, NULL));
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_sc_whole_cells", &sc->sc_whole_cells, NULL));
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_calibration", &v, NULL));
  sc->calibration = (PDCalibration)v;
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_kinematics", &v, NULL));
  sc->kinematics = (PDKinematics)v;
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_stretch", &v, NULL));
  sc->stretch = (PDStretch)v;
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_strength_scatter", &sc->strength_scatter, NULL));
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_sc_correction", &sc->sc_correction, NULL));
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_gf_lattice", &sc->gf_lattice, NULL));
  PetscFunctionReturn(0);
}

/* The curve's load and displacement, the CMOD gauge and the load steps. */
static PetscErrorCode ReadLoadPath(PetscOptionItems *PetscOptionsObject, MPI_Comm comm, PDScene *sc) {
  PetscReal pts[6] = {0, 0, 0, 0, 0, 0};
  PetscInt  n      = 2 * sc->dim;

  PetscFunctionBeginUser;
  sc->load_regions[0] = -1;
  for (PetscInt k = 0; k < sc->nregions && sc->load_regions[0] < 0; k++)
    if (sc->region[k].kind == PD_REGION_FORCE || sc->region[k].kind == PD_REGION_DISPLACEMENT) sc->load_regions[0] = k;
  sc->nload_regions = 1;
  PetscCall(PDOptionIntArray(PetscOptionsObject, sc, "-pd_load_region", sc->load_regions, PD_MAX_REGIONS, &sc->nload_regions, NULL));
  for (PetscInt i = 0; i < sc->nload_regions; i++) {
    const PetscInt r = sc->load_regions[i];
    PetscCheck(r >= 0 && r < sc->nregions && (sc->region[r].kind == PD_REGION_FORCE || sc->region[r].kind == PD_REGION_DISPLACEMENT), comm,
               PETSC_ERR_USER_INPUT, "Option -pd_load_region: %" PetscInt_FMT " is not a force or displacement region", r);
    /* one kind: a curve adds applied forces or reactions, not one to the other */
    PetscCheck(sc->region[r].kind == sc->region[sc->load_regions[0]].kind, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_load_region: region %" PetscInt_FMT " is a %s region, region %" PetscInt_FMT
               " a %s one; list regions of one kind",
               r, PDRegionKinds[sc->region[r].kind], sc->load_regions[0], PDRegionKinds[sc->region[sc->load_regions[0]].kind]);
    for (PetscInt j = 0; j < i; j++)
      PetscCheck(sc->load_regions[j] != r, comm, PETSC_ERR_USER_INPUT, "Option -pd_load_region: region %" PetscInt_FMT " is listed twice",
                 r);
  }
  sc->disp_region = sc->load_regions[0];
  PetscCall(PDOptionInt(PetscOptionsObject, sc, "-pd_disp_region", &sc->disp_region, NULL));
  PetscCheck(sc->disp_region >= 0 && sc->disp_region < sc->nregions, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_disp_region: %" PetscInt_FMT " is not a region", sc->disp_region);
  PetscCall(PDOptionRealArray(PetscOptionsObject, sc, "-pd_cmod_points", pts, &n, &sc->has_cmod));
  if (sc->has_cmod) {
    PetscCheck(n == 2 * sc->dim, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_cmod_points: expected %" PetscInt_FMT " numbers, got %" PetscInt_FMT, 2 * sc->dim, n);
    for (PetscInt p = 0; p < 2; p++)
      for (PetscInt a = 0; a < 3; a++) {
        sc->cmod[3 * p + a] = a < sc->dim ? pts[sc->dim * p + a] : 0;
        PetscCheck(a >= sc->dim || (sc->cmod[3 * p + a] >= sc->domain[a] && sc->cmod[3 * p + a] <= sc->domain[3 + a]), comm,
                   PETSC_ERR_USER_INPUT, "Option -pd_cmod_points: point %" PetscInt_FMT " lies outside the domain", p + 1);
      }
  }
  PetscCall(PDOptionInt(PetscOptionsObject, sc, "-pd_steps", &sc->steps, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_lambda_max", &sc->lambda_max, NULL));
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_stop_cmod", &sc->stop_cmod, NULL));
  PetscCheck(sc->stop_cmod == 0 || sc->has_cmod, comm, PETSC_ERR_USER_INPUT,
             "Option -pd_stop_cmod: the scene has no CMOD gauge (-pd_cmod_points)");
  PetscCall(PDOptionReal(PetscOptionsObject, sc, "-pd_section_x", &sc->section_x, &sc->has_section));
  if (sc->has_section) {
    /* the plane goes halfway between two node columns, first + (k - 1/2) dx, so that no bond lies in it */
    PetscReal       first;
    const PetscInt  n = PDSceneLayers(sc, 0, &first);
    const PetscReal k = PetscFloorReal((sc->section_x - first) / sc->dx + 1);
    PetscCheck(k >= 1 && k <= n - 1, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_section_x: %g m is not inside the body along x (%g to %g m, node columns %g m apart)", (double)sc->section_x,
               (double)sc->domain[0], (double)sc->domain[3], (double)sc->dx);
    PetscCheck(sc->kinematics == PD_KINEMATICS_SMALL, comm, PETSC_ERR_USER_INPUT,
               "Option -pd_section_x: section forces are summed under small kinematics only (-pd_kinematics small)");
    sc->section_x = first + (k - 0.5) * sc->dx;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadOutput(PetscOptionItems *PetscOptionsObject, PDScene *sc) {
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(sc->output_dir, sizeof sc->output_dir, "output/%s", sc->name));
  PetscCall(PDOptionString(PetscOptionsObject, sc, "-pd_output_dir", sc->output_dir, sizeof sc->output_dir, NULL));
  PetscCall(PDOptionString(PetscOptionsObject, sc, "-pd_data_file", sc->data_file, sizeof sc->data_file, NULL));
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_progress", &sc->progress, NULL));
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_dry_run", &sc->dry_run, NULL));
  PetscFunctionReturn(0);
}

/* A relative data path in a scene is taken relative to the directory of the options file, so that a
   scene runs from any working directory. */
static PetscErrorCode ResolveNextToOptionsFile(char *path, size_t len) {
  int    argc;
  char **argv;
  char   dir[PETSC_MAX_PATH_LEN] = "", joined[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  if (path[0] == '/') PetscFunctionReturn(0);
  PetscCall(PetscGetArgs(&argc, &argv));
  for (int i = 1; i + 1 < argc; i++) {
    PetscBool is;
    PetscCall(PetscStrcmp(argv[i], "-options_file", &is));
    if (is) PetscCall(PetscStrncpy(dir, argv[i + 1], sizeof dir));
  }
  {
    char *slash = strrchr(dir, '/');
    if (!slash) PetscFunctionReturn(0);
    slash[1] = '\0';
  }
  PetscCall(PetscSNPrintf(joined, sizeof joined, "%s%s", dir, path));
  PetscCall(PetscStrncpy(path, joined, len));
  PetscFunctionReturn(0);
}

PetscErrorCode PDSceneCreateFromOptions(MPI_Comm comm, PDScene *sc) {
  PetscInt mode = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(sc, sizeof *sc));
  PetscCall(PDOptionsCheckNames());
  PetscOptionsBegin(comm, NULL, "pdimplicit scene", NULL);
  PetscCall(PDOptionString(PetscOptionsObject, sc, "-pd_name", sc->name, sizeof sc->name, NULL));
  PetscCall(CheckName(sc->name));
  PetscCall(PDOptionEnum(PetscOptionsObject, sc, "-pd_mode", &mode, NULL));
  sc->explicit_mode = mode == 1 ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PDOptionBool(PetscOptionsObject, sc, "-pd_failure_search", &sc->failure_search, NULL));
  if (sc->failure_search) sc->explicit_mode = PETSC_TRUE;
  PetscCall(ReadBody(PetscOptionsObject, comm, sc));
  PetscCall(ReadDiscretisation(PetscOptionsObject, sc));
  PetscCall(PDSceneReadParts(PetscOptionsObject, sc));
  PetscCall(PDSceneReadBars(PetscOptionsObject, sc));
  PetscCall(ReadLoadPath(PetscOptionsObject, comm, sc));
  PetscCall(PDSceneReadSolution(PetscOptionsObject, comm, sc));
  PetscCall(ReadOutput(PetscOptionsObject, sc));
  PetscOptionsEnd();
  if (sc->data_file[0]) {
    PetscBool exists;
    PetscCall(ResolveNextToOptionsFile(sc->data_file, sizeof sc->data_file));
    PetscCall(PetscTestFile(sc->data_file, 'r', &exists));
    PetscCheck(exists, comm, PETSC_ERR_FILE_OPEN, "Option -pd_data_file: cannot read '%s'", sc->data_file);
  }
  PetscCall(PDOptionsCheckUnused(sc));
  PetscFunctionReturn(0);
}

PetscBool PDSceneHasDamage(const PDScene *sc) {
  for (PetscInt k = 0; k < sc->nmaterials; k++)
    if (sc->material[k].law != PD_LAW_ELASTIC) return PETSC_TRUE;
  for (PetscInt k = 0; k < sc->nbars; k++) /* a bond-slip law softens past its plateau */
    if (sc->bar[k].slip) return PETSC_TRUE;
  return PETSC_FALSE;
}

PetscBool PDSceneHasCrushingStrain(const PDScene *sc) {
  for (PetscInt k = 0; k < sc->nmaterials; k++)
    if (sc->material[k].eps_cu > 0) return PETSC_TRUE;
  return PETSC_FALSE;
}

PetscErrorCode PDSceneView(const PDScene *sc, PetscViewer v) {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(v, "Scene %s: %s, domain [%g %g %g] to [%g %g %g] m, dx %g m, horizon %g dx, influence %s\n", sc->name,
                                   PDModelKinds[sc->model], (double)sc->domain[0], (double)sc->domain[1], (double)sc->domain[2],
                                   (double)sc->domain[3], (double)sc->domain[4], (double)sc->domain[5], (double)sc->dx,
                                   (double)sc->horizon_ratio, PDInfluences[sc->influence]));
  PetscCall(PetscViewerASCIIPrintf(
      v, "  %" PetscInt_FMT " materials, %" PetscInt_FMT " notches, %" PetscInt_FMT " regions, %" PetscInt_FMT " steps, kinematics %s\n",
      sc->nmaterials, sc->nnotches, sc->nregions, sc->steps, PDKinematicsNames[sc->kinematics]));
  if (sc->nbars || sc->nplates || sc->nnofail || sc->nvoids)
    PetscCall(PetscViewerASCIIPrintf(
        v, "  %" PetscInt_FMT " steel bars, %" PetscInt_FMT " bearing plates, %" PetscInt_FMT " no-fail zones, %" PetscInt_FMT " voids\n",
        sc->nbars, sc->nplates, sc->nnofail, sc->nvoids));
  PetscFunctionReturn(0);
}
