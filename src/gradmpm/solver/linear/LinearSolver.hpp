#pragma once
// One interface for every sparse linear solver (direct or iterative, symmetric or not),
// in the manner of MFEM's Solver/Operator: analyse the pattern once, factorise (or set
// up a preconditioner) for new values with the same pattern, solve any number of
// right-hand sides. Implementations live in solver/linear/ (one file each) and are
// created by name through LinearSolverRegistry, so the driver never names one.
//
// Recipe "add a linear solver" (docs/architecture.md): derive from LinearSolver,
// implement do_analyze/do_factorize/do_solve (and general()), and add one line to
// register_builtins() in LinearSolverRegistry.cpp; tests/test_solver.cpp
// registers a toy one at run time the same way.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gradmpm/core/Registry.hpp"
#include "gradmpm/core/Types.hpp"
#include "gradmpm/solver/RowHalo.hpp"
#include "gradmpm/solver/linear/LinearSolverSettings.hpp"

namespace gradmpm {

/// What a solver may want to know about a system besides its matrix: an algebraic
/// multigrid (PETSc GAMG, hypre) wants the unknowns per node and the node coordinates
/// for the rigid-body modes of elasticity. Direct solvers ignore it.
struct SystemDescription {
  int block_size = 1;  ///< unknowns per node (consecutive equations)
  /// One row per node of the system, in equation order: x, y, z (dim columns). Computed
  /// only when called; empty function: not known.
  std::function<Eigen::MatrixXd()> node_coordinates;
  /// A distributed run's matrix (the Newton tangent, a Helmholtz system): each rank passes
  /// its share (its points' contributions, with its points' pattern only) and the solver
  /// adds the shares up. Only a solver that adds_shares() may be told so.
  bool shares = false;
  /// With shares, a distributed run's rows (RowHalo): rank r owns global rows
  /// [halo->rank_rows()[r], halo->rank_rows()[r + 1]) (DofMap::rank_rows: the nodes of
  /// its box, so that its share falls in its own rows but for its ghost rows), and the
  /// caller reads the solution in its own and ghost rows only, so the solver fetches the
  /// ghost rows from their owners instead of gathering the whole solution on every rank.
  /// The matrix and vectors passed are in the halo's local rows (halo->global_row():
  /// a load step's hold its own and ghost rows only). Null: rows split evenly by nodes,
  /// the whole system and solution on every rank.
  const RowHalo* halo = nullptr;
  /// The caller factorises each analysed pattern once (a Helmholtz system of the gradient
  /// step), not at every Newton iteration: a direct solver spends on its ordering only
  /// what a few factorisations win back (CHOLMOD: METIS beside AMD only where AMD's factor
  /// costs 6000 flops per matrix entry or more).
  bool factorized_once = false;
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual std::string name() const = 0;
  /// true: solves any square matrix (reads both triangles); false: symmetric only. Either
  /// way the matrix is passed whole: a symmetric solver reads whichever triangle it
  /// factorises fastest (CHOLMOD the upper, Eigen's LDLT the lower).
  virtual bool general() const = 0;
  /// Called before analyze() by callers that know more about the system (the Newton
  /// driver: block size dim and the active nodes' coordinates). Default: ignored.
  virtual void describe(const SystemDescription&) {}
  /// true: solves only to a tolerance (Krylov); the Newton driver then sets it per
  /// iteration (inexact Newton, set_relative_tolerance).
  virtual bool iterative() const { return false; }
  /// The relative residual the next solves must reach. Default: ignored (direct solvers).
  virtual void set_relative_tolerance(double) {}
  /// Whether it can be given each rank's share of a matrix (SystemDescription::shares):
  /// PETSc in a distributed run, which sends each entry to the rank owning its row.
  virtual bool adds_shares() const { return false; }
  /// Krylov iterations so far, over all solves (0 for direct solvers).
  virtual long iterations() const { return 0; }
  /// Entries of the factor from the last analysis (a direct solver's fill; 0 where not known).
  virtual double factor_nonzeros() const { return 0.0; }
  /// true: analyze() reads the matrix's pattern only (not its values) and makes no OpenMP
  /// region, BLAS or MPI call, so it may run on one thread while other threads assemble
  /// the values (run_beside, core/Parallel.hpp). Default: false.
  virtual bool analysis_reads_pattern_only() const { return false; }

  /// Frees the numeric factor and keeps the analysis: solve() needs a factorize() again
  /// (a SolverError before it, whatever the solver). The Newton driver calls it once a
  /// load step has converged (its last factor is never solved with again), so that the
  /// gradient step's systems and the next step's arrays can take the factor's memory: a
  /// lower peak, and fewer first touches of new pages, which are slow on the virtual
  /// machines we measure on (docs/performance.md). What is freed: do_release_factor.
  void release_factor() {
    do_release_factor();
    factorized_ = false;
  }

