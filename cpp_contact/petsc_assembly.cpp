#include "petsc_assembly.hpp"

#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace rf {

void check_petsc(PetscErrorCode ierr, const std::string& what) {
  if (ierr == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(static_cast<int>(ierr), &text, nullptr);
  std::ostringstream m;
  m << "PETSc error " << static_cast<int>(ierr) << " in " << what << ": " << (text ? text : "(no message)");
  throw std::runtime_error(m.str());
}

namespace {

void require_serial(PetscObject obj, const char* name) {
  MPI_Comm comm;
  check_petsc(PetscObjectGetComm(obj, &comm), std::string("PetscObjectGetComm(") + name + ")");
  int size = 1;
  MPI_Comm_size(comm, &size);
  if (size > 1) {
    std::ostringstream m;
    m << "contact assembly: the " << name << " lives on a communicator of " << size
      << " ranks; the contact module is serial (one run per communicator, MPI farming). Distributed "
         "meshes are not supported: create the run on MPI.COMM_SELF";
    throw std::runtime_error(m.str());
  }
}

PetscInt to_petsc(DofIndex d, PetscInt size, const char* what) {
  if (d < 0) return -1;
  if (d >= static_cast<DofIndex>(size) || d > static_cast<DofIndex>(std::numeric_limits<PetscInt>::max())) {
    std::ostringstream m;
    m << "contact assembly: " << what << " dof " << d << " is outside the global system of size " << size;
    throw std::runtime_error(m.str());
  }
  return static_cast<PetscInt>(d);
}

}  // namespace

AssemblyReport add_to_petsc(const ContactInterface& contact, Mat A, Vec b) {
  PetscBool initialized = PETSC_FALSE;
  check_petsc(PetscInitialized(&initialized), "PetscInitialized");
  if (!initialized) throw std::runtime_error("PETSc is not initialised: import petsc4py.PETSc first");
  AssemblyReport rep;
  const auto& blocks = contact.blocks();
  std::vector<PetscInt> rows, cols;
  if (A != nullptr) {
    require_serial(reinterpret_cast<PetscObject>(A), "matrix");
    PetscInt m = 0, n = 0;
    check_petsc(MatGetSize(A, &m, &n), "MatGetSize");
    check_petsc(MatAssemblyBegin(A, MAT_FLUSH_ASSEMBLY), "MatAssemblyBegin(FLUSH)");
    check_petsc(MatAssemblyEnd(A, MAT_FLUSH_ASSEMBLY), "MatAssemblyEnd(FLUSH)");
    if (contact.allow_new_nonzeros())
      check_petsc(MatSetOption(A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE),
                  "MatSetOption(MAT_NEW_NONZERO_ALLOCATION_ERR)");
    for (const LocalBlock& blk : blocks) {
      rows.resize(blk.rows.size());
      cols.resize(blk.cols.size());
      for (std::size_t i = 0; i < rows.size(); ++i)
        rows[i] = contact.is_fixed(blk.rows[i]) ? -1 : to_petsc(blk.rows[i], m, "row");
      for (std::size_t j = 0; j < cols.size(); ++j)
        cols[j] = contact.is_fixed(blk.cols[j]) ? -1 : to_petsc(blk.cols[j], n, "column");
      const PetscErrorCode ierr =
          MatSetValues(A, static_cast<PetscInt>(rows.size()), rows.data(), static_cast<PetscInt>(cols.size()),
                       cols.data(), blk.K.data(), ADD_VALUES);
      if (ierr != 0) {
        std::ostringstream w;
        w << "MatSetValues of a contact block (first row " << (rows.empty() ? -1 : rows[0]) << ", " << rows.size()
          << " x " << cols.size() << "). If the message says a new nonzero caused a malloc, the contact "
          << "coupling is missing from the sparsity pattern: insert contact.sparsity_pairs() before "
          << "creating the matrix, or allow new nonzeros (allow_new_nonzeros=True)";
        check_petsc(ierr, w.str());
      }
      rep.entries += static_cast<long>(rows.size() * cols.size());
    }
    if (contact.allow_new_nonzeros()) {
      // PETSc counts mallocs at the final assembly: finish it here so the count can be reported
      // (the caller's own final assembly afterwards is then a no-op).
      check_petsc(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin(FINAL)");
      check_petsc(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd(FINAL)");
    }
    MatInfo info;
    check_petsc(MatGetInfo(A, MAT_LOCAL, &info), "MatGetInfo");
    rep.mallocs = info.mallocs;
  }
  if (b != nullptr) {
    require_serial(reinterpret_cast<PetscObject>(b), "vector");
    PetscInt n = 0;
    check_petsc(VecGetSize(b, &n), "VecGetSize");
    std::vector<PetscScalar> vals;
    for (const LocalBlock& blk : blocks) {
      // VecSetValues does not skip negative indices (unlike MatSetValues): drop fixed rows here
      rows.clear();
      vals.clear();
      for (std::size_t i = 0; i < blk.rows.size(); ++i) {
        if (blk.rows[i] < 0 || contact.is_fixed(blk.rows[i])) continue;
        rows.push_back(to_petsc(blk.rows[i], n, "row"));
        vals.push_back(blk.r[i]);
      }
      if (rows.empty()) continue;
      check_petsc(VecSetValues(b, static_cast<PetscInt>(rows.size()), rows.data(), vals.data(), ADD_VALUES),
                  "VecSetValues of a contact block");
    }
    check_petsc(VecAssemblyBegin(b), "VecAssemblyBegin");
    check_petsc(VecAssemblyEnd(b), "VecAssemblyEnd");
  }
  return rep;
}

}  // namespace rf
