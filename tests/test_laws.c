/* Bond laws against the Hobbs thesis Tables 5.1 and 7.2, hand-computed points, irreversibility and
   the work of fracture. */
#include "pd_material.h"
#include "check.h"

/* Printed with 3 significant digits: the value must round to the printed one. */
static void ThreeDigits(const char *what, double got, double printed) {
  const double e = PetscPowReal(10, PetscFloorReal(PetscLog10Real(printed)) - 2);
  Check(PetscAbsReal(got - printed) <= 0.5 * e * (1 + 1e-9) ? PETSC_TRUE : PETSC_FALSE, what, got, printed);
}

static void MakeLaw(PDLawKind kind, PetscReal E, PetscReal Gf, PetscReal dx, PetscReal m, PDLaw *law) {
  PDScene    sc;
  PDMaterial mat;

  PetscMemzero(&sc, sizeof sc);
  PetscMemzero(&mat, sizeof mat);
  sc.model         = PD_MODEL_3D;
  sc.dim           = 3;
  sc.dx            = dx;
  sc.horizon_ratio = m;
  sc.influence     = PD_INFLUENCE_CONSTANT;
  mat.law          = kind;
  mat.E            = E;
  mat.ft           = 3.9e6;
  mat.Gf           = Gf;
  mat.kr           = 25;
  mat.beta         = 0.25;
  mat.k            = 25;
  mat.alpha        = 0.25;
  PDLawSetUp(&sc, &mat, law);
}

/* A bond's own thresholds (surface-correction factor lambda, strength factor) as the kernel evaluates them, by
   scaling the nominal ones, against the formulas themselves, for every law and both bilinear forms. */
static void ScaledThresholds(void) {
  const PDLawKind kinds[5]  = {PD_LAW_LINEAR, PD_LAW_BILINEAR, PD_LAW_BILINEAR, PD_LAW_TRILINEAR, PD_LAW_NONLINEAR};
  const char     *names[5]  = {"linear", "bilinear k_r", "bilinear Bobaru", "trilinear", "nonlinear"};
  const PetscReal lambda[3] = {0.7, 1.0, 1.6}, strength[3] = {0.95, 1.0, 1.05};

  for (PetscInt k = 0; k < 5; k++) {
    PDLaw     law;
    PetscReal worst = 0;
    MakeLaw(kinds[k], 37e9, 143.2, 5e-3, PETSC_PI, &law);
    law.bobaru   = k == 2 ? PETSC_TRUE : PETSC_FALSE;
    law.per_bond = PETSC_TRUE;
    PDLawBondThresholds(&law, 1, 1, &law.nominal); /* the nominal bond of the chosen form */
    for (PetscInt i = 0; i < 3; i++)
      for (PetscInt j = 0; j < 3; j++) {
        PDLawBond direct, scaled;
        PDLawBondThresholds(&law, lambda[i], strength[j], &direct);
        PDLawBondThresholdsScaled(&law, lambda[i], strength[j], &scaled);
        worst = PetscMax(worst, PetscAbsReal(scaled.s0 - direct.s0) / direct.s0);
        worst = PetscMax(worst, PetscAbsReal(scaled.s1 - direct.s1) / direct.s1);
        worst = PetscMax(worst, PetscAbsReal(scaled.sc - direct.sc) / direct.sc);
      }
    char what[96];
    PetscSNPrintf(what, sizeof what, "%s: scaled thresholds against the formulas (relative, 1e-13)", names[k]);
    Check(worst <= 1e-13 ? PETSC_TRUE : PETSC_FALSE, what, worst, 0);
  }
}

/* Force per unit micromodulus along a stretch path, with the history kept as the kernel keeps it. */
static PetscReal Force(const PDLaw *law, PetscReal *kappa, PetscReal s) {
  PetscReal dd, d;
  if (s < 0) return s;
  *kappa = PetscMax(*kappa, s);
  d      = PDLawDamage(law, &law->nominal, *kappa, &dd);
  return (1 - d) * s;
}

