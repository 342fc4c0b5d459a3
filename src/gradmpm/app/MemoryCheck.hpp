#pragma once
// Sizes checked before anything is allocated: a case whose grid cannot
// be numbered in 32-bit dofs, or whose memory estimate exceeds the memory the
// machine has available (MemAvailable; GRADMPM_MAX_MEMORY, in GiB, sets a lower limit), is
// refused with exit 2 and the estimate, before it is OOM-killed or fails with bad_alloc.
//
// The MPM estimate is fitted to measured peaks (docs/reliability.md) and a run prints it
// beside its own peak; the bar's is a lower bound.
#include <cstdint>
#include <string>

#include "gradmpm/io/CaseFile.hpp"

namespace gradmpm {

/// The process's peak resident memory so far (getrusage), in bytes.
double peak_resident_memory();

/// Bytes the process may use: min(MemAvailable, GRADMPM_MAX_MEMORY GiB); 0 when unknown.
std::uint64_t memory_available();

/// InputError on `key` when `bytes` exceeds memory_available(); `what` says what the
/// estimate counts ("1.2e9 points, 3.4e9 dofs"); `lower_bound`: the message says "at least",
/// not "about".
void require_memory(const CaseFile& cf, const std::string& key, double bytes, const std::string& what,
                    bool lower_bound = false);

/// An MPM run's peak memory on this machine: the program, the points, the tangent and its
/// factor over the `cells` the bodies cover, and the grid's nodes (their fields, the grid
/// VTU files). A distributed run's `on_this_machine` ranks share the machine, each with
/// `share` of the points and the tangent (1 / ranks) and every grid node.
double mpm_memory_estimate(int dim, double points, double cells, double nodes, bool grid_output, double share = 1.0,
                           int on_this_machine = 1);

/// Lower bound of the 1D bar's peak memory (measured: 2.6 KB per element at 4 points per
/// element, 1.25 KB at 2; as MPM 2.9 KB at 2).
double bar_memory_estimate(double elements, int points_per_element, bool as_mpm);

}  // namespace gradmpm
