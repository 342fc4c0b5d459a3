#pragma once
// A LinearSolver over one of Eigen's sparse decompositions (its own, or its wrappers of
// SuiteSparse): analyzePattern / factorize / solve, checked. `Traits` says what differs:
//   name, general             the LinearSolver answers
//   keeps_reference           the decomposition reads the matrix again in solve (UMFPACK):
//                             the solver then holds its own copy
//   Guard                     an object alive around every call (e.g. a thread cap)
//   configure(d)              once, at construction
//   failure(d)                after factorize: "" or what went wrong
#include <string>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

/// No-op Guard.
struct NoGuard {};

template <class Decomposition, class Traits>
class EigenSolver final : public LinearSolver {
 public:
  EigenSolver() { Traits::configure(decomposition_); }
  std::string name() const override { return Traits::name; }
  bool general() const override { return Traits::general; }

 protected:
  void do_analyze(const SparseMatrix& A) override {
    [[maybe_unused]] typename Traits::Guard guard;
    decomposition_.analyzePattern(hold(A));  // a failure surfaces in factorize
  }
  void do_factorize(const SparseMatrix& A) override {
    [[maybe_unused]] typename Traits::Guard guard;
    decomposition_.factorize(hold(A));
    if (const std::string why = Traits::failure(decomposition_); !why.empty())
      throw SolverError("sparse factorisation (" + name() + ") failed: " + why);
  }
  Vector do_solve(const Vector& b) const override {
    [[maybe_unused]] typename Traits::Guard guard;
    return decomposition_.solve(b);
  }
  Eigen::MatrixXd do_solve(const Eigen::MatrixXd& B) const override {
    [[maybe_unused]] typename Traits::Guard guard;
    return decomposition_.solve(B);
  }

 private:
  const SparseMatrix& hold(const SparseMatrix& A) {
    if constexpr (!Traits::keeps_reference) return A;
    matrix_ = A;
    return matrix_;
  }
  SparseMatrix matrix_;
  Decomposition decomposition_;
};

/// The failure message of a symmetric positive definite factorisation.
inline const char* kNotPositiveDefinite = "the matrix is not positive definite (is the body under-constrained?)";

}  // namespace gradmpm