/* The steel of a bar segment (E = 200 GPa, f_y = 500 MPa: s_y = 2.5e-3) along a stretch path, the state
   committed at every point as the kernel commits it at accepted steps. Returns force over E A. */
static PetscReal SteelAlong(const PDSteel *st, PetscReal s, PetscReal *sp, PetscBool *broken, PetscReal *slope) {
  PetscReal g;
  PDSteelResponse(st, s, *sp, *broken, &g, slope, sp, broken);
  return g;
}

static void SteelLaw(void) {
  PDBar           bar = {.E = 200e9, .fy = 500e6, .hardening = 0.01, .rupture = 0.05};
  PDSteel         st;
  PetscReal       sp = 0, g, gp, W = 0, s0 = 0, g0 = 0;
  PetscBool       broken = PETSC_FALSE;
  const PetscReal sy     = 2.5e-3;

  PDSteelSetUp(&bar, &st);
  g = SteelAlong(&st, 0.5 * sy, &sp, &broken, &gp);
  CheckRel("steel: elastic below yield, g = s", g, 0.5 * sy, 1e-14);
  Check(gp == 1 && sp == 0 ? PETSC_TRUE : PETSC_FALSE, "steel: elastic slope 1, no plastic stretch", gp, 1);
  /* monotonic loading to 4 s_y in small steps: the work done equals stored plus dissipated energy */
  for (PetscInt k = 1; k <= 400; k++) {
    const PetscReal s = 4 * sy * k / 400;
    g                 = SteelAlong(&st, s, &sp, &broken, &gp);
    W += 0.5 * (g + g0) * (s - s0);
    s0 = s;
    g0 = g;
  }
  CheckRel("steel: at 4 s_y, g = s_y + h (4 - 1) s_y (hardening 1 %)", g, sy * (1 + 0.01 * 3), 1e-12);
  CheckRel("steel: plastic slope = h, the consistent tangent", gp, 0.01, 1e-12);
  CheckRel("steel: work = stored + s_y |sp| on the monotonic path", W, PDSteelStored(&st, s0, sp) + sy * sp, 1e-9);
  /* unloading is elastic: slope 1 from the plastic stretch, no further plastic flow */
  {
    const PetscReal sp_peak = sp;
    g                       = SteelAlong(&st, 3 * sy, &sp, &broken, &gp);
    CheckRel("steel: unloading by s_y lowers the force by s_y (elastic)", g, sy * 1.03 - sy, 1e-12);
    Check(gp == 1 && sp == sp_peak ? PETSC_TRUE : PETSC_FALSE, "steel: unloading keeps the plastic stretch, slope 1", gp, 1);
    /* kinematic hardening: reversed yield where s - sp - H sp = -s_y, sp = (1 - h) 3 s_y from the loading */
    {
      const PetscReal H = 0.01 / 0.99, srev = sp_peak + H * sp_peak - sy;
      CheckRel("steel: plastic stretch after loading to 4 s_y is (1 - h) 3 s_y", sp_peak, 0.99 * 3 * sy, 1e-12);
      g = SteelAlong(&st, srev + 1e-9, &sp, &broken, &gp);
      Check(gp == 1 && sp == sp_peak ? PETSC_TRUE : PETSC_FALSE, "steel: elastic just before the reversed yield point", gp, 1);
      g = SteelAlong(&st, srev - 1e-4, &sp, &broken, &gp);
      CheckRel("steel: past the reversed yield point the slope is h", gp, 0.01, 1e-12);
      CheckRel("steel: reversed yield force -s_y + H sp - h 1e-4 (Bauschinger shift)", g, -sy + H * sp_peak - 0.01 * 1e-4, 1e-10);
    }
  }
  /* a cycle 0 -> 4 s_y -> -4 s_y -> 4 s_y from a virgin state: the work done is the stored energy plus s_y
     times the plastic stretch accumulated along the path (the dissipation the kernel commits) */
  {
    PetscReal acc = 0, ss = 0, gg = 0, Wc = 0;
    sp = 0;
    for (PetscInt k = 1; k <= 2000; k++) {
      const PetscReal s =
          k <= 400 ? 4 * sy * k / 400 : (k <= 1200 ? 4 * sy - 8 * sy * (k - 400) / 800 : -4 * sy + 8 * sy * (k - 1200) / 800);
      const PetscReal sp0 = sp;
      g                   = SteelAlong(&st, s, &sp, &broken, &gp);
      Wc += 0.5 * (g + gg) * (s - ss);
      acc += PetscAbsReal(sp - sp0);
      ss = s;
      gg = g;
    }
    CheckRel("steel: over a reversed cycle, work = stored + s_y (accumulated plastic stretch)", Wc, PDSteelStored(&st, ss, sp) + sy * acc,
             1e-6);
  }
  /* rupture at 5 %: the segment breaks for good */
  sp = 0;
  g  = SteelAlong(&st, 0.049, &sp, &broken, &gp);
  Check(!broken && g > 0 ? PETSC_TRUE : PETSC_FALSE, "steel: intact below the rupture strain", g, 0);
  g = SteelAlong(&st, 0.05, &sp, &broken, &gp);
  Check(broken && g == 0 && gp == 0 ? PETSC_TRUE : PETSC_FALSE, "steel: broken at the rupture strain, no force or stiffness", g, 0);
  g = SteelAlong(&st, 0.001, &sp, &broken, &gp);
  Check(broken && g == 0 ? PETSC_TRUE : PETSC_FALSE, "steel: a broken segment stays broken when unloaded", g, 0);
  /* perfectly plastic: the force stays at s_y */
  bar.hardening = 0;
  bar.rupture   = 0;
  PDSteelSetUp(&bar, &st);
  sp     = 0;
  broken = PETSC_FALSE;
  g      = SteelAlong(&st, 10 * sy, &sp, &broken, &gp);
  CheckRel("steel, perfectly plastic: g = s_y at 10 s_y", g, sy, 1e-14);
  Check(gp == 0 && !broken ? PETSC_TRUE : PETSC_FALSE, "steel, perfectly plastic: slope 0, no rupture without a rupture strain", gp, 0);
  g = SteelAlong(&st, -10 * sy, &sp, &broken, &gp);
  CheckRel("steel, perfectly plastic: g = -s_y in compression after tension", g, -sy, 1e-14);
}

