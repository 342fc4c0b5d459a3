// Requirements on the command line (runs the real gradmpm binary):
//  - `gradmpm run CASE --out DIR` writes bar.csv (with the documented columns),
//    bar_points.csv and bar.png;
//  - every bad input exits with code 2 and a one-line message naming file, key and
//    expectation; an unwritable output path too;
//  - outputs appear whole or not at all: a failure leaves earlier files untouched and no
//    temporaries behind;
//  - the 1D bar case started as several MPI ranks (mpirun -n 2) is refused with exit 2 and
//    one message, before it writes anything (MPM cases run distributed: tests/mpi/).
#include <gtest/gtest.h>

#include "CliTestUtil.hpp"

using namespace gradmpm::test;

namespace {
using Result = CliResult;

class Cli : public ScratchDirTest {
 protected:
  Result run(const std::string& args, const std::string& env = "") { return run_gradmpm(args, env); }
  std::string example() const { return std::string(GRADMPM_SOURCE_DIR) + "/examples/bar_bimaterial.toml"; }
};

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}
}  // namespace

TEST_F(Cli, RunWritesCsvAndPlot) {
  const Result r = run("run " + example() + " --out " + (dir / "o").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = slurp(dir / "o" / "bar.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "x,u_classical,u_gradient,strain_classical,strain_gradient,stress_classical,stress_gradient,u_exact,"
            "strain_exact");
  EXPECT_EQ(count_lines(csv), 1 + 81);
  EXPECT_EQ(count_lines(slurp(dir / "o" / "bar_points.csv")), 1 + 160);
  EXPECT_EQ(slurp(dir / "o" / "bar.png").substr(1, 3), "PNG");
  EXPECT_NE(r.out.find("max relative error"), std::string::npos);
}

TEST_F(Cli, HelpExplainsTheCommands) {
  Result r = run("--help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("run"), std::string::npos);
  r = run("run --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--set"), std::string::npos);
  EXPECT_NE(r.out.find("--out"), std::string::npos);
}

TEST_F(Cli, BadInputExitsWithCode2AndOneLine) {
  std::ofstream(dir / "broken.toml") << "[bar]\nlength = = 1\n";
  std::ofstream(dir / "nobar.toml") << "[mesh]\ncells = 3\n";
  std::ofstream(dir / "mpm.toml") << "[grid]\norigin = [0.0]\ncell_size = 1.0\ncells = [4]\n"
                                     "[materials.a]\nmodel = \"hencky\"\nyoung = 1.0\n"
                                     "[[bodies]]\nmaterial = \"b\"\nmin = [0.0]\nmax = [2.0]\n"
                                     "[load_steps]\ncount = 2\n";
  std::ofstream(dir / "a_file") << "x";
  const std::string ex = example();
  const std::string o = " --out " + (dir / "o").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"run " + (dir / "missing.toml").string(), "cannot open case file"},
      {"run " + (dir / "broken.toml").string(), "broken.toml:2:"},
      {"run " + (dir / "nobar.toml").string(), "no problem section found; expected [bar] (1D bar) or [grid] (MPM)"},
      {"run " + ex + o + " --set bar.lenght=3", "bar.lenght (from --set): unknown key"},
      {"run " + ex + o + " --set bar.length=-1", "bar.length (from --set): expected a length > 0, got -1"},
      {"run " + ex + o + " --set bar.elements=0", "bar.elements (from --set): expected an integer from 1"},
      {"run " + ex + o + " --set bar.elements=8.5", "bar.elements (from --set): expected an integer, got 8.5"},
      {"run " + ex + o + " --set gradient.length_scale=-1", "expected a length scale l >= 0"},
      {"run " + ex + o + " --set bar.split=1", "expected a fraction of the length strictly between 0 and 1"},
      {"run " + ex + o + " --set bar.split=0", "expected a fraction of the length strictly between 0 and 1"},
      {"run " + ex + o + " --set gradient.variant=x", "expected one of"},
      {"run " + ex + o + " --set bar.young=[1]", "expected an array of 2 numbers"},
      {"run " + ex + o + " --set bar.length=abc", "expected a number, got \"abc\""},
      {"run " + ex + " --out " + (dir / "a_file" / "sub").string(), "cannot create output directory"},
      {"run " + ex + o + " --set nokey", "expected section.key=value"},
      {"run " + (dir / "mpm.toml").string() + o,
       "bodies[0].material: expected the name of a [materials.NAME] section (one of: a)"},
      {"run " + (dir / "mpm.toml").string() + o + " --set bodies[0].material=a --set bodies[0].max=[5.0]",
       "bodies[0].max (from --set): expected a body inside the grid"},
      {"run " + (dir / "mpm.toml").string() + o + " --set bodies[0].material=a --set load_steps.count=0",
       "load_steps.count (from --set): expected an integer from 1"},
      {"run " + (dir / "mpm.toml").string() + o + " --set bodies[0].material=a --set materials.a.poisson=0.5",
       "materials.a.poisson (from --set): expected a Poisson's ratio in (-1, 0.5)"},
      {"run " + (dir / "mpm.toml").string() + o + " --set bodies[3].material=a", "bodies has no entry [3]"},
      {"run", "case is required"},
      {"run " + ex + " --bogus", "--bogus"},
      {"", "A subcommand is required"},
  };
  for (const auto& [args, message] : cases) {
    const Result r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << "\nstderr: " << r.err;
    EXPECT_NE(r.err.find("gradmpm: error: "), std::string::npos) << args;
    if (r.err.find("--help") == std::string::npos) EXPECT_EQ(count_lines(r.err), 1) << args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(dir / "o" / "bar.csv")) << args;
  }
}

