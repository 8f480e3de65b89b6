/* An accepted equilibrium state on a quasi-static path, shared by load/displacement control and path
   following: bond histories committed, a curve row with the measurements and the energy terms. */
#include "path.h"

PetscErrorCode PDPathCreate(PDModel *m, PDPath *p) {
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(p, sizeof *p));
  PetscCall(VecDuplicate(m->f_ref, &p->u_n));
  PetscCall(VecDuplicate(m->f_ref, &p->f_n));
  PetscCall(VecDuplicate(m->f_ref, &p->du));
  PetscCall(VecDuplicate(m->f_ref, &p->ku));
  PetscCall(VecZeroEntries(p->u_n));
  PetscCall(VecZeroEntries(p->f_n)); /* f_int(0) */
  PetscFunctionReturn(0);
}

PetscErrorCode PDPathDestroy(PDPath *p) {
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&p->u_n));
  PetscCall(VecDestroy(&p->f_n));
  PetscCall(VecDestroy(&p->du));
  PetscCall(VecDestroy(&p->ku));
  PetscFunctionReturn(0);
}

/* Commits the state u at load factor lam and fills a curve row. At equilibrium the applied forces and
   reactions are f_int on every dof, so the external work of the step is the integral of f_int along it,
   taken as the cubic through both ends and their tangents (Hermite):
   dW = (f_n + f).du / 2 + (K_n du - K du).du / 12, both tangents with the step's starting history.
   The plain trapezoid left a visible part of the work unbalanced after the large steps where cracking starts.
   Afterwards u_n = u and f_n = f_int(u). */
PetscErrorCode PDPathAccept(PDModel *m, PDRecord *rec, PDPath *p, Vec u, PetscReal lam, PetscInt its, PetscInt lits, PDCurveRow *row) {
  PetscScalar    dw, c = 0;
  PetscReal      energy[2];
  PetscLogDouble now;

  PetscFunctionBeginUser;
  PetscCall(VecWAXPY(p->du, -1, p->u_n, u));
  if (m->ka && m->scene->kinematics != PD_KINEMATICS_SMALL) { /* the tangent varies: end-slope correction (before the history moves) */
    const PetscReal lam_u = m->lambda;
    m->lambda             = p->lambda_n;
    PetscCall(PDModelTangentApplyAt(m, p->u_n, p->du, p->ku, PETSC_TRUE));
    m->lambda = lam;
    PetscCall(PDModelTangentApplyAt(m, u, p->du, m->f_work, PETSC_TRUE));
    PetscCall(VecAXPY(p->ku, -1, m->f_work));
    PetscCall(VecDot(p->ku, p->du, &c));
    m->lambda = lam_u;
  }
  m->lambda = lam;
  if (m->ka && m->scene->kinematics == PD_KINEMATICS_SMALL) { /* the same term by bonds, in the commit's loop */
    PetscReal change;
    PetscCall(PDModelCommitHistory(m, u, energy, p->u_n, p->lambda_n, &change));
    c = change;
  } else
    PetscCall(PDModelCommitHistory(m, u, energy, NULL, 0, NULL));
  PetscCall(PDModelMeasure(m, u, &row->load, &row->disp, &row->cmod));
  PetscCall(VecAXPY(p->f_n, 1, m->f_work));
  PetscCall(VecDot(p->f_n, p->du, &dw));
  p->w_ext += 0.5 * PetscRealPart(dw) + PetscRealPart(c) / 12;
  PetscCall(VecCopy(m->f_work, p->f_n));
  PetscCall(VecCopy(u, p->u_n));
  p->lambda_n = lam;
  p->step++;
  PetscCall(PetscTime(&now));
  row->step         = p->step;
  row->lambda       = lam;
  row->newton_its   = its;
  row->ksp_its      = lits;
  row->broken_bonds = m->broken;
  row->yielded      = m->yielded;
  row->wall         = now - rec->t_start;
  row->external     = p->w_ext;
  row->kinetic = row->damped = 0;
  row->stored                = energy[0];
  row->dissipated            = energy[1];
  PetscCall(PDModelSteelStress(m, u, &row->steel_stress, &row->slip));
  PetscCall(PDModelCrushing(m, u, PETSC_TRUE, &row->crush_ratio, &row->strain_min, row->crush_at)); /* the commit's strain state */
  PetscCall(PDModelSection(m, u, row->section));
  PetscCall(PDRecordAddRow(rec, row));
  rec->steps = p->step;
  PetscFunctionReturn(0);
}

PetscErrorCode PDPathStopCriteria(const PDScene *sc, PDRecord *rec, const PDCurveRow *row, PetscReal peak, PetscBool judge_separation,
                                  PetscBool *stop) {
  PetscFunctionBeginUser;
  *stop = PETSC_FALSE;
  if (row->crush_ratio >= 1) {
    *stop = PETSC_TRUE;
    PetscCall(PDCrushedStatus(sc, rec, row));
  } else if (sc->stop_cmod > 0 && row->cmod >= sc->stop_cmod) {
    *stop = PETSC_TRUE;
    PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "completed: CMOD reached %g m", (double)sc->stop_cmod));
  } else if (judge_separation && sc->stop_fraction > 0 && peak > 0 && PetscAbsReal(row->load) < sc->stop_fraction * peak) {
    *stop = PETSC_TRUE;
    PetscCall(PetscSNPrintf(rec->status, sizeof rec->status, "separated: load %.4g N below %g of the peak %.4g N", (double)row->load,
                            (double)sc->stop_fraction, (double)peak));
  }
  PetscFunctionReturn(0);
}
