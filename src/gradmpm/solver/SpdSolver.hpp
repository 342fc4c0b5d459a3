#pragma once
// Sparse symmetric positive definite solves. CHOLMOD (supernodal Cholesky) by
// default; Eigen's SimplicialLDLT as fallback; conjugate gradients preconditioned by an
// incomplete Cholesky factorisation for problems too large to factorise. The symbolic
// analysis is kept and reused for every factorisation of a matrix with the same pattern,
// and one factorisation serves any number of right-hand sides.
#include <memory>
#include <string_view>

#include "gradmpm/core/Types.hpp"

namespace gradmpm {

class SpdSolver {
 public:
  enum class Backend { Cholmod, EigenLDLT, PCG };

  explicit SpdSolver(Backend backend = Backend::Cholmod);
  ~SpdSolver();
  SpdSolver(SpdSolver&&) noexcept;
  SpdSolver& operator=(SpdSolver&&) noexcept;

  /// Symbolic analysis (ordering, elimination tree). Call again only if the pattern changes.
  void analyze(const SparseMatrix& A);
  /// Numeric factorisation; throws SolverError if A is not positive definite.
  void factorize(const SparseMatrix& A);
  /// analyze (if not yet done) + factorize.
  void compute(const SparseMatrix& A);
  /// x = A^{-1} b with the current factorisation. PCG: relative residual below
  /// pcg_tolerance within pcg_max_iterations (default max(200, 20 sqrt(n))), else
  /// SolverError naming the iterations and the residual reached.
  Vector solve(const Vector& b) const;
  /// X = A^{-1} B for several right-hand sides at once (direct backends in one sweep).
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;

  double pcg_tolerance = 1e-12;
  int pcg_max_iterations = 0;  ///< 0: scaled to the problem, max(200, 20 sqrt(n))

  Backend backend() const { return backend_; }
  /// Wall-clock seconds spent so far in factorize and solve, and in analyze.
  double seconds() const { return seconds_; }
  double analysis_seconds() const { return analysis_seconds_; }

  /// x = A^{-1} b for a general (e.g. indefinite) square A by sparse LU; throws
  /// SolverError if A is singular. For the occasional tangent that is not positive definite.
  static Vector solve_general(const SparseMatrix& A, const Vector& b);
  static std::string_view name(Backend b);

 private:
  struct Impl;
  Backend backend_;
  std::unique_ptr<Impl> impl_;
  bool analyzed_ = false;
  bool factorized_ = false;
  mutable double seconds_ = 0.0;
  double analysis_seconds_ = 0.0;
};

}  // namespace gradmpm
