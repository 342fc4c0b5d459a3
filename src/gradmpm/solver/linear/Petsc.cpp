// PETSc's KSP and PC behind the LinearSolver interface: linear_solver.type = "petsc",
// linear_solver.options go to PETSc's options database, so any KSP and PC (GAMG, hypre,
// MUMPS, ...) is one option away (docs/performance.md). Defaults: CG with GAMG for
// symmetric systems, given the rigid-body modes from the node coordinates (describe()),
// its interpolation kept across a load step's refactorisations; MUMPS's LU for general
// ones (GMRES with GAMG without MUMPS, or when the options name -ksp_type or -pc_type).
// The Newton driver sets each solve's relative tolerance (inexact Newton); other solves
// use 1e-12. Each solver's options get a prefix of its own in PETSc's database, so that
// the objects inside the preconditioner see them and two solvers never see each other's.
// Built into the plugin libgradmpm_petsc.so (core/Plugins.hpp), loaded on first use.
#include <fmt/format.h>
#include <petscksp.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <sstream>
#include <stdexcept>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"
#include "gradmpm/solver/linear/PetscSupport.hpp"

namespace gradmpm {

namespace {

using petsc_support::check;
using petsc_support::PetscRuntime;

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
  bool adds_shares() const override { return distributed_; }
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
    const PetscInt local_rows = static_cast<PetscInt>(A.rows());
    const int bs =
        description_.block_size > 1 && local_rows % description_.block_size == 0 ? description_.block_size : 1;
    split_rows(local_rows, bs);
    const PetscInt n = n_, m = last_ - first_;  // the rows this rank owns: global [first_, last_), local [lo_, lo_ + m)
    // Compressed rows (this rank's) from Eigen's compressed columns; `position_[k]`: where
    // the k-th stored value of A goes (-1: a row of another rank; with shares, -1 - its
    // place among the other ranks' rows), so that a refactorisation only copies values.
    std::vector<PetscInt> row_start(m + 1, 0);
    for (int c = 0; c < A.outerSize(); ++c)
      for (SparseMatrix::InnerIterator it(A, c); it; ++it)
        if (own(it.row())) ++row_start[it.row() - lo_ + 1];
    for (PetscInt r = 0; r < m; ++r) row_start[r + 1] += row_start[r];
    std::vector<PetscInt> next(row_start.begin(), row_start.end() - 1), columns(row_start[m]);
    position_.assign(A.nonZeros(), -1);
    Eigen::Index k = 0;
    for (int c = 0; c < A.outerSize(); ++c)
      for (SparseMatrix::InnerIterator it(A, c); it; ++it, ++k)
        if (own(it.row())) {
          position_[k] = next[it.row() - lo_]++;
          columns[position_[k]] = global(c);
        }
    if (const RowHalo* halo = rows_halo(); halo && !halo->local_is_global())
      sort_columns(row_start, columns);  // (a local numbering's ghost columns may precede its own)
    if (description_.shares) {
      share_other_rows(A);
      // Each rank's share holds only its points' couplings: this rank's rows get the
      // columns the other ranks' shares reach in them too (their pattern, exchanged once
      // per analysis), so that the matrix is preallocated for the sum of the shares.
      add_columns_of_other_shares(row_start, columns);
    }
    const PetscInt row_start_end = row_start[m];
    local_values_.assign(row_start_end, 0.0);
    check(MatCreate(comm(), &matrix_), "MatCreate");
    check(MatSetSizes(matrix_, m, m, n, n), "MatSetSizes");
    check(MatSetType(matrix_, distributed_ ? MATMPIAIJ : MATSEQAIJ), "MatSetType");
    if (bs > 1) check(MatSetBlockSize(matrix_, bs), "MatSetBlockSize");
    if (distributed_) {
      check(MatMPIAIJSetPreallocationCSR(matrix_, row_start.data(), columns.data(), local_values_.data()),
            "MatMPIAIJSetPreallocationCSR");
      row_start_ = std::move(row_start);
      columns_ = std::move(columns);
    } else {  // values go straight into PETSc's array (do_factorize)
      check(MatSeqAIJSetPreallocationCSR(matrix_, row_start.data(), columns.data(), local_values_.data()),
            "MatSeqAIJSetPreallocationCSR");
      std::vector<PetscScalar>().swap(local_values_);
    }
    MatInfo info;
    check(MatGetInfo(matrix_, MAT_LOCAL, &info), "MatGetInfo");
    if (static_cast<PetscInt>(info.nz_used) != row_start_end)
      throw SolverError(fmt::format("PETSc kept {} of the matrix's {} entries", info.nz_used, row_start_end));
    const bool rigid_modes = bs > 1 && description_.node_coordinates;
    if (rigid_modes) set_rigid_body_modes(bs);
    check(MatCreateVecs(matrix_, &x_, &b_), "MatCreateVecs");
    make_ksp(rigid_modes);
  }

