// GOMP_parallel for the regions of a SerialOpenMpRegions scope (see the header for why).
#include "gradmpm/tuning/SerialOpenMpRegions.hpp"

#include <dlfcn.h>
#include <omp.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace {

thread_local int scopes = 0;              // SerialOpenMpRegions alive on this thread
std::atomic<long> plain_calls_made{0};  // regions run as plain calls

using Body = void (*)(void*);
using GompParallel = void (*)(Body, void*, unsigned, unsigned);

/// libgomp's own GOMP_parallel (GOMP_4.0 is the version GCC 4.9 and later call).
GompParallel libgomp_parallel() {
  static const GompParallel real = [] {
    void* f = dlvsym(RTLD_NEXT, "GOMP_parallel", "GOMP_4.0");
    if (!f) f = dlsym(RTLD_NEXT, "GOMP_parallel");
    if (!f) {
      std::fprintf(stderr, "gradmpm: the OpenMP runtime's GOMP_parallel was not found (is libgomp linked?)\n");
      std::abort();
    }
    return reinterpret_cast<GompParallel>(f);
  }();
  return real;
}

}  // namespace

namespace gradmpm {

void SerialOpenMpRegions::enter() { ++scopes; }
void SerialOpenMpRegions::leave() { --scopes; }
long SerialOpenMpRegions::plain_calls() { return plain_calls_made.load(std::memory_order_relaxed); }

}  // namespace gradmpm

/// What `#pragma omp parallel` compiles into (GCC): the body, its data, the thread count
/// asked for (1 when the `if` clause is false; 0 when nothing is asked), proc_bind flags.
extern "C" void GOMP_parallel(Body body, void* data, unsigned num_threads, unsigned flags) {
  if (scopes > 0 && omp_get_level() == 0 && (num_threads == 1 || omp_get_max_active_levels() == 0)) {
    plain_calls_made.fetch_add(1, std::memory_order_relaxed);
    body(data);
    return;
  }
  libgomp_parallel()(body, data, num_threads, flags);
}
