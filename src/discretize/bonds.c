/* Bond list: neighbour search on lattice offsets, notch cuts, partial volumes, surface correction, bond constants. */
#include "pd_lattice.h"
#include "pd_material.h"

/* A notch is a flat box; a bond is cut when its segment crosses the notch plane, or touches it with one
   end, at a point inside the box. This rule reproduces the bond counts of Hobbs Table A.1. */
static PetscBool NotchCuts(const PDNotch *n, const PetscReal p[3], const PetscReal q[3], PetscInt dim, PetscReal tol) {
  const PetscInt  a  = n->normal;
  const PetscReal c  = n->box[a];
  PetscReal       dp = p[a] - c, dq = q[a] - c, t;

  if (PetscAbsReal(dp) < tol) dp = 0;
  if (PetscAbsReal(dq) < tol) dq = 0;
  if (dp * dq > 0 || (dp == 0 && dq == 0)) return PETSC_FALSE;
  t = dp / (dp - dq);
  for (PetscInt k = 0; k < dim; k++) {
    if (k == a) continue;
    const PetscReal r = p[k] + t * (q[k] - p[k]);
    if (r <= n->box[k] + tol || r >= n->box[3 + k] - tol) return PETSC_FALSE;
  }
  return PETSC_TRUE;
}

/* A neighbour's share of the family volume V_i in the surface correction, given its partial-volume
   factor beta: beta, or its whole cell as PeriPy counts it (the convention of the Hobbs thesis,
   docs/softening.md) */
static PetscReal FamilyVolumeShare(const PDScene *sc, PetscReal beta) {
  return sc->sc_whole_cells ? 1 : beta;
}

/* A neighbour's weights in the surface correction, from its lattice offset st (di, dj, dk, n2): [0] its
   share of the family volume (m^3); [1 + a] its share of the node's stiffness along axis a under the stencil
   calibration, omega beta |xi| e_a^4 in units of dx, the bond's term in C_aaaa (PDLatticeStiffnessRatio) */
static void FamilyShares(const PDScene *sc, const PDLattice *lat, const PetscInt st[4], PetscReal w[PD_SHARES]) {
  const PetscReal beta = PDFamilyPartialVolume(sc->horizon_ratio, st[3], sc->partial_volume), len = PetscSqrtReal((PetscReal)st[3]);
  const PetscReal k = PDInfluenceValue(sc->influence, len, sc->horizon_ratio) * beta * len;

  w[0] = FamilyVolumeShare(sc, beta) * lat->cell_volume;
  for (PetscInt a = 0; a < 3; a++) w[1 + a] = k * PetscPowRealInt(st[a] / len, 4);
}

typedef struct {
  PetscInt *a, *b, n, cap;
} PairList;

static PetscErrorCode PairListPush(PairList *pl, PetscInt a, PetscInt b) {
  PetscFunctionBeginUser;
  if (pl->n == pl->cap) {
    PetscInt newcap = PetscMax(1024, 2 * pl->cap);
    PetscCall(PetscRealloc(sizeof(PetscInt) * newcap, &pl->a));
    PetscCall(PetscRealloc(sizeof(PetscInt) * newcap, &pl->b));
    pl->cap = newcap;
  }
  pl->a[pl->n] = a;
  pl->b[pl->n] = b;
  pl->n++;
  PetscFunctionReturn(0);
}

/* Bars with bond slip (docs/reinforcement.md). A bar node has three kinds of partner: the bar nodes before
   and after it on its bar (the bar's segments), the node it shadows (the link, which carries the bond
   stress as a function of the slip along the bar; the bar node sits PD_BAR_NODE_SHIFT dx from it along the
   bar, so that the link is a bond with a length and a direction to every loop), and the lattice nodes one
   cross direction either side (ties, elastic, which hold the bar node to the concrete across the bar).
   Nothing joins a bar node to concrete beyond its own node: across a crack between two bar nodes only
   the bar carries. */
typedef enum { PD_BARPAIR_SEGMENT, PD_BARPAIR_LINK, PD_BARPAIR_TIE, PD_BARPAIR_ANCHOR, PD_BARPAIR_CORNER } PDBarPair;
#define PD_MAX_BAR_PARTNERS 32 /* a bar node has at most 9; a lattice node ties to at most this many */

static PetscInt Gcd(PetscInt a, PetscInt b) {
  a = PetscAbsInt(a);
  b = PetscAbsInt(b);
  while (b) {
    const PetscInt t = a % b;
    a                = b;
    b                = t;
  }
  return a;
}

/* Integer directions across a step: one in 2D, two in 3D (the step crossed with its smallest axis, then
   with that), each divided by the gcd of its components. */
