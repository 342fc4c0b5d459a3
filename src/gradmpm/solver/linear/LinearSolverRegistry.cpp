// The built-in linear solvers: one line each (its file defines the info).
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

LinearSolverInfo cholmod_solver_info();
LinearSolverInfo eigen_ldlt_solver_info();
LinearSolverInfo pcg_solver_info();
LinearSolverInfo umfpack_solver_info();   // SparseLu.cpp
LinearSolverInfo eigen_lu_solver_info();  // SparseLu.cpp
#ifdef GRADMPM_WITH_PETSC
LinearSolverInfo petsc_solver_info();
#endif

void register_builtins(LinearSolverRegistry& registry) {
  registry.add(cholmod_solver_info());
  registry.add(eigen_ldlt_solver_info());
  registry.add(pcg_solver_info());
  registry.add(umfpack_solver_info());
  registry.add(eigen_lu_solver_info());
#ifdef GRADMPM_WITH_PETSC
  registry.add(petsc_solver_info());
#endif
}

}  // namespace gradmpm
