/* Scene: what is simulated, read from PETSc options and validated. No numerics here. */
#pragma once
#include <petscsys.h>
#include <math.h>

#define PD_NAN ((PetscReal)NAN) /* PETSc 3.18 has no NaN constant */

#define PD_MAX_MATERIALS 8
#define PD_MAX_NOTCHES 8
#define PD_MAX_REGIONS 16
#define PD_MAX_VOIDS 16
#define PD_MAX_BARS 16
#define PD_MAX_NOFAIL 16
#define PD_NAME_LEN 256

typedef enum { PD_MODEL_3D, PD_MODEL_PLANE_STRESS, PD_MODEL_PLANE_STRAIN } PDModelKind;
typedef enum { PD_INFLUENCE_CONSTANT, PD_INFLUENCE_CONICAL, PD_INFLUENCE_QUARTIC } PDInfluence;
typedef enum { PD_KINEMATICS_SMALL, PD_KINEMATICS_FINITE } PDKinematics;
typedef enum { PD_CALIBRATION_CONTINUUM, PD_CALIBRATION_STENCIL } PDCalibration;
/* PD_LAW_SLIP is no material's: the law of a bar's bond-slip links (docs/reinforcement.md) */
typedef enum { PD_LAW_ELASTIC, PD_LAW_LINEAR, PD_LAW_BILINEAR, PD_LAW_TRILINEAR, PD_LAW_NONLINEAR, PD_LAW_SLIP } PDLawKind;
typedef enum { PD_STRETCH_EXACT, PD_STRETCH_MODIFIED } PDStretch;
typedef enum { PD_CONTROL_DISPLACEMENT, PD_CONTROL_FORCE, PD_CONTROL_ARCLENGTH, PD_CONTROL_AUTO } PDControl;
typedef enum { PD_ARC_SPHERICAL, PD_ARC_CYLINDRICAL, PD_ARC_CMOD, PD_ARC_DISSIPATION } PDArcType;
typedef enum { PD_TANGENT_CONSISTENT, PD_TANGENT_SECANT } PDTangent;
typedef enum { PD_PC_MATRIX_TANGENT, PD_PC_MATRIX_SECANT } PDPCMatrix;
typedef enum { PD_TANGENT_PRODUCT_BONDS, PD_TANGENT_PRODUCT_MATRIX } PDTangentProduct;
typedef enum { PD_SHAPE_BOX, PD_SHAPE_CYLINDER } PDShape;
typedef enum { PD_REGION_SUPPORT, PD_REGION_DISPLACEMENT, PD_REGION_FORCE, PD_REGION_MONITOR } PDRegionKind;
typedef enum { PD_FAILURE_DAMAGE, PD_FAILURE_VELOCITY, PD_FAILURE_FORCE } PDFailureCriterion;
/* Value types of the option schema (src/scene/schema.h). A prefix stands for the options of a PETSc object. */
typedef enum {
  PD_OPTION_REAL,
  PD_OPTION_INT,
  PD_OPTION_BOOL,
  PD_OPTION_ENUM,
  PD_OPTION_STRING,
  PD_OPTION_REALS,
  PD_OPTION_INTS,
  PD_OPTION_PREFIX
} PDOptionType;

extern const char *const PDModelKinds[];
extern const char *const PDInfluences[];
extern const char *const PDKinematicsNames[];
extern const char *const PDCalibrationNames[];
extern const char *const PDLawNames[];
extern const char *const PDStretchNames[];
extern const char *const PDControlNames[];
extern const char *const PDArcTypes[];
extern const char *const PDTangentNames[];
extern const char *const PDPCMatrixNames[];
extern const char *const PDTangentProductNames[];
extern const char *const PDShapes[];
extern const char *const PDRegionKinds[];
extern const char *const PDFailureCriteria[];
extern const char *const PDModes[];
extern const char *const PDMatTypes[];

/* An option the scene read, for the echo in summary.json: the value in canonical text (reals as the
   shortest text that reads back exactly, lists comma-separated, names as the schema spells them), or
   NULL where the value is not known before the model is built. */
typedef struct {
  char         name[48];
  PDOptionType type;
  PetscBool    set; /* given in the options, not the default */
  char        *value;
} PDOptionValue;

/* Geometry shared by materials and node regions. A box that has zero extent along an axis selects
   the layer of nodes whose cells it cuts (nodes within dx/2 of that plane). */
typedef struct {
  PDShape   shape;
  PetscReal box[6];    /* lo x,y,z then hi x,y,z */
  PetscInt  axis;      /* cylinder axis 0,1,2 */
  PetscReal center[3]; /* cylinder: a point on the axis */
  PetscReal radius;    /* cylinder radius */
} PDGeometry;

