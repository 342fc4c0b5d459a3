// PETSc's Krylov solvers and preconditioners (KSP, PC) behind the LinearSolver interface:
// linear_solver.type = "petsc", with linear_solver.options passed to PETSc's options
// database, so any KSP and PC PETSc has (GAMG, hypre BoomerAMG, MUMPS, ...) is one
// option away (docs/performance.md).
//
// Defaults: conjugate gradients with smoothed-aggregation algebraic multigrid (GAMG) for
// symmetric systems, GMRES with GAMG for general ones. Given the node coordinates
// (describe()), GAMG gets the rigid-body modes of elasticity as its near-null space; it
// keeps its interpolation across the refactorisations of one pattern (a load step's
// Newton iterations) and recomputes only the coarse operators. The Newton driver sets
// the relative tolerance of each solve (inexact Newton); other solves use 1e-12.
//
// Each solver's options get a prefix of its own in PETSc's global database, so that the
// objects PETSc creates inside the preconditioner (multigrid levels, smoothers) see
// them, and two solvers never see each other's.
#include <fmt/format.h>
#include <petscksp.h>

#include <atomic>
#include <cctype>
#include <sstream>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

namespace {

/// PETSc (and MPI, through it) initialised once, on first use, and finalised at exit.
/// Errors return codes instead of printing: they become SolverError messages.
class PetscRuntime {
 public:
  static void ensure() { static PetscRuntime runtime; }
  PetscRuntime(const PetscRuntime&) = delete;
  PetscRuntime& operator=(const PetscRuntime&) = delete;

 private:
  PetscRuntime() {
    if (PetscInitializeNoArguments() != 0) throw SolverError("PETSc could not be initialised");
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  }
  ~PetscRuntime() { PetscFinalize(); }
};

/// Throws SolverError with PETSc's message when `code` is an error.
void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  char* specific = nullptr;
  PetscErrorMessage(code, &text, &specific);
  throw SolverError(fmt::format("PETSc: {} failed: {}{}{}", what, text ? text : "error",
                                specific && *specific ? ": " : "", specific ? specific : ""));
}

/// An option name of a PETSc options string: a word starting with '-' and a letter
/// ("-ksp_type"); values ("cg", "-1e-3") are not.
bool is_option_name(const std::string& word) {
  return word.size() > 1 && word[0] == '-' && std::isalpha(static_cast<unsigned char>(word[1]));
}

class Petsc final : public LinearSolver {
 public:
  Petsc(const LinearSolverSettings& s, MatrixKind kind) : kind_(kind) {
    PetscRuntime::ensure();
    static std::atomic<int> count{0};
    prefix_ = fmt::format("gradmpm{}_", count++);
    // The user's string with every option name prefixed: values stay as written.
    std::string prefixed;
    std::istringstream words(s.options);
    for (std::string w; words >> w;) {
      if (is_option_name(w)) {
        names_.push_back({w.substr(1), "-" + prefix_ + w.substr(1)});
        user_rtol_ = user_rtol_ || names_.back().user == "ksp_rtol";
        w = names_.back().prefixed;
      }
      prefixed += w + " ";
    }
    check(PetscOptionsInsertString(nullptr, prefixed.c_str()), "reading linear_solver.options");
  }
  ~Petsc() override {
    destroy();
    for (const auto& n : names_) PetscOptionsClearValue(nullptr, n.prefixed.c_str());
  }
  Petsc(const Petsc&) = delete;
  Petsc& operator=(const Petsc&) = delete;

  std::string name() const override { return "petsc"; }
  bool general() const override { return kind_ == MatrixKind::General; }
  bool iterative() const override { return true; }
  void describe(const SystemDescription& d) override { description_ = d; }
  void set_relative_tolerance(double rtol) override {
    if (!user_rtol_) rtol_ = rtol;
  }
  long iterations() const override { return iterations_; }

  /// The option names PETSc did not use (misspelt, or for another object); call after a solve.
  std::vector<std::string> unused_options() const {
    std::vector<std::string> unused;
    for (const auto& n : names_) {
      PetscBool used = PETSC_FALSE;
      PetscOptionsUsed(nullptr, n.prefixed.c_str() + 1, &used);  // the database keeps names without the dash
      if (!used) unused.push_back("-" + n.user);
    }
    return unused;
  }

