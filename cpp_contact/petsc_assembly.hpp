// Assembly of contact blocks straight into PETSc Mat / Vec (serial, global indices).
//
// Values are added with ADD_VALUES; rows and columns of fixed (Dirichlet) dofs are skipped (the
// FE side owns those rows). Every PETSc call is checked: a failure throws std::runtime_error with
// PETSc's message and what was being done. A matrix or vector living on a communicator with more
// than one rank is refused: each contact run is serial on its own communicator.
#pragma once

#include "contact_interface.hpp"

#include <petscmat.h>
#include <petscvec.h>

#include <string>

namespace rf {

/// Throws std::runtime_error if `ierr` is nonzero.
void check_petsc(PetscErrorCode ierr, const std::string& what);

struct AssemblyReport {
  /// Mallocs of A reported by MatGetInfo (cumulative; PETSc counts them at final assembly, which
  /// this call performs itself when new nonzeros are allowed). 0 if A is null.
  double mallocs = 0.0;
  long entries = 0;  ///< matrix entries added
};

/// Adds the blocks into A (may be null) and their residual entries into b (may be null).
/// A is flushed (MAT_FLUSH_ASSEMBLY) before insertion so that it may follow INSERT_VALUES of the
/// caller; the caller finishes with MatAssemblyBegin/End(MAT_FINAL_ASSEMBLY) as usual. b is
/// assembled (VecAssemblyBegin/End) here.
AssemblyReport add_to_petsc(const ContactInterface& contact, Mat A, Vec b);

}  // namespace rf
