/* Bond loop entry points shared by the residual, the Jacobian and the measurements. */
#pragma once
#include "pd_model.h"

/* Geometry of one bond in the current configuration: direction e, reference and current lengths, the
   stretch s and the factor q with ds/deta = q e. Small kinematics: s = xi.eta/|xi|^2 along xi/|xi|
   (the linearised micromodulus of Eq. 4.13). Finite: exact s = (|y| - |xi|)/|xi|, q = 1/|xi|, or the
   modified s = (|y|^2 - |xi|^2)/(2|xi|^2), q = |y|/|xi|^2 (Miranda et al. Eq. 17). */
static inline void BondState(const PDScene *sc, PetscInt dim, const PetscReal *xa, const PetscReal *xb, const PetscScalar *ua,
                             const PetscScalar *ub, PetscReal e[3], PetscReal *len0, PetscReal *len, PetscReal *s, PetscReal *q) {
  PetscReal xi[3] = {0, 0, 0}, eta[3] = {0, 0, 0}, L2 = 0;
  for (PetscInt a = 0; a < dim; a++) {
    xi[a]  = xb[a] - xa[a];
    eta[a] = PetscRealPart(ub[a] - ua[a]);
    L2 += xi[a] * xi[a];
  }
  *len0 = PetscSqrtReal(L2);
  if (sc->kinematics == PD_KINEMATICS_SMALL) {
    PetscReal dot = 0;
    for (PetscInt a = 0; a < dim; a++) {
      dot += xi[a] * eta[a];
      e[a] = xi[a] / *len0;
    }
    *s   = dot / L2;
    *len = *len0;
    *q   = 1 / *len0;
  } else {
    PetscReal y2 = 0;
    for (PetscInt a = 0; a < dim; a++) y2 += (xi[a] + eta[a]) * (xi[a] + eta[a]);
    *len = PetscSqrtReal(y2);
    for (PetscInt a = 0; a < dim; a++) e[a] = (xi[a] + eta[a]) / *len;
    if (sc->stretch == PD_STRETCH_MODIFIED) {
      *s = (y2 - L2) / (2 * L2);
      *q = *len / L2;
    } else {
      *s = (*len - *len0) / *len0;
      *q = 1 / *len0;
    }
  }
}

/* A bond's squared reference length, summed as the bond loops sum it (bs dofs per node, coordinates by 3). */
static inline PetscReal PDBondLength2(PetscInt bs, const PetscReal *x, PetscInt i, PetscInt j) {
  PetscReal L2 = 0;
  for (PetscInt r = 0; r < bs; r++) {
    const PetscReal d = x[3 * j + r] - x[3 * i + r];
    L2 += d * d;
  }
  return L2;
}

/* Whether the bond i-j has its blocks in a matrix that keeps bonds up to the squared length reach2 (0:
   every bond; PDModelCreateMatrix) */
static inline PetscBool PDBondInReach(PetscInt bs, const PetscReal *x, PetscInt i, PetscInt j, PetscReal reach2) {
  return reach2 == 0 || PDBondLength2(bs, x, i, j) <= reach2 ? PETSC_TRUE : PETSC_FALSE;
}
PetscErrorCode PDModelAssembledAttach(PDModel *, Mat, PetscReal reach2, const PetscInt *ncols);

/* Diagonal added, times bc_scale, to a free dof left without stiffness (every bond of its node broken). */
#define PD_REGULARISATION 1e-8

PetscErrorCode PDModelInternalForceLocal(PDModel *, const PetscScalar *u, PetscScalar *f, PetscReal *ka, PetscReal *kb);
PetscErrorCode PDModelRowsUsable(PDModel *, PetscBool *usable);
PetscErrorCode PDModelInternalForceRows(PDModel *, const PetscScalar *u, PetscInt n, const PetscInt *rows, PetscScalar *fr, PetscReal *ka);
PetscErrorCode PDModelRowIndexDestroy(PDModel *);
PetscErrorCode PDModelTangentScalars(PDModel *, const PetscScalar *u, PetscReal *ka, PetscReal *kb, PetscReal *kp);
PetscErrorCode PDModelAssembleRows(PDModel *, const PetscScalar *u, const PetscReal *ka, const PetscReal *kb, Mat J,
                                   PetscInt *nregularised);
/* The tangent's product over the lattice's stencil offsets (stencil_product.c), kept up to date by the
   assemblies of the matrix it is attached to (which then owns it): bond e's scalar is K[slot[e]]. */
