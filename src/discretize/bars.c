/* Steel bar segments on the lattice (docs/reinforcement.md). A bar's line is laid on a chain of nodes one
   lattice offset (PDBar.step) apart, from the node nearest to its start; each pair of consecutive nodes
   of the chain within the bar's ends is a segment, an axial member of stiffness E A_s and yield force
   f_y A_s exactly, whatever dx. An embedded bar is on nodes of its own at its true places, evenly along it,
   whose consecutive pairs are its segments, exact alike. */
#include "pd_lattice.h"

/* As Chain below, and along the bar's line: where node k = 0 sits (t0, m from the bar's start), the step
   length and the bar's length. */
static void ChainAlong(const PDLattice *lat, const PDBar *b, PetscInt base[3], PetscInt *kmin, PetscInt *kmax, PetscReal along[3]) {
  PetscReal u[3], len = 0, ls = 0, t0 = 0;

  for (PetscInt c = 0; c < 3; c++) {
    const PetscInt near = (PetscInt)PetscFloorReal((b->line[c] - lat->origin[c]) / lat->dx + 0.5);
    base[c]             = c < lat->dim ? PetscMin(PetscMax(near, 0), lat->n[c] - 1) : 0;
    u[c]                = b->line[3 + c] - b->line[c];
    len += u[c] * u[c];
    ls += (PetscReal)(b->step[c] * b->step[c]);
  }
  len = PetscSqrtReal(len);
  ls  = PetscSqrtReal(ls) * lat->dx; /* one step along the chain (m) */
  for (PetscInt c = 0; c < 3; c++) t0 += (lat->origin[c] + base[c] * lat->dx - b->line[c]) * u[c] / len;
  /* node k sits at t0 + k ls along the bar, which holds it for t in [0, len] */
  *kmin = (PetscInt)PetscCeilReal(-t0 / ls - 1e-9);
  *kmax = (PetscInt)PetscFloorReal((len - t0) / ls + 1e-9);
  for (PetscInt c = 0; c < lat->dim; c++) { /* and the lattice holds it */
    const PetscInt s = b->step[c];
    if (s > 0) {
      *kmin = PetscMax(*kmin, -(base[c] / s));
      *kmax = PetscMin(*kmax, (lat->n[c] - 1 - base[c]) / s);
    } else if (s < 0) {
      *kmin = PetscMax(*kmin, -((lat->n[c] - 1 - base[c]) / -s));
      *kmax = PetscMin(*kmax, base[c] / -s);
    }
  }
  along[0] = t0;
  along[1] = ls;
  along[2] = len;
}

/* The chain of bar b: its base node's indices (the lattice node nearest to the bar's start) and the range
   of k for which base + k step lies within the bar's ends (projected on its line) and in the lattice. */
static void Chain(const PDLattice *lat, const PDBar *b, PetscInt base[3], PetscInt *kmin, PetscInt *kmax) {
  PetscReal along[3];
  ChainAlong(lat, b, base, kmin, kmax, along);
}

/* The nodes of an embedded bar b at station st: the bar node at its place along the bar (the ends included), in
   the x-layer of the lattice node nearest to it, which it shadows, and its anchors PD_BAR_NODE_SHIFT dx from it
   against their directions. */
static void EmbeddedStation(const PDLattice *lat, const PDBar *b, PetscInt st, PetscInt shadow[3], PetscReal place[3], PetscReal *share) {
  const PetscReal h = b->spacing;
  for (PetscInt c = 0; c < 3; c++) {
    place[c] = c < lat->dim ? b->line[c] + st * h * b->dir[0][c] : 0;
    shadow[c] =
        c < lat->dim ? PetscMin(PetscMax((PetscInt)PetscFloorReal((place[c] - lat->origin[c]) / lat->dx + 0.5), 0), lat->n[c] - 1) : 0;
  }
  *share = st == 0 || st == b->nstation - 1 ? 0.5 * h : h;
}

