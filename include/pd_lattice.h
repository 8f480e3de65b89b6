/* Discretisation: the regular lattice partitioned over ranks, ghost nodes within one horizon, bonds. */
#pragma once
#include "pd_scene.h"
#include <petscvec.h>

/* Bond family on the lattice (docs/design.md, point 28). Two nodes whose integer lattice offset is
   (di, dj, dk) lie n2 = di^2 + dj^2 + dk^2 grid spacings squared apart, an exact integer; they are bonded
   when n2 <= m^2, m = delta/dx. Only the comparison at equality allows round-off in m^2 (a relative
   4 ulps), so that m = 3 meets n2 = 9 and m = 2 sqrt(3) meets n2 = 12: pairs exactly one horizon apart
   are on the horizon's edge and are bonded. */
typedef enum {
  PD_FAMILY_OUT,  /* beyond the horizon: no bond */
  PD_FAMILY_IN,   /* strictly inside */
  PD_FAMILY_EDGE, /* exactly at r = delta */
} PDFamilyMember;
PDFamilyMember PDFamilyRule(PetscReal m, PetscInt n2);
/* Walks the family's lattice offsets in lexicographic order of (di, dj, dk), dk = 0 in 2D: st = {0, 0, 0,
   -1} starts; each call moves st to the next member (di, dj, dk, n2) and returns PETSC_FALSE past the last. */
PetscBool PDFamilyNext(PetscReal m, PetscInt dim, PetscInt st[4]);
/* Partial-volume factor of a neighbour n2 grid spacings squared away (PA-PDLAMMPS, THEORY.md Eq. 4.2, in
   units of dx): 1 up to m - 1/2, m + 1/2 - sqrt(n2) beyond, exactly 1/2 on the horizon's edge; 1 when
   partial volumes are off. */
PetscReal PDFamilyPartialVolume(PetscReal m, PetscInt n2, PetscBool partial_volume);

/* Nodes sit at cell centres of a regular grid. Global ids run x slowest, so a rank owns a contiguous
   slab of x-layers and its ghosts are the layers within one horizon on either side. Bars with bond slip
   have nodes of their own (bar nodes, docs/reinforcement.md): each x-layer ends with nslot slots after its
   n[1] n[2] lattice nodes, one per bar node whose lattice node (the one it shadows, at the same place) lies
   in the layer; slots no bar node takes are hollow. */
typedef struct {
  MPI_Comm   comm;
  PetscInt   dim;
  PetscInt   n[3];      /* global lattice size (n[2] = 1 in 2D) */
  PetscReal  origin[3]; /* position of node (0,0,0) */
  PetscReal  dx, horizon, cell_volume;
  PetscInt   layer_start, layer_end; /* owned x-layers [start, end) */
  PetscInt   nowned, nghost, nlocal, nglobal;
  PetscInt   gid_start; /* global id of the first owned node */
  PetscInt  *gid;       /* [nlocal] global id, owned first, then ghosts */
  PetscReal *x;         /* [3*nlocal] positions */
  PetscInt  *material;  /* [nlocal] material index */
  PetscBool *hollow;    /* [nlocal] the node lies in a void (-pd_voidK_*): no bonds, pinned, in no region */
  PetscBool *nofail;    /* [nlocal] the node lies in a no-fail zone (-pd_nofailK_*): its bonds stay elastic */
  PetscInt   nvoid;     /* nodes in voids (global) */
  PetscInt   reach;     /* largest offset along one axis within the horizon: ghost layers per side */
  PetscInt   nstencil;  /* neighbour offsets within the horizon, the node's own excluded */
  PetscInt  *stencil;   /* [4*nstencil] di, dj, dk and n2 = di^2 + dj^2 + dk^2, lexicographic in (di, dj, dk) */
  PetscInt   nslot;     /* bar-node slots per x-layer (0 without bond slip) */
  PetscInt   layer;     /* global ids per x-layer: n[1] n[2] + nslot */
  PetscInt   nunused;   /* slots no bar node takes (global): hollow */
  /* bar nodes, the same table on every rank, by bar and then along the bar's chain */
  PetscInt   nbarnodes;
  PetscInt  *bn_bar;        /* [nbarnodes] the bar */
  PetscInt  *bn_ijk;        /* [3*nbarnodes] lattice indices of the node it shadows */
  PetscInt  *bn_gid;        /* [nbarnodes] its global id */
  PetscReal *bn_length;     /* [nbarnodes] its share of the bar's length (m) */
  PetscReal *bn_shift;      /* [3*nbarnodes] its place less its shadow's: PD_BAR_NODE_SHIFT dx along the bar; on an
                               embedded bar its true place (an anchor's: less PD_BAR_NODE_SHIFT dx along its direction) */
  unsigned char *bn_role;   /* [nbarnodes] PDBarRole */
  PetscInt      *slot_node; /* [n[0]*nslot] the bar node in each slot, or -1 */
  PetscInt      *barnode;   /* [nlocal] the bar node a local node is, or -1 (NULL without bond slip) */
} PDLattice;

