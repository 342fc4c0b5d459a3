#include "gradmpm/core/LoadTimeEnvironment.hpp"

#include <unistd.h>

#include <cstdlib>

namespace gradmpm {

namespace {
constexpr const char* kHugetlb = "glibc.malloc.hugetlb=";

std::string tunables() {
  const char* t = std::getenv("GLIBC_TUNABLES");
  return t ? std::string(t) : std::string();
}
}  // namespace

std::string malloc_hugetlb() {
  const std::string t = tunables();
  // GLIBC_TUNABLES is name=value pairs separated by colons; the last one named counts.
  std::string value;
  for (std::size_t at = t.find(kHugetlb); at != std::string::npos; at = t.find(kHugetlb, at + 1)) {
    if (at > 0 && t[at - 1] != ':') continue;
    const std::size_t from = at + std::string(kHugetlb).size(), to = t.find(':', from);
    value = t.substr(from, to == std::string::npos ? std::string::npos : to - from);
  }
  return value;
}

void set_load_time_environment(char** argv, LoadTimeChoices choices) {
  if (std::getenv("GRADMPM_LOAD_TIME_SET")) return;  // the second start
  bool changed = false;
  if (choices.passive_openmp && !std::getenv("OMP_WAIT_POLICY")) {
    ::setenv("OMP_WAIT_POLICY", "passive", 1);
    changed = true;
  }
  if (choices.huge_pages && malloc_hugetlb().empty()) {
    const std::string t = tunables();
    ::setenv("GLIBC_TUNABLES", (t.empty() ? std::string() : t + ":") .append(kHugetlb).append("1").c_str(), 1);
    changed = true;
  }
  if (!changed) return;
  ::setenv("GRADMPM_LOAD_TIME_SET", "1", 1);  // never twice, whatever exec does
  ::execv("/proc/self/exe", argv);            // returns only when it fails: run on as we are
}

}  // namespace gradmpm
