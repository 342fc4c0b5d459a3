// The process tuning's decision, made before main (see the header), and its hooks.
#include "gradmpm/tuning/ProcessTuning.hpp"

#include <dlfcn.h>
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "gradmpm/core/PlatformHooks.hpp"
#include "gradmpm/tuning/SerialOpenMpRegions.hpp"

namespace gradmpm::tuning {

namespace {

Parts decided;                  // what parts() answers
const char* off_by = nullptr;   // "--no-tuning" or "GRADMPM_TUNING=0" when off
bool user_malloc = false;       // the user set malloc's mmap or trim thresholds
bool user_wait = false;         // OMP_WAIT_POLICY was the user's
std::string summary_text;       // the hooks' summary

/// openblas_set_num_threads, when the BLAS the process loaded is OpenBLAS.
bool set_blas_threads(int n) {
  using SetThreads = void (*)(int);
  static const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set) set(n);
  return set != nullptr;
}

/// `name`'s value in `env` (NAME=value entries), or nullptr.
char* lookup(char** env, const char* name) {
  const std::size_t n = std::strlen(name);
  for (char** e = env; e && *e; ++e)
    if (std::strncmp(*e, name, n) == 0 && (*e)[n] == '=') return *e + n + 1;
  return nullptr;
}

/// Runs from .preinit_array: after the dynamic loader has loaded every library, before
/// any of their initialisers (libgomp reads OMP_WAIT_POLICY in its own; any may
/// allocate), and before libc's own, which sets `environ`: the environment is read from `env`.
void decide(int argc, char** argv, char** env) {
  user_wait = lookup(env, "OMP_WAIT_POLICY") != nullptr;
  for (int i = 1; i < argc && argv[i]; ++i) {
    if (std::strcmp(argv[i], "--") == 0) break;
    if (std::strcmp(argv[i], "--no-tuning") == 0) off_by = "--no-tuning";
  }
  const char* value = lookup(env, "GRADMPM_TUNING");
  try {
    decided = off_by ? Parts{} : parse(value ? value : "");
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "gradmpm: error: GRADMPM_TUNING=%s: %s\n", value, e.what());
    std::fflush(stderr);
    ::_exit(2);
  }
  if (!off_by && decided == Parts{}) off_by = "GRADMPM_TUNING=0";
  const char* tunables = lookup(env, "GLIBC_TUNABLES");
  user_malloc = lookup(env, "MALLOC_MMAP_MAX_") || lookup(env, "MALLOC_TRIM_THRESHOLD_") ||
                (tunables && (std::strstr(tunables, "glibc.malloc.mmap_max=") ||
                              std::strstr(tunables, "glibc.malloc.trim_threshold=")));
  if (decided.memory && !user_malloc) {
    // Every block from the heap, never a mapping of its own (glibc maps each block above
    // its mmap threshold afresh and unmaps it when freed), and the heap never trimmed:
    // what a load step frees serves the next one's arrays without new pages.
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, -1);
  }
}

[[gnu::used, gnu::section(".preinit_array")]] void (*const preinit)(int, char**, char**) = decide;

/// The hooks, installed with the executable's static objects (after every library's).
struct Install {
  Install() {
    PlatformHooks& h = platform_hooks();
    if (decided.blas) h.set_blas_threads = set_blas_threads;
    if (decided.regions) {
      h.enter_serial_regions = SerialOpenMpRegions::enter;
      h.leave_serial_regions = SerialOpenMpRegions::leave;
    }
    summary_text = summary();
    h.summary = summary_text.c_str();
  }
} install;

}  // namespace

Parts parse(const std::string& value) {
  if (value.empty() || value == "1" || value == "on" || value == "all") return kAllParts;
  if (value == "0" || value == "off" || value == "none") return {};
  Parts p;
  std::size_t at = 0;
  while (at <= value.size()) {
    const std::size_t comma = std::min(value.find(',', at), value.size());
    const std::string name = value.substr(at, comma - at);
    if (name == "wait")
      p.wait = true;
    else if (name == "memory")
      p.memory = true;
    else if (name == "regions")
      p.regions = true;
    else if (name == "blas")
      p.blas = true;
    else
      throw std::invalid_argument("expected 1 (every part), 0 (none) or a comma-separated list of wait, memory, "
                                  "regions and blas, not the part '" + name + "'");
    at = comma + 1;
  }
  return p;
}

Parts parts() { return decided; }

std::string summary() {
  if (off_by) return std::string("tuning off (") + off_by + ")";
  std::string s;
  auto add = [&](const char* what) { s += (s.empty() ? "tuning: " : ", ") + std::string(what); };
  if (decided.wait) add(user_wait ? "OpenMP waiting as OMP_WAIT_POLICY says" : "OpenMP waiting passive");
  if (decided.memory) add(user_malloc ? "malloc as the user's settings say" : "freed memory kept");
  if (decided.regions) add("CHOLMOD's serial regions as calls");
  if (decided.blas) add("BLAS threads set under CHOLMOD");
  return s;
}

}  // namespace gradmpm::tuning

/// The environment as the process sees it, with OMP_WAIT_POLICY=passive added when the
/// waiting part is on and the user has not set it. libgomp reads the variable in its
/// initialiser, which runs after libc's, and libc's resets the process's environment to
/// the one it was started with: a variable set before then is lost, one set later comes
/// too late. So the executable's getenv (which libgomp's call binds to, as any library's
/// does) answers for it; nothing is set, and child processes see the user's environment.
/// Written out rather than forwarded: it may run before any library is initialised.
extern "C" char* getenv(const char* name) {
  if (char* value = gradmpm::tuning::lookup(environ, name)) return value;
  if (gradmpm::tuning::parts().wait && std::strcmp(name, "OMP_WAIT_POLICY") == 0) return const_cast<char*>("passive");
  return nullptr;
}