/* The place of the lattice node with indices ijk (0 along the axes the lattice does not have). */
static inline void PDLatticePlace(const PDLattice *lat, const PetscInt ijk[3], PetscReal x[3]) {
  for (PetscInt c = 0; c < 3; c++) x[c] = c < lat->dim ? lat->origin[c] + ijk[c] * lat->dx : 0;
}

/* What a node of a bar is: the bar's own (its segments join them), or on an embedded bar one of its anchors,
   each tied to the concrete of the lattice cell the bar node lies in and linked to the bar node along one
   direction: along the bar (the bond, slip or perfect) or across it (elastic). An embedded bar's nodes go
   by station: the bar node, then its 1 + (dim - 1) anchors. */
typedef enum { PD_BAR_NODE, PD_BAR_ANCHOR_ALONG, PD_BAR_ANCHOR_ACROSS1, PD_BAR_ANCHOR_ACROSS2 } PDBarRole;
/* Nodes of bar b per station: 1 on a chain, 1 + dim embedded. */
static inline PetscInt PDBarStride(const PDBar *b, PetscInt dim) {
  return b->embedded ? 1 + dim : 1;
}
/* Whether bar b has nodes of its own (bond slip, or embedded). */
static inline PetscBool PDBarHasNodes(const PDBar *b) {
  return b->slip || b->embedded ? PETSC_TRUE : PETSC_FALSE;
}

/* The material of bonds that never damage: a bar's segment across a notch (coefficient 0), a perfect
   bond's interface, a no-fail zone's bonds. Its law is elastic. */
#define PD_MATERIAL_ELASTIC PD_MAX_MATERIALS
/* The material of bar k's bond-slip links: their law is the bar's bond-slip law. */
#define PD_MATERIAL_SLIP(k) (PD_MAX_MATERIALS + 1 + (k))
/* The material of the ties from an embedded bar's anchors to the concrete of material m (bonds.c): m's law with its
   tensile onset lowered by PD_ANCHOR_STIFFNESS, the factor the ties are stiffer than the concrete they stand for, so
   that across a crack they carry no more than that concrete did. */
#define PD_MATERIAL_TIE(m) (PD_MAX_MATERIALS + 1 + PD_MAX_BARS + (m))
#define PD_MATERIALS_ALL (2 * PD_MAX_MATERIALS + 1 + PD_MAX_BARS)
/* An embedded bar's anchor is tied to the corners of the lattice cell its bar node lies in, together this
   many times as stiff as the concrete cell (E V / dx^2): along the bar the ties sit in series with the bond
   law, whose slope at zero slip is of the cell's order, and stiffer ties would only stiffen the equations */
#define PD_ANCHOR_STIFFNESS 10
_Static_assert(PD_MATERIALS_ALL <= 256, "a bond's material is held in one byte");

#define PD_SHARES 4 /* a node's family shares: volume, stiffness along x, y, z (bonds.c) */

/* Bonds with at least one owned end, stored once per rank, ordered by first (owned) end.
   A bond between two ranks is held by both; each adds only to its own rows. */
typedef struct {
  PetscInt       nbonds;
  PetscInt64     nbonds_global; /* every bond counted once (64-bit: a global count passes 2^31 from about 30 M nodes) */
  PetscInt      *a, *b;         /* [nbonds] local node indices, a owned */
  PetscReal     *coef;          /* [nbonds] c * omega * beta * lambda * V_a * V_b (N per unit stretch) */
  unsigned char *material;      /* [nbonds] material governing the bond (below PD_MATERIALS_ALL) */
  /* incidence of owned nodes, neighbours sorted by global id: rows of the stiffness */
  PetscInt *inc_start;              /* [nowned+1] */
  PetscInt *inc_bond;               /* bond index */
  PetscInt  ncut;                   /* bonds removed by notches (global) */
  PetscReal lambda_min, lambda_max; /* surface-correction range (global) */
  /* What a bond's surface-correction factor is evaluated from (PDBondSurfaceFactor), kept only for per-bond
     critical stretches: the family shares of each local node, ghosts included, and the bulk node's (the
     horizon's volume V0, or the stencil's stiffness S0): shares per node, not a factor per bond. */
  PetscReal *sc_shares; /* [PD_SHARES*nlocal], or NULL */
  PetscReal  sc_ref;
  PetscBool  sc_stencil;
  /* steel bar segments (bars.c): a bond between consecutive nodes of a bar's line carries one beside its
     concrete part; a pair a notch cuts is kept for its segment with no concrete (coef 0) */
  PetscInt   nseg, nseg_global;
  PetscInt  *seg;      /* [nbonds] segment of the bond, or -1; NULL without bars */
  PetscInt  *seg_bond; /* [nseg] its bond */
  PetscInt  *seg_bar;  /* [nseg] its bar */
  PetscReal *seg_coef; /* [nseg] axial stiffness E A_s (N per unit stretch) */
} PDBonds;

