// Eigen's SparseLU with COLAMD ordering: a dependency-free solver of general sparse systems.
#include <Eigen/SparseLU>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

namespace {

class EigenLu final : public LinearSolver {
 public:
  std::string name() const override { return "eigen-lu"; }
  bool general() const override { return true; }

 protected:
  void do_analyze(const SparseMatrix& A) override { lu_.analyzePattern(A); }
  void do_factorize(const SparseMatrix& A) override {
    lu_.factorize(A);
    if (lu_.info() != Eigen::Success) throw SolverError("sparse LU (eigen-lu) failed: the matrix is singular");
  }
  Vector do_solve(const Vector& b) const override { return lu_.solve(b); }
  Eigen::MatrixXd do_solve(const Eigen::MatrixXd& B) const override { return lu_.solve(B); }

 private:
  // solve() is logically const; Eigen's SparseLU::solve is const too.
  Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>> lu_;
};

}  // namespace

LinearSolverInfo eigen_lu_solver_info() {
  return {"eigen-lu", "Eigen SparseLU with COLAMD ordering (any square matrix)", true,
          [](const LinearSolverSettings&) { return std::make_unique<EigenLu>(); }};
}

}  // namespace gradmpm
