#pragma once
// Settings that libraries read once, when the program is loaded (before main): a program
// that wants them different sets their environment variables and executes itself again,
// once, first thing in main. A setting the user made (the variable or tunable already
// set) is always kept.
//
// - OMP_WAIT_POLICY=passive: GNU OpenMP's idle threads spin by default, which made runs on
//   a machine shared with other processes 10-25x slower than one thread (issue 12).
// - GLIBC_TUNABLES glibc.malloc.hugetlb=1: glibc's malloc asks for transparent huge pages
//   (madvise) on the memory it maps. A load step allocates its arrays afresh (stencils,
//   pattern, per-point responses: 50 MB of stencils alone for 2e5 points in 2D), and on a
//   virtual machine whose freed memory goes back to the host each first touch of a 4 KiB
//   page costs about 20 us: 0.18-0.32 s per load step for the stencils of the 1e5-dof 2D
//   column after a PETSc solve, against 0.003 s on 2 MiB pages (docs/performance.md).
#include <string>

namespace gradmpm {

struct LoadTimeChoices {
  bool passive_openmp = true;  ///< OMP_WAIT_POLICY=passive unless the user set it
  bool huge_pages = true;      ///< glibc.malloc.hugetlb=1 unless the user's GLIBC_TUNABLES names it
};

/// Sets the variables the choices ask for and executes /proc/self/exe again with argv,
/// once (GRADMPM_LOAD_TIME_SET marks the second start); returns when nothing needs
/// setting or exec fails (the program goes on as it is). Call before MPI or threads start.
void set_load_time_environment(char** argv, LoadTimeChoices choices = {});

/// The value of glibc.malloc.hugetlb in GLIBC_TUNABLES ("" when not set): "1" asks for
/// transparent huge pages by madvise, "0" not (glibc's default).
std::string malloc_hugetlb();

}  // namespace gradmpm