typedef struct {
  char       option[32]; /* option prefix, e.g. "-pd_material1", for messages */
  PDGeometry where;      /* material 0 covers the whole domain */
  PetscReal  E, rho;
  PDLawKind  law;
  PetscReal  ft, Gf;   /* tensile strength (Pa), fracture energy (N/m) */
  PetscReal  fc;       /* compressive strength (Pa) that raises tensile thresholds under compression; 0: off */
  PetscReal  eps_cu;   /* ultimate compressive strain: a run stops as crushed once a bond's stretch reaches -eps_cu; 0: off */
  PetscReal  kr;       /* bilinear sc/s0 (Zaccariotto form) */
  PetscBool  bobaru;   /* bilinear in the Bobaru form, s0 = ft/E */
  PetscReal  beta;     /* trilinear */
  PetscReal  k, alpha; /* non-linear */
} PDMaterial;

typedef struct {
  char      option[32];
  PetscReal box[6]; /* flat along exactly one axis: the notch plane */
  PetscInt  normal; /* axis of the flat direction */
} PDNotch;

/* A void: a box or cylinder of the domain without material (the same shape describes a no-fail zone). Its nodes keep their lattice place
   (global ids stay lattice indices) but get no bonds; they are pinned and left out of regions and output. */
typedef struct {
  char       option[32];
  PDGeometry where;
} PDVoid;

/* A straight steel bar along a lattice direction (docs/reinforcement.md): an axis, a diagonal, or any
   lattice offset within the horizon. Its line is laid on the chain of nodes from the node nearest to its
   start, one offset apart; every pair of consecutive nodes on it carries a bar segment of axial stiffness
   E_s A_s and yield force f_y A_s beside the concrete bond of the same pair (perfect bond: the bar shares
   the nodes). */
typedef struct {
  char      option[32];
  PetscReal line[6];   /* end points, x,y,z each */
  PetscInt  step[3];   /* the lattice offset between consecutive nodes of its chain, pointing from start to end */
  PetscReal diameter;  /* m */
  PetscInt  count;     /* identical bars lumped on the line (across a 2D model's thickness) */
  PetscReal E, fy;     /* Pa */
  PetscReal hardening; /* post-yield tangent over E (0: perfectly plastic) */
  PetscReal rupture;   /* strain at which the bar breaks; 0: never */
  PetscBool perfect;   /* interface bonds (bar node to concrete node) never fail (the thesis); else they are concrete */
  /* embedded (docs/reinforcement.md, "Bars in any direction"): off the lattice directions, or asked for; the bar on
     nodes of its own at its true places, tied to the concrete through anchor nodes */
  PetscBool embedded;
  PetscReal dir[3][3]; /* unit vectors: along the bar (a chain's: along its step), then, embedded, across it (one in 2D,
                          two in 3D) */
  PetscInt  nstation;  /* embedded: its nodes, ceil(length / dx) + 1 evenly along it, ends included */
  PetscReal spacing;   /* embedded: the distance between them (m) */
  /* bond slip (docs/reinforcement.md): the bar on nodes of its own, tied to the concrete by the fib Model Code 2010
     bond stress-slip law of ribbed bars in pull-out (good bond) */
  PetscBool slip;
  PetscReal fcm;      /* mean compressive strength of the concrete (Pa): tau_max = 2.5 sqrt(f_cm) in MPa */
  PetscReal slips[3]; /* s1, s2, s3 (m): end of the rise, end of the plateau, end of the fall (the clear rib spacing) */
} PDBar;

typedef struct {
  char         option[32];
  PDGeometry   where;
  PDRegionKind kind;
  PetscBool    dof[3];    /* support/displacement: constrained components */
  PetscReal    vector[3]; /* displacement (m) or total force (N) at load factor 1 */
  PetscBool    on_bars;   /* selects the nodes of bars with bond slip instead of the concrete's (-pd_regionK_nodes) */
} PDRegion;

