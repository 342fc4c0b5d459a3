// CHOLMOD (SuiteSparse) supernodal Cholesky: the default solver of symmetric positive
// definite systems. Reads the upper triangle of the whole symmetric matrix every caller
// stores.
//
// CHOLMOD is called directly, not through Eigen's wrapper, for one reason: its
// supernodal factorisation (cholmod_super_numeric) wants S = tril(P A P') and
// cholmod_factorize forms S anew at every call, by one permuted transpose of an upper
// triangle or two of a lower one (Eigen passes the lower): a count pass and a fill pass
// over the matrix each. The pattern, and with it S's, is fixed from one analysis to the
// next, so the analysis here forms S once with the source position of each of its
// entries in A's value array (permuted_lower), and each factorisation fills S's values by
// that list (one gather) and calls cholmod_super_numeric, which is what cholmod_factorize calls after
// its transposes (Eigen's settings: supernodal, the factor kept as computed).
#include <amd.h>
#include <cholmod.h>
#include <omp.h>

#include <algorithm>
#include <numeric>

#include "gradmpm/solver/linear/EigenSolver.hpp"
#include "gradmpm/core/PlatformHooks.hpp"

namespace gradmpm {

namespace {

/// CHOLMOD 3 (SuiteSparse 5, as Debian 12 ships it) runs parts of its supernodal
/// factorisation on a fixed team of 4 OpenMP threads (CHOLMOD_OMP_NUM_THREADS, a
/// num_threads clause that omp_set_num_threads cannot lower), however many cores the
/// machine has, while the BLAS under it (libblas.so.3 from the system's alternatives:
/// OpenBLAS once scripts/install-deps has run) does the dense work of the supernodes.
///
/// With the process tuning's BLAS part (tuning/ProcessTuning.hpp: OpenBLAS found at run
/// time) the BLAS gets the caller's thread count (--threads, OMP_NUM_THREADS) and
/// CHOLMOD's own parallel regions run serially (max-active-levels 0): its team and
/// OpenBLAS's pthread pool together oversubscribed the cores (docs/performance.md).
/// Without it (a program without the tuning, --no-tuning, the reference BLAS) CHOLMOD's
/// team is what runs in parallel, capped by dynamic adjustment at the caller's thread
/// setting and the idle processors. Either way, the regions that run serially run as plain
/// calls where the tuning offers it (libgomp spends a system call on each, about 69 000 per
/// factorisation at 1e5 dof in 2D).
class CholmodThreadCap {
 public:
  CholmodThreadCap() : dynamic_(omp_get_dynamic()), levels_(omp_get_max_active_levels()) {
    const auto set_blas_threads = platform_hooks().set_blas_threads;
    if (set_blas_threads && set_blas_threads(omp_get_max_threads()))
      omp_set_max_active_levels(0);
    else
      omp_set_dynamic(1);
  }
  ~CholmodThreadCap() {
    omp_set_dynamic(dynamic_);
    omp_set_max_active_levels(levels_);
  }
  CholmodThreadCap(const CholmodThreadCap&) = delete;
  CholmodThreadCap& operator=(const CholmodThreadCap&) = delete;