  void do_factorize(const SparseMatrix& A) override {
    const double* a = A.valuePtr();
    if (!distributed_) {
      PetscScalar* values = nullptr;
      check(MatSeqAIJGetArray(matrix_, &values), "MatSeqAIJGetArray");
      for (std::size_t k = 0; k < position_.size(); ++k) values[position_[k]] = a[k];
      check(MatSeqAIJRestoreArray(matrix_, &values), "MatSeqAIJRestoreArray");
    } else if (!description_.shares) {  // every rank holds A whole and sets its own rows: no communication
      for (std::size_t k = 0; k < position_.size(); ++k)
        if (position_[k] >= 0) local_values_[position_[k]] = a[k];
      set_own_rows(INSERT_VALUES);
      check(MatAssemblyBegin(matrix_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
      check(MatAssemblyEnd(matrix_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    } else {  // A is this rank's share: its own rows added, the others' sent to their owners
      for (std::size_t k = 0; k < position_.size(); ++k) {
        if (position_[k] >= 0)
          local_values_[position_[k]] = a[k];
        else
          other_values_[-1 - position_[k]] = a[k];
      }
      check(MatZeroEntries(matrix_), "MatZeroEntries");
      set_own_rows(ADD_VALUES);
      for (std::size_t r = 0; r < other_rows_.size(); ++r) {
        const PetscInt begin = other_start_[r], count = other_start_[r + 1] - begin;
        const PetscScalar* v = other_values_.data() + begin;
        if (std::all_of(v, v + count, [](PetscScalar x) { return x == 0.0; })) continue;  // not touched here
        check(MatSetValues(matrix_, 1, &other_rows_[r], count, other_columns_.data() + begin, v, ADD_VALUES),
              "MatSetValues");
      }
      check(MatAssemblyBegin(matrix_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
      check(MatAssemblyEnd(matrix_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    }
    check(KSPSetOperators(ksp_, matrix_, matrix_), "KSPSetOperators");
    check(KSPSetUp(ksp_), "setting up the preconditioner (KSPSetUp)");
  }

  Vector do_solve(const Vector& b) const override {
    const PetscScalar* xv = solve_own_rows(b);
    if (const RowHalo* halo = rows_halo()) {  // this rank's rows, then its ghost rows from their owners
      Vector x = Vector::Zero(b.size());
      std::copy(xv, xv + (last_ - first_), x.data() + lo_);
      check(VecRestoreArrayRead(x_, &xv), "VecRestoreArrayRead");
      halo->fetch_ghosts(x);
      return x;
    }
    Vector x(b.size());
    ranks::all_gather_rows(xv, row_counts_, x.data());  // every rank continues with the whole solution
    check(VecRestoreArrayRead(x_, &xv), "VecRestoreArrayRead");
    return x;
  }

  /// Several right-hand sides (the gradient step's strain or stress components): each
  /// solved in turn, the ghost rows of all fetched with one exchange.
  Eigen::MatrixXd do_solve(const Eigen::MatrixXd& B) const override {
    const RowHalo* halo = rows_halo();
    if (!halo) return LinearSolver::do_solve(B);
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(B.rows(), B.cols());
    for (Eigen::Index j = 0; j < B.cols(); ++j) {
      const PetscScalar* xv = solve_own_rows(B.col(j));
      std::copy(xv, xv + (last_ - first_), X.col(j).data() + lo_);
      check(VecRestoreArrayRead(x_, &xv), "VecRestoreArrayRead");
    }
    halo->fetch_ghosts(X);
    return X;
  }

 private:
  /// Solves for b's own rows (b: this rank's local rows [lo_, lo_ + m) are read); returns x_'s
  /// array of this rank's rows, to be restored by the caller (VecRestoreArrayRead). A
  /// Krylov method that did not converge throws SolverError with the iterations and the
  /// residual, relative to the whole right-hand side's norm (over every rank's rows).
  const PetscScalar* solve_own_rows(const Vector& b) const {
    if (!user_rtol_) check(KSPSetTolerances(ksp_, rtol_, 1e-300, PETSC_DEFAULT, max_iterations_), "KSPSetTolerances");
    PetscScalar* v = nullptr;
    check(VecGetArray(b_, &v), "VecGetArray");
    std::copy(b.data() + lo_, b.data() + lo_ + (last_ - first_), v);
    check(VecRestoreArray(b_, &v), "VecRestoreArray");
    check(KSPSolve(ksp_, b_, x_), "KSPSolve");
    PetscInt its = 0;
    KSPConvergedReason reason;
    PetscReal residual = 0.0, rtol = 0.0, b_norm = 0.0;
    check(KSPGetIterationNumber(ksp_, &its), "KSPGetIterationNumber");
    check(KSPGetConvergedReason(ksp_, &reason), "KSPGetConvergedReason");
    check(KSPGetResidualNorm(ksp_, &residual), "KSPGetResidualNorm");
    check(KSPGetTolerances(ksp_, &rtol, nullptr, nullptr, nullptr), "KSPGetTolerances");
    iterations_ += its;
    if (reason < 0) {  // (the reason is the same on every rank: each throws)
      check(VecNorm(b_, NORM_2, &b_norm), "VecNorm");
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
          residual / std::max(static_cast<double>(b_norm), 1e-300), its, rtol));
    }
    const PetscScalar* xv = nullptr;
    check(VecGetArrayRead(x_, &xv), "VecGetArrayRead");
    return xv;
  }

  void set_own_rows(InsertMode mode) {
    for (PetscInt r = 0; r + first_ < last_; ++r) {
      const PetscInt row = first_ + r, begin = row_start_[r];
      check(MatSetValues(matrix_, 1, &row, row_start_[r + 1] - begin, columns_.data() + begin,
                         local_values_.data() + begin, mode),
            "MatSetValues");
    }
  }

  /// With shares: the entries of A in other ranks' rows, as compressed rows, and their
  /// places in position_ (-1 - k for the k-th).
  /// (Rows ascending in local numbering ascend in global row outside the own ones.)
  void share_other_rows(const SparseMatrix& A) {
    const PetscInt local_rows = static_cast<PetscInt>(A.rows());
    std::vector<PetscInt> count(local_rows, 0);
    for (int c = 0; c < A.outerSize(); ++c)
      for (SparseMatrix::InnerIterator it(A, c); it; ++it)
        if (!own(it.row())) ++count[it.row()];
    std::vector<PetscInt> slot(local_rows, -1);  // local row -> its place in other_rows_
    other_rows_.clear();
    other_start_.assign(1, 0);
    for (PetscInt row = 0; row < local_rows; ++row)
      if (count[row] > 0) {
        slot[row] = static_cast<PetscInt>(other_rows_.size());
        other_rows_.push_back(global(static_cast<int>(row)));
        other_start_.push_back(other_start_.back() + count[row]);
      }
    std::vector<PetscInt> next(other_start_.begin(), other_start_.end() - 1);
    other_columns_.resize(other_start_.back());
    other_values_.assign(other_start_.back(), 0.0);
    Eigen::Index k = 0;
    for (int c = 0; c < A.outerSize(); ++c)
      for (SparseMatrix::InnerIterator it(A, c); it; ++it, ++k)
        if (!own(it.row())) {
          const PetscInt at = next[slot[it.row()]]++;
          other_columns_[at] = global(c);
          position_[k] = -1 - at;
        }
  }

  /// With shares: sends the columns of this share's entries in other ranks' rows to
  /// their owners and merges the columns received into this rank's rows (row_start,
  /// columns: compressed rows, columns ascending), renumbering position_ to match.
  void add_columns_of_other_shares(std::vector<PetscInt>& row_start, std::vector<PetscInt>& columns) {
    const int size = ranks::size();
    std::vector<PetscInt> row_offset(size + 1, 0);  // rank r owns rows [row_offset[r], row_offset[r + 1])
    for (int r = 0; r < size; ++r) row_offset[r + 1] = row_offset[r] + row_counts_[r];
    // Per row: row, count, columns... Rows ascend, so their owners' blocks come in rank order.
    std::vector<PetscInt> send;
    std::vector<int> send_count(size, 0), recv_count(size), send_at(size + 1, 0), recv_at(size + 1, 0);
    for (std::size_t k = 0; k < other_rows_.size(); ++k) {
      const PetscInt row = other_rows_[k], count = other_start_[k + 1] - other_start_[k];
      const int owner =
          static_cast<int>(std::upper_bound(row_offset.begin(), row_offset.end(), row) - row_offset.begin()) - 1;
      send.push_back(row);
      send.push_back(count);
      send.insert(send.end(), other_columns_.begin() + other_start_[k], other_columns_.begin() + other_start_[k + 1]);
      send_count[owner] += static_cast<int>(2 + count);
    }
    check(MPI_Alltoall(send_count.data(), 1, MPI_INT, recv_count.data(), 1, MPI_INT, PETSC_COMM_WORLD),
          "MPI_Alltoall (the shares' patterns)");
    for (int r = 0; r < size; ++r) {
      send_at[r + 1] = send_at[r] + send_count[r];
      recv_at[r + 1] = recv_at[r] + recv_count[r];
    }
    std::vector<PetscInt> received(recv_at[size]);
    check(MPI_Alltoallv(send.data(), send_count.data(), send_at.data(), MPIU_INT, received.data(), recv_count.data(),
                        recv_at.data(), MPIU_INT, PETSC_COMM_WORLD),
          "MPI_Alltoallv (the shares' patterns)");
    const PetscInt m = last_ - first_;
    std::vector<std::vector<PetscInt>> extra(m);
    for (std::size_t i = 0; i < received.size();) {
      const PetscInt row = received[i], count = received[i + 1];
      auto& e = extra[row - first_];
      e.insert(e.end(), received.begin() + static_cast<std::ptrdiff_t>(i) + 2,
               received.begin() + static_cast<std::ptrdiff_t>(i) + 2 + count);
      i += 2 + static_cast<std::size_t>(count);
    }
    std::vector<PetscInt> merged_start(m + 1, 0), merged, renumber(columns.size());
    merged.reserve(columns.size());
    for (PetscInt r = 0; r < m; ++r) {
      auto& e = extra[r];
      std::sort(e.begin(), e.end());
      e.erase(std::unique(e.begin(), e.end()), e.end());
      PetscInt i = row_start[r];
      std::size_t j = 0;
      while (i < row_start[r + 1] || j < e.size()) {
        if (j == e.size() || (i < row_start[r + 1] && columns[i] <= e[j])) {
          if (j < e.size() && columns[i] == e[j]) ++j;
          renumber[i] = static_cast<PetscInt>(merged.size());
          merged.push_back(columns[i++]);
        } else {
          merged.push_back(e[j++]);
        }
      }
      merged_start[r + 1] = static_cast<PetscInt>(merged.size());
    }
    for (auto& p : position_)
      if (p >= 0) p = renumber[p];
    row_start = std::move(merged_start);
    columns = std::move(merged);
  }

  void set_rigid_body_modes(int bs) {
    const Eigen::MatrixXd xyz = description_.node_coordinates();
    PetscInt n = 0;
    check(MatGetSize(matrix_, &n, nullptr), "MatGetSize");
    if (xyz.rows() * bs != local_rows_ || xyz.cols() != bs) return;  // not one row per node: no modes
    ::Vec coords;
    check(VecCreate(comm(), &coords), "VecCreate");
    check(VecSetSizes(coords, last_ - first_, n), "VecSetSizes");
    check(VecSetBlockSize(coords, bs), "VecSetBlockSize");
    check(VecSetType(coords, VECSTANDARD), "VecSetType");
    PetscScalar* c = nullptr;
    check(VecGetArray(coords, &c), "VecGetArray");
    for (Eigen::Index node = 0; node < (last_ - first_) / bs; ++node)  // this rank's nodes, local rows from lo_
      for (int d = 0; d < bs; ++d) c[node * bs + d] = xyz(lo_ / bs + node, d);
    check(VecRestoreArray(coords, &c), "VecRestoreArray");
    MatNullSpace modes;
    check(MatNullSpaceCreateRigidBody(coords, &modes), "MatNullSpaceCreateRigidBody");
    check(MatSetNearNullSpace(matrix_, modes), "MatSetNearNullSpace");
    MatNullSpaceDestroy(&modes);
    VecDestroy(&coords);
  }

  bool user_named(const char* option) const {
    return std::any_of(names_.begin(), names_.end(), [&](const OptionName& n) { return n.user == option; });
  }

  /// General matrices (F-bar, non-associated, indefinite) default to MUMPS's LU: GMRES
  /// with GAMG did not converge in useful time on the F-bar footing (bench_mpm tresca_2d:12
  /// ran over 6 minutes in its second step; MUMPS: 1.7 s per Newton iteration there,
  /// docs/performance.md).
  bool direct_default() const {
    if (kind_ != MatrixKind::General || user_named("ksp_type") || user_named("pc_type")) return false;
    PetscBool found = PETSC_FALSE, found_type = PETSC_FALSE;
    MatType type;
    check(MatGetType(matrix_, &type), "MatGetType");
    check(MatSolverTypeGet(MATSOLVERMUMPS, type, MAT_FACTOR_LU, &found, &found_type, nullptr), "MatSolverTypeGet");
    return found && found_type;  // a PETSc built without MUMPS keeps GMRES with GAMG
  }

  /// rigid_modes: GAMG has the rigid-body modes as its near-null space.
  void make_ksp(bool rigid_modes) {
    check(KSPCreate(comm(), &ksp_), "KSPCreate");
    check(KSPSetOptionsPrefix(ksp_, prefix_.c_str()), "KSPSetOptionsPrefix");
    PC pc;
    check(KSPGetPC(ksp_, &pc), "KSPGetPC");
    if (direct_default()) {
      check(KSPSetType(ksp_, KSPPREONLY), "KSPSetType");
      check(PCSetType(pc, PCLU), "PCSetType");
      check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
    } else {
      check(KSPSetType(ksp_, kind_ == MatrixKind::General ? KSPGMRES : KSPCG), "KSPSetType");
      if (kind_ == MatrixKind::General) check(KSPGMRESSetRestart(ksp_, 200), "KSPGMRESSetRestart");
      check(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
      check(PCSetType(pc, PCGAMG), "PCSetType");
      check(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE), "PCGAMGSetReuseInterpolation");
      // Without rigid-body modes (the scalar Helmholtz systems: rows of nodes a point barely
      // reaches are tiny) CG sees D^-1/2 A D^-1/2: tresca_2d:8's gradient solves 14.1 -> 0.78 s.
      check(KSPSetDiagonalScale(ksp_, rigid_modes ? PETSC_FALSE : PETSC_TRUE), "KSPSetDiagonalScale");
      check(KSPSetDiagonalScaleFix(ksp_, PETSC_TRUE), "KSPSetDiagonalScaleFix");
    }
    check(KSPSetTolerances(ksp_, rtol_, 1e-300, PETSC_DEFAULT, max_iterations_), "KSPSetTolerances");
    check(KSPSetOperators(ksp_, matrix_, matrix_), "KSPSetOperators");
    check(KSPSetFromOptions(ksp_), "reading linear_solver.options (KSPSetFromOptions)");
  }

  /// Distributed: rank r owns a contiguous range of rows, the halo's (the nodes of its
  /// cells) where given, else an even range of nodes.
  MPI_Comm comm() const { return distributed_ ? PETSC_COMM_WORLD : PETSC_COMM_SELF; }
  /// The halo whose rows the system follows and whose ghost rows a solve fetches (a
  /// distributed run's shares); null: an even split, the whole solution on every rank.
  const RowHalo* rows_halo() const {
    const RowHalo* halo = description_.halo;
    return distributed_ && description_.shares && halo && halo->distributed() ? halo : nullptr;
  }
  /// `local_rows`: the rows of the matrices and vectors this rank passes (with a halo of
  /// a local numbering, its own and ghost rows; otherwise the whole system's).
  void split_rows(PetscInt local_rows, int bs) {
    const int size = distributed_ ? ranks::size() : 1, rank = distributed_ ? ranks::rank() : 0;
    local_rows_ = local_rows;
    n_ = local_rows;
    row_counts_.assign(size, 0);
    const RowHalo* halo = rows_halo();
    if (halo) {
      const auto& given = halo->rank_rows();
      n_ = given.back();
      const bool fits = static_cast<int>(given.size()) == size + 1 && given.front() == 0 &&
                        (!halo->local_is_global() || given.back() == local_rows) &&
                        std::is_sorted(given.begin(), given.end()) &&
                        std::all_of(given.begin(), given.end(), [&](int row) { return row % bs == 0; });
      if (!fits)
        throw std::logic_error(
            fmt::format("PETSc: rows by rank that do not cover the {} rows in blocks of {}", given.back(), bs));
      for (int r = 0; r < size; ++r) row_counts_[r] = given[r + 1] - given[r];
    } else {
      const PetscInt nodes = n_ / bs;
      for (int r = 0; r < size; ++r) row_counts_[r] = static_cast<int>((nodes / size + (r < nodes % size)) * bs);
    }
    first_ = 0;
    for (int r = 0; r < rank; ++r) first_ += row_counts_[r];
    last_ = first_ + row_counts_[rank];
    lo_ = halo ? halo->first() : first_;
    if (halo && (halo->last() - halo->first() != last_ - first_ || lo_ % bs != 0 || halo->last() > local_rows))
      throw std::logic_error("PETSc: the halo's own rows do not match the rows by rank");
  }

  /// Whether local row `row` is one of this rank's own; the global row or column of a local one.
  bool own(PetscInt row) const { return row >= lo_ && row < lo_ + (last_ - first_); }
  PetscInt global(int local) const {
    const RowHalo* halo = rows_halo();
    return halo ? halo->global_row(local) : local;
  }

  /// Sorts each compressed row's columns (PETSc's CSR wants them ascending), moving
  /// position_ with them.
  void sort_columns(const std::vector<PetscInt>& row_start, std::vector<PetscInt>& columns) {
    std::vector<PetscInt> order, moved_to(columns.size()), sorted(columns.size());
    for (std::size_t r = 0; r + 1 < row_start.size(); ++r) {
      if (std::is_sorted(columns.begin() + row_start[r], columns.begin() + row_start[r + 1])) {  // most rows
        for (PetscInt i = row_start[r]; i < row_start[r + 1]; ++i) {
          moved_to[i] = i;
          sorted[i] = columns[i];
        }
        continue;
      }
      order.resize(row_start[r + 1] - row_start[r]);
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = row_start[r] + static_cast<PetscInt>(i);
      std::sort(order.begin(), order.end(), [&](PetscInt a, PetscInt b) { return columns[a] < columns[b]; });
      for (std::size_t i = 0; i < order.size(); ++i) {
        moved_to[order[i]] = row_start[r] + static_cast<PetscInt>(i);
        sorted[row_start[r] + static_cast<PetscInt>(i)] = columns[order[i]];
      }
    }
    columns = std::move(sorted);
    for (auto& p : position_)
      if (p >= 0) p = moved_to[p];
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
  bool distributed_ = ranks::distributed();
  PetscInt first_ = 0, last_ = 0;              ///< this rank's rows (global)
  PetscInt lo_ = 0;                            ///< this rank's first row in the vectors it passes (local)
  PetscInt n_ = 0, local_rows_ = 0;            ///< rows of the whole system; of the matrices passed
  std::vector<int> row_counts_;                ///< every rank's number of rows
  std::vector<PetscInt> position_;             ///< value k of A -> local_values_ (-1: not this rank's row)
  std::vector<PetscInt> row_start_, columns_;  ///< this rank's rows (distributed runs)
  std::vector<PetscScalar> local_values_;
  /// With shares: other ranks' rows this rank's share may touch (compressed rows).
  std::vector<PetscInt> other_rows_, other_start_, other_columns_;
  std::vector<PetscScalar> other_values_;
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
    // 60 unknowns: a multiple of every block size a case has (1 to 4 unknowns per node),
    // so that options splitting the unknowns by node (-pc_fieldsplit_block_size 3, the
    // coupled u-p step's fields) can be tried on it.
    constexpr int n = 60;
    Petsc solver(s, MatrixKind::Symmetric);
    const SparseMatrix A = check_matrix(n);
    solver.compute(A);
    solver.solve(Vector(Vector::Ones(n)));
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

}  // namespace gradmpm

/// The plugin's entry point (solver/linear/PetscPlugin.cpp reads it): how to make the
/// solver and check its options; its name and doc are the library's.
extern "C" const gradmpm::LinearSolverInfo* gradmpm_petsc_solver() {
  static const gradmpm::LinearSolverInfo info{
      .name = "petsc",
      .general = true,
      .make = [](const gradmpm::LinearSolverSettings& s, gradmpm::MatrixKind kind)
          -> std::unique_ptr<gradmpm::LinearSolver> { return std::make_unique<gradmpm::Petsc>(s, kind); },
      .takes_options = true,
      .check_options = gradmpm::check_petsc_options};
  return &info;
}
