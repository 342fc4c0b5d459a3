// Requirements on checkpoint and restart (app/Checkpoint.hpp):
//  R1 an archive read back from its HDF5 file is the archive written, bit for bit (NaN,
//     -0, subnormals, 1e308, integer extremes, texts with newlines and NUL bytes, empty
//     arrays);
//  R2 a damaged checkpoint (one flipped byte in an array, a truncated file) is refused
//     with exit 2, never read as other numbers;
//  R3 a run killed with SIGKILL after a checkpoint and restarted from it publishes the
//     uninterrupted run's outputs byte for byte: an elasto-plastic collapse with load
//     cuts (so the checkpoint's next increment is not the nominal one), indefinite
//     tangents, the ghost penalty and points moving through the grid (and so the
//     ordering the next step's analysis takes from the last: checked to be needed, R4
//     failed without it);
//  R4 the same with a gradient step that carries its fields at the points from step to
//     step (fields = points, u-RA and e-RA): points_gradient.csv is the uninterrupted one
//     (u-RA on this GIMP footing failed before: its consistent L2 projection is singular);
//  R5 a checkpoint of another case (naming the key that differs), another dimension,
//     another program version, a file that is not a gradmpm checkpoint, a missing one,
//     and --restart on a bar case are refused with exit 2 and a message saying which;
//  R6 only the last checkpoint_keep checkpoints stay, and a temporary left by a run
//     killed while writing one is removed by the next run;
//  R7 a restart on any number of ranks takes the points of a distributed run's point
//     files (each rank's, in its order) that lie in its cells: PointRows gathers the rows
//     kept from each file, of every per-point array (reals, integers, a stage's, several
//     values per point) and only those, in increasing id; a point in two files or an
//     array that does not hold the same number of values per point is refused.
//     (Restarts on other numbers of ranks: Mpi.CheckpointOfEachRanksPointsRestartsOnAnyNumberOfRanks.)
//  R8 a checkpoint records the run's threads, and a restart with other threads says that
//     it follows the uninterrupted run to round-off, not bit for bit (OpenBLAS splits its
//     sums by threads: tests/test_threads.cpp R2b); one with the same threads says nothing;
//  R3b the same for a dynamic run and an arc-length run (their own driver state);
//  R9 a checkpoint that cannot be written (the disk full: a file size limit here) stops
//     the run with exit 2 and one message, never a crash (HDF5 closed the failed file
//     again at exit: SIGSEGV), and leaves no part of itself in the checkpoint folder;
//  R10 --restart on a checkpoint whose checkpoint.h5 is not a regular file (a FIFO) is
//     refused with exit 2 at once, never blocks;
//  R11 a checkpoint whose outputs/ lacks a file it recorded, or holds one of another size
//     or with one flipped bit, is refused with exit 2 naming the file: a restart never
//     publishes incomplete outputs;
//  R12 the last step is checkpointed when checkpoint_every divides it, and a restart from
//     that checkpoint publishes the uninterrupted run's outputs;
//  R13 a restart whose case spells out a default (density = 0 where the case gives none)
//     or writes a number otherwise (1.0e-9 for 1e-9, 40.0 for 40) is the same case.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <thread>

#include "CliTestUtil.hpp"
#include "gradmpm/app/Checkpoint.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/io/Hdf5Archive.hpp"

using namespace gradmpm;
using namespace gradmpm::test;

namespace {

std::string example(const std::string& name) { return std::string(GRADMPM_SOURCE_DIR) + "/examples/" + name; }

std::map<std::string, std::string> files_of(const fs::path& d) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(d))
    if (e.path().extension() != ".png" && !e.path().filename().string().starts_with("."))  // not the manifest (pid)
      m[e.path().filename().string()] = slurp(e.path());
  return m;
}

/// The first file that differs between two output folders ("" when every file is equal).
std::string first_difference(const fs::path& a, const fs::path& b) {
  const auto fa = files_of(a), fb = files_of(b);
  for (const auto& [name, content] : fa) {
    const auto it = fb.find(name);
    if (it == fb.end()) return name + " is missing";
    if (it->second != content) return name + " differs";
  }
  if (fa.size() != fb.size()) return "a file too many";
  return "";
}

