#pragma once
// What an executable's process tuning (tuning/ProcessTuning.hpp) lends the library. The
// library itself never acts on the runtimes under it (libgomp, the BLAS, malloc): without
// tuning every hook is empty and they behave as their defaults and the environment say.
namespace gradmpm {

struct PlatformHooks {
  /// Sets the BLAS's own thread count; false when it has none (the reference BLAS).
  bool (*set_blas_threads)(int threads) = nullptr;
  /// Opens and closes, on the calling thread, a scope in which OpenMP regions that would
  /// run on one thread run as plain calls.
  void (*enter_serial_regions)() = nullptr;
  void (*leave_serial_regions)() = nullptr;
  /// What the tuning does, for the run's first line (nullptr: no tuning in this program).
  const char* summary = nullptr;
};

/// The process's hooks (installed before main by the tuning, when it is linked).
PlatformHooks& platform_hooks();

/// A scope of platform_hooks()'s serial regions (nothing without them).
class SerialRegionsScope {
 public:
  SerialRegionsScope() {
    if (platform_hooks().enter_serial_regions) platform_hooks().enter_serial_regions();
  }
  ~SerialRegionsScope() {
    if (platform_hooks().leave_serial_regions) platform_hooks().leave_serial_regions();
  }
  SerialRegionsScope(const SerialRegionsScope&) = delete;
  SerialRegionsScope& operator=(const SerialRegionsScope&) = delete;
};

}  // namespace gradmpm
