#include "gradmpm/core/LoadTimeEnvironment.hpp"

#include <unistd.h>

#include <cstdlib>

namespace gradmpm {

namespace {
std::string tunables() {
  const char* t = std::getenv("GLIBC_TUNABLES");
  return t ? std::string(t) : std::string();
}

/// Whether the user chose a malloc tunable: named in GLIBC_TUNABLES, or set by glibc's
/// older environment variable for it.
bool user_set(const std::string& tunable, const char* variable) {
  return !malloc_tunable(tunable).empty() || std::getenv(variable) != nullptr;
}
}  // namespace

std::string malloc_tunable(const std::string& name) {
  const std::string t = tunables(), key = "glibc.malloc." + name + "=";
  // GLIBC_TUNABLES is name=value pairs separated by colons; the last one named counts.
  std::string value;
  for (std::size_t at = t.find(key); at != std::string::npos; at = t.find(key, at + 1)) {
    if (at > 0 && t[at - 1] != ':') continue;
    const std::size_t from = at + key.size(), to = t.find(':', from);
    value = t.substr(from, to == std::string::npos ? std::string::npos : to - from);
  }
  return value;
}

std::string malloc_hugetlb() { return malloc_tunable("hugetlb"); }

bool malloc_keeps_freed_memory() {
  return malloc_tunable("mmap_max") == "0" && !malloc_tunable("trim_threshold").empty();
}

void set_load_time_environment(char** argv, LoadTimeChoices choices) {
  if (std::getenv("GRADMPM_LOAD_TIME_SET")) return;  // the second start
  bool changed = false;
  if (choices.passive_openmp && !std::getenv("OMP_WAIT_POLICY")) {
    ::setenv("OMP_WAIT_POLICY", "passive", 1);
    changed = true;
  }
  std::string added;  // tunables to add to the user's
  if (choices.huge_pages && malloc_hugetlb().empty()) added += ":glibc.malloc.hugetlb=1";
  if (choices.keep_freed_memory && !user_set("mmap_max", "MALLOC_MMAP_MAX_") &&
      !user_set("trim_threshold", "MALLOC_TRIM_THRESHOLD_"))
    added += ":glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=" + std::string(kKeptTrimThreshold);
  if (!added.empty()) {
    const std::string t = tunables();
    ::setenv("GLIBC_TUNABLES", (t.empty() ? added.substr(1) : t + added).c_str(), 1);
    changed = true;
  }
  if (!changed) return;
  ::setenv("GRADMPM_LOAD_TIME_SET", "1", 1);  // never twice, whatever exec does
  ::execv("/proc/self/exe", argv);            // returns only when it fails: run on as we are
}

}  // namespace gradmpm
