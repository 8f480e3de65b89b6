/* Model: the single bond loop (internal force, tangent), boundary conditions and measurements. */
#pragma once
#include "pd_lattice.h"
#include "pd_material.h"
#include <petscsnes.h>

/* Where each local node's internal force gathers from in the bond arrays (kernel.c PDModelInternalForceRows) */
typedef struct {
  PetscBool ready, usable;
  PetscInt *run_start, *run_end; /* [nlocal] the bonds the node starts */
  PetscInt *end_off, *end_bond;  /* CSR by node of the bonds that end at it, in bond order */
} PDModelRowIndex;

typedef struct {
  const PDScene   *scene;
  const PDLattice *lat;
  const PDBonds   *bonds;
  PetscInt         bs;               /* dofs per node: 2 or 3 */
  PetscBool        linear;           /* elastic law with small kinematics: K u = f, one solve per step */
  PetscReal        lambda;           /* current load factor */
  PetscReal        bc_scale;         /* diagonal given to constrained dofs, of the order of a bond stiffness */
  PetscReal        force_scale;      /* size of the load at lambda = 1 (N), for absolute tolerances */
  Vec              u_local;          /* ghosted work copy of the displacement */
  Vec              f_local;          /* ghosted work vector for internal forces */
  Vec              x_local;          /* ghosted work vector for tangent products (created on first use) */
  PetscReal       *ka, *kb;          /* bond tangent scalars, NULL while constant (kb also under small kinematics) */
  PetscReal       *kp;               /* ka of the secant preconditioning matrix (-pd_pc_matrix secant), or NULL */
  PetscBool        ka_with_residual; /* the residual computes ka and kb too (model.c PDModelResidual) */
  PetscBool        ka_at_residual;   /* ka and kb are those of the last residual, */
  Vec              ka_u;             /* at this displacement */
  PetscReal        ka_lambda;        /* and this load factor */
  /* a residual at the displacement of the last one, after a limiter grant, recomputes only the rows of the
     bonds the grant changed (PDModelResidual, -pd_residual_rows) */
  PetscBool track_grants;     /* the limiter records the bonds it changes */
  PetscBool rows_after_grant; /* set by the driver after a grant, taken by the next residual */
  PetscInt *changed;          /* bonds whose level changed since the last residual */
  PetscInt  nchanged;         /* their count; -1: too many to be worth it */
  PetscInt  changed_cap;
  Vec       r_last; /* the last residual, at ka_u and ka_lambda */
  /* path following under IMPL-EX: the internal force of the last residual's whole loop (at ka_u and
     ka_lambda), and the bonds whose force an accepted step's history commit changes, with their force
     (over the bond's length) before it, so that PDModelMeasure updates that force bond by bond */
  PetscBool       keep_force; /* set by the driver (with ka_with_residual): keep f_last */
  PetscBool       f_last_valid;
  Vec             f_last;
  PetscBool       fchange_ready; /* fchange_bond lists the bonds whose force changes since f_last */
  PetscInt       *fchange_bond, nfchange, fchange_cap;
  PetscReal      *fchange_g;
  PetscInt        forces_by_change;  /* accepted steps' forces so evaluated */
  PetscInt        residuals_by_rows; /* residuals so evaluated */
  PDModelRowIndex rows;
  PDLaw           law[PD_MATERIALS_ALL]; /* the materials', an elastic one for PD_MATERIAL_ELASTIC, the bars' bond slip */
  PDSteel         steel[PD_MAX_BARS];    /* the steel of each bar */
  PetscBool       softening;             /* some bond law softens or breaks: bonds carry history */
  PetscBool       gamg_after_icc;        /* ICC(0) failed on the tangent: algebraic multigrid from then on */
  /* per-bond history, allocated only when softening */
  PetscReal     *kappa;                   /* largest stretch reached, committed at accepted steps */
  unsigned char *level;                   /* PDBondLevel the limiter allows the bond to reach */
  unsigned char *level_n;                 /* levels at the last accepted step, to restart a step */
  PetscReal      onset[PD_MATERIALS_ALL]; /* per material, the smallest min(s0, sc) of its bonds on this rank: a
                                             bond whose stretch and history stay below it is elastic, and its
                                             thresholds need not be evaluated */
  PetscReal     *shift;                   /* [nbonds] rise of the thresholds under compression (-pd_fc), or NULL */
  Vec            dilatation;              /* ghosted nodal dilatation for that rise, or NULL */
  unsigned char *branch;                  /* path following: per-bond PDBranch frozen for a stage, or NULL */
  PetscBool      faces;                   /* branch's PD_BRANCH_SIDE bits are in force (PDModelFreezeSides) */
  PetscInt       limiter_max;             /* bond events granted per Newton iteration; 0: no cap */
  PetscReal      pc_reach;                /* longest bond of the preconditioning matrix, in grid spacings; 0: every bond */
  PetscBool      commit_history;          /* explicit path: every force evaluation raises kappa */
  PetscReal     *sp_n;                    /* [nseg] plastic stretch of each bar segment, committed at accepted steps */
  PetscBool     *ruptured_n;              /* [nseg] the segment has broken (committed) */
  PetscReal     *dissipated_n;            /* [nseg] energy the segment dissipated (J): s_y E A L0 times its accumulated
                                             plastic stretch, and the elastic energy it held when it broke */
  PetscInt  *slip_bond;                   /* [nslip] the bond-slip links (bars with bond slip) */
  PetscInt   nslip;
  PetscInt   yielded;                       /* bar segments with plastic stretch, or broken (global, counted once) */
  PetscInt64 broken;                        /* bonds broken (global, counted once) at the last accepted step */
  PetscInt64 softening_bonds;               /* bonds on the softening branch, not broken (global) */
  PetscInt   nregularised, max_regularised; /* free dofs left without stiffness by damage */
  Vec        f_ref;                         /* external force at load factor 1 (global) */
  Vec        u_ref;                         /* prescribed displacement at load factor 1 (global, zero on free dofs) */
  Vec        fixed;                         /* 1 on constrained dofs, 0 elsewhere (global) */
  PetscBool *fixed_local;                   /* [bs*nlocal] constrained flags including ghosts */
  PetscReal *uref_local;                    /* [bs*nlocal] prescribed values at load factor 1 including ghosts */
  Vec        load_pattern;                  /* unit direction on the load regions' nodes, each its own */
  Vec        disp_pattern;                  /* unit direction / count on the displacement region's nodes */
  Vec        cmod_pattern;                  /* -e on gauge point 1, +e on gauge point 2 */
  Vec        f_work;                        /* internal force for measurements (global) */
  PetscReal  force_magnitude;
  PetscInt   nconstrained;  /* global constrained dofs */
  PetscInt   nisolated;     /* global nodes without any bond, pinned */
  PetscInt   nzero_dofs;    /* global free dofs without stiffness (isolated nodes, notch planes), pinned */
  PetscInt64 history_bytes; /* per-bond history storage allocated (0 for elastic scenes) */
  PetscInt   nsection;      /* -pd_section_x: this rank's bonds across the plane, each counted once (section.c) */
  PetscInt  *section_bonds; /* their ids, found at the first cut (NULL before) */
  PetscInt   jacobian_assemblies;
  PetscInt64 rows_assembled;         /* node rows this rank has written into stiffness matrices (assembly.c) */
  PetscReal  t_assembly, t_residual; /* seconds spent in the Jacobian and residual */
} PDModel;