PetscErrorCode PDLatticeSetUpBarNodes(const PDScene *sc, PDLattice *lat) {
  const PetscInt nl = lat->n[1] * lat->n[2];
  PetscInt       n  = 0, *count;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < sc->nbars; k++) {
    PetscInt base[3], kmin, kmax;
    if (!PDBarHasNodes(&sc->bar[k])) continue;
    if (sc->bar[k].embedded) {
      n += sc->bar[k].nstation * PDBarStride(&sc->bar[k], lat->dim);
      continue;
    }
    Chain(lat, &sc->bar[k], base, &kmin, &kmax);
    n += PetscMax(0, kmax - kmin + 1);
  }
  lat->nbarnodes = n;
  if (!n) PetscFunctionReturn(0);
  PetscCall(PetscMalloc5(n, &lat->bn_bar, 3 * n, &lat->bn_ijk, n, &lat->bn_gid, n, &lat->bn_length, 3 * n, &lat->bn_shift));
  PetscCall(PetscMalloc1(n, &lat->bn_role));
  PetscCall(PetscCalloc1(lat->n[0], &count));
  n = 0;
  for (PetscInt k = 0; k < sc->nbars; k++) {
    const PDBar *b = &sc->bar[k];
    PetscInt     base[3], kmin, kmax;
    PetscReal    along[3];
    if (!PDBarHasNodes(b)) continue;
    if (b->embedded) {
      for (PetscInt st = 0; st < b->nstation; st++) {
        PetscInt  shadow[3];
        PetscReal place[3], share;
        EmbeddedStation(lat, b, st, shadow, place, &share);
        PetscReal x0[3];
        PDLatticePlace(lat, shadow, x0);
        for (PetscInt r = 0; r <= lat->dim; r++, n++) {
          lat->bn_bar[n]    = k;
          lat->bn_role[n]   = (unsigned char)r;
          lat->bn_length[n] = share;
          for (PetscInt a = 0; a < 3; a++) {
            lat->bn_ijk[3 * n + a]   = shadow[a];
            lat->bn_shift[3 * n + a] = place[a] - x0[a] - (r ? PD_BAR_NODE_SHIFT * lat->dx * b->dir[r - 1][a] : 0);
          }
          lat->bn_gid[n] = count[shadow[0]]++;
        }
      }
      continue;
    }
    ChainAlong(lat, b, base, &kmin, &kmax, along);
    for (PetscInt c = kmin; c <= kmax; c++, n++) {
      const PetscReal t = along[0] + c * along[1], ls = along[1];
      lat->bn_bar[n]  = k;
      lat->bn_role[n] = PD_BAR_NODE;
      for (PetscInt a = 0; a < 3; a++) {
        lat->bn_ijk[3 * n + a]   = base[a] + c * b->step[a];
        lat->bn_shift[3 * n + a] = PD_BAR_NODE_SHIFT * lat->dx * b->dir[0][a];
      }
      /* a node carries the bond of the bar within half a step either side, up to the bar's ends: the shares add up to
         the bar's length (a lattice that ends before the bar's end cuts it there) */
      lat->bn_length[n] = (c == kmin ? PetscMin(0.5 * ls, t) : 0.5 * ls) + (c == kmax ? PetscMin(0.5 * ls, along[2] - t) : 0.5 * ls);
      lat->bn_gid[n]    = count[lat->bn_ijk[3 * n]]++; /* its slot in the layer, for now */
    }
  }
  for (PetscInt i = 0; i < lat->n[0]; i++) lat->nslot = PetscMax(lat->nslot, count[i]);
  PetscCall(PetscMalloc1(lat->n[0] * lat->nslot, &lat->slot_node));
  for (PetscInt q = 0; q < lat->n[0] * lat->nslot; q++) lat->slot_node[q] = -1;
  for (PetscInt q = 0; q < n; q++) {
    const PetscInt i                                = lat->bn_ijk[3 * q];
    lat->slot_node[i * lat->nslot + lat->bn_gid[q]] = q;
    lat->bn_gid[q] += i * (nl + lat->nslot) + nl;
  }
  PetscCall(PetscFree(count));
  PetscFunctionReturn(0);
}

/* Whether bar b's chain holds the lattice node ijk within the bar's ends. */
static PetscBool Holds(const PDLattice *lat, const PDBar *b, const PetscInt ijk[3]) {
  PetscInt base[3], kmin, kmax, r[3], rs = 0, s2 = 0, k;

  Chain(lat, b, base, &kmin, &kmax);
  for (PetscInt c = 0; c < 3; c++) {
    r[c] = ijk[c] - base[c];
    rs += r[c] * b->step[c];
    s2 += b->step[c] * b->step[c];
  }
  if (rs % s2) return PETSC_FALSE;
  k = rs / s2;
  for (PetscInt c = 0; c < 3; c++)
    if (r[c] != k * b->step[c]) return PETSC_FALSE;
  return k >= kmin && k <= kmax ? PETSC_TRUE : PETSC_FALSE;
}

/* Whether bar b has a segment on the pair of nodes with lattice indices p and q. */
static PetscBool SegmentOf(const PDLattice *lat, const PDBar *b, const PetscInt p[3], const PetscInt q[3]) {
  PetscBool fwd = PETSC_TRUE, back = PETSC_TRUE;
  for (PetscInt c = 0; c < 3; c++) {
    fwd  = fwd && q[c] - p[c] == b->step[c] ? PETSC_TRUE : PETSC_FALSE;
    back = back && p[c] - q[c] == b->step[c] ? PETSC_TRUE : PETSC_FALSE;
  }
  return (fwd || back) && Holds(lat, b, p) && Holds(lat, b, q) ? PETSC_TRUE : PETSC_FALSE;
}

