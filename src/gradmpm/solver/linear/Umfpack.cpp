// SuiteSparse UMFPACK multifrontal LU: the solver of general (non-symmetric or
// indefinite) sparse systems. Reads the whole matrix; nothing is symmetrised.
#include <Eigen/UmfPackSupport>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

namespace {

class Umfpack final : public LinearSolver {
 public:
  std::string name() const override { return "umfpack"; }
  bool general() const override { return true; }

 protected:
  // Eigen's UmfPackLU keeps a reference to the matrix and UMFPACK reads it again in
  // every solve: the solver holds its own copy, so a caller's temporary may go.
  void do_analyze(const SparseMatrix& A) override {
    matrix_ = A;
    lu_.analyzePattern(matrix_);
    if (lu_.info() != Eigen::Success) throw SolverError("sparse LU (umfpack): symbolic analysis failed");
  }
  void do_factorize(const SparseMatrix& A) override {
    matrix_ = A;
    lu_.factorize(matrix_);
    if (lu_.info() != Eigen::Success) throw SolverError("sparse LU (umfpack) failed: the matrix is singular");
  }
  Vector do_solve(const Vector& b) const override { return lu_.solve(b); }
  Eigen::MatrixXd do_solve(const Eigen::MatrixXd& B) const override { return lu_.solve(B); }

 private:
  SparseMatrix matrix_;
  Eigen::UmfPackLU<SparseMatrix> lu_;
};

}  // namespace

LinearSolverInfo umfpack_solver_info() {
  return {"umfpack", "SuiteSparse UMFPACK sparse LU (any square matrix: non-symmetric, indefinite)", true,
          [](const LinearSolverSettings&) { return std::make_unique<Umfpack>(); }};
}

}  // namespace gradmpm