TEST_F(Cli, FailedRunLeavesEarlierOutputsUntouched) {
  fs::create_directories(dir / "o");
  std::ofstream(dir / "o" / "bar.csv") << "old";
  // A plotting interpreter that fails: the run must fail as a whole.
  const Result r = run("run " + example() + " --out " + (dir / "o").string(), "GRADMPM_PYTHON=/bin/false");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("plotting with /bin/false failed"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir / "o" / "bar.csv"), "old");
  EXPECT_FALSE(fs::exists(dir / "o" / "bar_points.csv"));
  EXPECT_FALSE(fs::exists(dir / "o" / "bar.png"));
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir / "o")) ++files;
  EXPECT_EQ(files, 1) << "no temporary files are left behind";
}

TEST_F(Cli, PlotCanBeSwitchedOff) {
  const Result r = run("run " + example() + " --out " + (dir / "o").string() + " --set output.plot=false");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "o" / "bar.csv"));
  EXPECT_FALSE(fs::exists(dir / "o" / "bar.png"));
}

TEST_F(Cli, TheBarStartedAsSeveralMpiRanksIsRefusedOnceAndWritesNothing) {
  const std::string out = (dir / "out").string();
  // One rank (the launcher's variables saying so) is a plain run.
  Result r = run("run " + example() + " --out " + out + " --quiet", "OMPI_COMM_WORLD_SIZE=1 OMPI_COMM_WORLD_RANK=0");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(fs::path(out) / "bar.csv"));
  fs::remove_all(out);
  // MPM cases run distributed (tests/mpi/); the 1D bar does not: rank 0 says so, once.
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "no mpirun on this machine";
#ifdef __SANITIZE_ADDRESS__
  // Open MPI is not built for the sanitizers (its own allocations read as leaks at exit);
  // the distributed runs are tested in the plain build (Mpi.*, tests/mpi/).
  GTEST_SKIP() << "MPI is not run under AddressSanitizer";
#endif
  r = run("run " + example() + " --out " + out, "mpirun --allow-run-as-root --oversubscribe -n 2");
  EXPECT_EQ(r.code, 2) << r.err;
#ifdef GRADMPM_WITH_PETSC
  const std::string why = "the 1D bar runs on one process";
#else
  const std::string why = "this build has no MPI";
#endif
  const auto first = r.err.find(why);
  ASSERT_NE(first, std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(why, first + 1), std::string::npos) << "one message, not one per rank:\n" << r.err;
  EXPECT_FALSE(fs::exists(out));
}
