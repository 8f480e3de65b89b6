/* An accepted equilibrium state on a quasi-static path, shared by load/displacement control and path
   following: bond histories committed, a curve row with the measurements and the energy terms. */
#include "path.h"

PetscErrorCode PDPathCreate(PDModel *m, PDPath *p) {
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(p, sizeof *p));
  PetscCall(VecDuplicate(m->f_ref, &p->u_n));
  PetscCall(VecDuplicate(m->f_ref, &p->f_n));
  PetscCall(VecDuplicate(m->f_ref, &p->du));
  PetscCall(VecZeroEntries(p->u_n));
  PetscCall(VecZeroEntries(p->f_n)); /* f_int(0) */
  PetscFunctionReturn(0);
}

PetscErrorCode PDPathDestroy(PDPath *p) {
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&p->u_n));
  PetscCall(VecDestroy(&p->f_n));
  PetscCall(VecDestroy(&p->du));
  PetscFunctionReturn(0);
}

/* Commits the state u at load factor lam and fills a curve row. External work is trapezoidal along the
   path: at equilibrium the applied forces and reactions are f_int on every dof, so
   dW = (f_int(u_n) + f_int(u)).(u - u_n) / 2. Afterwards u_n = u and f_n = f_int(u). */
PetscErrorCode PDPathAccept(PDModel *m, PDRecord *rec, PDPath *p, Vec u, PetscReal lam, PetscInt its, PetscInt lits, PDCurveRow *row) {
  PetscScalar    dw;
  PetscLogDouble now;

  PetscFunctionBeginUser;
  m->lambda = lam;
  PetscCall(PDModelCommitHistory(m, u));
  PetscCall(PDModelMeasure(m, u, &row->load, &row->disp, &row->cmod));
  PetscCall(VecWAXPY(p->du, -1, p->u_n, u));
  PetscCall(VecAXPY(p->f_n, 1, m->f_work));
  PetscCall(VecDot(p->f_n, p->du, &dw));
  p->w_ext += 0.5 * PetscRealPart(dw);
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
  row->wall         = now - rec->t_start;
  row->external     = p->w_ext;
  row->kinetic = row->damped = 0;
  PetscCall(PDModelEnergy(m, u, &row->stored, &row->dissipated));
  PetscCall(PDRecordAddRow(rec, row));
  rec->steps = p->step;
  PetscFunctionReturn(0);
}
