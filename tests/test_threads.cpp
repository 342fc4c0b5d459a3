// Requirements on threads:
//  R1 OpenMP's idle threads wait passively by default (spinning threads made small runs on
//     all cores 1.4-2.2 times slower, docs/performance.md); a user's OMP_WAIT_POLICY is kept;
//  R2 --threads N sets the threads of a run, and the answer does not depend on them
//     (points_final.csv byte for byte with 1 and 2 threads, on a case whose factorisations
//     are too small for the BLAS to split its work);
//  R2b where the BLAS (OpenBLAS) does split its products and factorisations among the
//     threads, its sums come in another order and the last bits move: 1 and 2 threads
//     agree to round-off as Newton's tolerance carries it (within 1e-6 relative; 1.3e-8
//     measured on a 2.3e4-dof footing), and a rerun with the same threads is byte for byte
//     the same (docs/reliability.md);
//  R3 --threads 0 is refused with exit 2.
// (The process tuning's other parts: test_tuning.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "CliTestUtil.hpp"

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
  expect_run_says("a", "env -u OMP_WAIT_POLICY -u GRADMPM_TUNING", "(OpenMP waiting passive)");
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