 private:
  int dynamic_, levels_;
  SerialRegionsScope serial_regions_;
};

/// cholmod_sparse views of A's upper triangle (CHOLMOD reads, never writes, through it).
cholmod_sparse upper_view(const SparseMatrix& A, double* values) {
  cholmod_sparse v{};
  v.nrow = v.ncol = static_cast<std::size_t>(A.rows());
  v.nzmax = static_cast<std::size_t>(A.nonZeros());
  v.p = const_cast<int*>(A.outerIndexPtr());
  v.i = const_cast<int*>(A.innerIndexPtr());
  v.x = values;
  v.stype = 1;
  v.itype = CHOLMOD_INT;
  v.xtype = CHOLMOD_REAL;
  v.dtype = CHOLMOD_DOUBLE;
  v.sorted = 1;
  v.packed = 1;
  return v;
}

cholmod_dense dense_view(const double* x, Eigen::Index rows, Eigen::Index cols) {
  cholmod_dense d{};
  d.nrow = d.d = static_cast<std::size_t>(rows);
  d.ncol = static_cast<std::size_t>(cols);
  d.nzmax = d.nrow * d.ncol;
  d.x = const_cast<double*>(x);
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  return d;
}

/// A system factorised once is ordered by METIS only where AMD's factor takes this many
/// flops per entry of A or more. Measured on Helmholtz systems with AMD's ordering
/// against METIS's (2 cores, OpenBLAS): 5e5 nodes in 2D, 3.0e3 flops per entry: METIS
/// took 3.1 s to save 0.25 s per factorisation; 1.6e4 nodes in 3D, 1.2e4 flops per
/// entry: METIS's analysis was paid back within one factorisation (0.45 s of 0.88 saved
/// over four, for 0.05 s more analysis).
constexpr double kMetisFlopsPerEntry = 6000.0;

class CholmodSolver final : public LinearSolver {
 public:
  CholmodSolver() {
    cholmod_start(&c_);
    // Failures are reported through SolverError; CHOLMOD's own printing would only
    // duplicate them on stderr.
    c_.print = 0;
    c_.error_handler = nullptr;
    c_.supernodal = CHOLMOD_SUPERNODAL;
    c_.final_asis = 1;
  }
  ~CholmodSolver() override {
    release();
    cholmod_finish(&c_);
  }
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;
  std::string name() const override { return "cholmod"; }
  bool general() const override { return false; }
  void describe(const SystemDescription& d) override {
    once_ = d.factorized_once;
    block_ = std::max(1, d.block_size);
  }
  /// The analysis (AMD, METIS where CHOLMOD's rule tries it, the symbolic factorisation,
  /// S's pattern) has no OpenMP region and no BLAS call in CHOLMOD 3 (SuiteSparse 5.12:
  /// the only ones are in the numeric factorisation), and reads a compressed matrix's
  /// pattern only (an uncompressed one is copied whole).
  bool analysis_reads_pattern_only() const override { return true; }

 protected:
  void do_analyze(const SparseMatrix& given) override {
    const SparseMatrix& A = compressed(given);
    release();  // (no CholmodThreadCap: nothing here runs threads; analysis_reads_pattern_only)
    cholmod_sparse view = upper_view(A, const_cast<double*>(A.valuePtr()));
    // CHOLMOD's default: AMD, then METIS too when AMD's factor is costly (flops >= 500
    // nnz(L), nnz(L) >= 5 nnz(A)), the one with fewer flops kept: right for the Newton
    // tangent, factorised at every iteration. Given an ordering (order_by: another
    // solver's, the previous load step's), only the symbolic factorisation is made; given
    // one to compare (made for another system on these nodes), AMD's too.
    const bool taken = given_.size() == static_cast<std::size_t>(A.rows());
    Analysis a;
    if (taken) {
      a = analyze_by(view, CHOLMOD_GIVEN);
      if (compare_) keep_cheaper(a, view, CHOLMOD_AMD);
    } else if (block_ > 1 && !once_ && A.rows() % block_ == 0) {
      a = analyze_on_nodes(A, view);
    } else {
      a = analyze_by(view, once_ ? CHOLMOD_AMD : -1);
    }
    // A system factorised once (describe): METIS is tried only where the factor so far
    // costs more flops per entry of A than kMetisFlopsPerEntry, where the flops METIS
    // saves in a factorisation pay for its time (measured, docs/performance.md).
    if (once_ && (!taken || compare_) && a.L && a.flops >= kMetisFlopsPerEntry * static_cast<double>(A.nonZeros()))
      keep_cheaper(a, view, CHOLMOD_METIS);
    L_ = a.L;
    lnz_ = a.lnz;
    given_.clear();
    if (!L_) throw SolverError(failure("symbolic analysis"));
    permuted_lower(A, static_cast<const int*>(L_->Perm));
    nonzeros_ = A.nonZeros();
  }

