/* The tangent's product from the bond scalars, looped over the lattice's stencil offsets instead of the
   bond list (design point 60). A 3D lattice under small kinematics gives every bond one of a few dozen
   offsets, and a bond's block is its scalar times the fixed xi xi^T of that offset. Held per offset as
   an array over the nodes of a box in lattice order (the rank's x-layers and its ghost layers), the
   scalars are read in sequence, the partner of node p along offset k is node p + stride_k, and the
   loop over p is one the compiler vectorises: no node ids, no coordinates, no scattered updates. The bond
   list's loop is bound by its loads and stores per bond; this one streams one scalar per bond and the
   box vectors, which stay in cache. */
#include "pd_model.h"
#include "kernel.h"
#include "pd_log.h"

struct PDStencil {
  PetscInt   n1, n2;    /* lattice sizes along y and z */
  PetscInt   nbox;      /* box nodes: its x-layers times n1 n2 */
  PetscInt   nhalf;     /* stencil offsets of positive lexicographic order */
  PetscInt  *stride;    /* [nhalf] box index of the partner less the base node's */
  PetscReal *xi;        /* [3*nhalf] the offset (m) */
  PetscInt  *lo, *hi;   /* [nhalf] base nodes [lo, hi) that hold a bond along the offset */
  PetscReal *K;         /* [nhalf*nbox] ka / |xi|^2 of the bond from base p along offset k; 0 where none */
  PetscInt  *slot;      /* [nbonds] the bond's place in K */
  PetscInt  *box;       /* [nlocal] a local node's box index */
  PetscReal *v, *y;     /* [3*nbox] each: x and y = K x in the box, one component after the other */
  PetscReal *tbuf;      /* [maxstride + nbox] the bonds' products of one offset, zero outside [lo, hi) */
  PetscInt   maxstride; /* the longest stride */
};

static void BoxIJK(const PDStencil *st, PetscInt p, PetscInt ijk[3]) {
  ijk[2] = p % st->n2;
  ijk[1] = (p / st->n2) % st->n1;
  ijk[0] = p / (st->n1 * st->n2);
}

/* The stencil view of the bonds, or NULL where it does not apply: 2D, bar nodes (their slots are not
   lattice places), finite kinematics (a block's direction follows the displacement), -pd_stencil_product
   false, or a bond whose offset is not in the stencil or whose place another bond took. */
PetscErrorCode PDStencilCreate(const PDModel *m, PDStencil **out) {
  const PDLattice *lat = m->lat;
  const PDBonds   *bd  = m->bonds;
  const PetscInt   R = lat->reach, w = 2 * R + 1;
  PDStencil       *st;
  PetscInt        *index, x0, x1;
  PetscBool        ok = PETSC_TRUE, allok;

  PetscFunctionBeginUser;
  *out = NULL;
  if (m->bs != 3 || lat->dim != 3 || lat->nslot || !m->scene->stencil_product || m->scene->kinematics != PD_KINEMATICS_SMALL)
    PetscFunctionReturn(0);
  PetscCall(PetscNew(&st));
  st->n1   = lat->n[1];
  st->n2   = lat->n[2];
  x0       = PetscMax(0, lat->layer_start - R); /* the box's x-layers [x0, x1) */
  x1       = PetscMin(lat->n[0], lat->layer_end + R);
  st->nbox = (x1 - x0) * st->n1 * st->n2;
  PetscCall(PetscMalloc1(w * w * w, &index));
  for (PetscInt k = 0; k < w * w * w; k++) index[k] = -1;
  PetscCall(PetscMalloc4(lat->nstencil, &st->stride, 3 * lat->nstencil, &st->xi, lat->nstencil, &st->lo, lat->nstencil, &st->hi));
  for (PetscInt s = 0; s < lat->nstencil; s++) {
    const PetscInt *d = &lat->stencil[4 * s];
    if (!(d[0] > 0 || (d[0] == 0 && (d[1] > 0 || (d[1] == 0 && d[2] > 0))))) continue;
    index[((d[0] + R) * w + d[1] + R) * w + d[2] + R] = st->nhalf;
    st->stride[st->nhalf]                             = (d[0] * st->n1 + d[1]) * st->n2 + d[2];
    for (PetscInt c = 0; c < 3; c++) st->xi[3 * st->nhalf + c] = d[c] * lat->dx;
    st->maxstride     = PetscMax(st->maxstride, st->stride[st->nhalf]);
    st->lo[st->nhalf] = st->nbox;
    st->hi[st->nhalf] = 0;
    st->nhalf++;
  }
  /* K's places are counted in PetscInt */
  ok = (PetscInt64)st->nhalf * st->nbox < PETSC_MAX_INT ? PETSC_TRUE : PETSC_FALSE;
  if (ok) {
    PetscCall(PetscCalloc1((size_t)st->nhalf * st->nbox, &st->K));
    PetscCall(PetscMalloc2(PetscMax(1, bd->nbonds), &st->slot, PetscMax(1, lat->nlocal), &st->box));
    for (PetscInt l = 0; l < lat->nlocal; l++) {
      const PetscInt g = lat->gid[l], layer = st->n1 * st->n2;
      st->box[l] = (g / layer - x0) * layer + g % layer;
      if (st->box[l] < 0 || st->box[l] >= st->nbox) ok = PETSC_FALSE;
    }
  }
  for (PetscInt e = 0; ok && e < bd->nbonds; e++) {
    PetscInt p = st->box[bd->a[e]], q = st->box[bd->b[e]], ip[3], iq[3], k = -1;
    if (p > q) {
      const PetscInt t = p;
      p                = q;
      q                = t;
    }
    BoxIJK(st, p, ip);
    BoxIJK(st, q, iq);
    if (PetscAbsInt(iq[0] - ip[0]) <= R && PetscAbsInt(iq[1] - ip[1]) <= R && PetscAbsInt(iq[2] - ip[2]) <= R)
      k = index[((iq[0] - ip[0] + R) * w + iq[1] - ip[1] + R) * w + iq[2] - ip[2] + R];
    if (k < 0 || st->K[k * st->nbox + p] != 0) {
      ok = PETSC_FALSE;
      break;
    }
    st->slot[e]        = k * st->nbox + p;
    st->K[st->slot[e]] = 1; /* taken; set to the bond's scalar by the assemblies */
    st->lo[k]          = PetscMin(st->lo[k], p);
    st->hi[k]          = PetscMax(st->hi[k], p + 1);
  }
  PetscCall(PetscFree(index));
  /* every rank takes the same loop, so that a product costs the same everywhere */
  PetscCall(MPIU_Allreduce(&ok, &allok, 1, MPIU_BOOL, MPI_LAND, lat->comm));
  if (!allok) {
    PetscCall(PDStencilDestroy(&st));
    PetscCall(PetscInfo(NULL, "Tangent products loop over the bond list: the stencil view does not hold every bond\n"));
    PetscFunctionReturn(0);
  }
  for (PetscInt e = 0; e < bd->nbonds; e++) st->K[st->slot[e]] = 0;
  PetscCall(PetscCalloc3(3 * st->nbox, &st->v, 3 * st->nbox, &st->y, st->maxstride + st->nbox, &st->tbuf));
  PetscCall(PetscInfo(NULL, "Tangent products loop over %" PetscInt_FMT " stencil offsets of a box of %" PetscInt_FMT " nodes\n", st->nhalf,
                      st->nbox));
  *out = st;
  PetscFunctionReturn(0);
}

