#pragma once
// OpenMP parallel regions that would run on a team of one thread, run as plain calls.
//
// Why: GCC's OpenMP runtime (libgomp) sets up a team for every parallel region, even one
// that its `if` clause or max-active-levels makes serial, and ends it at a team barrier
// whose last arrival wakes the futex of the barrier: one system call per region. CHOLMOD 3
// (Debian 12) opens several `parallel for` regions per supernode and per descendant
// update, about 69 000 per factorisation of the 1.0e5-dof 2D column, and runs them all
// serially under OpenBLAS (solver/linear/Cholmod.cpp). A system call costs 1.4-4 us on
// the virtual machines gradmpm is measured on (docs/performance.md): 0.1 s and more of a
// 0.3 s factorisation went to waking nobody.
//
// How: this object file defines GOMP_parallel, the entry point GCC compiles `#pragma omp
// parallel` into. An executable's definition takes precedence over libgomp's, for
// libcholmod's calls as for gradmpm's own. While a scope (enter() .. leave()) is open on a
// thread, a region that thread opens outside any other region (omp_get_level() == 0) and
// that would get one thread (its `if` clause false or num_threads(1), or
// max-active-levels 0) calls the region's body directly: outside any region,
// omp_get_thread_num() is 0 and omp_get_num_threads() 1, as in a team of one, and
// worksharing constructs and barriers without a team are the orphaned ones OpenMP allows.
// Every other region, and every region of a thread without the scope, goes to libgomp's
// GOMP_parallel unchanged.
//
// Part `regions` of the process tuning (tuning/ProcessTuning.hpp): only executables link
// it, and the library opens its scopes through core/PlatformHooks.hpp.
namespace gradmpm {

struct SerialOpenMpRegions {
  /// Opens and closes a scope on the calling thread (scopes nest).
  static void enter();
  static void leave();
  /// Regions run as plain calls since the program started (every thread).
  static long plain_calls();
};

}  // namespace gradmpm