 protected:
  void do_analyze(const SparseMatrix& A) override {
    destroy();
    const PetscInt n = static_cast<PetscInt>(A.rows());
    // Compressed rows from Eigen's compressed columns; `position_[k]`: where the k-th
    // stored value of A goes, so that a refactorisation only copies values.
    std::vector<PetscInt> row_start(n + 1, 0), columns(A.nonZeros());
    for (int c = 0; c < A.outerSize(); ++c)
      for (SparseMatrix::InnerIterator it(A, c); it; ++it) ++row_start[it.row() + 1];
    for (PetscInt r = 0; r < n; ++r) row_start[r + 1] += row_start[r];
    std::vector<PetscInt> next(row_start.begin(), row_start.end() - 1);
    position_.assign(A.nonZeros(), 0);
    Eigen::Index k = 0;
    for (int c = 0; c < A.outerSize(); ++c)
      for (SparseMatrix::InnerIterator it(A, c); it; ++it, ++k) {
        position_[k] = next[it.row()]++;
        columns[position_[k]] = c;
      }
    std::vector<PetscScalar> zeros(A.nonZeros(), 0.0);
    check(MatCreate(PETSC_COMM_SELF, &matrix_), "MatCreate");
    check(MatSetSizes(matrix_, n, n, n, n), "MatSetSizes");
    check(MatSetType(matrix_, MATSEQAIJ), "MatSetType");
    const int bs = description_.block_size;
    if (bs > 1 && n % bs == 0) check(MatSetBlockSize(matrix_, bs), "MatSetBlockSize");
    check(MatSeqAIJSetPreallocationCSR(matrix_, row_start.data(), columns.data(), zeros.data()),
          "MatSeqAIJSetPreallocationCSR");
    MatInfo info;
    check(MatGetInfo(matrix_, MAT_LOCAL, &info), "MatGetInfo");
    if (static_cast<Eigen::Index>(info.nz_used) != A.nonZeros())
      throw SolverError(fmt::format("PETSc kept {} of the matrix's {} entries", info.nz_used, A.nonZeros()));
    if (bs > 1 && description_.node_coordinates) set_rigid_body_modes(bs);
    check(MatCreateVecs(matrix_, &x_, &b_), "MatCreateVecs");
    make_ksp();
  }

  void do_factorize(const SparseMatrix& A) override {
    PetscScalar* values = nullptr;
    check(MatSeqAIJGetArray(matrix_, &values), "MatSeqAIJGetArray");
    const double* a = A.valuePtr();
    for (std::size_t k = 0; k < position_.size(); ++k) values[position_[k]] = a[k];
    check(MatSeqAIJRestoreArray(matrix_, &values), "MatSeqAIJRestoreArray");
    check(KSPSetOperators(ksp_, matrix_, matrix_), "KSPSetOperators");
    check(KSPSetUp(ksp_), "setting up the preconditioner (KSPSetUp)");
  }

  Vector do_solve(const Vector& b) const override {
    if (!user_rtol_) check(KSPSetTolerances(ksp_, rtol_, 1e-300, PETSC_DEFAULT, max_iterations_), "KSPSetTolerances");
    PetscScalar* v = nullptr;
    check(VecGetArray(b_, &v), "VecGetArray");
    std::copy(b.data(), b.data() + b.size(), v);
    check(VecRestoreArray(b_, &v), "VecRestoreArray");
    check(KSPSolve(ksp_, b_, x_), "KSPSolve");
    PetscInt its = 0;
    KSPConvergedReason reason;
    PetscReal residual = 0.0, rtol = 0.0;
    check(KSPGetIterationNumber(ksp_, &its), "KSPGetIterationNumber");
    check(KSPGetConvergedReason(ksp_, &reason), "KSPGetConvergedReason");
    check(KSPGetResidualNorm(ksp_, &residual), "KSPGetResidualNorm");
    check(KSPGetTolerances(ksp_, &rtol, nullptr, nullptr, nullptr), "KSPGetTolerances");
    iterations_ += its;
    if (reason < 0) {
      KSPType ksp_type;
      PCType pc_type;
      PC pc;
      KSPGetType(ksp_, &ksp_type);
      KSPGetPC(ksp_, &pc);
      PCGetType(pc, &pc_type);
      throw SolverError(fmt::format(
          "PETSc {} with {} did not converge ({}): residual {:.3e} ({:.2e} of the right-hand side's) after {} "
          "iterations (relative tolerance {:.1e})",
          ksp_type ? ksp_type : "?", pc_type ? pc_type : "?", KSPConvergedReasons[reason], residual,
          residual / std::max(b.norm(), 1e-300), its, rtol));
    }
    Vector x(b.size());
    const PetscScalar* xv = nullptr;
    check(VecGetArrayRead(x_, &xv), "VecGetArrayRead");
    std::copy(xv, xv + x.size(), x.data());
    check(VecRestoreArrayRead(x_, &xv), "VecRestoreArrayRead");
    return x;
  }

