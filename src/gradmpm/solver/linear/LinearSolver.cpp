#include "gradmpm/solver/linear/LinearSolver.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Timer.hpp"

namespace gradmpm {

void LinearSolver::analyze(const SparseMatrix& A) {
  ScopedSeconds timer(analysis_seconds_);
  do_analyze(A);
  analyzed_ = true;
  factorized_ = false;
}

bool LinearSolver::order_by(std::vector<int> perm, bool compare) {
  if (perm.empty()) return false;
  std::vector<char> seen(perm.size(), 0);
  for (const int k : perm) {
    if (k < 0 || static_cast<std::size_t>(k) >= perm.size() || seen[k])
      throw std::invalid_argument(name() + ": order_by given something other than a permutation");
    seen[k] = 1;
  }
  if (!do_order_by(perm, compare)) return false;
  analyzed_ = factorized_ = false;  // the next factorize analyses with that ordering
  return true;
}

void LinearSolver::factorize(const SparseMatrix& A) {
  if (!analyzed_) analyze(A);
  ScopedSeconds timer(seconds_);
  factorized_ = false;
  do_factorize(A);
  factorized_ = true;
}

Vector LinearSolver::solve(const Vector& b) const {
  if (!factorized_) throw SolverError(name() + ": solve called before factorize");
  ScopedSeconds timer(seconds_);
  Vector x = do_solve(b);
  if (!x.allFinite()) throw SolverError(name() + ": the solve produced non-finite values");
  return x;
}

Eigen::MatrixXd LinearSolver::solve(const Eigen::MatrixXd& B) const {
  if (!factorized_) throw SolverError(name() + ": solve called before factorize");
  ScopedSeconds timer(seconds_);
  Eigen::MatrixXd X = do_solve(B);
  if (!X.allFinite()) throw SolverError(name() + ": the solve produced non-finite values");
  return X;
}

Eigen::MatrixXd LinearSolver::do_solve(const Eigen::MatrixXd& B) const {
  Eigen::MatrixXd X(B.rows(), B.cols());
  for (Eigen::Index j = 0; j < B.cols(); ++j) X.col(j) = do_solve(Vector(B.col(j)));
  return X;
}

std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings, MatrixKind kind) {
  const auto& registry = LinearSolverRegistry::instance();
  const LinearSolverInfo* info = registry.find(settings.type);
  if (!info)
    throw SolverError(
        fmt::format("no linear solver named \"{}\" (registered: {})", settings.type, registry.quoted_names()));
  if (kind == MatrixKind::General && !info->general) {
    info = registry.find(settings.general);
    if (!info || !info->general)
      throw SolverError(fmt::format("no general (non-symmetric) linear solver named \"{}\" (registered: {})",
                                    settings.general, registry.quoted_names(true)));
  }
  return info->make(settings, kind);
}

}  // namespace gradmpm