using CheckpointCli = ScratchDirTest;
using Hdf5ArchiveTest = ScratchDirTest;

}  // namespace

TEST_F(Hdf5ArchiveTest, ReadsBackWhatWasWrittenBitForBit) {
  Archive a;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> reals = {0.1, -0.0, 1e308, std::numeric_limits<double>::denorm_min(), nan, -7.25};
  const std::vector<long long> ints = {std::numeric_limits<long long>::min(), -1, 0,
                                       std::numeric_limits<long long>::max()};
  const std::string text = std::string("line 1\nline 2\n") + '\0' + "after a NUL";
  a.put("group/reals", reals);
  a.put("group/sub/integers", ints);
  a.put_text("text", text);
  a.put("empty", std::vector<double>{});
  a.put_text("empty_text", "");
  write_hdf5_archive(dir / "a.h5", a);
  const Archive b = read_hdf5_archive(dir / "a.h5");
  const auto& r = b.reals("group/reals", 6);
  for (std::size_t i = 0; i < reals.size(); ++i)
    EXPECT_EQ(std::memcmp(&r[i], &reals[i], sizeof(double)), 0) << "value " << i;
  EXPECT_EQ(b.integers("group/sub/integers"), ints);
  EXPECT_EQ(b.text("text"), text);
  EXPECT_TRUE(b.reals("empty").empty());
  EXPECT_EQ(b.text("empty_text"), "");
  try {
    (void)b.reals("group/reals", 7);
    ADD_FAILURE() << "a short array was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'group/reals' holds 6 values, expected 7"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)b.reals("nothing"), InputError);
}

namespace {
/// A point file of the points `ids` (in that order): per point a real pair (10 id, 10 id
/// + 1), an integer (-id) and a stage's real (id / 2), and arrays that are not per point.
Archive point_file(const std::vector<long long>& ids) {
  Archive a;
  std::vector<double> pair, half;
  std::vector<long long> minus;
  for (const long long id : ids) {
    pair.insert(pair.end(), {10.0 * id, 10.0 * id + 1.0});
    minus.push_back(-id);
    half.push_back(0.5 * id);
  }
  a.put_integer("points/count", static_cast<long long>(ids.size()));
  a.put("points/id", ids);
  a.put("points/position", pair);
  a.put("points/material", minus);
  a.put("stage/field", half);
  a.put("driver/load_factor", std::vector<double>{0.25, 0.5, 0.75});  // not a per-point array
  return a;
}
}  // namespace

TEST(PointRows, GathersTheKeptPointsOfEveryFileInIdOrder) {
  PointRows rows({"points/", "stage/"});
  rows.add(point_file({1, 4, 6}), {1, 0, 1});
  rows.add(point_file({0, 2, 3, 7}), {0, 1, 1, 1});
  rows.add(point_file({}), {});  // a rank that owned no point
  rows.add(point_file({5, 8}), {0, 0});
  EXPECT_EQ(rows.count(), 5);
  const Archive a = rows.take("test");
  const std::vector<long long> ids = {1, 2, 3, 6, 7};
  EXPECT_EQ(a.integer("points/count"), 5);
  EXPECT_EQ(a.integers("points/id"), ids);
  const Archive expected = point_file(ids);  // the kept points' rows, made in id order
  EXPECT_EQ(a.reals("points/position"), expected.reals("points/position"));
  EXPECT_EQ(a.integers("points/material"), expected.integers("points/material"));
  EXPECT_EQ(a.reals("stage/field"), expected.reals("stage/field"));
  EXPECT_FALSE(a.has("driver/load_factor"));
}