 private:
  void set_rigid_body_modes(int bs) {
    const Eigen::MatrixXd xyz = description_.node_coordinates();
    PetscInt n = 0;
    check(MatGetSize(matrix_, &n, nullptr), "MatGetSize");
    if (xyz.rows() * bs != n || xyz.cols() != bs) return;  // not one row per node: no modes
    ::Vec coords;
    check(VecCreateSeq(PETSC_COMM_SELF, n, &coords), "VecCreateSeq");
    check(VecSetBlockSize(coords, bs), "VecSetBlockSize");
    PetscScalar* c = nullptr;
    check(VecGetArray(coords, &c), "VecGetArray");
    for (Eigen::Index node = 0; node < xyz.rows(); ++node)
      for (int d = 0; d < bs; ++d) c[node * bs + d] = xyz(node, d);
    check(VecRestoreArray(coords, &c), "VecRestoreArray");
    MatNullSpace modes;
    check(MatNullSpaceCreateRigidBody(coords, &modes), "MatNullSpaceCreateRigidBody");
    check(MatSetNearNullSpace(matrix_, modes), "MatSetNearNullSpace");
    MatNullSpaceDestroy(&modes);
    VecDestroy(&coords);
  }

  void make_ksp() {
    check(KSPCreate(PETSC_COMM_SELF, &ksp_), "KSPCreate");
    check(KSPSetOptionsPrefix(ksp_, prefix_.c_str()), "KSPSetOptionsPrefix");
    check(KSPSetType(ksp_, kind_ == MatrixKind::General ? KSPGMRES : KSPCG), "KSPSetType");
    if (kind_ == MatrixKind::General) check(KSPGMRESSetRestart(ksp_, 200), "KSPGMRESSetRestart");
    check(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
    PC pc;
    check(KSPGetPC(ksp_, &pc), "KSPGetPC");
    check(PCSetType(pc, PCGAMG), "PCSetType");
    check(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE), "PCGAMGSetReuseInterpolation");
    check(KSPSetTolerances(ksp_, rtol_, 1e-300, PETSC_DEFAULT, max_iterations_), "KSPSetTolerances");
    check(KSPSetOperators(ksp_, matrix_, matrix_), "KSPSetOperators");
    check(KSPSetFromOptions(ksp_), "reading linear_solver.options (KSPSetFromOptions)");
  }

  void destroy() {
    if (ksp_) KSPDestroy(&ksp_);
    if (matrix_) MatDestroy(&matrix_);
    if (x_) VecDestroy(&x_);
    if (b_) VecDestroy(&b_);
  }

  MatrixKind kind_;
  bool user_rtol_ = false;  ///< -ksp_rtol given: the options decide, not the Newton driver
  std::string prefix_;
  struct OptionName {
    std::string user, prefixed;  ///< "ksp_type", "-gradmpm3_ksp_type"
  };
  std::vector<OptionName> names_;
  SystemDescription description_;
  std::vector<PetscInt> position_;
  Mat matrix_ = nullptr;
  KSP ksp_ = nullptr;
  ::Vec x_ = nullptr, b_ = nullptr;
  double rtol_ = 1e-12;  ///< solves outside Newton (the Helmholtz systems) are as good as a direct one
  PetscInt max_iterations_ = 10000;
  mutable long iterations_ = 0;
};

/// The 1D Laplacian of `n` unknowns (+ a shift), for checking options on a real solve.
SparseMatrix check_matrix(int n) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0 + 1e-2);
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, -1.0);
      t.emplace_back(i + 1, i, -1.0);
    }
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

}  // namespace

std::string check_petsc_options(const LinearSolverSettings& s) {
  try {
    Petsc solver(s, MatrixKind::Symmetric);
    const SparseMatrix A = check_matrix(64);
    solver.compute(A);
    solver.solve(Vector(Vector::Ones(64)));
    if (const auto unused = solver.unused_options(); !unused.empty()) {
      std::string list;
      for (const auto& u : unused) list += (list.empty() ? "" : ", ") + u;
      return fmt::format("options PETSc uses (it did not use {}: misspelt, or not for this solver?)", list);
    }
  } catch (const SolverError& e) {
    return fmt::format("options PETSc accepts ({})", e.what());
  }
  return "";
}

LinearSolverInfo petsc_solver_info() {
  LinearSolverInfo info{
      "petsc",
      "PETSc KSP (default: CG with GAMG and the rigid-body modes; GMRES for general matrices); "
      "linear_solver.options go to PETSc's options database",
      true, [](const LinearSolverSettings& s, MatrixKind kind) { return std::make_unique<Petsc>(s, kind); }};
  info.takes_options = true;
  info.check_options = check_petsc_options;
  return info;
}

}  // namespace gradmpm
