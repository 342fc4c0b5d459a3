// Eigen's SimplicialLDLT: a dependency-free fallback for symmetric positive definite
// systems. Reads the lower triangle. LDLT succeeds on indefinite matrices, so a
// non-positive pivot counts as failure.
#include <Eigen/SparseCholesky>

#include "gradmpm/solver/linear/EigenSolver.hpp"

namespace gradmpm {

namespace {
using Ldlt = Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower>;

struct LdltTraits {
  static constexpr const char* name = "eigen-ldlt";
  static constexpr bool general = false, keeps_reference = false;
  using Guard = NoGuard;
  static void configure(Ldlt&) {}
  static std::string failure(const Ldlt& d) {
    return d.info() == Eigen::Success && (d.vectorD().array() > 0.0).all() ? "" : kNotPositiveDefinite;
  }
};
}  // namespace

LinearSolverInfo eigen_ldlt_solver_info() {
  return {LdltTraits::name, "Eigen SimplicialLDLT (symmetric positive definite)", false,
          [](const LinearSolverSettings&, MatrixKind) { return std::make_unique<EigenSolver<Ldlt, LdltTraits>>(); }};
}

}  // namespace gradmpm