TEST(PointRows, APointInTwoFilesOrAnUnevenArrayIsRefused) {
  PointRows twice({"points/"});
  twice.add(point_file({0, 1}), {1, 1});
  twice.add(point_file({1, 2}), {1, 1});
  try {
    (void)twice.take("ck");
    ADD_FAILURE() << "a point kept twice was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ck: point 1 is there twice"), std::string::npos) << e.what();
  }
  Archive uneven = point_file({0, 1});
  uneven.put("points/volume", std::vector<double>{1.0, 2.0, 3.0});
  PointRows rows({"points/"});
  try {
    rows.add(uneven, {1, 1});
    ADD_FAILURE() << "3 values for 2 points were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'points/volume' holds 3 values"), std::string::npos) << e.what();
  }
}

TEST_F(Hdf5ArchiveTest, ADamagedOrTruncatedFileIsRefused) {
  Archive a;
  a.put("data", std::vector<double>(4096, 1234.5678));
  write_hdf5_archive(dir / "a.h5", a);
  std::string bytes = slurp(dir / "a.h5");
  const double v = 1234.5678;
  const std::string pattern(reinterpret_cast<const char*>(&v), sizeof v);
  const auto at = bytes.find(pattern + pattern);
  ASSERT_NE(at, std::string::npos) << "the array is not stored as it is";
  bytes[at + 1000 * sizeof v + 3] ^= 0x10;  // one bit inside the array
  std::ofstream(dir / "flipped.h5", std::ios::binary) << bytes;
  try {
    (void)read_hdf5_archive(dir / "flipped.h5");
    ADD_FAILURE() << "a flipped bit was read as data";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("checksum mismatch"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "short.h5", std::ios::binary) << slurp(dir / "a.h5").substr(0, 20000);
  EXPECT_THROW((void)read_hdf5_archive(dir / "short.h5"), InputError);
}

TEST_F(CheckpointCli, AKilledRunRestartedFromItsCheckpointEndsAsTheUninterruptedRun) {
  // The vertical cut of AMPLE in 20 nominal steps: steps 13, 15, 17, ... need a cut.
  const std::string args = "run " + example("vertical_cut_2d.toml") +
                           " --set load_steps.count=20 --set output.checkpoint_every=3 --set output.checkpoint_keep=0";
  const fs::path whole = dir / "whole", killed = dir / "killed";
  const CliResult r = run_gradmpm(args + " --out " + whole.string());
  ASSERT_EQ(r.code, 0) << r.err;
  // (how many iterations step 15 takes is round-off's: the ordering the solver took)
  const auto line15 = r.out.find("step   15  load 0.6750  iterations");
  ASSERT_NE(line15, std::string::npos) << "the case changed";
  ASSERT_NE(r.out.substr(line15, r.out.find('\n', line15) - line15).find("cuts 1"), std::string::npos)
      << "step 15 must need a cut";
  // The same run, killed by SIGKILL once it has written the checkpoint of step 15.
  const std::string cmd = std::string(GRADMPM_EXE) + " " + args + " --out " + killed.string() +
                          " >/dev/null 2>&1 & echo $! > " + (dir / "pid").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const fs::path checkpoint = dir / "killed.checkpoints" / "step_000015";
  for (int i = 0; i < 3000 && !fs::exists(checkpoint); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ::kill(std::stoi(slurp(dir / "pid")), SIGKILL);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ASSERT_TRUE(fs::exists(checkpoint / "checkpoint.h5"));
  ASSERT_FALSE(fs::exists(killed)) << "the killed run published its folder";
  const CliResult again = run_gradmpm(args + " --out " + killed.string() + " --restart " + checkpoint.string());
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.out.find("restarting from"), std::string::npos);
  EXPECT_EQ(again.out.find("step   15 "), std::string::npos) << "step 15 was solved again";
  EXPECT_EQ(first_difference(whole, killed), "");
  // Every output but load_displacement.png (a plot of reactions.csv): 7 files, and a
  // points and a grid VTU file at step 0, every 5th step and the last. How many steps the
  // collapse takes depends on its cuts, which round-off in the BLAS decides past step 15.
  const auto done = r.out.find("done: ");
  ASSERT_NE(done, std::string::npos) << r.out;
  int steps = 0;
  ASSERT_EQ(std::sscanf(r.out.c_str() + done, "done: %d steps", &steps), 1) << r.out;
  const std::size_t vtk = static_cast<std::size_t>(steps / 5 + 1 + (steps % 5 != 0));
  EXPECT_EQ(files_of(whole).size(), 7 + 2 * vtk) << steps << " steps";
}

TEST_F(CheckpointCli, TheGradientFieldsCarriedAtThePointsContinueBitForBit) {
  for (const char* variant : {"u-RA", "e-RA"}) {
    const std::string args = "run " + example("footing_2d.toml") + " -q --set gradient.variant=" + variant +
                             " --set gradient.length_scale=0.3 --set output.checkpoint_every=7";
    ASSERT_EQ(run_gradmpm(args + " --out " + (dir / "whole").string()).code, 0);
    const std::string from = (dir / "whole.checkpoints" / "step_000028").string();
    const CliResult r = run_gradmpm(args + " --out " + (dir / "restarted").string() + " --restart " + from);
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_TRUE(fs::exists(dir / "whole" / "points_gradient.csv"));
    EXPECT_EQ(first_difference(dir / "whole", dir / "restarted"), "") << variant;
  }
}

TEST_F(CheckpointCli, DynamicArcLengthAndConsolidationRunsContinueBitForBit) {
  // A dynamic run (the points' velocity and acceleration, the time, the peak kinetic
  // energy), an arc-length run (the arc, its cap, the last increment at the grid nodes)
  // and a consolidation run (the points' pore pressure) restarted from a checkpoint
  // publish the uninterrupted run's outputs.
  const std::vector<std::pair<std::string, std::string>> cases = {
      {example("vertical_cut_dynamic_2d.toml") + " --set time.end_time=0.4", "step_000010"},
      {example("softening_bar_arclength_1d.toml"), "step_000020"},
      {example("consolidation_1d.toml") + " --set time.end_time=0.04", "step_000020"}};
  for (const auto& [what, at] : cases) {
    const std::string args = "run " + what + " -q --set output.checkpoint_every=10 --set output.checkpoint_keep=0";
    ASSERT_EQ(run_gradmpm(args + " --out " + (dir / "whole").string()).code, 0) << what;
    const std::string from = (dir / "whole.checkpoints" / at).string();
    const CliResult r = run_gradmpm(args + " --out " + (dir / "restarted").string() + " --restart " + from);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(first_difference(dir / "whole", dir / "restarted"), "") << what;
    fs::remove_all(dir / "whole");
    fs::remove_all(dir / "whole.checkpoints");
    fs::remove_all(dir / "restarted");
  }
}

TEST_F(CheckpointCli, ARestartWithOtherThreadsSaysItContinuesToRoundOffOnly) {
  const std::string args = "run " + example("footing_2d.toml") + " --set output.checkpoint_every=10";
  ASSERT_EQ(run_gradmpm(args + " -q --threads 2 --out " + (dir / "a").string()).code, 0);
  const std::string from = " --restart " + (dir / "a.checkpoints" / "step_000030").string();
  const CliResult other = run_gradmpm(args + " --threads 1 --out " + (dir / "one").string() + from);
  ASSERT_EQ(other.code, 0) << other.err;
  EXPECT_NE(other.out.find("written with 2 thread(s), this run has 1: the answer follows the uninterrupted run's to "
                           "round-off, not bit for bit"),
            std::string::npos)
      << other.out;
  const CliResult same = run_gradmpm(args + " --threads 2 --out " + (dir / "two").string() + from);
  ASSERT_EQ(same.code, 0) << same.err;
  EXPECT_NE(same.out.find("restarting from"), std::string::npos) << same.out;
  EXPECT_EQ(same.out.find("thread(s), this run has"), std::string::npos) << same.out;
  EXPECT_EQ(first_difference(dir / "a", dir / "two"), "");
}

TEST_F(CheckpointCli, ACheckpointOfAnotherCaseVersionOrKindIsRefused) {
  const std::string footing = "run " + example("footing_2d.toml") + " -q --set output.checkpoint_every=10";
  ASSERT_EQ(run_gradmpm(footing + " --out " + (dir / "a").string()).code, 0);
  const fs::path ck = dir / "a.checkpoints" / "step_000030";
  auto refused = [&](const std::string& args, const std::string& fragment) {
    const CliResult r = run_gradmpm(args + " --out " + (dir / "b").string());
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << r.err;
  };
  refused(footing + " --set nonlinear_solver.tolerance=1e-8 --restart " + ck.string(),
          "written for another case (nonlinear_solver.tolerance: the default in the checkpoint, 1e-08 in this run)");
  refused("run " + example("column_1d.toml") + " --restart " + ck.string(), "a 2D checkpoint; this case is 1D");
  refused("run " + example("bar_bimaterial.toml") + " --restart " + ck.string(), "is a 1D bar case");
  refused(footing + " --restart " + (dir / "none").string(), "no such checkpoint");
  // Another version: the same checkpoint as an older program would have written it.
  Archive a = read_hdf5_archive(ck / "checkpoint.h5");
  a.put_text("program", "gradmpm 0.0.9");
  write_hdf5_archive(dir / "old.h5", a);
  fs::create_directories(dir / "outputs");
  refused(footing + " --restart " + (dir / "old.h5").string(), "written by gradmpm 0.0.9");
  Archive other;
  other.put_real("x", 1.0);
  write_hdf5_archive(dir / "other.h5", other);
  refused(footing + " --restart " + (dir / "other.h5").string(), "not a gradmpm checkpoint");
  std::ofstream(dir / "text.h5") << "not HDF5";
  refused(footing + " --restart " + (dir / "text.h5").string(), "not a readable HDF5 checkpoint");
}

TEST_F(CheckpointCli, OnlyTheLatestCheckpointsStayAndStaleTemporariesGo) {
  fs::create_directories(dir / "a.checkpoints" / ".step_000003.tmp-99999");
  const CliResult r =
      run_gradmpm("run " + example("footing_2d.toml") +
                  " --set output.checkpoint_every=4 --set output.checkpoint_keep=3 --out " + (dir / "a").string());
  ASSERT_EQ(r.code, 0) << r.err;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir / "a.checkpoints")) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"step_000032", "step_000036", "step_000040"}));
  EXPECT_NE(r.out.find("checkpoint " + (dir / "a").string() + ".checkpoints/step_000040"), std::string::npos) << r.out;
}

