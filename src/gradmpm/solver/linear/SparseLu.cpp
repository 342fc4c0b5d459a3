// The sparse LU solvers of general (non-symmetric or indefinite) systems; they read the
// whole matrix and symmetrise nothing:
//   umfpack   SuiteSparse UMFPACK multifrontal LU. Eigen's UmfPackLU keeps a reference to
//             the matrix and UMFPACK reads it again in every solve, so the solver holds
//             its own copy (a caller's temporary may go).
//   eigen-lu  Eigen's SparseLU with COLAMD ordering, dependency-free.
#include <Eigen/SparseLU>
#include <Eigen/UmfPackSupport>

#include "gradmpm/solver/linear/EigenSolver.hpp"

namespace gradmpm {

namespace {
template <class Lu, bool keeps>
struct LuTraits {
  static constexpr bool general = true, keeps_reference = keeps;
  using Guard = NoGuard;
  static void configure(Lu&) {}
  static std::string failure(const Lu& d) { return d.info() == Eigen::Success ? "" : "the matrix is singular"; }
};
struct UmfpackTraits : LuTraits<Eigen::UmfPackLU<SparseMatrix>, true> {
  static constexpr const char* name = "umfpack";
};
struct SparseLuTraits : LuTraits<Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>>, false> {
  static constexpr const char* name = "eigen-lu";
};
template <class Lu, class Traits>
LinearSolverInfo lu_info(const char* doc) {
  return {Traits::name, doc, true,
          [](const LinearSolverSettings&, MatrixKind) { return std::make_unique<EigenSolver<Lu, Traits>>(); }};
}
}  // namespace

LinearSolverInfo umfpack_solver_info() {
  return lu_info<Eigen::UmfPackLU<SparseMatrix>, UmfpackTraits>(
      "SuiteSparse UMFPACK sparse LU (any square matrix: non-symmetric, indefinite)");
}

LinearSolverInfo eigen_lu_solver_info() {
  return lu_info<Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>>, SparseLuTraits>(
      "Eigen SparseLU with COLAMD ordering (any square matrix)");
}

}  // namespace gradmpm