/* A softened bond's force has a kink at its largest stretch (softening beyond it, secant below it), and
   Newton can cycle across it. Frozen on one branch, the force is smooth; path following freezes the
   bonds that cycle and flips those that end up on the wrong side (see arclength.c). */
typedef enum {
  PD_BRANCH_FREE,     /* loading beyond the history, secant below it */
  PD_BRANCH_SECANT,   /* secant at the committed history, whatever the stretch */
  PD_BRANCH_ENVELOPE, /* the softening envelope at the current stretch, whatever the history */
  PD_BRANCH_KINK,     /* the real law's force with the secant slope: a bond flipped back, whose equilibrium
                         lies at its kink (the slope keeps Newton from swapping its branch for ever) */
} PDBranch;
#define PD_BRANCH_MASK 3 /* the branch; the bit above marks a bond flipped once in this step */
#define PD_BRANCH_FLIPPED 4
/* A damaged bond is elastic in compression (its crack closed) and on its secant in tension (open): a kink at
   s = 0 where a crack's faces slide. An IMPL-EX step whose Newton cycles freezes each damaged bond on the side
   it had at the last accepted step (PDModelFreezeSides): open takes the secant in compression too, closed the
   elastic slope in tension too, and the step's equations are linear (docs/arclength.md, "Crack faces"). */
