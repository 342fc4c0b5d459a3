#include "gradmpm/app/MemoryCheck.hpp"

#include "gradmpm/core/Ranks.hpp"

#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

namespace gradmpm {

double peak_resident_memory() {
  rusage usage{};
  if (::getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
  return static_cast<double>(usage.ru_maxrss) * 1024.0;  // (kilobytes on Linux)
}

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

void require_memory(const CaseFile& cf, const std::string& key, double bytes, const std::string& what,
                    bool lower_bound) {
  // A distributed run: every rank decides from the same number (the smallest any rank
  // read; 0, unknown, if any could not), so every rank meets the same error.
  double negative = -static_cast<double>(memory_available());
  ranks::max(&negative, 1);
  const auto available = static_cast<std::uint64_t>(-negative);
  if (available == 0 || bytes <= static_cast<double>(available)) return;
  constexpr double gib = 1024.0 * 1024.0 * 1024.0;
  cf.require(false, key,
             fmt::format("a case that fits in memory: it needs {} {:.3g} GiB ({}), more than the {:.3g} GiB "
                         "available",
                         lower_bound ? "at least" : "about", bytes / gib, what, static_cast<double>(available) / gib));
}

double mpm_memory_estimate(int dim, double points, double cells, double nodes, bool grid_output,
                           double share, int on_this_machine) {
  // Fitted to the peak resident memory of elastic blocks under gravity (GIMP, 1 to 3
  // points per cell per direction; 1e4 to 4e5 cells in 2D, 1e3 to 3e4 in 3D) and of a
  // footing on grids of 1e6 to 4e6 mostly empty nodes, each within 20 % (docs/reliability.md):
  //  - the program and its libraries: 34 MB per process;
  //  - per point: positions, F, stress, state, stencil, response: 1.0 KB in 2D, 2.3 KB in 3D;
  //  - per covered cell: the tangent's entries (GIMP couples 5^dim nodes, dim^2 entries per
  //    pair), its factor and the nodal arrays of the active nodes: 3.1 KB in 2D; in 3D
  //    13.5 KB plus the factor's fill, which grows as the cube root of the cells (nested
  //    dissection: 0.75 KB times it);
  //  - per grid node, covered or not: the nodal fields of the step's reactions and outputs
  //    (displacement, reaction, mass: 40 B) and the dof map's pages, 45 B; the grid VTU
  //    file built in memory, 280 B more.
  const double base = 34e6;
  const double per_point = dim == 1 ? 500.0 : (dim == 2 ? 1000.0 : 2300.0);
  const double my_cells = share * cells;
  const double per_cell = dim == 1 ? 200.0 : (dim == 2 ? 3100.0 : 13500.0 + 750.0 * std::cbrt(std::max(my_cells, 1.0)));
  const double per_node = 45.0 + (grid_output ? 280.0 : 0.0);
  // The ranks on this machine share its memory: each holds its share of the points and of
  // the tangent, and every grid-sized vector whole.
  return on_this_machine * (base + share * points * per_point + my_cells * per_cell + nodes * per_node);
}

double bar_memory_estimate(double elements, int points_per_element, bool as_mpm) {
  return elements * ((as_mpm ? 800.0 : 300.0) + 450.0 * points_per_element);
}

}  // namespace gradmpm