static PetscInt CrossDirections(const PetscInt st[3], PetscInt dim, PetscInt p[2][3]) {
  PetscInt n = dim == 2 ? 1 : 2, a = 0;
  if (dim == 2) {
    p[0][0] = -st[1];
    p[0][1] = st[0];
    p[0][2] = 0;
  } else {
    PetscInt e[3] = {0, 0, 0};
    for (PetscInt c = 1; c < 3; c++)
      if (PetscAbsInt(st[c]) < PetscAbsInt(st[a])) a = c;
    e[a]    = 1;
    p[0][0] = st[1] * e[2] - st[2] * e[1];
    p[0][1] = st[2] * e[0] - st[0] * e[2];
    p[0][2] = st[0] * e[1] - st[1] * e[0];
    p[1][0] = st[1] * p[0][2] - st[2] * p[0][1];
    p[1][1] = st[2] * p[0][0] - st[0] * p[0][2];
    p[1][2] = st[0] * p[0][1] - st[1] * p[0][0];
  }
  for (PetscInt k = 0; k < n; k++) {
    const PetscInt g = Gcd(Gcd(p[k][0], p[k][1]), p[k][2]);
    for (PetscInt c = 0; c < 3; c++) p[k][c] /= g;
  }
  return n;
}

static PetscBool InVoid(const PDScene *sc, const PetscReal x[3]) {
  for (PetscInt v = 0; v < sc->nvoids; v++)
    if (PDGeometryContains(&sc->voids[v].where, x, sc)) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* The place of bar node q: its shadow's place plus its shift. */
static void BarNodePlace(const PDLattice *lat, PetscInt q, PetscReal x[3]) {
  PDLatticePlace(lat, &lat->bn_ijk[3 * q], x);
  for (PetscInt c = 0; c < 3; c++) x[c] += lat->bn_shift[3 * q + c];
}

/* The lattice nodes an anchor of an embedded bar ties to: the corners of the lattice cell its bar node (bar
   node qb) lies in, as global ids, less those outside the lattice, in a void or behind a notch. The same on
   every rank. */
static PetscInt AnchorCorners(const PDScene *sc, const PDLattice *lat, PetscInt qb, PetscInt gid[8]) {
  const PetscReal tol = 1e-9 * lat->dx;
  PetscReal       p[3];
  PetscInt        lo[3] = {0, 0, 0}, n = 0;

  BarNodePlace(lat, qb, p);
  for (PetscInt c = 0; c < lat->dim; c++) lo[c] = (PetscInt)PetscFloorReal((p[c] - lat->origin[c]) / lat->dx);
  for (PetscInt k = 0; k < (1 << lat->dim); k++) {
    PetscInt  ijk[3] = {0, 0, 0};
    PetscReal x[3];
    PetscBool out = PETSC_FALSE, cut = PETSC_FALSE;
    for (PetscInt c = 0; c < lat->dim; c++) {
      ijk[c] = lo[c] + ((k >> c) & 1);
      out    = out || ijk[c] < 0 || ijk[c] >= lat->n[c] ? PETSC_TRUE : PETSC_FALSE;
    }
    PDLatticePlace(lat, ijk, x);
    if (out || InVoid(sc, x)) continue;
    for (PetscInt m = 0; m < sc->nnotches && !cut; m++) cut = NotchCuts(&sc->notch[m], p, x, sc->dim, tol);
    if (!cut) gid[n++] = PDLatticeGid(lat, ijk);
  }
  return n;
}

/* The bar's own nodes before and after bar node q (its segments), the first partners of every bar node. */
static PetscInt SegmentPartners(const PDScene *sc, const PDLattice *lat, PetscInt q, PetscInt gid[PD_MAX_BAR_PARTNERS],
                                PDBarPair kind[PD_MAX_BAR_PARTNERS]) {
  const PetscInt stride = PDBarStride(&sc->bar[lat->bn_bar[q]], lat->dim);
  PetscInt       n      = 0;
  for (PetscInt d = -stride; d <= stride; d += 2 * stride)
    if (q + d >= 0 && q + d < lat->nbarnodes && lat->bn_bar[q + d] == lat->bn_bar[q]) {
      gid[n]    = lat->bn_gid[q + d];
      kind[n++] = PD_BARPAIR_SEGMENT;
    }
  return n;
}

/* The partners of a node q of an embedded bar (PDBarRole): a bar node's are the bar nodes before and after
   it (the segments) and its anchors, an anchor's its bar node and its corners. An anchor without corners
   (its bar node in a void) is left out, and left without bonds, as a void's node is. */
static PetscInt EmbeddedPartners(const PDScene *sc, const PDLattice *lat, PetscInt q, PetscInt gid[PD_MAX_BAR_PARTNERS],
                                 PDBarPair kind[PD_MAX_BAR_PARTNERS]) {
  const PDBar   *b      = &sc->bar[lat->bn_bar[q]];
  const PetscInt stride = PDBarStride(b, lat->dim), r = lat->bn_role[q];
  PetscInt       n = 0, corner[8], nc;

  if (r != PD_BAR_NODE) {
    nc = AnchorCorners(sc, lat, q - r, corner);
    if (!nc) return 0;
    gid[n]    = lat->bn_gid[q - r];
    kind[n++] = PD_BARPAIR_ANCHOR;
    for (PetscInt k = 0; k < nc; k++) {
      gid[n]    = corner[k];
      kind[n++] = PD_BARPAIR_CORNER;
    }
    return n;
  }
  n = SegmentPartners(sc, lat, q, gid, kind);
  if (AnchorCorners(sc, lat, q, corner))
    for (PetscInt a = 1; a < stride; a++) {
      gid[n]    = lat->bn_gid[q + a];
      kind[n++] = PD_BARPAIR_ANCHOR;
    }
  return n;
}

/* The partners of bar node q, as global ids, and their kinds. Lattice nodes outside the lattice, in a void
   or behind a notch are left out: the bar does not bond to concrete across a cut. The same on every rank. */
static PetscInt BarPartners(const PDScene *sc, const PDLattice *lat, PetscInt q, PetscInt gid[PD_MAX_BAR_PARTNERS],
                            PDBarPair kind[PD_MAX_BAR_PARTNERS]) {
  const PDBar    *b   = &sc->bar[lat->bn_bar[q]];
  const PetscInt *c0  = &lat->bn_ijk[3 * q];
  const PetscReal tol = 1e-9 * lat->dx;
  PetscInt        n   = 0, p[3][3], cross[2][3], np;
  PetscReal       x0[3];

  if (b->embedded) return EmbeddedPartners(sc, lat, q, gid, kind);
  n = SegmentPartners(sc, lat, q, gid, kind);
  for (PetscInt c = 0; c < 3; c++) p[0][c] = b->step[c];
  PDLatticePlace(lat, c0, x0);
  np = 1 + CrossDirections(b->step, lat->dim, cross);
  for (PetscInt k = 1; k < np; k++)
    for (PetscInt c = 0; c < 3; c++) p[k][c] = cross[k - 1][c];
  if (!InVoid(sc, x0)) { /* the link */
    gid[n]  = PDLatticeGid(lat, c0);
    kind[n] = PD_BARPAIR_LINK;
    n++;
  }
  for (PetscInt k = 1; k < np; k++) /* the ties */
    for (PetscInt d = -1; d <= 1; d += 2) {
      PetscInt  ijk[3];
      PetscReal x[3];
      PetscBool out = PETSC_FALSE, cut = PETSC_FALSE;
      for (PetscInt c = 0; c < 3; c++) {
        ijk[c] = c0[c] + d * p[k][c];
        out    = out || ijk[c] < 0 || ijk[c] >= lat->n[c] ? PETSC_TRUE : PETSC_FALSE;
      }
      PDLatticePlace(lat, ijk, x);
      if (out || InVoid(sc, x)) continue;
      for (PetscInt m = 0; m < sc->nnotches && !cut; m++) cut = NotchCuts(&sc->notch[m], x0, x, sc->dim, tol);
      if (cut) continue;
      gid[n]  = PDLatticeGid(lat, ijk);
      kind[n] = PD_BARPAIR_TIE;
      n++;
    }
  return n;
}

/* The constants of a pair of an embedded bar (local nodes i, j; EmbeddedPartners): a segment's as on a chain;
   the link of a bar node to its anchor along the bar carries, with bond slip, the bond force as on a chain,
   and under perfect bond is elastic and as stiff as the anchor's ties; the link to an anchor across the bar
   is elastic and as stiff as the concrete cell (E V / dx^2, the shadow's material); an anchor's ties to its
   corners share PD_ANCHOR_STIFFNESS times that equally. A coefficient c gives a bond of length L the
   stiffness c / L along it. */
static void EmbeddedPairConstants(const PDScene *sc, const PDLattice *lat, PetscInt i, PetscInt j, PetscReal *coef,
                                  unsigned char *material) {
  const PetscInt  qi = lat->barnode[i], qj = lat->barnode[j];
  const PetscInt  q = qi >= 0 && (qj < 0 || lat->bn_role[qi] != PD_BAR_NODE) ? qi : qj; /* the anchor, or the bar node of a segment */
  const PDBar    *b = &sc->bar[lat->bn_bar[q]];
  const PetscInt  r = lat->bn_role[q], shadow = PDLatticeLocalIndex(lat, PDLatticeGid(lat, &lat->bn_ijk[3 * q]));
  const PetscReal link = PD_BAR_NODE_SHIFT * lat->dx;
  const PetscReal cell = sc->material[lat->material[shadow]].E * lat->cell_volume / (lat->dx * lat->dx);

  if (r == PD_BAR_NODE) return; /* a segment */
  if (qi >= 0 && qj >= 0) {     /* an anchor's link */
    if (r == PD_BAR_ANCHOR_ALONG && b->slip) {
      PDSlipEnvelope env;
      PDSlipEnvelopeSetUp(b, &env);
      *coef     = env.k0 * b->count * PETSC_PI * b->diameter * lat->bn_length[q] * link;
      *material = PD_MATERIAL_SLIP(lat->bn_bar[q]);
    } else
      *coef = (r == PD_BAR_ANCHOR_ALONG ? PD_ANCHOR_STIFFNESS : 1) * cell * link;
    return;
  }
  {
    PetscInt  corner[8];
    PetscReal L2 = 0;
    for (PetscInt a = 0; a < 3; a++) L2 += PetscSqr(lat->x[3 * j + a] - lat->x[3 * i + a]);
    *coef            = PD_ANCHOR_STIFFNESS * cell / AnchorCorners(sc, lat, q - r, corner) * PetscSqrtReal(L2);
    const PetscInt m = lat->material[qi >= 0 ? j : i]; /* the corner's: a crack through the cell breaks the ties across it */
    *material        = m < sc->nmaterials ? PD_MATERIAL_TIE(m) : PD_MATERIAL_ELASTIC; /* a plate's stay elastic */
  }
}

/* The constants of a pair with a bar node at one end at least (local nodes i, j): a segment has no
   concrete (its steel is set up with the other segments, bars.c); the link of bar node q carries the bond
   force tau(slip) times the bar's perimeter times q's share of the bar's length; a tie is as stiff across
   the bar as the concrete cell, E V / dx^2, split over its two. */
static void BarPairConstants(const PDScene *sc, const PDLattice *lat, PetscInt i, PetscInt j, PetscReal *coef, unsigned char *material) {
  const PetscInt q = lat->barnode[i] >= 0 ? lat->barnode[i] : lat->barnode[j], c = lat->barnode[i] >= 0 ? j : i;
  const PDBar   *b = &sc->bar[lat->bn_bar[q]];
  PetscInt       d[3], n2 = PDLatticeOffset(lat, i, j, d);

  *coef     = 0;
  *material = PD_MATERIAL_ELASTIC;
  if (b->embedded) {
    EmbeddedPairConstants(sc, lat, i, j, coef, material);
    return;
  }
  if (lat->barnode[i] >= 0 && lat->barnode[j] >= 0) return;
  if (n2 == 0) { /* the link to the node q shadows */
    PDSlipEnvelope env;
    PDSlipEnvelopeSetUp(b, &env);
    *coef     = env.k0 * b->count * PETSC_PI * b->diameter * lat->bn_length[q] * PD_BAR_NODE_SHIFT * lat->dx;
    *material = PD_MATERIAL_SLIP(lat->bn_bar[q]);
  } else
    *coef = sc->material[lat->material[c]].E * lat->cell_volume / (lat->dx * lat->dx) * PetscSqrtReal((PetscReal)n2) * lat->dx / 2;
}

/* Pairs with a bar node that the owned node i starts (FindPairs' rule: a pair of two owned nodes from the
   lower global id). The lattice nodes' pairs come from rev, the links and ties of the local bar nodes
   sorted by lattice node: rev[2k] the lattice node's global id, rev[2k + 1] the bar node's. */
static PetscErrorCode PushBarPairs(const PDScene *sc, const PDLattice *lat, PetscInt i, const PetscInt *rev, PetscInt nrev, PairList *pl) {
  const PetscInt gi = lat->gid[i], first = lat->gid_start, last = lat->gid_start + lat->nowned;
  PetscInt       gid[PD_MAX_BAR_PARTNERS], n = 0, lo = 0, hi = nrev;
  PDBarPair      kind[PD_MAX_BAR_PARTNERS];

  PetscFunctionBeginUser;
  if (lat->barnode[i] >= 0)
    n = BarPartners(sc, lat, lat->barnode[i], gid, kind);
  else {
    while (lo < hi) { /* the first entry of gi */
      const PetscInt mid = (lo + hi) / 2;
      if (rev[2 * mid] < gi)
        lo = mid + 1;
      else
        hi = mid;
    }
    for (; lo < nrev && rev[2 * lo] == gi; lo++) {
      PetscCheck(n < PD_MAX_BAR_PARTNERS, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                 "Options -pd_bar*_line: more than %d bar nodes with bond slip tie to the lattice node at %g,%g,%g m; move the bars apart",
                 PD_MAX_BAR_PARTNERS, (double)lat->x[3 * i], (double)lat->x[3 * i + 1], (double)lat->x[3 * i + 2]);
      gid[n++] = rev[2 * lo + 1];
    }
  }
  for (PetscInt k = 0; k < n; k++) {
    const PetscInt j = PDLatticeLocalIndex(lat, gid[k]);
    if (gid[k] < gi && gid[k] >= first && gid[k] < last) continue;
    PetscCheck(j >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "bar pair beyond the ghost layers");
    PetscCall(PairListPush(pl, i, j));
  }
  PetscFunctionReturn(0);
}

static int ComparePairs(const void *pa, const void *pb) {
  const PetscInt *a = (const PetscInt *)pa, *b = (const PetscInt *)pb;
  return a[0] != b[0] ? (a[0] < b[0] ? -1 : 1) : (a[1] < b[1] ? -1 : a[1] > b[1]);
}

/* rev for PushBarPairs: every link and tie of the local bar nodes, by lattice node. */
static PetscErrorCode BarPairsByLatticeNode(const PDScene *sc, const PDLattice *lat, PetscInt **rev, PetscInt *nrev) {
  PetscInt n = 0;

  PetscFunctionBeginUser;
  *rev  = NULL;
  *nrev = 0;
  if (!lat->barnode) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < sc->nbars; k++) { /* a tie reaches no further than the ghost layers */
    PetscInt cross[2][3], nc;
    if (!sc->bar[k].slip || sc->bar[k].embedded) continue;
    nc = CrossDirections(sc->bar[k].step, lat->dim, cross);
    for (PetscInt c = 0; c < nc; c++)
      PetscCheck(PetscAbsInt(cross[c][0]) <= lat->reach &&
                     cross[c][0] * cross[c][0] + cross[c][1] * cross[c][1] + cross[c][2] * cross[c][2] <= lat->reach * lat->reach,
                 lat->comm, PETSC_ERR_USER_INPUT,
                 "Option %s_bond slip: the bar's direction (%" PetscInt_FMT ", %" PetscInt_FMT ", %" PetscInt_FMT
                 ") has no lattice direction across it within %" PetscInt_FMT
                 " spacings to tie it to the concrete; run it along an axis or a diagonal",
                 sc->bar[k].option, sc->bar[k].step[0], sc->bar[k].step[1], sc->bar[k].step[2], lat->reach);
  }
  PetscCall(PetscMalloc1(2 * PD_MAX_BAR_PARTNERS * PetscMax(1, lat->nbarnodes), rev));
  for (PetscInt l = 0; l < lat->nlocal; l++) {
    PetscInt  gid[PD_MAX_BAR_PARTNERS], np;
    PDBarPair kind[PD_MAX_BAR_PARTNERS];
    if (lat->barnode[l] < 0) continue;
    np = BarPartners(sc, lat, lat->barnode[l], gid, kind);
    for (PetscInt k = 0; k < np; k++) {
      if (kind[k] == PD_BARPAIR_SEGMENT || kind[k] == PD_BARPAIR_ANCHOR) continue; /* bar node to bar node */
      (*rev)[2 * n]     = gid[k];
      (*rev)[2 * n + 1] = lat->gid[l];
      n++;
    }
  }
  qsort(*rev, n, 2 * sizeof(PetscInt), ComparePairs);
  *nrev = n;
  PetscFunctionReturn(0);
}