#define PD_BRANCH_OPEN 8
#define PD_BRANCH_CLOSED 16
#define PD_BRANCH_SIDE (PD_BRANCH_OPEN | PD_BRANCH_CLOSED)

PetscErrorCode PDModelCreate(const PDScene *, const PDLattice *, const PDBonds *, PDModel *);
/* Mass of a local node (kg): its material's density times the cell, or for a bar node the steel of its share of the bar. */
PetscReal      PDModelNodeMass(const PDModel *, PetscInt i);
PetscErrorCode PDModelDestroy(PDModel *);
/* Per-bond thresholds as built (strength scatter, surface correction), without crushing's rises. */
void PDModelResetThresholds(PDModel *);
#define PD_MAX_EFFECTS 12
PetscInt       PDModelEffects(const PDModel *, const char *names[PD_MAX_EFFECTS]);
PetscErrorCode PDModelCreateMatrix(PDModel *, PetscReal reach2, Mat *);
PetscErrorCode PDMatUseDiagonalIndex(Mat);
PetscErrorCode PDModelCreateOperators(PDModel *, Mat *J, Mat *P);
PetscErrorCode PDModelDestroyOperators(Mat *J, Mat *P);
PetscBool      PDModelDefaultsToGAMG(const PDModel *);
PetscErrorCode PDModelInternalForce(PDModel *, Vec u, Vec F);
PetscErrorCode PDModelResidual(SNES, Vec u, Vec R, void *);
PetscErrorCode PDModelJacobian(SNES, Vec u, Mat J, Mat P, void *);
PetscErrorCode PDModelApplyBoundaryValues(PDModel *, PetscReal lambda, Vec u);
PetscErrorCode PDModelMeasure(PDModel *, Vec u, PetscReal *load, PetscReal *disp, PetscReal *cmod);
/* Damage limiter: bonds whose stretch at u passes the threshold of their allowed level are candidates;
   the max_events most critical (ties by global bond id) move up one level. */
PetscErrorCode PDModelGrantEvents(PDModel *, Vec u, PetscInt max_events, PetscInt *ncandidates, PetscInt *granted);
PetscErrorCode PDModelInternalForceKeepTangent(PDModel *, Vec u, Vec F);
PetscErrorCode PDModelCommitHistory(PDModel *, Vec u, PetscReal energy[2], Vec u0, PetscReal lambda0, PetscReal *change);
/* Bond e's force over its length at u (local, small kinematics), recorded as one whose force the next history
   commit changes (m->fchange_bond; PDModelMeasure), up to an eighth of the bonds. */
PetscErrorCode PDModelNoteForceChange(PDModel *, const PetscScalar *u, PetscInt e);
/* The strain state at u that outlives it: where a criterion or a law reads it (-pd_fc, -pd_eps_cu), the
   nodes' dilatation into m->dilatation. PDModelCommitHistory takes it first. */
PetscErrorCode PDModelStrainState(PDModel *, Vec u);
/* Crushing (-pd_fc): raises the thresholds of bonds still elastic by their law's confine times the
   compression of their two nodes, from the last strain state; a rise is never taken back. */
