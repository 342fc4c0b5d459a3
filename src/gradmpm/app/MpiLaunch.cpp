#include "gradmpm/app/MpiLaunch.hpp"

#include <algorithm>
#include <cstdlib>
#include <utility>

namespace gradmpm {

namespace {
/// A non-negative integer variable's value, or -1 when unset or not a number.
int integer_variable(const char* name) {
  const char* v = std::getenv(name);
  if (!v || !*v) return -1;
  char* end = nullptr;
  const long n = std::strtol(v, &end, 10);
  return *end == '\0' && n >= 0 && n < (1L << 30) ? static_cast<int>(n) : -1;
}
}  // namespace

MpiLaunch mpi_launch_from_environment() {
  for (const auto& [size, rank] :
       {std::pair{"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"}, std::pair{"PMI_SIZE", "PMI_RANK"}}) {
    const int n = integer_variable(size);
    if (n >= 1) return {n, std::max(0, integer_variable(rank))};
  }
  return {};
}

}  // namespace gradmpm