/* Neighbour search: for every owned node outside the voids, every node within the horizon, outside the
   voids too, that no notch separates. The family is the lattice stencil (design point 28) laid on the
   node's integer lattice indices, so the set depends neither on where the domain sits nor on the slab
   partition. cut[PD_SHARES i + k] collects the shares (FamilyShares) of the owned node's neighbours behind a notch. */
static PetscErrorCode FindPairs(const PDScene *sc, const PDLattice *lat, PairList *pl, PetscInt *ncut_local, PetscReal *cut) {
  const PetscReal tol   = 1e-9 * sc->dx;
  const PetscInt  first = lat->gid_start, last = lat->gid_start + lat->nowned;

  PetscInt *rev, nrev;

  PetscFunctionBeginUser;
  *ncut_local = 0;
  PetscCall(BarPairsByLatticeNode(sc, lat, &rev, &nrev));
  for (PetscInt i = 0; i < lat->nowned; i++) {
    const PetscInt   gi = first + i;
    const PetscReal *xi = &lat->x[3 * i];
    PetscInt         c[3];
    if (lat->hollow[i]) continue;
    if (lat->barnode && lat->barnode[i] >= 0) {
      PetscCall(PushBarPairs(sc, lat, i, rev, nrev, pl));
      continue;
    }
    PDLatticeNodeIndices(lat, gi, c);
    for (PetscInt s = 0; s < lat->nstencil; s++) {
      const PetscInt *st = &lat->stencil[4 * s];
      const PetscInt  ni = c[0] + st[0], nj = c[1] + st[1], nk = c[2] + st[2];
      PetscInt        gj, j;
      PetscBool       cuts = PETSC_FALSE;
      if (ni < 0 || ni >= lat->n[0] || nj < 0 || nj >= lat->n[1] || nk < 0 || nk >= lat->n[2]) continue;
      {
        const PetscInt ijk[3] = {ni, nj, nk};
        gj                    = PDLatticeGid(lat, ijk);
      }
      /* each owned pair once (lower global id first); a pair with a ghost is held by both ranks */
      if (gj < gi && gj >= first && gj < last) continue;
      j = PDLatticeLocalIndex(lat, gj);
      if (lat->hollow[j]) continue; /* no material there: the void's faces are free surfaces */
      for (PetscInt q = 0; q < sc->nnotches && !cuts; q++) cuts = NotchCuts(&sc->notch[q], xi, &lat->x[3 * j], sc->dim, tol);
      if (cuts) {
        PetscReal w[PD_SHARES];
        FamilyShares(sc, lat, st, w);
        for (PetscInt k = 0; k < PD_SHARES; k++) {
          cut[PD_SHARES * i + k] += w[k];
          if (j < lat->nowned) cut[PD_SHARES * j + k] += w[k]; /* a pair with a ghost is seen by the ghost's owner too */
        }
        if (gi < gj) (*ncut_local)++;
        if (PDBarOfPair(sc, lat, gi, gj) < 0) continue;
        /* a bar crosses the notch: the pair stays for its segment, without concrete */
        PetscCall(PairListPush(pl, i, -1 - j));
        continue;
      }
      PetscCall(PairListPush(pl, i, j));
    }
    if (lat->barnode) PetscCall(PushBarPairs(sc, lat, i, rev, nrev, pl));
  }
  PetscCall(PetscFree(rev));
  PetscFunctionReturn(0);
}