PetscInt PDBarOfPair(const PDScene *sc, const PDLattice *lat, PetscInt gi, PetscInt gj) {
  PetscInt p[3], q[3];

  if (!sc->nbars) return -1;
  PDLatticeNodeIndices(lat, gi, p);
  PDLatticeNodeIndices(lat, gj, q);
  for (PetscInt k = 0; k < sc->nbars; k++)
    if (!PDBarHasNodes(&sc->bar[k]) && SegmentOf(lat, &sc->bar[k], p, q)) return k;
  return -1;
}

PetscInt PDBarHoldingNode(const PDScene *sc, const PDLattice *lat, PetscInt gid) {
  PetscInt p[3];

  PDLatticeNodeIndices(lat, gid, p);
  for (PetscInt k = 0; k < sc->nbars; k++)
    if (!PDBarHasNodes(&sc->bar[k]) && Holds(lat, &sc->bar[k], p)) return k;
  return -1;
}

/* The bar of the segment joining two local nodes: consecutive bar nodes of a bar with bond slip, or a pair
   of lattice nodes on another bar's chain; -1 for any other pair. */
static PetscInt SegmentBar(const PDScene *sc, const PDLattice *lat, PetscInt i, PetscInt j, const PetscInt p[3], const PetscInt q[3],
                           PetscInt *clash) {
  PetscInt bar = -1;

  if (lat->barnode && (lat->barnode[i] >= 0 || lat->barnode[j] >= 0)) {
    const PetscInt bi = lat->barnode[i], bj = lat->barnode[j];
    if (bi < 0 || bj < 0 || lat->bn_bar[bi] != lat->bn_bar[bj] || lat->bn_role[bi] != PD_BAR_NODE || lat->bn_role[bj] != PD_BAR_NODE)
      return -1;
    return PetscAbsInt(bi - bj) == PDBarStride(&sc->bar[lat->bn_bar[bi]], lat->dim) ? lat->bn_bar[bi] : -1;
  }
  for (PetscInt k = 0; k < sc->nbars; k++) {
    if (PDBarHasNodes(&sc->bar[k]) || !SegmentOf(lat, &sc->bar[k], p, q)) continue;
    /* two bars sharing a pair of nodes would give it two segments: one bar with both areas is what is meant */
    if (bar >= 0) *clash = PetscMax(*clash, bar * PD_MAX_BARS + k + 1);
    bar = k;
  }
  return bar;
}

PetscErrorCode PDBondsSetUpBars(const PDScene *sc, const PDLattice *lat, PDBonds *bd) {
  PetscInt mine = 0, n = 0, clash = 0; /* clash: the first bar of a shared pair times PD_MAX_BARS plus the second, plus 1 */

  PetscFunctionBeginUser;
  if (!sc->nbars) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < sc->nbars; k++) { /* an embedded bar has at least two stations */
    PetscInt base[3], kmin, kmax;
    if (sc->bar[k].embedded) continue;
    Chain(lat, &sc->bar[k], base, &kmin, &kmax);
    PetscCheck(kmax > kmin, lat->comm, PETSC_ERR_USER_INPUT, "Option %s_line: the bar holds no two nodes of the lattice (dx = %g m)",
               sc->bar[k].option, (double)lat->dx);
  }
  /* the bar of each bond (or -1) in seg first, then its segment index */
  PetscCall(PetscMalloc1(PetscMax(1, bd->nbonds), &bd->seg));
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    PetscInt p[3], q[3];
    PDLatticeNodeIndices(lat, lat->gid[bd->a[e]], p);
    PDLatticeNodeIndices(lat, lat->gid[bd->b[e]], q);
    bd->seg[e] = SegmentBar(sc, lat, bd->a[e], bd->b[e], p, q, &clash);
    if (bd->seg[e] >= 0) n++;
  }
  PetscCall(MPIU_Allreduce(MPI_IN_PLACE, &clash, 1, MPIU_INT, MPI_MAX, lat->comm));
  PetscCheck(!clash, lat->comm, PETSC_ERR_USER_INPUT,
             "Options %s_line and %s_line: the two bars share a pair of nodes; give one bar with _count, or move one by at least dx = %g m",
             sc->bar[(clash - 1) / PD_MAX_BARS].option, sc->bar[(clash - 1) % PD_MAX_BARS].option, (double)lat->dx);
  bd->nseg = n;
  PetscCall(PetscMalloc3(PetscMax(1, n), &bd->seg_bond, PetscMax(1, n), &bd->seg_bar, PetscMax(1, n), &bd->seg_coef));
  n = 0;
  for (PetscInt e = 0; e < bd->nbonds; e++) {
    const PetscInt k = bd->seg[e];
    if (k < 0) continue;
    bd->seg[e]      = n;
    bd->seg_bond[n] = e;
    bd->seg_bar[n]  = k;
    bd->seg_coef[n] = sc->bar[k].E * PDBarArea(&sc->bar[k]);
    if (PDBondCountedHere(lat, bd, e)) mine++;
    n++;
  }
  PetscCall(MPIU_Allreduce(&mine, &bd->nseg_global, 1, MPIU_INT, MPI_SUM, lat->comm));
  PetscFunctionReturn(0);
}
