// CHOLMOD (SuiteSparse) supernodal Cholesky: the default solver of symmetric positive
// definite systems. Reads the lower triangle.
#include <dlfcn.h>
#include <omp.h>
#include <Eigen/CholmodSupport>

#include "gradmpm/solver/linear/EigenSolver.hpp"
#include "gradmpm/solver/linear/SerialOpenMpRegions.hpp"

namespace gradmpm {

namespace {

/// CHOLMOD 3 (SuiteSparse 5, as Debian 12 ships it) runs parts of its supernodal
/// factorisation on a fixed team of 4 OpenMP threads (CHOLMOD_OMP_NUM_THREADS, a
/// num_threads clause that omp_set_num_threads cannot lower), however many cores the
/// machine has, while the BLAS under it (libblas.so.3 from the system's alternatives:
/// OpenBLAS once scripts/install-deps has run) does the dense work of the supernodes.
///
/// With OpenBLAS (found at run time: the reference BLAS has no openblas_set_num_threads)
/// the BLAS gets the caller's thread count (--threads, OMP_NUM_THREADS) and CHOLMOD's own
/// parallel regions run serially (max-active-levels 0): its team and OpenBLAS's pthread
/// pool together oversubscribed the 2 cores. Measured at 2 threads, per factorisation
/// (docs/performance.md): 1e5-dof 2D 0.56-0.93 s -> 0.23-0.32 s, 1e6-dof 2D 12.6 -> 4.7 s;
/// one BLAS thread under CHOLMOD's team instead gave 0.26-0.31 s at 1e5 dof.
/// (OpenBLAS's OpenMP build would share gradmpm's team, but it hung in dsyrk when the
/// runtime gave its regions fewer threads than planned: not used.)
/// With the reference BLAS, CHOLMOD's team is what runs in parallel: dynamic adjustment
/// caps it at the caller's thread setting and the idle processors (1e5-dof 2D: 1.13 ->
/// 0.75 s against the fixed 4).
/// Either way, the regions that run serially run as plain calls (SerialOpenMpRegions:
/// libgomp spends a system call on each, about 69 000 per factorisation at 1e5 dof in 2D).
bool set_blas_threads(int n) {
  using SetThreads = void (*)(int);
  static const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set) set(n);
  return set != nullptr;
}

class CholmodThreadCap {
 public:
  CholmodThreadCap() : dynamic_(omp_get_dynamic()), levels_(omp_get_max_active_levels()) {
    if (set_blas_threads(omp_get_max_threads()))
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
  SerialOpenMpRegions serial_regions_;
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