/* Rows of the stiffness: for each owned node the bonds it belongs to, sorted by the neighbour's global id. */
static PetscErrorCode BuildIncidence(const PDLattice *lat, PDBonds *bd) {
  PetscInt *fill, *key;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(lat->nowned + 1, &bd->inc_start));
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    bd->inc_start[bd->a[e] + 1]++;
    if (bd->b[e] < lat->nowned) bd->inc_start[bd->b[e] + 1]++;
  }
  for (PetscInt i = 0; i < lat->nowned; i++) bd->inc_start[i + 1] += bd->inc_start[i];
  PetscCall(PetscMalloc1(bd->inc_start[lat->nowned], &bd->inc_bond));
  PetscCall(PetscCalloc1(lat->nowned, &fill));
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    bd->inc_bond[bd->inc_start[bd->a[e]] + fill[bd->a[e]]++] = e;
    if (bd->b[e] < lat->nowned) bd->inc_bond[bd->inc_start[bd->b[e]] + fill[bd->b[e]]++] = e;
  }
  PetscCall(PetscMalloc1(PetscMax(1, bd->inc_start[lat->nowned]), &key));
  for (PetscInt i = 0; i < lat->nowned; i++) {
    const PetscInt s = bd->inc_start[i], n = bd->inc_start[i + 1] - s;
    for (PetscInt p = 0; p < n; p++) {
      const PetscInt e = bd->inc_bond[s + p];
      key[p]           = lat->gid[bd->a[e] == i ? bd->b[e] : bd->a[e]];
    }
    PetscCall(PetscSortIntWithArray(n, key, bd->inc_bond + s));
  }
  PetscCall(PetscFree(key));
  PetscCall(PetscFree(fill));
  PetscFunctionReturn(0);
}

