// CHOLMOD (SuiteSparse) supernodal Cholesky: the default solver of symmetric positive
// definite systems. Reads the lower triangle.
#include <dlfcn.h>
#include <omp.h>
#include <Eigen/CholmodSupport>

#include "gradmpm/solver/linear/EigenSolver.hpp"

namespace gradmpm {

namespace {

/// CHOLMOD 3 (SuiteSparse 5, as Debian 12 ships it) runs parts of its supernodal
/// factorisation on a fixed team of 4 OpenMP threads (CHOLMOD_OMP_NUM_THREADS), however
/// many cores the machine has and whatever the caller asked for. On 2 cores that
/// oversubscribes them: a 1e5-dof 2D factorisation took 1.13 s instead of 0.75 s
/// (docs/performance.md). With dynamic adjustment on, libgomp caps every team at the
/// caller's thread setting and the idle processors, so it is switched on around CHOLMOD.
///
/// The BLAS under CHOLMOD is whichever libblas.so.3 the system's alternatives give
/// (OpenBLAS once scripts/install-deps has run). OpenBLAS's pthread build keeps its own
/// pool of one thread per core, beside gradmpm's OpenMP team: it is told the caller's
/// thread count (--threads, OMP_NUM_THREADS) around every CHOLMOD call, so that the two
/// never run more threads than asked. (OpenBLAS's OpenMP build would share the team, but
/// it hangs when dynamic adjustment gives its parallel regions fewer threads than it
/// planned: seen here, in dsyrk.) Found at run time: the reference BLAS has no such call.
void set_blas_threads(int n) {
  using SetThreads = void (*)(int);
  static const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set) set(n);
}

class CholmodThreadCap {
 public:
  CholmodThreadCap() : previous_(omp_get_dynamic()) {
    set_blas_threads(omp_get_max_threads());
    omp_set_dynamic(1);
  }
  ~CholmodThreadCap() { omp_set_dynamic(previous_); }
  CholmodThreadCap(const CholmodThreadCap&) = delete;
  CholmodThreadCap& operator=(const CholmodThreadCap&) = delete;

 private:
  int previous_;
};

using Decomposition = Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower>;

struct CholmodTraits {
  static constexpr const char* name = "cholmod";
  static constexpr bool general = false, keeps_reference = false;
  using Guard = CholmodThreadCap;
  static void configure(Decomposition& d) {
    // Failures are reported through SolverError; CHOLMOD's own printing would only
    // duplicate them on stderr.
    d.cholmod().print = 0;
    d.cholmod().error_handler = nullptr;
  }
  static std::string failure(const Decomposition& d) { return d.info() == Eigen::Success ? "" : kNotPositiveDefinite; }
};

}  // namespace

LinearSolverInfo cholmod_solver_info() {
  return {CholmodTraits::name, "SuiteSparse CHOLMOD supernodal Cholesky (symmetric positive definite)", false,
          [](const LinearSolverSettings&, MatrixKind) {
            return std::make_unique<EigenSolver<Decomposition, CholmodTraits>>();
          }};
}

}  // namespace gradmpm
