#include "gradmpm/app/MemoryCheck.hpp"

#include "gradmpm/core/Ranks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

namespace gradmpm {

std::uint64_t memory_available() {
  std::uint64_t bytes = 0;
  std::ifstream in("/proc/meminfo");
  for (std::string key; in >> key;) {
    std::uint64_t kb = 0;
    std::string unit;
    in >> kb >> unit;
    if (key == "MemAvailable:") bytes = kb * 1024;
  }
  if (const char* limit = std::getenv("GRADMPM_MAX_MEMORY")) {
    const double gib = std::atof(limit);
    if (gib > 0.0) {
      const auto cap = static_cast<std::uint64_t>(gib * 1024.0 * 1024.0 * 1024.0);
      bytes = bytes ? std::min(bytes, cap) : cap;
    }
  }
  return bytes;
}

void require_memory(const CaseFile& cf, const std::string& key, double bytes, const std::string& what) {
  // A distributed run: every rank decides from the same number (the smallest any rank
  // read; 0, unknown, if any could not), so every rank meets the same error.
  double negative = -static_cast<double>(memory_available());
  ranks::max(&negative, 1);
  const auto available = static_cast<std::uint64_t>(-negative);
  if (available == 0 || bytes <= static_cast<double>(available)) return;
  constexpr double gib = 1024.0 * 1024.0 * 1024.0;
  cf.require(false, key,
             fmt::format("a case that fits in memory: it needs at least {:.3g} GiB ({}), more than the {:.3g} GiB "
                         "available",
                         bytes / gib, what, static_cast<double>(available) / gib));
}

double mpm_memory_estimate(int dim, double points, double cells, double nodes, bool grid_output,
                           double share, int on_this_machine) {
  // Per point (positions, F, stress, state, stencil, response, gradients): measured 1.8 KB
  // in 2D with the factorisation; lower bounds 0.5, 1, 2.5 KB in 1D, 2D, 3D.
  const double per_point = dim == 1 ? 500.0 : (dim == 2 ? 1000.0 : 2500.0);
  // Per grid node: the dof map and nodal fields (16 B), the grid VTU text (~100 B).
  const double per_node = 16.0 + (grid_output ? 100.0 : 0.0);
  // Tangent entries (12 B each) of the active dofs: at least one active node per covered
  // cell, 5^dim coupled nodes per node, dim^2 entries per node pair.
  const double entries = cells * std::pow(5.0, dim) * dim * dim;
  // The ranks on this machine share its memory: each holds its share of the points and of
  // the tangent, and every grid-sized vector whole.
  return on_this_machine * (share * (points * per_point + 12.0 * entries) + nodes * per_node);
}

double bar_memory_estimate(double elements, int points_per_element, bool as_mpm) {
  return elements * ((as_mpm ? 800.0 : 300.0) + 450.0 * points_per_element);
}

}  // namespace gradmpm