/* Surface correction: the bonds of a node near a face are stiffened to make up for the material missing
   beyond it. A notch is a cut through material that is there, so by default the neighbours behind it still
   count (cut); otherwise the bonds around the notch tip are stiffened and strengthened, the spurious
   strengthening Hobbs Sec. 5.4.2 suspects near notches. -pd_sc_notch_surface treats the notch faces as
   free surfaces instead. Node sums are shared with neighbouring ranks through a ghosted vector.
   - continuum calibration, the volume method (Eq. 4.11): V_i = sum_j beta_ij V_j over the family of i and
     lambda_ij = 2 V0 / (V_i + V_j), V0 the horizon's analytic volume. In the bulk this is V0 over the
     lattice's family volume, which makes up for part of the stencil's quadrature error as well.
   - stencil calibration (the bulk is right already, PDMicromodulus), the energy method of Madenci and
     Oterkus (2014, Sec. 4.2) on the lattice: a node's stiffness along axis a, S_a = sum_j omega beta |xi|
     e_a^4, against a bulk node's S0 gives the factor S0 / S_a per axis; along a bond's direction e they
     combine as an ellipsoid, G(e) = (sum_a e_a^2 (S_a / S0)^2)^(-1/2), and lambda_ij = (G_i + G_j) / 2.
     A node by a face parallel to the load keeps nearly all of its stiffness along the face, so the bonds
     along the face are hardly stiffened, where the volume method stiffens them with the lost volume. */