/* The bond-slip law (fib Model Code 2010, pull-out, good bond) at hand-computed points: f_cm = 38 MPa gives
   tau_max = 2.5 sqrt(38) = 15.411 MPa, tau_f = 0.4 tau_max; a 12 mm bar's s3 = 0.6 d = 7.2 mm. Then the law as
   the links see it (stretch of a 10 mm link): damage and its slope against central differences, the envelope
   work against a trapezoidal integral, secant unloading, and the same force in compression. */
static void SlipLaw(void) {
  PDBar           bar = {.diameter = 0.012, .fcm = 38e6, .slips = {1e-3, 2e-3, 7.2e-3}};
  const PetscReal L = 0.01, tm = 2.5 * PetscSqrtReal(38.0) * 1e6;
  PDLaw           law;
  PetscReal       slope, dd, W = 0, prev = 0, fprev = 0;
  const PetscInt  n = 100000;

  PDLawSetUpSlip(&bar, L, &law);
  CheckRel("slip: tau_max = 2.5 sqrt(f_cm)", law.slip.tau_max, tm, 1e-14);
  CheckRel("slip: tau(s1) = tau_max", PDSlipStress(&law.slip, 1e-3, &slope), tm, 1e-14);
  CheckRel("slip: tau(s1/2) = tau_max 0.5^0.4", PDSlipStress(&law.slip, 0.5e-3, &slope), tm * PetscPowReal(0.5, 0.4), 1e-14);
  CheckRel("slip: slope at s1/2 = 0.4 tau / s", slope, 0.4 * tm * PetscPowReal(0.5, 0.4) / 0.5e-3, 1e-12);
  CheckRel("slip: plateau at 1.5 mm", PDSlipStress(&law.slip, 1.5e-3, &slope), tm, 1e-14);
  CheckRel("slip: halfway down the fall, (tau_max + tau_f)/2", PDSlipStress(&law.slip, 4.6e-3, &slope), 0.7 * tm, 1e-12);
  CheckRel("slip: residual tau_f = 0.4 tau_max beyond s3", PDSlipStress(&law.slip, 9e-3, &slope), 0.4 * tm, 1e-14);
  CheckRel("slip: k0 = (2 - alpha) tau(x_lin) / x_lin, x_lin = 0.02 s1", law.slip.k0 * 2e-5, 1.6 * tm * PetscPowReal(0.02, 0.4), 1e-12);
  CheckRel("slip: the parabola meets the curve at x_lin", PDSlipStress(&law.slip, 2e-5 * (1 - 1e-12), &slope), tm * PetscPowReal(0.02, 0.4),
           1e-9);
  CheckRel("slip: with its slope", slope, 0.4 * tm * PetscPowReal(0.02, 0.4) / 2e-5, 1e-9);
  /* damage slope against central differences on every branch (stretch = slip / L) */
  for (PetscInt k = 0; k < 5; k++) {
    const PetscReal x[5] = {1e-5, 0.3e-3, 1.5e-3, 4e-3, 8e-3}, kap = x[k] / L, h = 1e-7 * kap;
    PetscReal       dp, dm, ddum;
    char            what[96];
    PDLawDamage(&law, &law.nominal, kap, &dd);
    dp = PDLawDamage(&law, &law.nominal, kap + h, &ddum);
    dm = PDLawDamage(&law, &law.nominal, kap - h, &ddum);
    PetscSNPrintf(what, sizeof what, "slip: d'(kappa) at %.2f mm against central differences", (double)(x[k] * 1e3));
    CheckRel(what, dd, (dp - dm) / (2 * h), 1e-6);
  }
  /* envelope work: g/c = (1 - d) s along monotonic loading to 10 mm of slip */
  for (PetscInt i = 1; i <= n; i++) {
    const PetscReal sv = 1e-2 / L * i / n, f = (1 - PDLawDamage(&law, &law.nominal, sv, &dd)) * sv;
    W += 0.5 * (f + fprev) * (sv - prev);
    prev  = sv;
    fprev = f;
  }
  CheckRel("slip: envelope work to 10 mm = closed form", W, PDLawEnvelopeWork(&law, &law.nominal, 1e-2 / L), 1e-6);
  CheckRel("slip: k0 L (1 - d) s = tau at 3 mm", law.slip.k0 * L * (1 - PDLawDamage(&law, &law.nominal, 3e-3 / L, &dd)) * 3e-3 / L,
           PDSlipStress(&law.slip, 3e-3, &slope), 1e-12);
  Check(PDLawNextThreshold(&law, &law.nominal, 0) == PETSC_MAX_REAL ? PETSC_TRUE : PETSC_FALSE, "slip: the limiter holds no link", 0, 0);
}