PetscErrorCode PDLatticeCreate(MPI_Comm, const PDScene *, PDLattice *);
PetscReal      PDBondSurfaceFactorStencil(const PDLattice *, const PDBonds *, PetscInt e);

/* A bond's surface-correction factor lambda, as its coefficient holds it (bonds.c, SurfaceCorrection): from
   its two nodes' family shares, evaluated in the same operations as when it was built, so the same bits;
   1 for a bar node's link or tie, which nothing corrects. */
static inline PetscReal PDBondSurfaceFactor(const PDLattice *lat, const PDBonds *bd, PetscInt e) {
  const PetscInt i = bd->a[e], j = bd->b[e];
  PetscReal      vsum;
  if (lat->barnode && (lat->barnode[i] >= 0 || lat->barnode[j] >= 0)) return 1;
  if (bd->sc_stencil) return PDBondSurfaceFactorStencil(lat, bd, e);
  vsum = bd->sc_shares[PD_SHARES * i] + bd->sc_shares[PD_SHARES * j];
  return vsum > 0 ? 2 * bd->sc_ref / vsum : 1;
}

/* Global id of a bond (same on every rank): lower node id times N plus the higher one. */
static inline PetscInt64 PDBondGlobalId(const PDLattice *lat, const PDBonds *bd, PetscInt e) {
  const PetscInt64 ga = lat->gid[bd->a[e]], gb = lat->gid[bd->b[e]];
  return ga < gb ? ga * lat->nglobal + gb : gb * lat->nglobal + ga;
}
PetscErrorCode PDLatticeDestroy(PDLattice *);
PetscErrorCode PDLatticeCreateGhostVec(const PDLattice *, PetscInt bs, Vec *);
/* Local index of the node with global id gid, or -1 when this rank holds it neither as owned nor as ghost. */
PetscInt PDLatticeLocalIndex(const PDLattice *, PetscInt gid);
/* Lattice indices (i, j, k) of the node with global id gid (k = 0 in 2D); of a bar node, those of the node
   it shadows. */
void PDLatticeNodeIndices(const PDLattice *, PetscInt gid, PetscInt ijk[3]);
/* Global id of the lattice node with indices ijk. */
static inline PetscInt PDLatticeGid(const PDLattice *lat, const PetscInt ijk[3]) {
  return ijk[0] * lat->layer + ijk[1] * lat->n[2] + ijk[2];
}
/* A bar node sits this many grid spacings from the node it shadows, along its bar: the link between the two,
   which carries the bond stress, is then a bond with a length and a direction like any other. */
#define PD_BAR_NODE_SHIFT 1e-4
/* The bar-node table (bars.c): bar nodes of the bars with bond slip, their slots, nslot. */
PetscErrorCode PDLatticeSetUpBarNodes(const PDScene *, PDLattice *);
/* Integer lattice offset of node l from node k, and its n2. */
PetscInt PDLatticeOffset(const PDLattice *, PetscInt k, PetscInt l, PetscInt d[3]);
void     PDLatticeInterpolation(const PDLattice *, const PetscReal p[3], PetscInt gid[8], PetscReal w[8], PetscInt *n);
/* The bar whose line holds the pair of nodes (global ids) as consecutive nodes, or -1. */
PetscInt PDBarOfPair(const PDScene *, const PDLattice *, PetscInt gi, PetscInt gj);
/* The bar whose line holds the node (global id) within its ends, or -1. */
PetscInt       PDBarHoldingNode(const PDScene *, const PDLattice *, PetscInt gid);
PetscErrorCode PDBondsSetUpBars(const PDScene *, const PDLattice *, PDBonds *);
/* A bond's elastic axial stiffness (N per unit stretch): its concrete part and its bar segment's. */
static inline PetscReal PDBondStiffness(const PDBonds *bd, PetscInt e) {
  return bd->coef[e] + (bd->seg && bd->seg[e] >= 0 ? bd->seg_coef[bd->seg[e]] : 0);
}
PetscErrorCode PDBondsCreate(const PDScene *, const PDLattice *, PetscBool keep_lambda, PDBonds *);
/* True on exactly one rank for every bond: the rank that owns its lower-id end. */
PetscBool      PDBondCountedHere(const PDLattice *, const PDBonds *, PetscInt e);
PetscErrorCode PDBondsDestroy(PDBonds *);
/* Parts of the body the bonds hold together (nodes without bonds not counted), and the global ids of the
   lowest nodes of the first two parts (PETSC_MAX_INT where there is none). */
PetscErrorCode PDBondsCountParts(const PDLattice *, const PDBonds *, PetscInt *nparts, PetscInt first[2]);
