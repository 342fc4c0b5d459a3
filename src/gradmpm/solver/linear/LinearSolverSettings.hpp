#pragma once
// What a case chooses about its linear solves ([linear_solver], docs/case-files.md). A
// light header: the driver and the gradient step carry it without including a solver.
#include <string>

namespace gradmpm {

struct LinearSolverSettings {
  /// Solver of the symmetric systems: the tangent when every material's tangent is
  /// symmetric, and the Helmholtz systems of the gradient step. A registered name
  /// (LinearSolverRegistry): "cholmod", "eigen-ldlt", "pcg", "umfpack", "eigen-lu".
  std::string type = "cholmod";
  /// Solver of non-symmetric tangents, and of a symmetric tangent that `type` cannot
  /// factorise because it is not positive definite. Must solve general matrices.
  std::string general = "umfpack";
  double pcg_tolerance = 1e-12;  ///< relative residual of "pcg"
  int pcg_max_iterations = 0;    ///< 0: scaled to the problem, max(200, 20 sqrt(n))
  /// Options for solvers that take them (LinearSolverInfo::takes_options), passed as
  /// written, e.g. a PETSc options string. Empty for the built-in ones.
  std::string options;
};

/// Which matrices a solve will see.
enum class MatrixKind {
  Symmetric,  ///< symmetric (positive definite expected: an SPD solver may refuse it)
  General,    ///< any square matrix: both triangles are read
};

}  // namespace gradmpm
