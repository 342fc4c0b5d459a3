// Requirements on the output folder of a run (io/RunFolder.hpp):
//  R1 a failed run does not mix with the previous one: its folder afterwards holds that
//     run's files only (its converged steps), none of the previous run's, and the user's
//     own files stay;
//  R2 a run killed with SIGKILL leaves the previous run's complete results (every file
//     byte for byte), and the next run removes what the killed one left and publishes;
//  R3 a second run on a folder in use is refused with exit 2, naming the other run;
//  R4 a folder holding folders of its own (such as `--out .`) is refused with exit 2;
//  R5 no temporary or staging file is left beside or inside the folder after a run;
//  R6 `--out LINK`, a symbolic link to a folder (out -> /scratch/run, as on clusters),
//     publishes in the link's target and leaves the link a link; a dangling link's target
//     is made; `--out LINK` and `--out TARGET` take one lock (a second run is refused);
//  R7 an empty --out or --restart is refused with exit 2 (never read as the default).
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <map>
#include <thread>

#include "CliTestUtil.hpp"

using namespace gradmpm::test;

namespace {
class RunFolderCli : public ScratchDirTest {
 protected:
  std::string column() const { return std::string(GRADMPM_SOURCE_DIR) + "/examples/column_2d.toml"; }
  fs::path out() const { return dir / "o"; }
  std::map<std::string, std::string> contents(const fs::path& d) const {
    std::map<std::string, std::string> m;
    for (const auto& e : fs::directory_iterator(d)) m[e.path().filename().string()] = slurp(e.path());
    return m;
  }
  /// Names beside the output folder other than the folder, stdout, stderr and the lock.
  std::vector<std::string> leftovers() const {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string n = e.path().filename().string();
      if (n != "o" && n != "stdout" && n != "stderr" && n != ".o.lock" && n != "pid") v.push_back(n);
    }
    return v;
  }
};
}  // namespace

TEST_F(RunFolderCli, AFailedRunReplacesThePreviousOneWholeAndKeepsTheUsersFiles) {
  ASSERT_EQ(run_gradmpm("run " + column() + " --out " + out().string() + " --set output.vtk_every=5").code, 0);
  ASSERT_TRUE(fs::exists(out() / "points_final.csv"));
  ASSERT_TRUE(fs::exists(out() / "points_0020.vtu"));
  std::ofstream(out() / "notes.txt") << "mine";
  const CliResult r = run_gradmpm("run " + column() + " --out " + out().string() +
                                  " --set nonlinear_solver.max_iterations=1 --set nonlinear_solver.max_cuts=0");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(fs::exists(out() / "points_0000.vtu")) << "the failed run's converged state is there";
  for (const char* old : {"points_final.csv", "points_0005.vtu", "points_0020.vtu", "column_check.csv", "column.png"})
    EXPECT_FALSE(fs::exists(out() / old)) << old << " is the previous run's";
  const std::string pvd = slurp(out() / "points.pvd");
  EXPECT_NE(pvd.find("points_0000.vtu"), std::string::npos);
  EXPECT_EQ(pvd.find("points_0005.vtu"), std::string::npos) << pvd;
  EXPECT_EQ(slurp(out() / "notes.txt"), "mine");
  EXPECT_TRUE(leftovers().empty()) << leftovers().front();
  for (const auto& e : fs::directory_iterator(out()))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

TEST_F(RunFolderCli, AKilledRunLeavesThePreviousResultsComplete) {
  ASSERT_EQ(run_gradmpm("run " + column() + " --out " + out().string() + " --set output.vtk_every=5").code, 0);
  const auto before = contents(out());
  // A long run (thousands of steps, VTK every step), killed once it has written some files.
  const std::string cmd = std::string(GRADMPM_EXE) + " run " + column() + " --out " + out().string() +
                          " --set load_steps.count=4000 --set output.vtk_every=1 >/dev/null 2>&1 & echo $! > " +
                          (dir / "pid").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  bool writing = false;
  for (int i = 0; i < 600 && !writing; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().filename().string().rfind(".o.staging-", 0) == 0 && fs::exists(e.path() / "points_0003.vtu"))
        writing = true;
  }
  const int pid = std::stoi(slurp(dir / "pid"));
  ::kill(pid, SIGKILL);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ASSERT_TRUE(writing) << "the long run never wrote its first steps";
  EXPECT_EQ(contents(out()), before) << "the previous results changed";
  EXPECT_FALSE(leftovers().empty()) << "the killed run's staging folder is beside";
  ASSERT_EQ(run_gradmpm("run " + column() + " --out " + out().string() + " --set output.vtk_every=10").code, 0);
  EXPECT_TRUE(leftovers().empty()) << leftovers().front();
  EXPECT_FALSE(fs::exists(out() / "points_0005.vtu")) << "a file of the first run";
  EXPECT_TRUE(fs::exists(out() / "points_0010.vtu"));
}