typedef struct PDStencil PDStencil;
PetscErrorCode           PDStencilCreate(const PDModel *, PDStencil **);
PetscErrorCode           PDStencilDestroy(PDStencil **);
void                     PDStencilScalars(PDStencil *, PetscReal **K, const PetscInt **slot);
PetscErrorCode           PDStencilApply(PDStencil *, PDModel *, Vec x, Vec y);
PetscErrorCode           PDModelAssembledSetStencil(Mat P, PDStencil *);
PetscErrorCode           PDModelAssembledState(Mat P, const PetscReal **kl, PDStencil **st, const unsigned char **reg);
PetscErrorCode           PDModelEnergiesLocal(PDModel *, const PetscScalar *u, PetscReal *stored, PetscReal *dissipated);
/* scaled: ka holds ka / |xi|^2 (small kinematics, kb NULL) */
PetscErrorCode PDModelTangentApplyLocal(PDModel *, const PetscScalar *u, const PetscReal *ka, const PetscReal *kb, PetscBool scaled,
                                        const PetscScalar *x, PetscScalar *y);
PetscReal      PDModelBondStretch(const PDModel *, const PetscScalar *u, PetscInt e);
#define PD_STRETCH_BLOCK 256 /* bonds whose stretches PDModelBondStretches fills at once */
void PDModelBondStretches(const PDModel *, const PetscScalar *u, PetscInt e0, PetscInt n, PetscReal *s);
void PDModelBondEnergies(const PDModel *, PetscInt e0, PetscInt n, const PetscReal *s, PetscReal *es, PetscReal *ed);
void PDModelTangentChangeBlock(const PDModel *, const PetscScalar *u0, const PetscScalar *u1, PetscInt e0, PetscInt n, const PetscReal *s0,
                               const PetscReal *s1, PetscReal *sum);
PetscReal PDModelTangentChangeLocal(const PDModel *, const PetscScalar *u0, const PetscScalar *u1);
PetscReal PDModelBondForceSmall(const PDModel *, const PetscScalar *u, PetscInt e, PetscReal xi[3]);
void      PDModelForceChangeLocal(const PDModel *, const PetscScalar *u, PetscInt n, const PetscInt *bonds, const PetscReal *g_old,
                                  PetscScalar *f);
void      PDModelCommitBond(PDModel *, PetscInt e, PetscReal s);
void      PDModelCommitSegment(PDModel *, PetscInt sg, PetscReal s);
PetscReal PDModelSteelStressLocal(PDModel *, const PetscScalar *u);
PetscReal PDModelSlipLocal(PDModel *, const PetscScalar *u);
void      PDModelBarFieldsLocal(PDModel *, const PetscScalar *u, PetscScalar *stress, PetscScalar *plastic, PetscScalar *slip);
#define PD_CRUSH_TIE 1e-6 /* relative difference of two bonds' compression below which they tie */
void PDModelCrushingLocal(PDModel *, const PetscScalar *u, const PetscScalar *theta, PetscReal *ratio, PetscInt64 *gid, PetscReal *s_min,
                          PetscReal at[3]);
/* m->dilatation (ghosted) from the bond stretches at the local displacements u (confinement.c) */
PetscErrorCode PDModelNodalDilatation(PDModel *, const PetscScalar *u);

/* A bond's stretch thresholds: its own (surface correction, strength scatter, crushing's rise) or its law's
   nominal ones. Evaluated from the nominal ones, not stored (PDLawBondThresholdsScaled). */
static inline PDLawBond PDModelBondThresholds(const PDModel *m, PetscInt e, const PDLaw *law) {
  PDLawBond t;
  if (!m->bonds->sc_shares && m->scene->strength_scatter == 0 && !m->shift) return law->nominal;
  PDLawBondThresholdsScaled(law, m->bonds->sc_shares ? PDBondSurfaceFactor(m->lat, m->bonds, e) : 1, PDModelBondStrength(m, e), &t);
  if (m->shift) PDLawBondRaise(&t, m->shift[e]);
  return t;
}
PetscReal      PDModelBondDamage(const PDModel *, PetscInt e);
PetscErrorCode PDModelGetProductInput(PDModel *, Vec x, PetscBool eliminate, PetscScalar **xl, Vec *xloc);
PetscErrorCode PDModelRestoreProductInput(PDModel *, PetscScalar **xl, Vec *xloc);
PetscErrorCode PDModelScatterToLocal(PDModel *, Vec u, const PetscScalar **ul, Vec *loc);
PetscErrorCode PDModelRestoreLocal(PDModel *, const PetscScalar **ul, Vec *loc);
void           PDModelSectionLocal(PDModel *, const PetscScalar *u, PetscReal sum[PD_SECTION_N]);
PetscErrorCode PDModelScatterSecondToLocal(PDModel *, Vec u, PetscReal lambda, const PetscScalar **ul, Vec *loc);
PetscErrorCode PDModelRestoreSecondLocal(PDModel *, const PetscScalar **ul, Vec *loc);