  /// S_ = tril(P A P') (P: the factor's ordering) as a pattern, and source_: the position in
  /// A's values of each of S_'s entries. A's upper triangle (column j, rows i <= j) is
  /// read twice: to count the entries of each column of S_, then to place them. The
  /// entries that cholmod_factorize's transpose would make (A(i, j) goes to column
  /// min(p(i), p(j)), row max), each column's rows in another order, which
  /// cholmod_super_numeric does not need (it assigns each entry to its place in L).
  /// CHOLMOD's own transpose would carry the positions as doubles: an array of 8 bytes per
  /// entry of A, 24 MB at 1e5 dof in 2D.
  void permuted_lower(const SparseMatrix& A, const int* perm) {
    const int n = static_cast<int>(A.rows());
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    std::vector<int> inverse(n), next(n + 1, 0);
    for (int k = 0; k < n; ++k) inverse[perm[k]] = k;
    for (int j = 0; j < n; ++j)
      for (int k = outer[j]; k < outer[j + 1]; ++k)
        if (inner[k] <= j) ++next[std::min(inverse[inner[k]], inverse[j]) + 1];
    std::partial_sum(next.begin(), next.end(), next.begin());  // next[c]: column c's first place
    const std::size_t entries = static_cast<std::size_t>(next[n]);
    S_ = cholmod_allocate_sparse(n, n, entries, 0, 1, -1, CHOLMOD_REAL, &c_);
    if (!S_) throw SolverError(failure("permuting the matrix"));
    std::copy(next.begin(), next.end(), static_cast<int*>(S_->p));
    int* Si = static_cast<int*>(S_->i);
    source_.resize(entries);
    for (int j = 0; j < n; ++j)
      for (int k = outer[j]; k < outer[j + 1]; ++k) {
        const int i = inner[k];
        if (i > j) continue;
        const int r = inverse[i], c = inverse[j], at = next[std::min(r, c)]++;
        Si[at] = std::max(r, c);
        source_[static_cast<std::size_t>(at)] = k;
      }
  }

  /// A symbolic factorisation and what its factor costs.
  struct Analysis {
    cholmod_factor* L = nullptr;
    double flops = 0.0, lnz = 0.0;
  };
  /// cholmod_analyze_p with one ordering method (-1: CHOLMOD's default choice).
  Analysis analyze_by(cholmod_sparse& view, int method) {
    const int methods = c_.nmethods, ordering = c_.method[0].ordering;
    if (method >= 0) {
      c_.nmethods = 1;
      c_.method[0].ordering = method;
    }
    cholmod_factor* L = cholmod_analyze_p(&view, method == CHOLMOD_GIVEN ? given_.data() : nullptr, nullptr, 0, &c_);
    c_.nmethods = methods;
    c_.method[0].ordering = ordering;
    return {L, c_.fl, c_.lnz};
  }
  /// CHOLMOD's default strategy (AMD; METIS too where AMD's factor is costly, the one with
  /// fewer entries kept) with AMD run on the graph of the nodes (block_ consecutive
  /// equations each, as describe() said) and its ordering expanded to the equations: the
  /// same ordering's quality (AMD merges a node's indistinguishable equations anyway:
  /// 1.359e7 entries of L and 4.51e9 flops either way at 1e5 dof in 2D), on a graph with
  /// block_^2 times fewer entries. Any ordering gives the right factor; a pattern that is
  /// not made of node blocks would only get a poorer one.
  Analysis analyze_on_nodes(const SparseMatrix& A, cholmod_sparse& view) {
    const int bs = block_, nodes = static_cast<int>(A.rows()) / bs;
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    std::vector<int> Np(nodes + 1, 0), Ni;
    Ni.reserve(static_cast<std::size_t>(A.nonZeros()) / (bs * bs) + 1);
    for (int j = 0; j < nodes; ++j) {  // node j's first column, node rows at their first equation
      for (int k = outer[bs * j]; k < outer[bs * j + 1]; ++k)
        if (inner[k] % bs == 0) Ni.push_back(inner[k] / bs);
      Np[j + 1] = static_cast<int>(Ni.size());
    }
    std::vector<int> node_perm(nodes);
    double control[AMD_CONTROL], info[AMD_INFO];
    amd_defaults(control);
    const int status = amd_order(nodes, Np.data(), Ni.data(), node_perm.data(), control, info);
    if (status != AMD_OK && status != AMD_OK_BUT_JUMBLED) return analyze_by(view, -1);  // CHOLMOD's own way
    given_.resize(A.rows());
    for (int k = 0; k < nodes; ++k)
      for (int c = 0; c < bs; ++c) given_[bs * k + c] = bs * node_perm[k] + c;
    Analysis a = analyze_by(view, CHOLMOD_GIVEN);
    // CHOLMOD's rule for METIS after AMD (cholmod_analyze_p2's default strategy: the
    // ordering with fewer entries of L kept).
    const double anz = 0.5 * static_cast<double>(A.nonZeros() + A.rows());  // entries of tril(A)
    if (a.L && a.flops >= 500.0 * a.lnz && a.lnz >= 5.0 * anz) keep_cheaper(a, view, CHOLMOD_METIS, &Analysis::lnz);
    return a;
  }

