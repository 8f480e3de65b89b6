/* The stiffness matrix: block size = dofs per node, preallocated exactly from the bond incidence,
   with the rigid-body near-null space attached for algebraic multigrid. */
#include "pd_model.h"
#include "kernel.h"
#include <petscpc.h>

/* Algebraic multigrid is the default preconditioner where ICC(0)'s iteration count (which doubles as dx
   halves) outweighs GAMG's set-up: every 2D model (long 2D beams under path following) and non-linear 3D
   models from PD_GAMG_MIN_NODES nodes, whose tangent is solved hundreds of times. With the tangent's
   product from the bond scalars and right-preconditioned GMRES, GAMG's V-cycle costs little more than
   ICC(0)'s triangular solves and needs far fewer of them: on the D = 50 mm half-notched beam GAMG wins
   from about a thousand nodes and draws even below (docs/benchmarks/solve_profile.md, row "block
   ICC(0)"). Smaller models, whose runs take seconds either way, keep ICC(0). Other non-linear models
   (steel bars in elastic concrete, whose contrast of stiffnesses GAMG's aggregation handles worse) switch
   at PD_GAMG_MIN_NODES. Linear 3D models keep SBAIJ with point Jacobi (PDSolverConfigureKSP): one solve, half the memory. */
#define PD_GAMG_MIN_NODES 10000
#define PD_GAMG_MIN_NODES_SOFTENING 2000

PetscBool PDModelDefaultsToGAMG(const PDModel *m) {
  /* block storage chosen with -pd_mat_type keeps block Jacobi: GAMG reads AIJ only */
  if (m->scene->mat_type[0] && strcmp(m->scene->mat_type, MATAIJ)) return PETSC_FALSE;
  return (m->bs == 2 || m->gamg_after_icc ||
          (!m->linear && m->lat->nglobal >= (m->softening ? PD_GAMG_MIN_NODES_SOFTENING : PD_GAMG_MIN_NODES)))
             ? PETSC_TRUE
             : PETSC_FALSE;
}

/* The matrix of the bonds up to the squared length reach2 (0: every bond), with the record of what it
   holds (assembly.c). */
PetscErrorCode PDModelCreateMatrix(PDModel *m, PetscReal reach2, Mat *J) {
  const PDLattice *lat = m->lat;
  const PDBonds   *bd  = m->bonds;
  const PetscInt   bs  = m->bs;
  PetscInt        *dnnz, *onnz, *dnnzu, *onnzu;
  Vec              coords;
  PetscScalar     *c;
  MatNullSpace     nsp;
  PetscBool        sbaij;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc4(lat->nowned, &dnnz, lat->nowned, &onnz, lat->nowned, &dnnzu, lat->nowned, &onnzu));
  for (PetscInt i = 0; i < lat->nowned; i++) {
    dnnz[i] = dnnzu[i] = 1;
    onnz[i] = onnzu[i] = 0;
    for (PetscInt p = bd->inc_start[i]; p < bd->inc_start[i + 1]; p++) {
      const PetscInt  e = bd->inc_bond[p], j = bd->a[e] == i ? bd->b[e] : bd->a[e];
      const PetscBool upper = lat->gid[j] > lat->gid[i];
      if (!PDBondInReach(bs, lat->x, i, j, reach2)) continue;
      if (j < lat->nowned) {
        dnnz[i]++;
        dnnzu[i] += upper;
      } else {
        onnz[i]++;
        onnzu[i] += upper;
      }
    }
  }
  PetscCall(MatCreate(lat->comm, J));
  PetscCall(MatSetSizes(*J, bs * lat->nowned, bs * lat->nowned, PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetBlockSize(*J, bs));
  /* Symmetric block storage moves the fewest bytes per mat-vec and is the fastest with CG + ICC
     (docs/benchmarks/elastic.md). GAMG in PETSc 3.18 builds its graph from AIJ only, so choosing it
     switches the default storage to AIJ. -pd_mat_type (read with the scene) overrides either choice. */
  if (m->scene->mat_type[0])
    PetscCall(MatSetType(*J, m->scene->mat_type));
  else {
    /* AIJ where the user's preconditioner or package cannot read symmetric block storage (GAMG among them,
       scene_solution.c), or where the default of PDSolverConfigureKSP is GAMG */
    const PetscBool aij = m->scene->pc_aij || (!m->scene->pc_chosen && PDModelDefaultsToGAMG(m)) ? PETSC_TRUE : PETSC_FALSE;
    PetscCall(MatSetType(*J, aij ? MATAIJ : MATSBAIJ));
  }
  PetscCall(MatXAIJSetPreallocation(*J, bs, dnnz, onnz, dnnzu, onnzu));
  for (PetscInt i = 0; i < lat->nowned; i++) dnnz[i] += onnz[i]; /* blocks per row, for the record */
  if (m->scene->diagonal_index) PetscCall(PDMatUseDiagonalIndex(*J));
  PetscCall(MatSetOption(*J, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  PetscCall(MatSetOption(*J, MAT_NO_OFF_PROC_ENTRIES, PETSC_TRUE));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)*J, &sbaij, MATSBAIJ, MATSEQSBAIJ, MATMPISBAIJ, ""));
  if (sbaij) PetscCall(MatSetOption(*J, MAT_IGNORE_LOWER_TRIANGULAR, PETSC_TRUE));
  /* dF_i/du_j = dF_j/du_i for every bond, and the elimination of constrained dofs is symmetric */
  PetscCall(MatSetOption(*J, MAT_SYMMETRIC, PETSC_TRUE));
  PetscCall(MatSetOption(*J, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
  PetscCall(PDModelAssembledAttach(m, *J, reach2, dnnz));
  PetscCall(PetscFree4(dnnz, onnz, dnnzu, onnzu));

  PetscCall(VecCreate(lat->comm, &coords));
  PetscCall(VecSetSizes(coords, bs * lat->nowned, PETSC_DECIDE));
  PetscCall(VecSetBlockSize(coords, bs));
  PetscCall(VecSetFromOptions(coords));
  PetscCall(VecGetArray(coords, &c));
  for (PetscInt i = 0; i < lat->nowned; i++)
    for (PetscInt a = 0; a < bs; a++) c[bs * i + a] = lat->x[3 * i + a];
  PetscCall(VecRestoreArray(coords, &c));
  PetscCall(MatNullSpaceCreateRigidBody(coords, &nsp));
  PetscCall(MatSetNearNullSpace(*J, nsp));
  PetscCall(MatNullSpaceDestroy(&nsp));
  PetscCall(VecDestroy(&coords));
  PetscFunctionReturn(0);
}