static PetscErrorCode SurfaceCorrection(const PDScene *sc, const PDLattice *lat, PDBonds *bd, const PetscReal *beta, const PetscReal *cut,
                                        PetscBool keep) {
  Vec             shares, sloc;
  PetscScalar    *v;
  const PetscReal delta   = lat->horizon;
  const PetscBool stencil = sc->calibration == PD_CALIBRATION_STENCIL ? PETSC_TRUE : PETSC_FALSE;
  const PetscReal V0      = sc->dim == 3 ? 4.0 / 3.0 * PETSC_PI * delta * delta * delta : PETSC_PI * delta * delta * sc->thickness;
  PetscReal       S0 = 0, lmin = PETSC_MAX_REAL, lmax = PETSC_MIN_REAL, w[PD_SHARES];

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < lat->nstencil; k++) {
    FamilyShares(sc, lat, &lat->stencil[4 * k], w);
    S0 += w[1];
  }
  PetscCall(PDLatticeCreateGhostVec(lat, PD_SHARES, &shares));
  PetscCall(VecGetArray(shares, &v));
  for (PetscInt i = 0; i < lat->nowned; i++) {
    for (PetscInt k = 0; k < PD_SHARES; k++) v[PD_SHARES * i + k] = sc->notch_surface ? 0 : cut[PD_SHARES * i + k];
    for (PetscInt p = bd->inc_start[i]; p < bd->inc_start[i + 1]; p++) {
      const PetscInt e = bd->inc_bond[p];
      PetscInt       st[4];
      if (beta[e] == 0) continue; /* a bar-only pair (counted as cut), or a pair with a bar node */
      st[3] = PDLatticeOffset(lat, bd->a[e], bd->b[e], st);
      FamilyShares(sc, lat, st, w);
      for (PetscInt k = 0; k < PD_SHARES; k++) v[PD_SHARES * i + k] += w[k];
    }
  }
  PetscCall(VecRestoreArray(shares, &v));
  PetscCall(VecGhostUpdateBegin(shares, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(shares, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostGetLocalForm(shares, &sloc));
  PetscCall(VecGetArray(sloc, &v));
  PetscCall(PetscMalloc1(PD_SHARES * PetscMax(1, lat->nlocal), &bd->sc_shares));
  for (PetscInt k = 0; k < PD_SHARES * lat->nlocal; k++) bd->sc_shares[k] = PetscRealPart(v[k]);
  PetscCall(VecRestoreArray(sloc, &v));
  PetscCall(VecGhostRestoreLocalForm(shares, &sloc));
  PetscCall(VecDestroy(&shares));
  bd->sc_stencil = stencil;
  bd->sc_ref     = stencil ? S0 : V0;
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    /* no concrete, or a bar node's link or tie: nothing to correct */
    const PetscReal lam = beta[e] == 0 ? 1 : PDBondSurfaceFactor(lat, bd, e);
    bd->coef[e] *= lam;
    lmin = PetscMin(lmin, lam);
    lmax = PetscMax(lmax, lam);
  }
  if (!keep) PetscCall(PetscFree(bd->sc_shares));
  PetscCall(MPIU_Allreduce(&lmin, &bd->lambda_min, 1, MPIU_REAL, MPIU_MIN, lat->comm));
  PetscCall(MPIU_Allreduce(&lmax, &bd->lambda_max, 1, MPIU_REAL, MPIU_MAX, lat->comm));
  PetscFunctionReturn(0);
}

