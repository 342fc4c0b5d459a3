// Conjugate gradients preconditioned by an incomplete Cholesky factorisation (Eigen),
// for symmetric positive definite problems too large to factorise. Not converging is a
// SolverError naming the iterations and the residual reached.
#include <fmt/format.h>
#include <Eigen/IterativeLinearSolvers>
#include <cmath>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

namespace {

class Pcg final : public LinearSolver {
 public:
  explicit Pcg(const LinearSolverSettings& s) : tolerance_(s.pcg_tolerance), max_iterations_(s.pcg_max_iterations) {}
  std::string name() const override { return "pcg"; }
  bool general() const override { return false; }

 protected:
  // Eigen's CG keeps a reference to its matrix: the solver holds its own copy, so that a
  // caller's temporary may go (a Helmholtz matrix local to a constructor once dangled).
  void do_analyze(const SparseMatrix& A) override {
    matrix_ = A;
    cg_.analyzePattern(matrix_);
  }
  void do_factorize(const SparseMatrix& A) override {
    matrix_ = A;
    cg_.factorize(matrix_);  // the incomplete Cholesky preconditioner
    if (cg_.info() != Eigen::Success)
      throw SolverError(
          "sparse factorisation (pcg) failed: the matrix is not positive definite (is the body "
          "under-constrained?)");
    const int n = static_cast<int>(A.rows());
    cg_.setTolerance(tolerance_);
    cg_.setMaxIterations(max_iterations_ > 0 ? max_iterations_
                                             : std::max(200, static_cast<int>(20 * std::sqrt(double(n)))));
  }
  Vector do_solve(const Vector& b) const override {
    Vector x = cg_.solve(b);
    if (cg_.info() != Eigen::Success || !x.allFinite())
      throw SolverError(
          fmt::format("preconditioned CG did not converge: relative residual {:.2e} after {} iterations "
                      "(tolerance {:.1e}, limit {})",
                      cg_.error(), cg_.iterations(), cg_.tolerance(), cg_.maxIterations()));
    return x;
  }

 private:
  double tolerance_;
  int max_iterations_;
  SparseMatrix matrix_;
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper, Eigen::IncompleteCholesky<double>> cg_;
};

}  // namespace

LinearSolverInfo pcg_solver_info() {
  return {"pcg",
          "conjugate gradients with an incomplete-Cholesky preconditioner (symmetric positive definite; relative "
          "residual linear_solver.pcg_tolerance within pcg_max_iterations)",
          false, [](const LinearSolverSettings& s, MatrixKind) { return std::make_unique<Pcg>(s); }};
}

}  // namespace gradmpm