  /// Analyses by `method` too and keeps, of the two, the factor with less of `cost`
  /// (flops by default; CHOLMOD's own rule compares the entries of L).
  void keep_cheaper(Analysis& kept, cholmod_sparse& view, int method, double Analysis::*cost = &Analysis::flops) {
    Analysis other = analyze_by(view, method);
    if (other.L && (!kept.L || other.*cost < kept.*cost)) std::swap(kept, other);
    if (other.L) cholmod_free_factor(&other.L, &c_);
  }

  bool do_order_by(std::vector<int>& perm, bool compare) override {
    given_ = std::move(perm);
    compare_ = compare;
    return true;
  }

  void do_factorize(const SparseMatrix& given) override {
    const SparseMatrix& A = compressed(given);
    if (static_cast<std::size_t>(A.rows()) != L_->n || A.nonZeros() != nonzeros_)
      throw SolverError("cholmod: factorize given a matrix of another pattern than the one analysed");
    if (L_->xtype == CHOLMOD_PATTERN && L_->is_super) allocate_factor_values();
    CholmodThreadCap guard;
    const double* a = A.valuePtr();
    double* Sx = static_cast<double*>(S_->x);
    for (std::size_t k = 0; k < source_.size(); ++k) Sx[k] = a[source_[k]];
    double zero[2] = {0.0, 0.0};
    cholmod_super_numeric(S_, nullptr, zero, L_, &c_);
    if (c_.status < CHOLMOD_OK) throw SolverError(failure("numeric factorisation"));
    if (L_->minor < L_->n)
      throw SolverError(std::string("sparse factorisation (cholmod) failed: ") + kNotPositiveDefinite);
  }

  /// The first factorisation after an analysis: L's values are allocated here (as
  /// cholmod_super_numeric would: supernodal, real) and their pages touched once by all
  /// threads. The first touch of memory the process has not had before is what costs on
  /// the virtual machines we measure on; CHOLMOD's own first touch is its clearing of each
  /// supernode, serial under OpenBLAS (CholmodThreadCap). A load step whose factor is
  /// larger than any before (the second, once the points have moved) paid it on one core:
  /// at 1e5 dof in 2D the step's first factorisation took about twice its next.
  void allocate_factor_values() {
    if (!cholmod_change_factor(CHOLMOD_REAL, 1, 1, 1, 1, L_, &c_)) throw SolverError(failure("allocating the factor"));
    double* x = static_cast<double*>(L_->x);
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(L_->xsize);
    constexpr std::ptrdiff_t per_page = 4096 / sizeof(double);
#pragma omp parallel for schedule(static) if (n >= (std::ptrdiff_t(1) << 20))  // 8 MiB and more
    for (std::ptrdiff_t k = 0; k < n; k += per_page) x[k] = 0.0;  // CHOLMOD clears each supernode before use
  }