typedef struct {
  char          name[PD_NAME_LEN];
  char          output_dir[PETSC_MAX_PATH_LEN];
  char          data_file[PETSC_MAX_PATH_LEN]; /* experimental curve overlaid on curve.svg */
  PDModelKind   model;
  PetscInt      dim; /* 2 or 3, derived from model */
  PetscReal     thickness;
  PetscReal     domain[6];
  PetscReal     dx, horizon_ratio;
  PDInfluence   influence;
  PetscBool     partial_volume, surface_correction;
  PetscBool     notch_surface;  /* notch faces count as free surfaces in the surface correction */
  PetscBool     sc_whole_cells; /* surface correction: family volume counts neighbour cells whole (PeriPy) */
  PDCalibration calibration;    /* bond constants from the continuum integral or from the lattice stencil */
  PDKinematics  kinematics;
  PDStretch     stretch;
  PetscBool     sc_correction;    /* per-bond critical stretch from lambda_ij c */
  PetscBool     gf_lattice;       /* critical stretches from the lattice's own crack-plane bond sum, not the continuum */
  PetscReal     strength_scatter; /* per-bond tensile strength f_t (1 + r xi), xi uniform in [-1, 1] by bond id; 0: none */
  PDControl     control;
  /* path following (-pd_control arclength|auto) */
  PDArcType        arc_type;       /* constraint */
  PetscBool        arc_augmented;  /* linear constraints: one augmented solve per Newton iteration, not two (bordering) */
  PetscReal        arc_initial;    /* first arc length (units of the constraint); 0: from the first load step */
  PetscReal        arc_growth;     /* largest arc length over the first one */
  PetscInt         arc_target_its; /* Newton iterations per step the adaptive arc length aims at */
  PetscReal        arc_rtol;       /* equilibrium: |residual| below this times |f_int|; 0: the path's default */
  PetscBool        arc_secant;     /* an IMPL-EX step under the augmented corrector starts from the last step, not a direction solve */
  PetscBool        arc_guess;      /* the path direction's Krylov solve starts from the last direction */
  PetscInt         arc_halved_its; /* halved Newton updates allowed before a step is cut; 0: the whole budget */
  PetscInt         arc_hold;       /* accepted steps after a cut during which the arc length does not grow */
  PetscReal        arc_implex;     /* > 0: IMPL-EX (damage extrapolated, secant steps), the error per step aimed at; 0: implicit */
  PetscReal        stop_fraction;  /* after the peak, stop with status separated below this fraction of it; 0: off */
  PetscReal        unload_at;      /* after the peak, reverse the path once the load falls to this fraction of it; 0: off */
  PetscReal        reload_at;      /* while unloading, load again once the load falls to this fraction of the peak */
  PDTangent        tangent;
  PetscReal        steel_tangent_floor;   /* least slope, over E, a yielded bar segment gives Newton's tangent */
  PDPCMatrix       pc_matrix;             /* matrix the preconditioner is built from: the tangent, or the secant one */
  PetscReal        pc_reach;              /* bonds up to this length (grid spacings) in the preconditioning matrix; 0: all; -1: default */
  PetscBool        assembly_changed_rows; /* later assemblies rewrite only rows with a changed bond tangent */
  PDTangentProduct tangent_product;       /* Newton's operator: products from the bond scalars, or the assembled matrix */
  PetscBool        stencil_product;       /* those products loop over the stencil offsets (3D, no bar nodes) */
  PetscBool        tangent_with_residual; /* Newton's tangent scalars from the residual's bond loop */
  PetscBool        residual_rows;         /* after a limiter grant, the residual recomputes only the rows it changed */
  PetscBool        diagonal_index;        /* an AIJ stiffness's diagonal read through an index of its positions */
  PetscInt         limiter_max;           /* bond events granted per Newton iteration; 0: no cap; -1: by bond count */
  PetscInt         limiter_stage_its;     /* Newton iterations between grants while events are pending */
  PetscInt         limiter_sublevels;     /* limiter levels on the softening branch (1: one, s0 to sc) */
  PetscBool        limiter_settle_first;  /* load/displacement control: equilibrium before the increment's first grant */
  PetscReal        lambda_max;            /* end of the load path */
  PetscReal        dlambda_min, dlambda_max;
  PetscReal        stop_cmod; /* stop once the CMOD gauge opens this much (m); 0: off */
  PetscInt         nmaterials, nnotches, nregions, nvoids, nbars, nnofail;
  PetscInt         nplates;                    /* bearing plates (-pd_plateK_*), kept as elastic materials after the nmaterials given */
  PDMaterial       material[PD_MAX_MATERIALS]; /* the materials given, then the plates' */
  PDNotch          notch[PD_MAX_NOTCHES];
  PDRegion         region[PD_MAX_REGIONS];
  PDVoid           voids[PD_MAX_VOIDS];
  PDBar            bar[PD_MAX_BARS];
  PDVoid           nofail[PD_MAX_NOFAIL];        /* no-fail zones: the bonds of their nodes stay elastic (Ness) */
  PetscInt         nload_regions;                /* regions whose forces or reactions add up to the curve's load */
  PetscInt         load_regions[PD_MAX_REGIONS]; /* the first's kind and direction set the control */
  PetscInt         disp_region;                  /* region whose mean displacement is the curve's displacement */
  PetscBool        has_cmod;
  PetscBool        has_section;      /* -pd_section_x given */
  PetscReal        section_x;        /* its plane, halfway between two node columns (m) */
  PetscReal        cmod[6];          /* two gauge points */
  PetscInt         steps;            /* load steps */
  PetscBool        bar_mass_scaling; /* explicit: bar nodes' mass raised to the concrete's stable step */
  PetscBool        predictor;        /* load/displacement control: secant predictor from the last increment */
  PetscBool        control_fallback; /* load/displacement control: path following where it finds no equilibrium */
  PetscInt         fields_every;
  PetscInt         checkpoint_every;            /* path following: write checkpoint.h5 every N accepted steps; 0: only when stopped early */
  char             restart[PETSC_MAX_PATH_LEN]; /* path following: checkpoint to go on from, or empty */
  PetscBool        progress;
  PetscBool        dry_run;     /* build the scene and report it, do not solve */
  char             mat_type[8]; /* stiffness storage (-pd_mat_type), or empty for the default */
  PetscBool        pc_chosen;   /* -pc_type given: the user's preconditioner stands (read once, with the scene) */
  PetscBool        pc_aij;      /* the preconditioner or factorisation package chosen cannot read symmetric block storage */
  /* explicit path (-pd_mode explicit) */
  PetscBool explicit_mode;
  PetscReal ramp_time;       /* smoothstep ramp of the load factor from 0 to lambda_max (s); 0: 20,000 steps */
  PetscReal hold_time;       /* time after the ramp, at lambda_max (s) */
  PetscReal explicit_cmod;   /* CMOD control: the gauge's opening at the end of the ramp (m); 0: the load factor is ramped */
  PetscReal servo_bandwidth; /* CMOD control: the servo's frequency over the body's fundamental one */
  PetscReal dt_safety;       /* fraction of the stable time step */
  PetscInt  dt_power_its;    /* power iterations for the largest eigenvalue of M^-1 K */
  PetscReal damping;         /* local damping C (kg/(m^3 s)) */
  PetscBool adr;             /* adaptive dynamic relaxation: fictitious masses, unit steps, adaptive damping */
  PetscInt  out_stride;      /* time steps between curve rows; 0: about 400 rows */
  /* failure search (-pd_failure_search): explicit trials held at constant loads, geometric bisection */
  PetscBool          failure_search;
  PDFailureCriterion failure_criterion;
  PetscReal          failure_bracket[2]; /* first lower and upper test loads (N); 0: half and twice the scene's load */
  PetscReal          failure_tol;        /* stop when (upper - lower) / lower is below this */
  PetscReal          failure_vtol;       /* velocity decay: mean loaded-node speed over its largest value in the trial */
  PetscReal          failure_ftol;       /* force decay: mean out-of-balance over applied force at the loaded nodes */
  PetscReal          failure_dtol;       /* bond damage: fraction of bonds broken per time step counted as still */
  PetscReal          failure_window;     /* bond damage: time (s) damage stays still, or load and velocity stay aligned */
  PetscInt           noptions;           /* options read, in the order read */
  PDOptionValue     *options;
} PDScene;