TEST_F(RunFolderCli, ASecondRunOnAFolderInUseIsRefused) {
  const std::string cmd = std::string(GRADMPM_EXE) + " run " + column() + " --out " + out().string() +
                          " --set load_steps.count=4000 --set output.vtk_every=0 >/dev/null 2>&1 & echo $! > " +
                          (dir / "pid").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const int pid = std::stoi(slurp(dir / "pid"));
  // Wait until the first run holds the folder (its staging folder exists).
  for (int i = 0; i < 500 && !fs::exists(dir / (".o.staging-" + std::to_string(pid))); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(fs::exists(dir / (".o.staging-" + std::to_string(pid))));
  const CliResult r = run_gradmpm("run " + column() + " --out " + out().string());
  ::kill(pid, SIGKILL);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("another gradmpm run (pid " + std::to_string(pid) + ") is writing this folder"),
            std::string::npos)
      << r.err;
}

TEST_F(RunFolderCli, AFolderOfFoldersIsRefused) {
  fs::create_directories(out() / "src");
  const CliResult r = run_gradmpm("run " + column() + " --out " + out().string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("holds the folder src, which gradmpm did not write"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_directory(out() / "src"));
}

TEST_F(RunFolderCli, ALinkAsOutPublishesInItsTargetAndKeepsTheLink) {
  fs::create_directories(dir / "scratch" / "run");
  fs::create_directory_symlink("scratch/run", out());
  const CliResult r = run_gradmpm("run " + column() + " -q --out " + out().string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(out())) << "the link was replaced";
  EXPECT_TRUE(fs::exists(dir / "scratch" / "run" / "points_final.csv"));
  // A dangling link: its target is made, and the results land there.
  fs::create_directory_symlink("scratch/later", dir / "dangling");
  const CliResult d = run_gradmpm("run " + column() + " -q --out " + (dir / "dangling").string());
  ASSERT_EQ(d.code, 0) << d.err;
  EXPECT_TRUE(fs::is_symlink(dir / "dangling"));
  EXPECT_TRUE(fs::exists(dir / "scratch" / "later" / "points_final.csv"));
}

TEST_F(RunFolderCli, ALinkAndItsTargetTakeOneLock) {
  fs::create_directories(dir / "scratch" / "run");
  fs::create_directory_symlink("scratch/run", out());
  const std::string cmd = std::string(GRADMPM_EXE) + " run " + column() + " --out " + out().string() +
                          " --set load_steps.count=4000 --set output.vtk_every=0 >/dev/null 2>&1 & echo $! > " +
                          (dir / "pid").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const int pid = std::stoi(slurp(dir / "pid"));
  const fs::path staging = dir / "scratch" / (".run.staging-" + std::to_string(pid));
  for (int i = 0; i < 500 && !fs::exists(staging); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(fs::exists(staging)) << "the first run stages beside the link's target";
  const CliResult r = run_gradmpm("run " + column() + " --out " + (dir / "scratch" / "run").string());
  ::kill(pid, SIGKILL);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("is writing this folder"), std::string::npos) << r.err;
}

TEST_F(RunFolderCli, AnEmptyOutOrRestartIsRefused) {
  for (const std::string opt : {"--out ''", "--restart ''"}) {
    const CliResult r = run_gradmpm("run " + column() + " " + opt);
    EXPECT_EQ(r.code, 2) << opt << "\n" << r.err;
    EXPECT_NE(r.err.find("expected a path, got an empty one"), std::string::npos) << r.err;
  }
}
