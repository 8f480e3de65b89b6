/* Discretisation: the regular lattice partitioned over ranks, ghost nodes within one horizon, bonds. */
#pragma once
#include "pd_scene.h"
#include <petscvec.h>

/* Nodes sit at cell centres of a regular grid. Global ids run x slowest, so a rank owns a contiguous
   slab of x-layers and its ghosts are the layers within one horizon on either side. */
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
} PDLattice;

/* Bonds with at least one owned end, stored once per rank, ordered by first (owned) end.
   A bond between two ranks is held by both; each adds only to its own rows. */
typedef struct {
  PetscInt   nbonds;
  PetscInt   nbonds_global; /* every bond counted once */
  PetscInt  *a, *b;         /* [nbonds] local node indices, a owned */
  PetscReal *coef;          /* [nbonds] c * omega * beta * lambda * V_a * V_b (N per unit stretch) */
  PetscInt  *material;      /* [nbonds] material governing the bond */
  /* incidence of owned nodes, neighbours sorted by global id: rows of the stiffness */
  PetscInt  *inc_start;              /* [nowned+1] */
  PetscInt  *inc_bond;               /* bond index */
  PetscInt   ncut;                   /* bonds removed by notches (global) */
  PetscReal  lambda_min, lambda_max; /* surface-correction range (global) */
  PetscReal *lambda;                 /* [nbonds] surface-correction factor, kept only for per-bond critical stretches */
} PDBonds;

PetscErrorCode PDLatticeCreate(MPI_Comm, const PDScene *, PDLattice *);
PetscErrorCode PDLatticeDestroy(PDLattice *);
PetscErrorCode PDLatticeCreateGhostVec(const PDLattice *, PetscInt bs, Vec *);
void           PDLatticeInterpolation(const PDLattice *, const PetscReal p[3], PetscInt gid[8], PetscReal w[8], PetscInt *n);
PetscErrorCode PDBondsCreate(const PDScene *, const PDLattice *, PetscBool keep_lambda, PDBonds *);
/* Global id of a bond (same on every rank): lower node id times N plus the higher one. */
PetscInt64 PDBondGlobalId(const PDLattice *, const PDBonds *, PetscInt e);
/* True on exactly one rank for every bond: the rank that owns its lower-id end. */
PetscBool      PDBondCountedHere(const PDLattice *, const PDBonds *, PetscInt e);
PetscErrorCode PDBondsDestroy(PDBonds *);
