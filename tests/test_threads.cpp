// Requirements on threads:
//  R1 OpenMP's idle threads wait passively by default (spinning made runs 10-25x slower on a
//     machine shared with other processes); a user's OMP_WAIT_POLICY is kept;
//  R2 --threads N sets the threads of a run, and the answer does not depend on them
//     (points_final.csv byte for byte with 1 and 2 threads, on a case whose factorisations
//     are too small for the BLAS to split its work);
//  R2b where the BLAS (OpenBLAS) does split its products and factorisations among the
//     threads, its sums come in another order and the last bits move: 1 and 2 threads
//     agree to round-off as Newton's tolerance carries it (within 1e-6 relative; 1.3e-8
//     measured on a 2.3e4-dof footing), and a rerun with the same threads is byte for byte
//     the same (docs/reliability.md);
//  R3 --threads 0 is refused with exit 2.
// and on the run's other load-time settings (core/LoadTimeEnvironment.hpp):
//  R4 glibc's malloc asks for transparent huge pages (glibc.malloc.hugetlb=1, added to the
//     user's GLIBC_TUNABLES) unless the user's GLIBC_TUNABLES names that tunable: first
//     touches of 4 KiB pages made a load step's allocations cost 0.2-0.3 s on this machine
//     kind (docs/performance.md);
//  R5 the tunable is read as glibc reads GLIBC_TUNABLES (colon-separated, last one wins);
//  R6 freed memory stays in the process (glibc.malloc.mmap_max=0 and a trim threshold of
//     1 TiB added to the user's GLIBC_TUNABLES) unless the user set either tunable (in
//     GLIBC_TUNABLES or by glibc's MALLOC_MMAP_MAX_ / MALLOC_TRIM_THRESHOLD_): memory given
//     back and touched again made the first factorisation of each load step 3 times slower
//     on this machine kind (docs/performance.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "CliTestUtil.hpp"
#include "gradmpm/core/LoadTimeEnvironment.hpp"

using namespace gradmpm::test;

namespace {
class Threads : public ScratchDirTest {
 protected:
  std::string footing() const {
    return std::string(GRADMPM_SOURCE_DIR) +
           "/examples/footing_tresca_2d.toml --set output.vtk_every=0 --set "
           "output.plot=false --set load_steps.count=10 "
           "--set 'constraints[3].displacement=[0.0,-0.05]'";
  }
  /// Runs the footing into dir/folder with `env` before the command: exit 0, and `says`
  /// in what the run prints (its first line names the load-time settings).
  void expect_run_says(const std::string& folder, const std::string& env, const std::string& says) const {
    const CliResult r = run_gradmpm("run " + footing() + " --out " + (dir / folder).string(), env);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find(says), std::string::npos) << r.out;
  }
};
}  // namespace

TEST_F(Threads, OpenMpWaitsPassivelyUnlessTheUserSaysOtherwise) {
  expect_run_says("a", "env -u OMP_WAIT_POLICY", "(OpenMP waiting passive)");
  expect_run_says("b", "OMP_WAIT_POLICY=active", "(OpenMP waiting active)");
}

TEST_F(Threads, TheAnswerDoesNotDependOnTheThreads) {
  CliResult one = run_gradmpm("run " + footing() + " --threads 1 --out " + (dir / "one").string());
  CliResult two = run_gradmpm("run " + footing() + " --threads 2 --out " + (dir / "two").string());
  ASSERT_EQ(one.code, 0) << one.err;
  ASSERT_EQ(two.code, 0) << two.err;
  EXPECT_NE(one.out.find(" 1 thread(s)"), std::string::npos) << one.out;
  EXPECT_NE(two.out.find(" 2 thread(s)"), std::string::npos) << two.out;
  const std::string a = slurp(dir / "one" / "points_final.csv"), b = slurp(dir / "two" / "points_final.csv");
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, b);
  EXPECT_EQ(slurp(dir / "one" / "reactions.csv"), slurp(dir / "two" / "reactions.csv"));
}