/* Notches and voids must not cut the body apart (connectivity.c): the error names them and a node on
   either side of the cut. */
static PetscErrorCode CheckOnePiece(const PDScene *sc, const PDLattice *lat, const PDBonds *bd) {
  PetscInt nparts, first[2];
  char     cuts[256] = "", *p = cuts;

  PetscFunctionBeginUser;
  if (!sc->nnotches && !sc->nvoids) PetscFunctionReturn(0); /* a whole box with m >= 1 is one piece */
  PetscCall(PDBondsCountParts(lat, bd, &nparts, first));
  if (nparts <= 1) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < sc->nnotches && p < cuts + sizeof cuts - 40; k++)
    p += snprintf(p, 40, "%s%s_box", p > cuts ? ", " : "", sc->notch[k].option);
  for (PetscInt k = 0; k < sc->nvoids && p < cuts + sizeof cuts - 40; k++)
    p += snprintf(p, 40, "%s%s_%s", p > cuts ? ", " : "", sc->voids[k].option,
                  sc->voids[k].where.shape == PD_SHAPE_BOX ? "box" : "cylinder");
  {
    PetscInt  ijk[2][3];
    PetscReal x[2][3];
    for (PetscInt s = 0; s < 2; s++) {
      PDLatticeNodeIndices(lat, first[s], ijk[s]);
      PDLatticePlace(lat, ijk[s], x[s]);
    }
    SETERRQ(lat->comm, PETSC_ERR_USER_INPUT,
            "Options %s: the notches and voids cut the body into %" PetscInt_FMT
            " pieces that share no bond (the node at %g,%g,%g m and the one at %g,%g,%g m are apart); a loose piece is a mechanism",
            cuts, nparts, (double)x[0][0], (double)x[0][1], (double)x[0][2], (double)x[1][0], (double)x[1][1], (double)x[1][2]);
  }
}

/* Bonds whose concrete stays elastic: to a node in a no-fail zone (Ness), or between a node of a bar with
   perfect bond and a concrete node (the interface bonds of the thesis, which never fail). */
static PetscBool NeverDamages(const PDScene *sc, const PDLattice *lat, const PetscInt *node_bar, PetscInt i, PetscInt j) {
  PetscInt ki, kj;
  if (lat->nofail[i] || lat->nofail[j]) return PETSC_TRUE;
  if (!node_bar) return PETSC_FALSE;
  ki = node_bar[i];
  kj = node_bar[j];
  return (ki >= 0) != (kj >= 0) && sc->bar[ki >= 0 ? ki : kj].perfect ? PETSC_TRUE : PETSC_FALSE;
}

/* The stencil calibration's factor of bond e (SurfaceCorrection): its nodes' ellipsoids along its direction. */
PetscReal PDBondSurfaceFactorStencil(const PDLattice *lat, const PDBonds *bd, PetscInt e) {
  const PetscReal *va = &bd->sc_shares[PD_SHARES * bd->a[e]], *vb = &bd->sc_shares[PD_SHARES * bd->b[e]];
  PetscInt         d[3];
  PetscReal        n2 = PDLatticeOffset(lat, bd->a[e], bd->b[e], d), qa = 0, qb = 0;
  for (PetscInt a = 0; a < 3; a++) {
    qa += d[a] * d[a] / n2 * PetscSqr(va[1 + a] / bd->sc_ref);
    qb += d[a] * d[a] / n2 * PetscSqr(vb[1 + a] / bd->sc_ref);
  }
  return qa > 0 && qb > 0 ? 0.5 * (1 / PetscSqrtReal(qa) + 1 / PetscSqrtReal(qb)) : 1;
}

