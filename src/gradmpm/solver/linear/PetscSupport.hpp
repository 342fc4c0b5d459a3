#pragma once
// PETSc's start and stop, and its error codes as SolverError, for solver/linear/Petsc.cpp.
#include <fmt/format.h>
#include <petscsys.h>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Ranks.hpp"

namespace gradmpm::petsc_support {

/// PETSc (and MPI, through it, in a serial run) initialised once, on first use, and
/// finalised at exit, or before MPI stops in a distributed run (core/Ranks.hpp: PETSc
/// uses MPI_COMM_WORLD then). Errors return codes instead of printing: they become
/// SolverError messages.
class PetscRuntime {
 public:
  static void ensure() { static PetscRuntime runtime; }
  PetscRuntime(const PetscRuntime&) = delete;
  PetscRuntime& operator=(const PetscRuntime&) = delete;

 private:
  PetscRuntime() {
    if (PetscInitializeNoArguments() != 0) throw SolverError("PETSc could not be initialised");
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    ranks::before_stop([] { finalise(); });
  }
  ~PetscRuntime() { finalise(); }
  static void finalise() {
    PetscBool initialised = PETSC_FALSE, finalised = PETSC_FALSE;
    PetscInitialized(&initialised);
    PetscFinalized(&finalised);
    if (initialised && !finalised) PetscFinalize();
  }
};

/// Throws SolverError with PETSc's message when `code` is an error.
inline void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  char* specific = nullptr;
  PetscErrorMessage(code, &text, &specific);
  throw SolverError(fmt::format("PETSc: {} failed: {}{}{}", what, text ? text : "error",
                                specific && *specific ? ": " : "", specific ? specific : ""));
}

}  // namespace gradmpm::petsc_support