TEST_F(CheckpointCli, TheLastStepIsCheckpointedAndARestartFromItPublishesTheRun) {
  const std::string args = "run " + example("footing_2d.toml") + " -q --set output.checkpoint_every=10";
  ASSERT_EQ(run_gradmpm(args + " --out " + (dir / "a").string()).code, 0);
  const fs::path last = dir / "a.checkpoints" / "step_000040";
  ASSERT_TRUE(fs::exists(last / "checkpoint.h5")) << "40 steps, a checkpoint every 10: none at step 40";
  const CliResult r = run_gradmpm(args + " --out " + (dir / "b").string() + " --restart " + last.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(first_difference(dir / "a", dir / "b"), "");
}

TEST_F(CheckpointCli, ACheckpointWhoseOutputsAreIncompleteOrChangedIsRefused) {
  const std::string args = "run " + example("footing_2d.toml") + " -q --set output.checkpoint_every=10 --set output.checkpoint_keep=0";
  ASSERT_EQ(run_gradmpm(args + " --out " + (dir / "a").string()).code, 0);
  auto refused = [&](int step, const std::string& fragment) {
    const std::string from = (dir / "a.checkpoints" / fmt::format("step_{:06d}", step)).string();
    const CliResult r = run_gradmpm(args + " --out " + (dir / "b").string() + " --restart " + from);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "b"));
  };
  // Each damage in its own checkpoint (the outputs are hard links: a file changed in one
  // is changed in every checkpoint that holds it, and in the run's folder).
  fs::remove(dir / "a.checkpoints" / "step_000010" / "outputs" / "points_0010.vtu");
  refused(10, "its outputs/points_0010.vtu is missing");
  const fs::path energy = dir / "a.checkpoints" / "step_000020" / "outputs" / "energy.csv";
  std::string text = slurp(energy);
  fs::remove(energy);  // (a file of its own, not the link)
  std::ofstream(energy, std::ios::binary) << text.substr(0, text.size() - 1);
  refused(20, "its outputs/energy.csv has " + std::to_string(text.size() - 1) + " bytes, the checkpoint recorded " +
                  std::to_string(text.size()));
  const fs::path grid = dir / "a.checkpoints" / "step_000030" / "outputs" / "grid_0030.vtu";
  text = slurp(grid);
  text[text.size() / 2] ^= 1;  // one flipped bit, the size kept
  fs::remove(grid);
  std::ofstream(grid, std::ios::binary) << text;
  refused(30, "its outputs/grid_0030.vtu is not the file the checkpoint recorded: its CRC-32 differs");
  // The undamaged checkpoint still restarts.
  const std::string from = (dir / "a.checkpoints" / "step_000040").string();
  EXPECT_EQ(run_gradmpm(args + " --out " + (dir / "c").string() + " --restart " + from).code, 0);
}

