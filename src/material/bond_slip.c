/* The bond stress-slip envelope of ribbed bars, fib Model Code 2010 Sec. 6.1.1 (Table 6.1-1, pull-out
   failure, good bond conditions): tau_max = 2.5 sqrt(f_cm), tau_f = 0.4 tau_max, alpha = 0.4. */
#include "pd_material.h"

void PDSlipEnvelopeSetUp(const PDBar *b, PDSlipEnvelope *env) {
  env->tau_max = 2.5 * PetscSqrtReal(b->fcm / 1e6) * 1e6;
  env->tau_f   = 0.4 * env->tau_max;
  env->alpha   = 0.4;
  env->x[0]    = PD_SLIP_LINEAR * b->slips[0];
  for (PetscInt k = 0; k < 3; k++) env->x[1 + k] = b->slips[k];
  /* the start tau = k0 x + b x^2 meets the power law at x_lin with its value tau_l and slope alpha tau_l / x_lin */
  env->k0 = (2 - env->alpha) * env->tau_max * PetscPowReal(PD_SLIP_LINEAR, env->alpha) / env->x[0];
}

PetscReal PDSlipStress(const PDSlipEnvelope *env, PetscReal x, PetscReal *slope) {
  const PetscReal *s = env->x;
  if (x <= s[0]) {
    const PetscReal b = (env->alpha - 1) * env->tau_max * PetscPowReal(PD_SLIP_LINEAR, env->alpha) / (s[0] * s[0]);
    *slope            = env->k0 + 2 * b * x;
    return (env->k0 + b * x) * x;
  }
  if (x <= s[1]) {
    const PetscReal tau = env->tau_max * PetscPowReal(x / s[1], env->alpha);
    *slope              = env->alpha * tau / x;
    return tau;
  }
  *slope = 0;
  if (x <= s[2]) return env->tau_max;
  if (x >= s[3]) return env->tau_f;
  *slope = -(env->tau_max - env->tau_f) / (s[3] - s[2]);
  return env->tau_max + *slope * (x - s[2]);
}

PetscReal PDSlipWork(const PDSlipEnvelope *env, PetscReal x) {
  const PetscReal *s = env->x, a1 = 1 + env->alpha;
  PetscReal        w, slope;
  const PetscReal  b = (env->alpha - 1) * env->tau_max * PetscPowReal(PD_SLIP_LINEAR, env->alpha) / (s[0] * s[0]);
  if (x <= s[0]) return (0.5 * env->k0 + b * x / 3) * x * x;
  w = (0.5 * env->k0 + b * s[0] / 3) * s[0] * s[0];
  w += env->tau_max * s[1] / a1 * (PetscPowReal(PetscMin(x, s[1]) / s[1], a1) - PetscPowReal(s[0] / s[1], a1));
  if (x <= s[1]) return w;
  w += env->tau_max * (PetscMin(x, s[2]) - s[1]);
  if (x <= s[2]) return w;
  w += 0.5 * (PetscMin(x, s[3]) - s[2]) * (env->tau_max + PDSlipStress(env, PetscMin(x, s[3]), &slope));
  if (x <= s[3]) return w;
  return w + env->tau_f * (x - s[3]);
}