  /// L's values freed (its pattern, ordering and S_'s pattern kept: the next
  /// factorisation allocates them again, allocate_factor_values).
  void do_release_factor() override {
    if (L_ && L_->xtype != CHOLMOD_PATTERN && L_->is_super)
      cholmod_change_factor(CHOLMOD_PATTERN, 1, 1, 1, 1, L_, &c_);  // cannot fail (CHOLMOD)
  }

  double factor_nonzeros() const override { return L_ ? lnz_ : 0.0; }
  std::vector<int> ordering() const override {
    if (!L_) return {};
    const int* perm = static_cast<const int*>(L_->Perm);
    return std::vector<int>(perm, perm + L_->n);
  }

  Vector do_solve(const Vector& b) const override { return solve_dense(b.data(), b.rows(), 1); }
  Eigen::MatrixXd do_solve(const Eigen::MatrixXd& B) const override {
    return solve_dense(B.data(), B.rows(), B.cols());
  }

 private:
  Eigen::MatrixXd solve_dense(const double* b, Eigen::Index rows, Eigen::Index cols) const {
    CholmodThreadCap guard;
    cholmod_dense B = dense_view(b, rows, cols);
    cholmod_dense* X = cholmod_solve(CHOLMOD_A, L_, &B, &c_);
    if (!X) throw SolverError(failure("solve"));
    Eigen::MatrixXd out = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(X->x), rows, cols);
    cholmod_free_dense(&X, &c_);
    return out;
  }

  std::string failure(const char* what) const {
    return std::string("cholmod: ") + what + " failed (CHOLMOD status " + std::to_string(c_.status) +
           (c_.status == CHOLMOD_OUT_OF_MEMORY ? ", out of memory)" : ")");
  }

  /// A itself, or (a matrix with room left in its columns) a compressed copy.
  const SparseMatrix& compressed(const SparseMatrix& A) {
    if (A.isCompressed()) return A;
    copy_ = A;
    copy_.makeCompressed();
    return copy_;
  }

  void release() {
    if (S_) cholmod_free_sparse(&S_, &c_);
    if (L_) cholmod_free_factor(&L_, &c_);
  }

  mutable cholmod_common c_;  ///< CHOLMOD's settings, statistics and workspace (a solve uses it too)
  cholmod_factor* L_ = nullptr;
  cholmod_sparse* S_ = nullptr;  ///< tril(P A P'): its pattern from the analysis, its values from A
  std::vector<int> source_;    ///< S_'s k-th value is A's value source_[k]
  std::vector<int> given_;     ///< order_by: the ordering the next analysis takes
  bool compare_ = false;       ///< order_by: given_ is compared with AMD's ordering
  bool once_ = false;          ///< describe: each analysis is factorised once
  int block_ = 1;              ///< describe: equations per node (AMD on the nodes' graph when above 1)
  double lnz_ = 0.0;           ///< the analysed factor's entries
  Eigen::Index nonzeros_ = 0;  ///< A's entries at the analysis (its size is L_->n)
  SparseMatrix copy_;          ///< compressed(): an uncompressed matrix's compressed copy
};

}  // namespace

LinearSolverInfo cholmod_solver_info() {
  return {"cholmod", "SuiteSparse CHOLMOD supernodal Cholesky (symmetric positive definite)", false,
          [](const LinearSolverSettings&, MatrixKind) { return std::make_unique<CholmodSolver>(); }};
}

}  // namespace gradmpm