  /// The fill-reducing ordering of the last analysis: the equations in the order they are
  /// eliminated (empty: none, as for iterative solvers, or not analysed yet).
  virtual std::vector<int> ordering() const { return {}; }
  /// The next analysis takes `perm` (a permutation of the next matrix's equations) as its
  /// ordering instead of computing one (AMD, METIS: most of an analysis), where the
  /// solver orders at all. Any ordering gives the same solution, to round-off; a poor one
  /// only costs fill (factor_nonzeros). Returns whether it will (false for an iterative
  /// solver); a `perm` that is not a permutation is a std::invalid_argument.
  /// `compare`: `perm` was made for another system on the same nodes (the gradient step's
  /// scalar system, given the load step's ordering), so the analysis also makes the
  /// solver's own cheap ordering (CHOLMOD: AMD) and keeps whichever factor costs fewer flops.
  bool order_by(std::vector<int> perm, bool compare = false);
  /// order_by(analysed.ordering()): systems of one pattern (the gradient step's
  /// smoothers) share one ordering.
  bool order_like(const LinearSolver& analysed) { return order_by(analysed.ordering()); }

  /// Symbolic analysis (ordering, elimination tree). Call again only if the pattern changes.
  void analyze(const SparseMatrix& A);
  /// Numeric factorisation (or preconditioner set-up); analyses first if not yet done.
  /// Throws SolverError if it cannot (e.g. an SPD solver given an indefinite matrix).
  void factorize(const SparseMatrix& A);
  /// analyze (if not yet done) + factorize.
  void compute(const SparseMatrix& A) { factorize(A); }
  /// x = A^{-1} b with the current factorisation; throws SolverError on failure
  /// (non-finite values; an iterative solver that did not converge says how far it got).
  Vector solve(const Vector& b) const;
  /// X = A^{-1} B for several right-hand sides at once.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;

  /// Wall-clock seconds spent so far in factorize and solve, and in analyze.
  double seconds() const { return seconds_; }
  double analysis_seconds() const { return analysis_seconds_; }

 protected:
  virtual void do_analyze(const SparseMatrix& A) = 0;
  /// Keeps `perm` (a permutation) for the next analysis; default: no ordering to take.
  virtual bool do_order_by(std::vector<int>&, bool /*compare*/) { return false; }
  virtual void do_factorize(const SparseMatrix& A) = 0;
  /// release_factor's part: free the factor's values, keep the analysis. Default: nothing.
  virtual void do_release_factor() {}
  virtual Vector do_solve(const Vector& b) const = 0;
  /// Default: column by column.
  virtual Eigen::MatrixXd do_solve(const Eigen::MatrixXd& B) const;

 private:
  bool analyzed_ = false, factorized_ = false;
  mutable double seconds_ = 0.0;
  double analysis_seconds_ = 0.0;
};

/// A solver the registry can make: its case-file name, a one-line description, whether
/// it solves general (non-symmetric) matrices, and how to make one.
struct LinearSolverInfo {
  std::string name;
  std::string doc;
  bool general = false;
  /// Makes one for matrices of `kind` (a general solver may choose its method by it).
  std::function<std::unique_ptr<LinearSolver>(const LinearSolverSettings&, MatrixKind)> make;
  /// Whether it reads LinearSolverSettings::options (e.g. a PETSc options string); the
  /// case reader refuses options for a solver that would ignore them.
  bool takes_options = false;
  /// For one that takes options: "" when settings.options are good, else what is
  /// expected (the case reader's message, exit 2). Empty function: not checked.
  std::function<std::string(const LinearSolverSettings&)> check_options;
};

class LinearSolverRegistry : public Registry<LinearSolverRegistry, LinearSolverInfo, &LinearSolverInfo::name> {
 public:
  /// "\"cholmod\", \"pcg\", ..." for messages and docs (general ones only if asked).
  std::string quoted_names(bool general_only = false) const {
    return Registry::quoted_names([&](const LinearSolverInfo& s) { return !general_only || s.general; }, ", ");
  }
};

/// The built-in solvers (LinearSolverRegistry.cpp: one line each).
void register_builtins(LinearSolverRegistry& registry);

/// The solver for matrices of `kind`: settings.type when it can solve them, else
/// settings.general. Throws InputError-free SolverError if a name is not registered
/// (case readers check names first, with the key in the message).
std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings,
                                                 MatrixKind kind = MatrixKind::Symmetric);

}  // namespace gradmpm
