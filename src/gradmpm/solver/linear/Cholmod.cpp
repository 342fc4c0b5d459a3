// CHOLMOD (SuiteSparse) supernodal Cholesky: the default solver of symmetric positive
// definite systems. Reads the lower triangle.
#include <Eigen/CholmodSupport>
#include <omp.h>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

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

class Cholmod final : public LinearSolver {
 public:
  Cholmod() {
    // Failures are reported through SolverError; CHOLMOD's own printing would only
    // duplicate them on stderr.
    llt_.cholmod().print = 0;
    llt_.cholmod().error_handler = nullptr;
  }
  std::string name() const override { return "cholmod"; }
  bool general() const override { return false; }

 protected:
  void do_analyze(const SparseMatrix& A) override {
    CholmodThreadCap cap;
    llt_.analyzePattern(A);
  }
  void do_factorize(const SparseMatrix& A) override {
    CholmodThreadCap cap;
    llt_.factorize(A);
    if (llt_.info() != Eigen::Success)
      throw SolverError("sparse factorisation (cholmod) failed: the matrix is not positive definite (is the body "
                        "under-constrained?)");
  }
  Vector do_solve(const Vector& b) const override {
    CholmodThreadCap cap;
    return llt_.solve(b);
  }
  Eigen::MatrixXd do_solve(const Eigen::MatrixXd& B) const override {
    CholmodThreadCap cap;
    return llt_.solve(B);
  }

 private:
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt_;
};

}  // namespace

LinearSolverInfo cholmod_solver_info() {
  return {"cholmod", "SuiteSparse CHOLMOD supernodal Cholesky (symmetric positive definite)", false,
          [](const LinearSolverSettings&) { return std::make_unique<Cholmod>(); }};
}

}  // namespace gradmpm