TEST_F(CheckpointCli, ACaseThatSpellsOutADefaultOrWritesANumberOtherwiseIsTheSameCase) {
  const std::string args = "run " + example("column_2d.toml") + " -q --set output.plot=false --set output.checkpoint_every=10";
  ASSERT_EQ(run_gradmpm(args + " --out " + (dir / "a").string()).code, 0);
  const std::string from = (dir / "a.checkpoints" / "step_000010").string();
  // the tolerance and checkpoint_keep at their defaults, which column_2d does not give, and
  // density 1 for its 1.0
  const CliResult r = run_gradmpm(args + " --set output.checkpoint_keep=2 --set nonlinear_solver.tolerance=1.0e-9" +
                                  " --set materials.soil.density=1 --set 'loads.gravity=[0, -10]'" +
                                  " --out " + (dir / "b").string() + " --restart " + from);
  EXPECT_EQ(r.code, 0) << r.err;
  const CliResult other = run_gradmpm(args + " --set output.checkpoint_keep=3 --out " + (dir / "c").string() + " --restart " + from);
  EXPECT_EQ(other.code, 2) << other.err;
  EXPECT_NE(other.err.find("output.checkpoint_keep: the default in the checkpoint, 3 in this run"), std::string::npos) << other.err;
}

TEST_F(CheckpointCli, ACheckpointOnAFullDiskStopsTheRunWithOneMessageAndLeavesNoPartOfIt) {
  // A file size limit of 30 KiB (the column's checkpoint is about 47 KiB, its other files
  // a few): writes beyond it fail with EFBIG as on a full disk (SIGXFSZ ignored).
  const CliResult r =
      run_gradmpm("run " + example("column_2d.toml") +
                      " -q --set output.checkpoint_every=1 --set output.plot=false --out " + (dir / "a").string(),
                  "trap '' XFSZ; ulimit -f 30;");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("cannot write the checkpoint file"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "a")) << "a refused run publishes nothing";
  for (const auto& e : fs::directory_iterator(dir / "a.checkpoints"))
    ADD_FAILURE() << "left in the checkpoint folder: " << e.path().filename();
}

TEST_F(CheckpointCli, ARestartFromAFifoIsRefusedAtOnce) {
  fs::create_directories(dir / "ck" / "outputs");
  ASSERT_EQ(::mkfifo((dir / "ck" / "checkpoint.h5").c_str(), 0644), 0);
  const CliResult r = run_gradmpm(
      "run " + example("column_2d.toml") + " -q --out " + (dir / "a").string() + " --restart " + (dir / "ck").string(),
      "timeout 20");
  EXPECT_EQ(r.code, 2) << "124: it blocked\n" << r.err;
  EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
}