int main(int argc, char **argv) {
  PDLaw           law;
  const PDLawKind kinds[4] = {PD_LAW_LINEAR, PD_LAW_BILINEAR, PD_LAW_TRILINEAR, PD_LAW_NONLINEAR};
  const char     *names[4] = {"linear", "bilinear", "trilinear", "nonlinear"};

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  SlipLaw();
  ScaledThresholds();
  /* Table 5.1: E = 37 GPa, ft = 3.9 MPa, G_F = 143.2 N/m, dx = 5 mm. All nine printed values round
     alike with delta = pi dx; with delta = 3.14 dx (Table A.1) the non-linear sc would read 7.49e-3. */
  MakeLaw(PD_LAW_LINEAR, 37e9, 143.2, 5e-3, PETSC_PI, &law);
  ThreeDigits("Table 5.1 linear sc = 4.53e-4", law.nominal.sc, 4.53e-4);
  MakeLaw(PD_LAW_BILINEAR, 37e9, 143.2, 5e-3, PETSC_PI, &law);
  ThreeDigits("Table 5.1 bilinear s0 = 9.06e-5", law.nominal.s0, 9.06e-5);
  ThreeDigits("Table 5.1 bilinear sc = 2.27e-3", law.nominal.sc, 2.27e-3);
  MakeLaw(PD_LAW_TRILINEAR, 37e9, 143.2, 5e-3, PETSC_PI, &law);
  ThreeDigits("Table 5.1 trilinear s0 = 1.05e-4", law.nominal.s0, 1.05e-4);
  ThreeDigits("Table 5.1 trilinear s1 = 6.90e-4", law.nominal.s1, 6.90e-4);
  ThreeDigits("Table 5.1 trilinear sc = 5.56e-3", law.nominal.sc, 5.56e-3);
  MakeLaw(PD_LAW_NONLINEAR, 37e9, 143.2, 5e-3, PETSC_PI, &law);
  ThreeDigits("Table 5.1 nonlinear s0 = 1.05e-4", law.nominal.s0, 1.05e-4);
  ThreeDigits("Table 5.1 nonlinear sc = 7.48e-3 (corrected Eq. 5.21)", law.nominal.sc, 7.48e-3);

  /* Table 7.2: E = 30.5 GPa, G_F = 133 N/m, bilinear k_r = 25. The printed pairs are not consistent
     with k_r = 25 to three digits (1.60e-3 / 6.34e-5 = 25.2, 1.95e-3 / 7.78e-5 = 25.1), so s0 is held
     to 0.2 % and sc to 1 %, the spread of the printed values themselves. */
  MakeLaw(PD_LAW_BILINEAR, 30.5e9, 133, 11.5e-3, 3.14, &law);
  ThreeDigits("Table 7.2 dx 11.5 mm s0 = 6.34e-5", law.nominal.s0, 6.34e-5);
  CheckRel("Table 7.2 dx 11.5 mm sc = 1.60e-3 (1 %)", law.nominal.sc, 1.60e-3, 0.01);
  MakeLaw(PD_LAW_BILINEAR, 30.5e9, 133, 7.67e-3, 3.14, &law);
  CheckRel("Table 7.2 dx 7.67 mm s0 = 7.78e-5 (0.2 %)", law.nominal.s0, 7.78e-5, 0.002);
  CheckRel("Table 7.2 dx 7.67 mm sc = 1.95e-3 (1 %)", law.nominal.sc, 1.95e-3, 0.01);

  for (PetscInt k = 0; k < 4; k++) {
    char           what[128];
    PetscReal      kappa = 0, W = 0, prev = 0, fprev = 0, dd, d;
    const PetscInt n = 200000;
    MakeLaw(kinds[k], 37e9, 143.2, 5e-3, PETSC_PI, &law);
    /* work of fracture: trapezoidal integral of g/c along monotonic loading to sc, against the
       closed form; then the energy balance each printed formula for sc is built on: G_F = geo A for
       the linear and bilinear laws, G_F = geo (A - s0^2/2) for the trilinear and non-linear laws, whose
       formulas leave out the elastic work below s0 (so a bond dissipates geo s0^2/2 more than G_F). */
    for (PetscInt i = 1; i <= n; i++) {
      const PetscReal s = law.nominal.sc * i / n, f = Force(&law, &kappa, s);
      W += 0.5 * (f + fprev) * (s - prev);
      prev  = s;
      fprev = f;
      /* the envelope work part-way (every branch is passed: s0 is below sc/20 for all four laws) */
      if (i == n / 20 || i == n / 5 || i == n / 2 || i == 4 * n / 5) {
        PetscCall(PetscSNPrintf(what, sizeof what, "%s: envelope work to %.2g sc = closed form", names[k], (double)i / n));
        CheckRel(what, W, PDLawEnvelopeWork(&law, &law.nominal, s), 1e-4);
      }
    }
    PetscCall(PetscSNPrintf(what, sizeof what, "%s: integral of g/c to sc = closed form", names[k]));
    CheckRel(what, W, PDLawWorkOfFracture(&law), 1e-4);
    {
      const PetscBool soft_only = kinds[k] == PD_LAW_TRILINEAR || kinds[k] == PD_LAW_NONLINEAR;
      const PetscReal A         = PDLawWorkOfFracture(&law) - (soft_only ? 0.5 * law.nominal.s0 * law.nominal.s0 : 0);
      PetscCall(PetscSNPrintf(what, sizeof what, "%s: geo * %s = G_F", names[k], soft_only ? "(A - s0^2/2)" : "A"));
      CheckRel(what, law.geo * A, 143.2, 1e-9);
    }
    /* unloading and reloading below kappa follow the secant; damage never decreases */
    if (kinds[k] != PD_LAW_LINEAR) {
      const PetscReal smax = 0.5 * (law.nominal.s0 + law.nominal.sc);
      PetscReal       f1, f2, f3, d1;
      kappa = 0;
      f1    = Force(&law, &kappa, smax);
      d1    = PDLawDamage(&law, &law.nominal, kappa, &dd);
      f2    = Force(&law, &kappa, 0.5 * smax); /* unload to half */
      PetscCall(PetscSNPrintf(what, sizeof what, "%s: unloading to s/2 halves the force (secant)", names[k]));
      CheckRel(what, f2, 0.5 * f1, 1e-12);
      f3 = Force(&law, &kappa, smax); /* reload */
      PetscCall(PetscSNPrintf(what, sizeof what, "%s: reloading returns to the same point", names[k]));
      CheckRel(what, f3, f1, 1e-12);
      d = PDLawDamage(&law, &law.nominal, kappa, &dd);
      PetscCall(PetscSNPrintf(what, sizeof what, "%s: damage unchanged by the unload-reload cycle", names[k]));
      CheckRel(what, d, d1, 1e-14);
      PetscCall(PetscSNPrintf(what, sizeof what, "%s: compression is linear, undamaged", names[k]));
      CheckRel(what, Force(&law, &kappa, -1e-4), -1e-4, 1e-14);
      /* damage derivative against a central difference */
      {
        const PetscReal s = 0.3 * law.nominal.s0 + 0.7 * law.nominal.sc, h = 1e-7 * s;
        PetscReal       dp, dm, dx;
        d  = PDLawDamage(&law, &law.nominal, s, &dx);
        dp = PDLawDamage(&law, &law.nominal, s + h, &dd);
        dm = PDLawDamage(&law, &law.nominal, s - h, &dd);
        PetscCall(PetscSNPrintf(what, sizeof what, "%s: d'(kappa) against finite difference", names[k]));
        CheckRel(what, dx, (dp - dm) / (2 * h), 1e-6);
      }
    }
  }
  /* hand-computed points (force per unit micromodulus) */
  MakeLaw(PD_LAW_BILINEAR, 37e9, 143.2, 5e-3, PETSC_PI, &law);
  {
    PetscReal kappa = 0, s0 = law.nominal.s0, sc = law.nominal.sc;
    CheckRel("bilinear: g(s0)/c = s0", Force(&law, &kappa, s0), s0, 1e-12);
    CheckRel("bilinear: g((s0+sc)/2)/c = s0/2", Force(&law, &kappa, 0.5 * (s0 + sc)), 0.5 * s0, 1e-12);
    Check(Force(&law, &kappa, sc) == 0 ? PETSC_TRUE : PETSC_FALSE, "bilinear: g(sc) = 0, broken", 0, 0);
    Check(Force(&law, &kappa, 0.5 * s0) == 0 ? PETSC_TRUE : PETSC_FALSE, "bilinear: a broken bond carries no tension", 0, 0);
  }
  MakeLaw(PD_LAW_TRILINEAR, 37e9, 143.2, 5e-3, PETSC_PI, &law);
  {
    PetscReal kappa = 0;
    CheckRel("trilinear: g(s1)/c = beta s0", Force(&law, &kappa, law.nominal.s1), 0.25 * law.nominal.s0, 1e-12);
  }
  MakeLaw(PD_LAW_NONLINEAR, 37e9, 143.2, 5e-3, PETSC_PI, &law);
  {
    PetscReal       kappa = 0;
    const PetscReal s0 = law.nominal.s0, sc = law.nominal.sc, x = 0.5;
    const PetscReal h = (1 - (1 - PetscExpReal(-25 * x)) / (1 - PetscExpReal(-25.0)) + 0.25 * (1 - x)) / 1.25;
    CheckRel("nonlinear: g at x = 1/2 (Eq. 5.16 by hand)", Force(&law, &kappa, s0 + x * (sc - s0)), s0 * h, 1e-12);
  }
  MakeLaw(PD_LAW_LINEAR, 37e9, 143.2, 5e-3, PETSC_PI, &law);
  {
    PetscReal kappa = 0, sc = law.nominal.sc;
    CheckRel("linear: elastic just below sc", Force(&law, &kappa, 0.999 * sc), 0.999 * sc, 1e-12);
    Check(Force(&law, &kappa, sc) == 0 ? PETSC_TRUE : PETSC_FALSE, "linear: broken at sc", 0, 0);
  }
  /* Limiter thresholds: s0, then K parts of the softening branch geometric in stretch, sc, open; the
     level of a history is the number of thresholds it has passed. */
  MakeLaw(PD_LAW_NONLINEAR, 37e9, 143.2, 5e-3, PETSC_PI, &law);
  {
    const PDLawBond *t = &law.nominal;
    CheckRel("one part: level 0 leaves at s0", PDLawNextThreshold(&law, t, 0), t->s0, 1e-15);
    CheckRel("one part: level 1 leaves at sc", PDLawNextThreshold(&law, t, 1), t->sc, 1e-15);
    Check(PDLawNextThreshold(&law, t, 2) == PETSC_MAX_REAL, "one part: level 2 open", PDLawNextThreshold(&law, t, 2), PETSC_MAX_REAL);
    law.sublevels = 4;
    CheckRel("4 parts: level 2 leaves at sqrt(s0 sc)", PDLawNextThreshold(&law, t, 2), PetscSqrtReal(t->s0 * t->sc), 1e-12);
    CheckRel("4 parts: level 4 leaves at sc", PDLawNextThreshold(&law, t, 4), t->sc, 1e-15);
    Check(PDLawNextThreshold(&law, t, 5) == PETSC_MAX_REAL, "4 parts: level 5 open", PDLawNextThreshold(&law, t, 5), PETSC_MAX_REAL);
    Check(PDLawLevelOf(&law, t, 0.5 * t->s0) == 0, "4 parts: history below s0 is level 0", PDLawLevelOf(&law, t, 0.5 * t->s0), 0);
    Check(PDLawLevelOf(&law, t, 1.01 * PetscSqrtReal(t->s0 * t->sc)) == 3, "4 parts: history just past sqrt(s0 sc) is level 3",
          PDLawLevelOf(&law, t, 1.01 * PetscSqrtReal(t->s0 * t->sc)), 3);
    Check(PDLawLevelOf(&law, t, t->sc) == 5, "4 parts: history at sc is level 5 (broken)", PDLawLevelOf(&law, t, t->sc), 5);
  }
  MakeLaw(PD_LAW_LINEAR, 37e9, 143.2, 5e-3, PETSC_PI, &law);
  law.sublevels = 4;
  Check(PDLawNextThreshold(&law, &law.nominal, 2) == PETSC_MAX_REAL, "linear law: no parts, level 2 open whatever K",
        PDLawNextThreshold(&law, &law.nominal, 2), PETSC_MAX_REAL);
  SteelLaw();
  {
    const int rc = CheckSummary();
    PetscCall(PetscFinalize());
    return rc;
  }
}
