/* Unit tests of the pure functions: micromodulus constants (Hobbs Table 3.1, Eq. 3.27/3.28),
   influence functions, the bond-family rule and the node-selection rule of regions. */
#include "pd_material.h"
#include "pd_lattice.h"
#include "check.h"

int main(int argc, char **argv) {
  PDScene         sc;
  const PetscReal E = 37e9, dx = 5e-3, m = 3.14, t = 0.05, d = m * dx;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscMemzero(&sc, sizeof sc));
  sc.dx            = dx;
  sc.horizon_ratio = m;
  sc.thickness     = t;
  sc.model         = PD_MODEL_3D;
  sc.dim           = 3;
  sc.influence     = PD_INFLUENCE_CONSTANT;
  CheckRel("3D constant c = 12E/(pi d^4)", PDMicromodulus(&sc, E), 12 * E / (PETSC_PI * d * d * d * d), 1e-12);
  sc.influence = PD_INFLUENCE_CONICAL;
  CheckRel("3D conical c0 = 60E/(pi d^4)", PDMicromodulus(&sc, E), 60 * E / (PETSC_PI * d * d * d * d), 1e-12);
  sc.influence = PD_INFLUENCE_QUARTIC;
  CheckRel("3D quartic c0 = 72E/(pi d^4)", PDMicromodulus(&sc, E), 72 * E / (PETSC_PI * d * d * d * d), 1e-12);
  sc.influence = PD_INFLUENCE_CONSTANT;
  sc.model     = PD_MODEL_PLANE_STRESS;
  CheckRel("plane stress c = 9E/(pi t d^3)", PDMicromodulus(&sc, E), 9 * E / (PETSC_PI * t * d * d * d), 1e-12);
  sc.model = PD_MODEL_PLANE_STRAIN;
  CheckRel("plane strain c = 48E/(5 pi t d^3)", PDMicromodulus(&sc, E), 48 * E / (5 * PETSC_PI * t * d * d * d), 1e-12);

  /* fracture energy across a lattice plane over the continuum integral (docs/arclength.md): values at
     delta = pi dx from an independent count in Python; the continuum is approached as delta/dx grows */
  sc.model          = PD_MODEL_PLANE_STRESS;
  sc.dim            = 2;
  sc.partial_volume = PETSC_TRUE;
  sc.horizon_ratio  = PETSC_PI;
  CheckRel("2D lattice fracture ratio at pi dx", PDLatticeFractureRatio(&sc), 0.7436490012, 1e-9);
  sc.horizon_ratio = 30.5;
  CheckRel("2D lattice fracture ratio at 30.5 dx -> 1", PDLatticeFractureRatio(&sc), 1, 0.02);
  sc.model         = PD_MODEL_3D;
  sc.dim           = 3;
  sc.horizon_ratio = PETSC_PI;
  CheckRel("3D lattice fracture ratio at pi dx", PDLatticeFractureRatio(&sc), 0.7607711772, 1e-9);
  sc.horizon_ratio = m;

  CheckRel("conical omega(d/2) = 1/2", PDInfluenceValue(PD_INFLUENCE_CONICAL, d / 2, d), 0.5, 1e-14);
  CheckRel("quartic omega(d/2) = 9/16", PDInfluenceValue(PD_INFLUENCE_QUARTIC, d / 2, d), 9.0 / 16.0, 1e-14);
  Check(PDInfluenceValue(PD_INFLUENCE_QUARTIC, d, d) == 0 ? PETSC_TRUE : PETSC_FALSE, "quartic omega(d) = 0",
        PDInfluenceValue(PD_INFLUENCE_QUARTIC, d, d), 0);

  {
    /* a box flat in x selects one layer: the nearest, the upper one at a tie, the lower one on the
       domain's upper face */
    PDScene    sc2;
    PDGeometry g     = {PD_SHAPE_BOX, {0.025, 0, 0, 0.025, 0.05, 0}, 0, {0, 0, 0}, 0};
    PDGeometry t     = {PD_SHAPE_BOX, {0.0875, 0, 0.05, 0.0875, 0.05, 0.05}, 0, {0, 0, 0}, 0};
    PetscReal  up[3] = {0.0275, 0.01, 0.0025}, lo[3] = {0.0225, 0.01, 0.0025}, far[3] = {0.0325, 0.01, 0.0025},
              second[3] = {0.0275, 0.01, 0.0075};
    PetscReal top[3] = {0.0875, 0.01, 0.0475}, below[3] = {0.0875, 0.01, 0.0425};
    PetscCall(PetscMemzero(&sc2, sizeof sc2));
    sc2.dx           = dx;
    sc2.dim          = 3;
    PetscReal dom[6] = {0, 0, 0, 0.175, 0.05, 0.05};
    PetscCall(PetscArraycpy(sc2.domain, dom, 6));
    Check(PDGeometryContains(&g, up, &sc2), "plane between layers: the upper layer is in", 1, 1);
    Check(!PDGeometryContains(&g, lo, &sc2), "plane between layers: the lower layer is out (no clamp)", 0, 0);
    Check(!PDGeometryContains(&g, far, &sc2), "flat box drops a node 3dx/2 away", 0, 0);
    Check(!PDGeometryContains(&g, second, &sc2), "bottom plane z = 0 holds only the first layer", 0, 0);
    Check(PDGeometryContains(&t, top, &sc2), "plane on the upper face holds the top layer", 1, 1);
    Check(!PDGeometryContains(&t, below, &sc2), "plane on the upper face drops the layer below it", 0, 0);
  }
  {
    PDGeometry c    = {PD_SHAPE_CYLINDER, {0, 0, 0, 0, 0, 0}, 1, {0.1, 0, 0.05}, 0.01};
    PetscReal  a[3] = {0.105, 3.0, 0.055}, b[3] = {0.115, 0.0, 0.05};
    Check(PDGeometryContains(&c, a, &sc), "cylinder along y holds a point at r = 7 mm", 1, 1);
    Check(!PDGeometryContains(&c, b, &sc), "cylinder along y drops a point at r = 15 mm", 0, 0);
  }
  {
    /* the bond family in lattice units (design point 28): n2 = di^2 + dj^2 + dk^2 against m^2, pairs at
       r = delta bonded with partial volume exactly 1/2 */
    const PetscReal r3 = 2 * PetscSqrtReal(3.0);
    Check(PDFamilyRule(3, 9) == PD_FAMILY_EDGE, "m = 3: offset (3,0,0) on the horizon's edge", PDFamilyRule(3, 9), PD_FAMILY_EDGE);
    Check(PDFamilyRule(3, 8) == PD_FAMILY_IN, "m = 3: offset (2,2,0) inside", PDFamilyRule(3, 8), PD_FAMILY_IN);
    Check(PDFamilyRule(3, 10) == PD_FAMILY_OUT, "m = 3: offset (3,1,0) outside", PDFamilyRule(3, 10), PD_FAMILY_OUT);
    Check(PDFamilyRule(r3, 12) == PD_FAMILY_EDGE, "m = 2 sqrt(3): offset (2,2,2) on the edge despite m^2 < 12", PDFamilyRule(r3, 12),
          PD_FAMILY_EDGE);
    Check(PDFamilyRule(PETSC_PI, 9) == PD_FAMILY_IN && PDFamilyRule(PETSC_PI, 10) == PD_FAMILY_OUT, "m = pi: n2 = 9 inside, 10 outside",
          PDFamilyRule(PETSC_PI, 10), PD_FAMILY_OUT);
    Check(PDFamilyRule(3 * (1 - 1e-12), 9) == PD_FAMILY_OUT, "m = 3 (1 - 1e-12): (3,0,0) outside (tolerance only at round-off)",
          PDFamilyRule(3 * (1 - 1e-12), 9), PD_FAMILY_OUT);
    Check(PDFamilyPartialVolume(3, 9, PETSC_TRUE) == 0.5, "m = 3: partial volume 1/2 at r = delta", PDFamilyPartialVolume(3, 9, PETSC_TRUE),
          0.5);
    Check(PDFamilyPartialVolume(r3, 12, PETSC_TRUE) == 0.5, "m = 2 sqrt(3): partial volume 1/2 at r = delta",
          PDFamilyPartialVolume(r3, 12, PETSC_TRUE), 0.5);
    CheckRel("m = pi: partial volume at n2 = 9 is pi + 1/2 - 3", PDFamilyPartialVolume(PETSC_PI, 9, PETSC_TRUE), PETSC_PI - 2.5, 1e-15);
    Check(PDFamilyPartialVolume(3, 6, PETSC_TRUE) == 1, "m = 3: whole volume at r = sqrt(6) <= m - 1/2",
          PDFamilyPartialVolume(3, 6, PETSC_TRUE), 1);
    Check(PDFamilyPartialVolume(3, 9, PETSC_FALSE) == 1, "partial volumes off: 1 at r = delta", PDFamilyPartialVolume(3, 9, PETSC_FALSE),
          1);
  }
  {
    const int rc = CheckSummary();
    PetscCall(PetscFinalize());
    return rc;
  }
}
