#pragma once
// When point loops run on OpenMP threads. Waking a team and crossing the barriers of a
// scatter by strips (two per matrix: even strips, then odd) costs microseconds on an idle
// machine, but up to a scheduler time slice each when several processes share the
// cores: two test programs with 2 threads each on 2 cores took 100 s instead of 2.5 s
// (docs/performance.md). Loops over fewer points than this run serially; their results
// are the same either way (the scatter order does not depend on the threads).
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

}  // namespace gradmpm
