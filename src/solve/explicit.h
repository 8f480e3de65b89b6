/* The explicit integrator's state, shared by the reference path (explicit.c) and the failure search
   (failure_search.c), which runs it repeatedly at different loads. */
#pragma once
#include "pd_solve.h"
#include <petscts.h>

/* The servo that drives the load factor under CMOD control (servo.c, -pd_explicit_cmod). */
typedef struct {
  PetscBool on;
  PetscReal target;                 /* the gauge's opening at the end of the ramp (m) */
  PetscReal t_ramp;                 /* ramp duration (s) */
  PetscReal gain;                   /* the gauge's opening per unit load factor, static elastic (m) */
  PetscReal omega1;                 /* fundamental circular frequency, Rayleigh quotient of the static deflection (1/s) */
  PetscReal omega;                  /* the servo's circular frequency (1/s) */
  PetscInt  ksp_its;                /* CG iterations of the static solve */
  PetscReal t0, lam, lam_t, lam_tt; /* load factor and its rate at t0; its acceleration, held over the step */
} PDServo;

PetscErrorCode PDServoSetUp(PDModel *, Vec mass, PetscReal target, PetscReal t_ramp, PDServo *);
PetscErrorCode PDServoUpdate(PDServo *, const PDModel *, PetscReal t, Vec u);
void           PDServoAt(const PDServo *, PetscReal t, PetscReal *lam, PetscReal *lam_tt);
void           PDServoReset(PDServo *);
void           PDSmoothstep(PetscReal L, PetscReal T, PetscReal t, PetscReal v[3]);

typedef struct PDExplicit PDExplicit;
/* Called every tenth time step with the velocities; setting *stop ends the integration. */
typedef PetscErrorCode (*PDExplicitMonitor)(PDExplicit *, PetscInt step, PetscReal t, Vec v, PetscBool *stop);

struct PDExplicit {
  PDModel          *m;
  PDRecord         *rec;
  TS                ts;
  Vec               X; /* [u; v] */
  IS                is_u, is_v;
  Vec               mass;         /* nodal mass rho V per dof */
  Vec               f_int;        /* internal force at the last evaluation, then work */
  Vec               f_ext;        /* applied forces and reactions at the last force evaluation */
  Vec               u_prev;       /* displacement at the previous step */
  Vec               v_local;      /* ghosted velocities, for the stability check */
  PetscReal         lambda_max;   /* load factor at the end of the ramp */
  PetscReal         t_ramp;       /* ramp duration */
  PetscReal         t_end;        /* ramp and hold */
  PetscReal         dt;           /* time step */
  PetscReal         eig_est;      /* largest eigenvalue of M^-1 K on free dofs, power iteration (1/s^2) */
  PetscReal         eig_bound;    /* its Gershgorin bound (1/s^2) */
  PetscReal         dt_stable;    /* 2/sqrt(eig_est) */
  PetscInt          nsteps;       /* time steps to t_end */
  PetscInt          stride;       /* steps between curve rows */
  PetscReal         ke_max;       /* largest kinetic energy recorded (J) */
  PetscReal         v_peak;       /* largest nodal velocity seen (m/s) */
  PetscReal         ds_peak;      /* largest stretch gained by a bond in one step, at the checks */
  PetscReal         excess;       /* energy held less the work at the last suspicious check (J) */
  PetscInt          excess_step;  /* the step of that check */
  PetscReal         jump;         /* growth of the excess over the work that stopped the run */
  PetscReal         w_ext;        /* external work so far (J) */
  PetscReal         w_damp;       /* kinetic energy removed by damping so far, this rank (J) */
  PetscBool         stopped;      /* the CMOD stop or the monitor ended the integration */
  PetscBool         cmod_reached; /* the CMOD stop was reached */
  PetscBool         crushed;      /* a bond reached its material's -pd_eps_cu (at the record's last row) */
  PetscBool         blew_up;      /* non-finite or runaway state */
  PetscBool         interrupted;  /* SIGTERM (interrupt.c) ended the integration at a recorded row */
  Vec               adr_r, adr_u; /* dynamic relaxation: out-of-balance force and displacement at the last evaluation */
  PetscReal         adr_c;        /* dynamic relaxation: damping coefficient of the step (1/step) */
  PDServo           servo;        /* under -pd_explicit_cmod: what drives the load factor */
  TSConvergedReason reason;
  PDExplicitMonitor monitor;
  void             *monitor_ctx;
};

PetscErrorCode PDExplicitCreate(PDModel *, PDRecord *, PDExplicit *);
PetscErrorCode PDExplicitSolve(PDExplicit *, PetscReal lambda_max);
PetscErrorCode PDExplicitStatus(PDExplicit *);
PetscErrorCode PDExplicitDestroy(PDExplicit *);
