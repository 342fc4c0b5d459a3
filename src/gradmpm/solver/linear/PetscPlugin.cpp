// linear_solver.type = "petsc" as the registry lists it: the name, the doc and what it
// takes are here; the solver itself is in the plugin libgradmpm_petsc.so
// (solver/linear/Petsc.cpp, core/Plugins.hpp), loaded the first time one is made or its
// options are checked, so that a run that never uses PETSc never loads it.
#include "gradmpm/core/Plugins.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

namespace {
const LinearSolverInfo& plugin() {
  static const LinearSolverInfo& info =
      *plugin_function<const LinearSolverInfo* (*)()>("petsc", "gradmpm_petsc_solver",
                                                       "linear_solver.type = \"petsc\"")();
  return info;
}
}  // namespace

LinearSolverInfo petsc_solver_info() {
  LinearSolverInfo info{
      "petsc",
      "PETSc KSP (default: CG with GAMG and the rigid-body modes; MUMPS LU for general matrices); "
      "linear_solver.options go to PETSc's options database",
      true, [](const LinearSolverSettings& s, MatrixKind kind) { return plugin().make(s, kind); }};
  info.takes_options = true;
  info.check_options = [](const LinearSolverSettings& s) { return plugin().check_options(s); };
  return info;
}

}  // namespace gradmpm
