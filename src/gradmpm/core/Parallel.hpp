#pragma once
// When point loops run on OpenMP threads. Waking a team and crossing the barriers of a
// scatter by strips (two per matrix: even strips, then odd) costs microseconds on an idle
// machine, but up to a scheduler time slice each when several processes share the
// cores: two test programs with 2 threads each on 2 cores took 100 s instead of 2.5 s
// (docs/performance.md). Loops over fewer points than this run serially; their results
// are the same either way (the scatter order does not depend on the threads).
#include <algorithm>
#include <exception>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace gradmpm {

/// The threshold, in points. Tests lower it to exercise the threaded paths on small models.
inline int& min_points_for_threads() {
  static int n = 2048;
  return n;
}

inline bool use_threads(long points) { return points >= min_points_for_threads(); }

/// The threads a parallel region would get (1 without OpenMP).
inline int max_threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

/// Runs `serial` (single-threaded work) on the calling thread while `work` runs on the
/// other threads at the same time: `work`'s own parallel regions get the threads there are
/// less one (a nested team). For work that cannot use the threads (the sparse solver's
/// symbolic analysis: serial, a second core idle for 0.08 s per load step at 1e5 dof in
/// 2D) beside work that can (the step's first tangent). Neither may depend on the other's
/// results. With one thread, without OpenMP, or inside a parallel region: `work`, then
/// `serial`. An exception of either is rethrown once both have finished (`work`'s first).
template <class Serial, class Work>
void run_beside(Serial&& serial, Work&& work) {
#ifdef _OPENMP
  const int threads = omp_get_max_threads();
  if (threads >= 2 && omp_get_level() == 0) {
    std::exception_ptr serial_error, work_error;
    const int levels = omp_get_max_active_levels();
    omp_set_max_active_levels(std::max(levels, 2));  // work's regions: a team of threads - 1
#pragma omp parallel num_threads(2)
    {
      const bool alone = omp_get_num_threads() < 2;  // (the runtime may give fewer threads)
      if (alone) {
        try {
          work();
        } catch (...) {
          work_error = std::current_exception();
        }
      }
      if (omp_get_thread_num() == 0) {  // the calling thread: its memory arena, its MPI rights
        try {
          serial();
        } catch (...) {
          serial_error = std::current_exception();
        }
      } else {
        omp_set_num_threads(threads - 1);  // (this thread's own setting, for its regions)
        try {
          work();
        } catch (...) {
          work_error = std::current_exception();
        }
      }
    }
    omp_set_max_active_levels(levels);
    if (work_error) std::rethrow_exception(work_error);
    if (serial_error) std::rethrow_exception(serial_error);
    return;
  }
#endif
  work();
  serial();
}

}  // namespace gradmpm
