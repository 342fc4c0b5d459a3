// Eigen's SimplicialLDLT: a dependency-free fallback for symmetric positive definite
// systems. Reads the lower triangle.
#include <Eigen/SparseCholesky>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

namespace {

class EigenLdlt final : public LinearSolver {
 public:
  std::string name() const override { return "eigen-ldlt"; }
  bool general() const override { return false; }

 protected:
  void do_analyze(const SparseMatrix& A) override { ldlt_.analyzePattern(A); }
  void do_factorize(const SparseMatrix& A) override {
    ldlt_.factorize(A);
    // LDLT succeeds on indefinite matrices: insist on a positive diagonal.
    if (ldlt_.info() != Eigen::Success || (ldlt_.vectorD().array() <= 0.0).any())
      throw SolverError("sparse factorisation (eigen-ldlt) failed: the matrix is not positive definite (is the body "
                        "under-constrained?)");
  }
  Vector do_solve(const Vector& b) const override { return ldlt_.solve(b); }
  Eigen::MatrixXd do_solve(const Eigen::MatrixXd& B) const override { return ldlt_.solve(B); }

 private:
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> ldlt_;
};

}  // namespace

LinearSolverInfo eigen_ldlt_solver_info() {
  return {"eigen-ldlt", "Eigen SimplicialLDLT (symmetric positive definite)", false,
          [](const LinearSolverSettings&) { return std::make_unique<EigenLdlt>(); }};
}

}  // namespace gradmpm
