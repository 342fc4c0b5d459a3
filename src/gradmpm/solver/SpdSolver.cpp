#include "gradmpm/solver/SpdSolver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseLU>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <omp.h>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

namespace {
/// CHOLMOD 3 (SuiteSparse 5, as Debian 12 ships it) runs parts of its supernodal
/// factorisation on a fixed team of 4 OpenMP threads (CHOLMOD_OMP_NUM_THREADS), however
/// many cores the machine has and whatever the caller asked for. On 2 cores that
/// oversubscribes them: a 1e5-dof 2D factorisation took 1.13 s instead of 0.75 s
/// (docs/performance.md). With dynamic adjustment on, libgomp caps every team at the
/// caller's thread setting and the idle processors, so it is switched on around CHOLMOD.
class CholmodThreadCap {
 public:
  CholmodThreadCap() : previous_(omp_get_dynamic()) { omp_set_dynamic(1); }
  ~CholmodThreadCap() { omp_set_dynamic(previous_); }
  CholmodThreadCap(const CholmodThreadCap&) = delete;
  CholmodThreadCap& operator=(const CholmodThreadCap&) = delete;

 private:
  int previous_;
};

/// Adds the lifetime of the scope to a running total of seconds.
class ScopedSeconds {
 public:
  explicit ScopedSeconds(double& total) : total_(total), start_(std::chrono::steady_clock::now()) {}
  ~ScopedSeconds() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  ScopedSeconds(const ScopedSeconds&) = delete;
  ScopedSeconds& operator=(const ScopedSeconds&) = delete;

 private:
  double& total_;
  std::chrono::steady_clock::time_point start_;
};
}  // namespace

struct SpdSolver::Impl {
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> cholmod;
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> ldlt;
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper, Eigen::IncompleteCholesky<double>> pcg;
  SparseMatrix pcg_matrix;  ///< CG keeps a reference to its matrix: it must outlive factorize()'s argument
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
  return b == Backend::Cholmod ? "cholmod" : (b == Backend::EigenLDLT ? "eigen-ldlt" : "pcg");
}

void SpdSolver::analyze(const SparseMatrix& A) {
  ScopedSeconds timer(analysis_seconds_);
  if (backend_ == Backend::Cholmod) {
    CholmodThreadCap cap;
    impl_->cholmod.analyzePattern(A);
  } else if (backend_ == Backend::EigenLDLT)
    impl_->ldlt.analyzePattern(A);
  else {
    impl_->pcg_matrix = A;
    impl_->pcg.analyzePattern(impl_->pcg_matrix);
  }
  analyzed_ = true;
  factorized_ = false;
}

void SpdSolver::factorize(const SparseMatrix& A) {
  if (!analyzed_) analyze(A);
  ScopedSeconds timer(seconds_);
  Eigen::ComputationInfo info;
  if (backend_ == Backend::Cholmod) {
    CholmodThreadCap cap;
    impl_->cholmod.factorize(A);
    info = impl_->cholmod.info();
  } else if (backend_ == Backend::PCG) {
    impl_->pcg_matrix = A;
    impl_->pcg.factorize(impl_->pcg_matrix);  // the incomplete Cholesky preconditioner
    info = impl_->pcg.info();
    const int n = static_cast<int>(A.rows());
    impl_->pcg.setTolerance(pcg_tolerance);
    impl_->pcg.setMaxIterations(pcg_max_iterations > 0 ? pcg_max_iterations
                                                       : std::max(200, static_cast<int>(20 * std::sqrt(double(n)))));
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
  ScopedSeconds timer(seconds_);
  if (!factorized_) throw SolverError("SpdSolver::solve called before factorize");
  if (backend_ == Backend::PCG) {
    Vector x = impl_->pcg.solve(b);
    if (impl_->pcg.info() != Eigen::Success || !x.allFinite())
      throw SolverError(fmt::format("preconditioned CG did not converge: relative residual {:.2e} after {} iterations "
                                    "(tolerance {:.1e}, limit {})",
                                    impl_->pcg.error(), impl_->pcg.iterations(), impl_->pcg.tolerance(),
                                    impl_->pcg.maxIterations()));
    return x;
  }
  CholmodThreadCap cap;
  Vector x = backend_ == Backend::Cholmod ? Vector(impl_->cholmod.solve(b))
                                          : Vector(impl_->ldlt.solve(b));
  if (!x.allFinite()) throw SolverError("sparse solve produced non-finite values");
  return x;
}

Eigen::MatrixXd SpdSolver::solve(const Eigen::MatrixXd& B) const {
  if (backend_ == Backend::PCG) {  // column by column, each checked
    Eigen::MatrixXd X(B.rows(), B.cols());
    for (Eigen::Index j = 0; j < B.cols(); ++j) X.col(j) = solve(Vector(B.col(j)));
    return X;
  }
  if (!factorized_) throw SolverError("SpdSolver::solve called before factorize");
  ScopedSeconds timer(seconds_);
  CholmodThreadCap cap;
  Eigen::MatrixXd X = backend_ == Backend::Cholmod ? Eigen::MatrixXd(impl_->cholmod.solve(B))
                                                   : Eigen::MatrixXd(impl_->ldlt.solve(B));
  if (!X.allFinite()) throw SolverError("sparse solve produced non-finite values");
  return X;
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