PetscErrorCode PDBondsCreate(const PDScene *sc, const PDLattice *lat, PetscBool keep_lambda, PDBonds *bd) {
  PairList   pl = {NULL, NULL, 0, 0};
  PetscInt   ncut_local, nonce = 0;
  PetscReal *beta, *cut;
  PetscReal  c0[PD_MAX_MATERIALS];
  PetscInt  *node_bar = NULL; /* the bar holding each local node, or -1 (scenes with bars) */

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(bd, sizeof *bd));
  PetscCall(PetscCalloc1(PD_SHARES * PetscMax(1, lat->nowned), &cut));
  PetscCall(FindPairs(sc, lat, &pl, &ncut_local, cut));
  bd->nbonds = pl.n;
  bd->a      = pl.a;
  bd->b      = pl.b;
  PetscCall(PetscMalloc2(PetscMax(1, bd->nbonds), &bd->coef, PetscMax(1, bd->nbonds), &bd->material));
  PetscCall(PetscMalloc1(PetscMax(1, bd->nbonds), &beta));
  for (PetscInt m = 0; m < sc->nmaterials + sc->nplates; m++) c0[m] = PDMicromodulus(sc, sc->material[m].E);
  if (sc->nbars) {
    PetscCall(PetscMalloc1(lat->nlocal, &node_bar));
    for (PetscInt l = 0; l < lat->nlocal; l++) node_bar[l] = PDBarHoldingNode(sc, lat, lat->gid[l]);
  }
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscBool bar_only = bd->b[e] < 0 ? PETSC_TRUE : PETSC_FALSE;
    PetscInt        i, j, mi, mj, d[3], n2, m;
    if (bar_only) bd->b[e] = -1 - bd->b[e];
    i = bd->a[e];
    j = bd->b[e];
    if (lat->barnode && (lat->barnode[i] >= 0 || lat->barnode[j] >= 0)) {
      BarPairConstants(sc, lat, i, j, &bd->coef[e], &bd->material[e]);
      beta[e] = 0;
      if (PDBondCountedHere(lat, bd, e)) nonce++;
      continue;
    }
    mi = lat->material[i];
    mj = lat->material[j];
    /* length and partial volume from the exact lattice offset, in units of dx */
    n2 = PDLatticeOffset(lat, i, j, d);
    /* a bond joining two materials takes the softer one: the interface is no stronger than its weaker side */
    m               = sc->material[mi].E <= sc->material[mj].E ? mi : mj;
    bd->material[e] = m;
    beta[e]         = PDFamilyPartialVolume(sc->horizon_ratio, n2, sc->partial_volume);
    bd->coef[e] = c0[m] * PDInfluenceValue(sc->influence, PetscSqrtReal((PetscReal)n2), sc->horizon_ratio) * beta[e] * lat->cell_volume *
                  lat->cell_volume;
    if (NeverDamages(sc, lat, node_bar, i, j)) bd->material[e] = PD_MATERIAL_ELASTIC;
    if (bar_only) { /* its neighbour counts in the surface correction as cut already (cut) */
      beta[e]         = 0;
      bd->coef[e]     = 0;
      bd->material[e] = PD_MATERIAL_ELASTIC;
    }
    if (PDBondCountedHere(lat, bd, e)) nonce++;
  }
  PetscCall(PetscFree(node_bar));
  PetscCall(BuildIncidence(lat, bd));
  bd->lambda_min = bd->lambda_max = 1;
  keep_lambda                     = keep_lambda && sc->surface_correction;
  if (sc->surface_correction) PetscCall(SurfaceCorrection(sc, lat, bd, beta, cut, keep_lambda));
  PetscCall(PetscFree(beta));
  PetscCall(PetscFree(cut));
  {
    PetscInt64 n = nonce;
    PetscCall(MPIU_Allreduce(&n, &bd->nbonds_global, 1, MPIU_INT64, MPI_SUM, lat->comm));
  }
  PetscCall(MPIU_Allreduce(&ncut_local, &bd->ncut, 1, MPIU_INT, MPI_SUM, lat->comm));
  PetscCall(PDBondsSetUpBars(sc, lat, bd));
  PetscCall(CheckOnePiece(sc, lat, bd));
  PetscFunctionReturn(0);
}

PetscErrorCode PDBondsDestroy(PDBonds *bd) {
  PetscFunctionBeginUser;
  PetscCall(PetscFree(bd->a));
  PetscCall(PetscFree(bd->b));
  PetscCall(PetscFree2(bd->coef, bd->material));
  PetscCall(PetscFree(bd->inc_start));
  PetscCall(PetscFree(bd->inc_bond));
  PetscCall(PetscFree(bd->sc_shares));
  PetscCall(PetscFree(bd->seg));
  PetscCall(PetscFree3(bd->seg_bond, bd->seg_bar, bd->seg_coef));
  PetscFunctionReturn(0);
}

PetscBool PDBondCountedHere(const PDLattice *lat, const PDBonds *bd, PetscInt e) {
  return (bd->b[e] < lat->nowned || lat->gid[bd->a[e]] < lat->gid[bd->b[e]]) ? PETSC_TRUE : PETSC_FALSE;
}
