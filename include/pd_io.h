/* Reporter: curve.csv, summary.json, fields.h5/.xmf, curve.svg, progress line. curve.csv grows by one
   flushed row per accepted step; the other files are written whole (temporary name, then rename) by
   rank 0 or collectively for HDF5. */
#pragma once
#include "pd_model.h"

typedef struct {
  PetscInt   step, newton_its, ksp_its;
  PetscInt64 broken_bonds;
  PetscReal  lambda, load, disp, cmod, wall;
  /* energy (J): work of the external forces and reactions, strain energy in the bonds, dissipated by
     damage, kinetic and removed by damping (the last two in explicit mode) */
  PetscReal external, stored, dissipated, kinetic, damped;
  PetscInt  yielded;      /* bar segments yielded or broken */
  PetscReal steel_stress; /* largest |stress| in a bar segment (Pa) */
  PetscReal slip;         /* largest |slip| of a bar node with bond slip (m) */
  /* -pd_eps_cu: the bond closest to crushing, its stretch, -stretch / eps_cu and its midpoint (m) */
  PetscReal strain_min, crush_ratio, crush_at[3];
  PetscReal section[PD_SECTION_N]; /* -pd_section_x: the forces across the section (PDModelSection) */
} PDCurveRow;

typedef struct {
  MPI_Comm    comm;
  PetscMPIInt rank;
  FILE       *curve;   /* curve.csv, open on rank 0 from PDOutputPrepare to PDCurveClose */
  PetscBool   section; /* curve.csv has the section's columns (-pd_section_x) */
  PetscInt    nrows, capacity;
  PDCurveRow *rows;
  PetscInt    steps, newton_its, ksp_its;
  PetscInt    max_events_per_its; /* largest number of bond events granted at once */
  PetscBool   converged;
  char        status[256];
  PetscReal   t_setup, t_assembly, t_solve, t_output, t_start;
  PetscInt    nfield_steps;
  PetscInt   *field_steps;     /* steps whose fields were written */
  PetscViewer h5;              /* open HDF5 viewer on the temporary fields file */
  PetscReal   matrix_nonzeros; /* stored scalar entries of the stiffness */
  char        solver[128];     /* snes/ksp/pc types actually used */
  char        dir[PETSC_MAX_PATH_LEN];
  char        restart_from[PETSC_MAX_PATH_LEN]; /* checkpoint the path went on from, or empty */
  PetscInt    restart_step;                     /* its step */
  /* load or displacement control that handed over to path following (-pd_control_fallback) */
  PetscInt  fallback_step;        /* after this accepted step; 0: it did not */
  PetscReal fallback_lambda;      /* its load factor */
  char      fallback_why[160];    /* why plain control stopped */
  PetscInt  fallback_implex_step; /* path following went on with IMPL-EX after this step; 0: it did not */
  /* path following's equilibrium tolerances (|R| over |f_int|) of implicit and IMPL-EX steps; 0: no path following */
  PetscReal arc_rtol, implex_rtol;
  PetscInt  implex_insensitive; /* IMPL-EX steps taken once a cut had left their damage error where it was */
  PetscInt  implex_faces;       /* IMPL-EX steps whose Newton froze its damaged bonds' sides of zero stretch */
  /* explicit path */
  PetscReal eig_est, eig_bound; /* largest eigenvalue of M^-1 K: power-iteration estimate, Gershgorin bound (1/s^2) */
  PetscReal dt_stable, dt;      /* stable step 2/sqrt(eig_est) and step used (s) */
  PetscReal dt_eq46;            /* the estimate of THEORY.md Eq. 4.6 (s) */
  PetscReal bar_mass_added;     /* explicit: mass added to bar nodes by -pd_bar_mass_scaling (kg) */
  PetscReal servo_gain;         /* explicit under CMOD control: the gauge's static opening per unit load factor (m) */
  PetscReal servo_omega1;       /* explicit under CMOD control: fundamental circular frequency estimate (1/s) */
  PetscInt  servo_its;          /* explicit under CMOD control: CG iterations of the static solve */
  PetscInt  time_steps;
  PetscReal ke_max;  /* largest kinetic energy at a recorded step (J) */
  PetscReal v_peak;  /* largest nodal velocity (m/s) */
  PetscReal ds_peak; /* largest stretch a bond gained in one time step */
  /* failure search */
  PetscInt ntrials;
  struct {
    PetscReal load;    /* test load (N) */
    PetscInt  verdict; /* 1 carried (converged), -1 failed */
    PetscInt  steps;   /* time steps the trial took */
    char      why[96];
  } trial[64];
  PetscReal fail_lower, fail_upper; /* largest load carried, smallest that failed (N); 0: none */
} PDRecord;

PetscErrorCode PDRecordCreate(MPI_Comm, const PDScene *, PDRecord *);
/* Rows go to the record and, flushed, to curve.csv; clearing starts the curve afresh (a new trial, the rows
   of a checkpoint). */
PetscErrorCode PDRecordAddRow(PDRecord *, const PDCurveRow *);
PetscErrorCode PDRecordClearRows(PDRecord *);
PetscErrorCode PDCrushedStatus(const PDScene *, PDRecord *, const PDCurveRow *);
PetscErrorCode PDRecordDestroy(PDRecord *);
/* Before anything is built: the output directory is a writable directory, or can be made one. */
PetscErrorCode PDOutputCheck(MPI_Comm, const PDScene *);
/* Creates the output directory and starts curve.csv. */
PetscErrorCode PDOutputPrepare(MPI_Comm, const PDScene *, PDRecord *);
/* Removes temporary files a failed write may have left. */
PetscErrorCode PDOutputDiscardTemporary(PDRecord *);
PetscErrorCode PDFieldsWrite(PDModel *, PDRecord *, PetscInt step, Vec u);
PetscErrorCode PDFieldsFinish(PDModel *, PDRecord *);
PetscErrorCode PDCurveStart(PDRecord *);
PetscErrorCode PDCurveAppend(PDRecord *, const PDCurveRow *);
PetscErrorCode PDCurveClose(PDRecord *);
PetscErrorCode PDSummaryWrite(MPI_Comm, const PDModel *, const PDRecord *);
PetscErrorCode PDCurvePlotWrite(MPI_Comm, const PDScene *, const PDRecord *);
PetscErrorCode PDProgress(MPI_Comm, const PDScene *, const PDCurveRow *, PetscBool last);
PetscErrorCode PDFileCommit(MPI_Comm, const char *dir, const char *name);
/* User text escaped into a new string (PetscFree it): a quoted JSON string, or XML text and attribute. */
PetscErrorCode PDEscapeJSON(const char *, char **);
PetscErrorCode PDEscapeXML(const char *, char **);
/* checkpoint.h5: a path's state at an accepted step (-pd_checkpoint_every, -pd_restart); kappa_prev: the
   bond history a step earlier, kept where the driver extrapolates histories (NULL: none) */
PetscErrorCode PDCheckpointValidate(const PDModel *, const char *path, PetscInt nvec, const char *const vec_name[], PetscInt nreal,
                                    const char *const real_name[]);
PetscErrorCode PDCheckpointWrite(PDModel *, PDRecord *, PetscInt nvec, const Vec vec[], const char *const vec_name[], PetscInt nreal,
                                 const char *const real_name[], const PetscReal real[], const PetscReal *kappa_prev);
PetscErrorCode PDCheckpointRead(PDModel *, PDRecord *, const char *path, PetscInt nvec, Vec vec[], const char *const vec_name[],
                                PetscInt nreal, const char *const real_name[], PetscReal real[], PetscReal *kappa_prev);