/* The lattice's node layers along axis a < dim: their number, and the first one's coordinate (nodes sit at cell
   centres; when dx does not divide the box, the lattice is centred in it). */
static inline PetscInt PDSceneLayers(const PDScene *sc, PetscInt a, PetscReal *first) {
  const PetscReal len = sc->domain[3 + a] - sc->domain[a];
  const PetscInt  n   = PetscMax(1, (PetscInt)PetscFloorReal(len / sc->dx + 0.5));
  *first              = sc->domain[a] + 0.5 * (len - n * sc->dx) + 0.5 * sc->dx;
  return n;
}

/* A bar's steel area A_s = count pi d^2 / 4 (m^2). */
static inline PetscReal PDBarArea(const PDBar *b) {
  return b->count * PETSC_PI * b->diameter * b->diameter / 4;
}

/* Reads and validates the scene. Every -pd_ option given must belong to the schema and be used by the
   scene; anything else is an input error naming the option (and the closest valid name). */
PetscErrorCode PDSceneCreateFromOptions(MPI_Comm, PDScene *);
PetscErrorCode PDSceneDestroy(PDScene *);
/* -help: every -pd_ option with its type, default, range and help, and whether the scene (NULL: none
   could be read, for the reason in note) uses it. */
PetscErrorCode PDSceneOptionsHelp(MPI_Comm, const PDScene *, const char *note);
/* The README's option table, in Markdown (-pd_help_markdown). */
PetscErrorCode PDSceneOptionsMarkdown(MPI_Comm);
PetscErrorCode PDSceneView(const PDScene *, PetscViewer);
/* Whether a material has a law that damages bonds (every law but elastic), or a bar's bond slips. */
PetscBool PDSceneHasDamage(const PDScene *);
/* Whether a material has an ultimate compressive strain (-pd_eps_cu): the crushing criterion is on. */
PetscBool PDSceneHasCrushingStrain(const PDScene *);
/* Whether a region holds the node at x. A box with zero extent along an axis selects one layer of nodes:
   the nearest to its plane; a plane halfway between two layers takes the upper one, except on the
   domain's upper face, where it takes the layer below. */
PetscBool PDGeometryContains(const PDGeometry *, const PetscReal x[3], const PDScene *);
