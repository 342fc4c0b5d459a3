#pragma once
// Settings that libraries read once, when the program is loaded (before main): a program
// that wants them different sets their environment variables and executes itself again,
// once, first thing in main. A setting the user made (the variable or tunable already
// set) is always kept.
//
// - OMP_WAIT_POLICY=passive: GNU OpenMP's idle threads spin by default, which made runs on
//   a machine shared with other processes 10-25x slower than one thread.
// - GLIBC_TUNABLES glibc.malloc.hugetlb=1: glibc's malloc asks for transparent huge pages
//   (madvise) on the memory it maps. A load step allocates its arrays afresh (stencils,
//   pattern, per-point responses: 50 MB of stencils alone for 2e5 points in 2D), and on a
//   virtual machine whose freed memory goes back to the host each first touch of a 4 KiB
//   page costs about 20 us: 0.18-0.32 s per load step for the stencils of the 1e5-dof 2D
//   column after a PETSc solve, against 0.003 s on 2 MiB pages (docs/performance.md).
// - GLIBC_TUNABLES glibc.malloc.mmap_max=0 and glibc.malloc.trim_threshold=1 TiB: freed
//   memory stays in the process for the next load step's arrays instead of going back to
//   the system. glibc serves every block above 32 MiB (its largest mmap threshold) with a
//   fresh mapping and unmaps it when freed, so CHOLMOD's factor (109 MB at 1e5 dof in 2D)
//   came back on new pages at every load step, and on these virtual machines the first
//   touch of a page the host has taken back is what costs: the first factorisation after
//   each analysis took 0.48 s against 0.17 s for the next (0.22 s against 0.21 s with the
//   memory kept; docs/performance.md). The peak memory does not change (measured); the
//   process does not shrink after it.
#include <string>

namespace gradmpm {

/// glibc.malloc.trim_threshold when freed memory is kept: 1 TiB, more than any heap here.
inline constexpr const char* kKeptTrimThreshold = "1099511627776";

struct LoadTimeChoices {
  bool passive_openmp = true;  ///< OMP_WAIT_POLICY=passive unless the user set it
  bool huge_pages = true;      ///< glibc.malloc.hugetlb=1 unless the user's GLIBC_TUNABLES names it
  /// glibc.malloc.mmap_max=0 and glibc.malloc.trim_threshold=kKeptTrimThreshold unless the
  /// user set either (in GLIBC_TUNABLES, or as MALLOC_MMAP_MAX_ / MALLOC_TRIM_THRESHOLD_)
  bool keep_freed_memory = true;
};

/// Sets the variables the choices ask for and executes /proc/self/exe again with argv,
/// once (GRADMPM_LOAD_TIME_SET marks the second start); returns when nothing needs
/// setting or exec fails (the program goes on as it is). Call before MPI or threads start.
void set_load_time_environment(char** argv, LoadTimeChoices choices = {});

/// The value of glibc.malloc.`name` in GLIBC_TUNABLES ("" when not named), read as glibc
/// reads it (colon-separated name=value pairs, the last one named counts).
std::string malloc_tunable(const std::string& name);

/// The value of glibc.malloc.hugetlb in GLIBC_TUNABLES ("" when not set): "1" asks for
/// transparent huge pages by madvise, "0" not (glibc's default).
std::string malloc_hugetlb();

/// Whether GLIBC_TUNABLES keeps freed memory in the process: mmap_max 0 and a trim
/// threshold named.
bool malloc_keeps_freed_memory();

}  // namespace gradmpm
