#pragma once
// Sizes checked before anything is allocated (issue 12, point 3): a case whose grid cannot
// be numbered in 32-bit dofs, or whose lower-bound memory estimate exceeds the memory the
// machine has available (MemAvailable; GRADMPM_MAX_MEMORY, in GiB, sets a lower limit), is
// refused with exit 2 and the estimate, before it is OOM-killed or fails with bad_alloc.
//
// The estimates are lower bounds from measured peaks (docs/reliability.md): they leave out
// the factorisation's fill-in, so a refused case could not have run, and a case that fits
// may still need more.
#include <cstdint>
#include <string>

#include "gradmpm/io/CaseFile.hpp"

namespace gradmpm {

/// Bytes the process may use: min(MemAvailable, GRADMPM_MAX_MEMORY GiB); 0 when unknown.
std::uint64_t memory_available();

/// InputError on `key` when `bytes` exceeds memory_available(); `what` says what the
/// estimate counts ("1.2e9 points, 3.4e9 dofs").
void require_memory(const CaseFile& cf, const std::string& key, double bytes, const std::string& what);

/// Lower bound of an MPM run's peak memory on this machine: points, grid nodes (dof map,
/// grid outputs) and the tangent's entries of the `cells` the bodies cover (GIMP couples 5
/// nodes per direction), no fill-in. A distributed run's `on_this_machine` ranks share the
/// machine, each with `share` of the points and the tangent (1 / ranks) and every grid node.
double mpm_memory_estimate(int dim, double points, double cells, double nodes, bool grid_output, double share = 1.0,
                           int on_this_machine = 1);

/// Lower bound of the 1D bar's peak memory (measured: 2.6 KB per element at 4 points per
/// element, 1.25 KB at 2; as MPM 2.9 KB at 2).
double bar_memory_estimate(double elements, int points_per_element, bool as_mpm);

}  // namespace gradmpm