PetscErrorCode PDStencilDestroy(PDStencil **st) {
  PetscFunctionBeginUser;
  if (!*st) PetscFunctionReturn(0);
  PetscCall(PetscFree4((*st)->stride, (*st)->xi, (*st)->lo, (*st)->hi));
  PetscCall(PetscFree((*st)->K));
  PetscCall(PetscFree2((*st)->slot, (*st)->box));
  PetscCall(PetscFree3((*st)->v, (*st)->y, (*st)->tbuf));
  PetscCall(PetscFree(*st));
  PetscFunctionReturn(0);
}

/* The view's scalars and each bond's place among them, which the assemblies write (assembly.c) */
void PDStencilScalars(PDStencil *st, PetscReal **K, const PetscInt **slot) {
  *K    = st->K;
  *slot = st->slot;
}

/* One offset: t_p = K_p xi.(v_{p+s} - v_p) for the bonds' base nodes p in [lo, hi), then
   y_q += xi (t_{q-s} - t_q), which is -t xi on each base node and +t xi on its partner: two loops without
   a dependence between iterations, so that both vectorise (t is zero outside [lo, hi), and is left so). */
static void ApplyOffset(PetscInt nbox, PetscInt lo, PetscInt hi, PetscInt s, const PetscReal xi[3], const PetscReal *restrict K,
                        const PetscReal *restrict v, PetscReal *restrict y, PetscReal *restrict t) {
  const PetscReal  a0 = xi[0], a1 = xi[1], a2 = xi[2];
  const PetscReal *vx = v, *vy = v + nbox, *vz = v + 2 * nbox;
  PetscReal       *yx = y, *yy = y + nbox, *yz = y + 2 * nbox;

  for (PetscInt p = lo; p < hi; p++) t[p] = K[p] * (a0 * (vx[p + s] - vx[p]) + a1 * (vy[p + s] - vy[p]) + a2 * (vz[p + s] - vz[p]));
  for (PetscInt q = lo; q < hi + s; q++) {
    const PetscReal d = t[q - s] - t[q];
    yx[q] += a0 * d;
    yy[q] += a1 * d;
    yz[q] += a2 * d;
  }
  for (PetscInt p = lo; p < hi; p++) t[p] = 0;
}

/* y = K x on the owned dofs from the scalars the assemblies set, constrained columns eliminated (their
   entries of x count as zero), as PDModelTangentApplyScalars does with the bond list. */
PetscErrorCode PDStencilApply(PDStencil *st, PDModel *m, Vec x, Vec y) {
  const PDLattice *lat = m->lat;
  const PetscInt   nb  = st->nbox;
  PetscScalar     *yy, *xl;
  Vec              xloc;

  PetscFunctionBeginUser;
  PetscCall(PDModelGetProductInput(m, x, PETSC_TRUE, &xl, &xloc));
  for (PetscInt l = 0; l < lat->nlocal; l++)
    for (PetscInt c = 0; c < 3; c++) st->v[c * nb + st->box[l]] = xl[3 * l + c];
  PetscCall(PDModelRestoreProductInput(m, &xl, &xloc));
  PetscCall(PetscArrayzero(st->y, 3 * nb));
  for (PetscInt k = 0; k < st->nhalf; k++)
    if (st->lo[k] < st->hi[k])
      ApplyOffset(nb, st->lo[k], st->hi[k], st->stride[k], &st->xi[3 * k], st->K + (size_t)k * nb, st->v, st->y, st->tbuf + st->maxstride);
  PetscCall(PetscLogFlops(25.0 * m->bonds->nbonds));
  PetscCall(VecGetArray(y, &yy));
  for (PetscInt i = 0; i < lat->nowned; i++)
    for (PetscInt c = 0; c < 3; c++) yy[3 * i + c] = st->y[c * nb + st->box[i]];
  PetscCall(VecRestoreArray(y, &yy));
  PetscFunctionReturn(0);
}