TEST_F(Threads, WhereTheBlasSplitsItsWorkTheThreadsMoveOnlyRoundOffAndARerunIsTheSame) {
  // examples/footing_2d.toml with cells a quarter as wide (2.3e4 dof), 4 load steps.
  const std::string footing_2d = std::string(GRADMPM_SOURCE_DIR) +
                                 "/examples/footing_2d.toml --set output.vtk_every=0 --set output.plot=false "
                                 "--set load_steps.count=4 --set 'grid.origin=[-0.03125,-0.0625]' "
                                 "--set grid.cell_size=0.03125 --set 'grid.cells=[140,80]' "
                                 "--set 'constraints[0].min=[-0.03125,-0.0625]' "
                                 "--set 'constraints[1].min=[-0.03125,-0.0625]' "
                                 "--set 'point_loads[0].min=[0.0,1.984375]' --set 'point_loads[0].force=[0.0,-3.75]'";
  const auto run = [&](int threads, const std::string& folder) {
    const CliResult r = run_gradmpm("run " + footing_2d + " --threads " + std::to_string(threads) + " --out " +
                                    (dir / folder).string());
    ASSERT_EQ(r.code, 0) << r.err;
  };
  run(1, "one");
  run(2, "two");
  run(2, "again");
  EXPECT_EQ(slurp(dir / "two" / "points_final.csv"), slurp(dir / "again" / "points_final.csv"));
  const auto one = csv_columns(dir / "one" / "points_final.csv"), two = csv_columns(dir / "two" / "points_final.csv");
  ASSERT_EQ(one.size(), two.size());
  for (const auto& [name, a] : one) {
    const std::vector<double>& b = two.at(name);
    ASSERT_EQ(a.size(), b.size()) << name;
    double scale = 0.0, gap = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) {
      scale = std::max(scale, std::abs(a[k]));
      gap = std::max(gap, std::abs(a[k] - b[k]));
    }
    EXPECT_LE(gap, 1e-6 * scale) << name;
  }
  EXPECT_GT(one.at("sxx").size(), 30000u);  // the case is the size it says (32768 points)
}

TEST_F(Threads, ZeroThreadsIsRefused) {
  const CliResult r = run_gradmpm("run " + footing() + " --threads 0 --out " + (dir / "z").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--threads"), std::string::npos) << r.err;
}

TEST_F(Threads, MallocAsksForHugePagesUnlessTheUserSaysOtherwise) {
  expect_run_says("h", "env -u GLIBC_TUNABLES", "), huge pages (glibc.malloc.hugetlb=1)");
  expect_run_says("o", "GLIBC_TUNABLES=glibc.malloc.hugetlb=0", "), no huge pages");
  // another tunable of the user's: hugetlb is added beside it
  expect_run_says("a", "GLIBC_TUNABLES=glibc.malloc.arena_max=2", "), huge pages (glibc.malloc.hugetlb=1)");
}

TEST_F(Threads, FreedMemoryIsKeptUnlessTheUserSaysOtherwise) {
  const std::string plain = "env -u GLIBC_TUNABLES -u MALLOC_MMAP_MAX_ -u MALLOC_TRIM_THRESHOLD_";
  expect_run_says("k", plain, "huge pages (glibc.malloc.hugetlb=1), freed memory kept (glibc.malloc.mmap_max=0)");
  expect_run_says("m", plain + " GLIBC_TUNABLES=glibc.malloc.mmap_max=65536", "), freed memory returned");
  expect_run_says("t", plain + " MALLOC_TRIM_THRESHOLD_=131072", "), freed memory returned");
  // the user's hugetlb choice and the kept memory go together
  expect_run_says("h", plain + " GLIBC_TUNABLES=glibc.malloc.hugetlb=0", "no huge pages, freed memory kept");
}

TEST(LoadTimeEnvironment, HugetlbIsReadAsGlibcReadsItsTunables) {
  const char* saved = std::getenv("GLIBC_TUNABLES");
  const std::string keep = saved ? saved : "";
  const auto read = [](const char* tunables) {
    ::setenv("GLIBC_TUNABLES", tunables, 1);
    return gradmpm::malloc_hugetlb();
  };
  EXPECT_EQ(read("glibc.malloc.hugetlb=1"), "1");
  EXPECT_EQ(read("glibc.malloc.arena_max=2:glibc.malloc.hugetlb=0"), "0");
  EXPECT_EQ(read("glibc.malloc.hugetlb=1:glibc.malloc.arena_max=2"), "1");
  EXPECT_EQ(read("glibc.malloc.hugetlb=1:glibc.malloc.hugetlb=0"), "0");  // the last one
  EXPECT_EQ(read("glibc.malloc.arena_max=2"), "");
  EXPECT_EQ(read("xglibc.malloc.hugetlb=1"), "");  // another name that ends the same
  EXPECT_EQ(read("glibc.malloc.arena_max=2"), "");
  EXPECT_EQ(gradmpm::malloc_tunable("arena_max"), "2");  // any tunable of malloc's
  const auto keeps = [](const char* tunables) {
    ::setenv("GLIBC_TUNABLES", tunables, 1);
    return gradmpm::malloc_keeps_freed_memory();
  };
  EXPECT_TRUE(keeps("glibc.malloc.hugetlb=1:glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=1099511627776"));
  EXPECT_FALSE(keeps("glibc.malloc.mmap_max=0"));  // the top of the heap would still be trimmed
  EXPECT_FALSE(keeps("glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=1:glibc.malloc.mmap_max=8"));
  ::unsetenv("GLIBC_TUNABLES");
  EXPECT_EQ(gradmpm::malloc_hugetlb(), "");
  EXPECT_FALSE(gradmpm::malloc_keeps_freed_memory());
  if (saved) ::setenv("GLIBC_TUNABLES", keep.c_str(), 1);
}
