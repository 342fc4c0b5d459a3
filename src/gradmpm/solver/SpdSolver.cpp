#include "gradmpm/solver/SpdSolver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

struct SpdSolver::Impl {
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> cholmod;
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> ldlt;
};

SpdSolver::SpdSolver(Backend backend) : backend_(backend), impl_(std::make_unique<Impl>()) {
  // Failures are reported through SolverError; CHOLMOD's own printing would only
  // duplicate them on stderr.
  impl_->cholmod.cholmod().print = 0;
  impl_->cholmod.cholmod().error_handler = nullptr;
}
SpdSolver::~SpdSolver() = default;
SpdSolver::SpdSolver(SpdSolver&&) noexcept = default;
SpdSolver& SpdSolver::operator=(SpdSolver&&) noexcept = default;

std::string_view SpdSolver::name(Backend b) {
  return b == Backend::Cholmod ? "cholmod" : "eigen-ldlt";
}

void SpdSolver::analyze(const SparseMatrix& A) {
  if (backend_ == Backend::Cholmod)
    impl_->cholmod.analyzePattern(A);
  else
    impl_->ldlt.analyzePattern(A);
  analyzed_ = true;
  factorized_ = false;
}

void SpdSolver::factorize(const SparseMatrix& A) {
  if (!analyzed_) analyze(A);
  Eigen::ComputationInfo info;
  if (backend_ == Backend::Cholmod) {
    impl_->cholmod.factorize(A);
    info = impl_->cholmod.info();
  } else {
    impl_->ldlt.factorize(A);
    info = impl_->ldlt.info();
    // LDLT succeeds on indefinite matrices: insist on a positive diagonal.
    if (info == Eigen::Success && (impl_->ldlt.vectorD().array() <= 0.0).any())
      info = Eigen::NumericalIssue;
  }
  if (info != Eigen::Success)
    throw SolverError("sparse factorisation (" + std::string(name(backend_)) +
                      ") failed: the matrix is not positive definite (is the body "
                      "under-constrained?)");
  factorized_ = true;
}

void SpdSolver::compute(const SparseMatrix& A) {
  if (!analyzed_) analyze(A);
  factorize(A);
}

Vector SpdSolver::solve(const Vector& b) const {
  if (!factorized_) throw SolverError("SpdSolver::solve called before factorize");
  Vector x = backend_ == Backend::Cholmod ? Vector(impl_->cholmod.solve(b))
                                          : Vector(impl_->ldlt.solve(b));
  if (!x.allFinite()) throw SolverError("sparse solve produced non-finite values");
  return x;
}

Vector SpdSolver::solve_general(const SparseMatrix& A, const Vector& b) {
  Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>> lu;
  lu.compute(A);
  if (lu.info() != Eigen::Success) throw SolverError("sparse LU failed: the matrix is singular");
  Vector x = lu.solve(b);
  if (lu.info() != Eigen::Success || !x.allFinite()) throw SolverError("sparse LU solve failed");
  return x;
}

}  // namespace gradmpm