PetscErrorCode PDModelConfine(PDModel *);
PetscErrorCode PDModelRestoreLevels(PDModel *);
PetscErrorCode PDModelFreezeBranches(PDModel *, Vec u, unsigned char *branch, PetscInt *nfrozen);
PetscErrorCode PDModelFlipBranches(PDModel *, Vec u, PetscInt *nflipped, PetscInt *nkink);
PetscErrorCode PDModelFreezeSides(PDModel *, Vec u, PetscInt *nfrozen);
PetscErrorCode PDModelFreeSides(PDModel *);
PetscErrorCode PDModelCountDamage(PDModel *);
PetscErrorCode PDModelTangentApply(PDModel *, Vec u, Vec x, Vec y);
PetscErrorCode PDModelTangentApplyScalars(PDModel *, Vec u, const PetscReal *ka, const PetscReal *kb, PetscBool scaled, PetscBool eliminate,
                                          Vec x, Vec y);
PetscErrorCode PDModelTangentApplyAt(PDModel *, Vec u, Vec x, Vec y, PetscBool refresh);
PetscErrorCode PDModelTangentChange(PDModel *, Vec u0, Vec u1, PetscReal *change);
PetscErrorCode PDModelElasticApply(PDModel *, Vec x, Vec y);
PetscErrorCode PDModelStiffnessRowBound(const PDModel *, Vec row);
/* A number in [-1, 1] from a global id (splitmix64): the same bond or dof gets the same value on any
   rank count. */
static inline PetscReal PDUnitFromId(PetscInt64 id) {
  uint64_t z = (uint64_t)id + 0x9E3779B97F4A7C15ull;
  z          = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z          = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return 2 * (PetscReal)(z >> 11) / (PetscReal)(1ull << 53) - 1;
}

/* Bond e's tensile strength over its law's (-pd_strength_scatter): from the bond's global id, so that any
   rank count draws the same; evaluated, not stored. */
static inline PetscReal PDModelBondStrength(const PDModel *m, PetscInt e) {
  const PetscReal r = m->scene->strength_scatter;
  return r > 0 ? 1 + r * PDUnitFromId(PDBondGlobalId(m->lat, m->bonds, e)) : 1;
}
PetscErrorCode PDModelEnergy(PDModel *, Vec u, PetscReal *stored, PetscReal *dissipated);
PetscErrorCode PDModelNodalDamage(PDModel *, Vec damage);
PetscErrorCode PDModelBarFields(PDModel *, Vec u, Vec stress, Vec plastic, Vec slip);
/* Forces across the section plane -pd_section_x at u: the bars', the concrete's in tension and in compression
   (negative) along x, the heights at which the three act, and the shear; height and shear along the vertical,
   the last axis (y in 2D, z in 3D). */
typedef enum {
  PD_SECTION_STEEL,
  PD_SECTION_TENSION,
  PD_SECTION_COMPRESSION,
  PD_SECTION_STEEL_Y,
  PD_SECTION_TENSION_Y,
  PD_SECTION_COMPRESSION_Y,
  PD_SECTION_SHEAR,
  PD_SECTION_N
} PDSectionColumn;
PetscErrorCode PDModelSection(PDModel *, Vec u, PetscReal out[PD_SECTION_N]);
/* The largest |stress| in any bar segment at u with the committed state (Pa; 0 without bars), and the
   largest |slip| of a bar node with bond slip along its bar, against the node it shadows (m; 0 without). */
PetscErrorCode PDModelSteelStress(PDModel *, Vec u, PetscReal *stress, PetscReal *slip);
/* The bond closest to crushing (-pd_eps_cu) at u; strain_state_at_u where the last strain state is u's
   already (an accepted step's, which PDModelCommitHistory took), so that its dilatations are not taken again. */
PetscErrorCode PDModelCrushing(PDModel *, Vec u, PetscBool strain_state_at_u, PetscReal *ratio, PetscReal *s_min, PetscReal at[3]);
