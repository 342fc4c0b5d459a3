#pragma once
// Process tuning: what gradmpm's executables (gradmpm, bench_mpm) set in the runtimes under
// them, all in this module, which only executables link: libgradmpm acts on no runtime by
// itself (core/PlatformHooks.hpp), so any other program that links it gets the runtimes'
// defaults. The parts, each kept because it gained at least 10 % of a Newton iteration's
// wall time (docs/performance.md, "Process tuning", with the figures):
//   wait     OpenMP's idle threads wait passively (OMP_WAIT_POLICY=passive unless the
//            user set it): small and medium runs on all cores wait on threads that spin;
//   memory   freed memory stays in the process for the next load step (mallopt: no
//            block gets a mapping of its own, the heap is never trimmed) unless the user
//            set malloc's thresholds: memory given back and touched again costs page
//            faults, which a virtual machine makes dear;
//   regions  OpenMP regions of one thread run as plain calls in CHOLMOD's factorisation
//            (tuning/SerialOpenMpRegions.hpp): libgomp spends a system call on each;
//   blas     the BLAS (OpenBLAS, found at run time) gets the run's threads under CHOLMOD,
//            whose own regions then run serially (solver/linear/Cholmod.cpp).
// Off with `--no-tuning` on the command line or GRADMPM_TUNING=0; GRADMPM_TUNING=a,b keeps
// only the parts named (to measure them one by one: scripts/bench-tuning).
// The decision is made from the executable's .preinit_array, before any shared library's
// initialiser runs, and every part is set from inside the process: libgomp reads the
// waiting policy through the executable's getenv (ProcessTuning.cpp says why). No second
// exec, nothing set in the environment. (Measured and not kept: malloc on transparent huge
// pages, which only GLIBC_TUNABLES can ask for: docs/performance.md.)
#include <string>

namespace gradmpm::tuning {

struct Parts {
  bool wait = false;
  bool memory = false;
  bool regions = false;
  bool blas = false;
  bool operator==(const Parts&) const = default;
};

/// Every part.
constexpr Parts kAllParts{true, true, true, true};

/// GRADMPM_TUNING's value read: "" (unset), "1", "on" or "all": every part; "0", "off" or
/// "none": none; else a comma-separated list of part names. Throws std::invalid_argument
/// saying what is expected.
Parts parse(const std::string& value);

/// The parts on in this process (decided before main, from GRADMPM_TUNING and --no-tuning).
Parts parts();

/// What is on, for the run's first line: "tuning: OpenMP waiting passive, ..." or
/// "tuning off (--no-tuning)".
std::string summary();

}  // namespace gradmpm::tuning
