// Requirements on the process tuning (tuning/ProcessTuning.hpp), which this test program
// links as gradmpm and bench_mpm do:
//  T1 GRADMPM_TUNING is read as documented: 1/on/all, 0/off/none, or a list of parts;
//     anything else is refused saying what is expected (and the program exits 2);
//  T2 the run's first line says what is on; --no-tuning and GRADMPM_TUNING=0 turn all of
//     it off, GRADMPM_TUNING=blas keeps that part only;
//  T3 the answer does not depend on the tuning (points_final.csv byte for byte);
//  T4 CHOLMOD's serial OpenMP regions are plain calls, and only those;
//  T5 the BLAS (OpenBLAS) runs on the caller's threads under CHOLMOD;
//  T7 freed memory stays in the process: a large block comes from the heap, not a mapping
//     of its own, and the heap keeps it when it is freed (a user's malloc settings kept);
//  T6 libgomp's idle threads wait passively: they burn no CPU between regions; a user's
//     OMP_WAIT_POLICY and malloc settings are kept (the first line says so).
#include <dlfcn.h>
#include <malloc.h>
#include <gtest/gtest.h>
#include <omp.h>
#include <pthread.h>
#include <time.h>

#include <cstdlib>
#include <stdexcept>
#include <thread>

#include "CliTestUtil.hpp"
#include "SolverTestUtil.hpp"
#include "gradmpm/core/PlatformHooks.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"
#include "gradmpm/tuning/ProcessTuning.hpp"
#include "gradmpm/tuning/SerialOpenMpRegions.hpp"

using namespace gradmpm;
using namespace gradmpm::test;

TEST(Tuning, GradmpmTuningIsReadAsDocumented) {
  using tuning::parse;
  for (const char* all : {"", "1", "on", "all"}) EXPECT_EQ(parse(all), tuning::kAllParts) << all;
  for (const char* none : {"0", "off", "none"}) EXPECT_EQ(parse(none), tuning::Parts{}) << none;
  EXPECT_EQ(parse("blas"), (tuning::Parts{.blas = true}));
  EXPECT_EQ(parse("wait,regions"), (tuning::Parts{.wait = true, .regions = true}));
  EXPECT_EQ(parse("memory"), (tuning::Parts{.memory = true}));
  EXPECT_THROW(parse("blas,"), std::invalid_argument);
  try {
    parse("hugepages");
    ADD_FAILURE() << "an unknown part was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'hugepages'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("wait, memory, regions and blas"), std::string::npos) << e.what();
  }
}

TEST(Tuning, ThisProcessIsTunedAndItsHooksAreInstalled) {
  if (std::getenv("GRADMPM_TUNING")) GTEST_SKIP() << "GRADMPM_TUNING is set for this test run";
  EXPECT_EQ(tuning::parts(), tuning::kAllParts);
  ASSERT_NE(platform_hooks().summary, nullptr);
  EXPECT_EQ(std::string(platform_hooks().summary), tuning::summary());
  EXPECT_NE(platform_hooks().enter_serial_regions, nullptr);
  EXPECT_NE(platform_hooks().set_blas_threads, nullptr);
}

TEST(Tuning, OpenMpsIdleThreadsWaitPassively) {
  if (std::getenv("GRADMPM_TUNING") || !tuning::parts().wait) GTEST_SKIP() << "GRADMPM_TUNING is set for this test run";
  ASSERT_STREQ(std::getenv("OMP_WAIT_POLICY"), "passive");
  // 200 short regions on 2 threads, the main thread asleep 1 ms after each: libgomp's
  // default spins some 300 000 times before it sleeps, 0.23 s of the other thread's CPU
  // here; passive, none. (The other thread's own clock: OpenBLAS's threads spin on their
  // own for a while after the process starts.)
  clockid_t other{};
  bool found = false;
#pragma omp parallel num_threads(2)
  if (omp_get_thread_num() == 1) found = pthread_getcpuclockid(pthread_self(), &other) == 0;
  ASSERT_TRUE(found) << "no second OpenMP thread";
  timespec start{}, end{};
  clock_gettime(other, &start);
  double sum = 0.0;
  for (int i = 0; i < 200; ++i) {
#pragma omp parallel for reduction(+ : sum) num_threads(2)
    for (int k = 0; k < 1000; ++k) sum += k;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  clock_gettime(other, &end);
  const double cpu = double(end.tv_sec - start.tv_sec) + 1e-9 * double(end.tv_nsec - start.tv_nsec);
  EXPECT_EQ(sum, 200 * 499500.0);
  EXPECT_LT(cpu, 0.05) << "CPU seconds of the second thread: it spun while idle";
}

TEST(Tuning, FreedMemoryStaysInTheProcess) {
  if (std::getenv("GRADMPM_TUNING") || std::getenv("MALLOC_MMAP_MAX_") || std::getenv("MALLOC_TRIM_THRESHOLD_") ||
      std::getenv("GLIBC_TUNABLES"))
    GTEST_SKIP() << "malloc or the tuning is set for this test run";
  constexpr std::size_t kBlock = std::size_t(64) << 20;  // above glibc's largest mmap threshold (32 MiB)
  const std::size_t mapped = mallinfo2().hblkhd;
  auto* block = static_cast<volatile char*>(std::malloc(kBlock));
  ASSERT_NE(block, nullptr);
  block[kBlock - 1] = 1;
  EXPECT_EQ(mallinfo2().hblkhd, mapped) << "the block got a mapping of its own";
  std::free(const_cast<char*>(block));
  EXPECT_GE(mallinfo2().arena, kBlock) << "the heap was trimmed";
}

TEST(Tuning, TheBlasRunsOnTheCallersThreadsUnderCholmod) {
  using GetThreads = int (*)();
  const auto get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  if (!get) GTEST_SKIP() << "the BLAS is not OpenBLAS (scripts/install-deps selects it)";
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const SparseMatrix A = test::laplacian_2d(40);
  make_linear_solver(LinearSolverSettings{.type = "cholmod"})->compute(A);
  EXPECT_EQ(get(), 1);
  omp_set_num_threads(2);
  make_linear_solver(LinearSolverSettings{.type = "cholmod"})->compute(A);
  EXPECT_EQ(get(), 2);
  omp_set_num_threads(threads);
}

// Requirement: CHOLMOD's OpenMP regions that run serially are plain calls, not libgomp
// teams of one (a system call each, tuning/SerialOpenMpRegions.hpp), and the
// factorisation's answer is unchanged. The count stays put if the executable's
// GOMP_parallel is not the one libcholmod calls.
TEST(Tuning, CholmodsSerialRegionsRunAsPlainCalls) {
  const SparseMatrix A = test::laplacian_2d(60);
  const Vector b = Vector::Ones(A.rows());
  const long before = SerialOpenMpRegions::plain_calls();
  const auto s = make_linear_solver(LinearSolverSettings{.type = "cholmod"});
  s->compute(A);
  const Vector x = s->solve(b);
  EXPECT_GT(SerialOpenMpRegions::plain_calls(), before);
  EXPECT_LT((A * x - b).norm(), 1e-12 * b.norm());
}

// Requirement: within a SerialOpenMpRegions scope (enter .. leave), a region that would get one thread
// sees what a team of one sees (thread 0 of 1; orphaned worksharing, single and barrier
// do all the work once), and every other region, and every region outside a scope, is
// libgomp's: the scope changes how serial regions start, never which regions run in
// parallel.
TEST(SerialOpenMpRegions, OnlyRegionsOfOneThreadInTheScopeAreCalledDirectly) {
  const int levels = omp_get_max_active_levels(), dynamic = omp_get_dynamic();
  omp_set_dynamic(0);
  auto one_thread_region = [](bool parallel, int& thread, int& team, int& level, long& sum) {
    sum = 0;
#pragma omp parallel if (parallel) num_threads(2)
    {
#pragma omp single
      {
        thread = omp_get_thread_num();
        team = omp_get_num_threads();
        level = omp_get_level();
      }
      long local = 0;
#pragma omp for schedule(dynamic, 7)
      for (int i = 1; i <= 100; ++i) local += i;
#pragma omp atomic
      sum += local;
#pragma omp barrier
    }
  };
  int thread = -1, team = -1, level = -1;
  long sum = 0;
  long calls = SerialOpenMpRegions::plain_calls();
  one_thread_region(false, thread, team, level, sum);  // outside a scope: libgomp's team of one
  EXPECT_EQ(SerialOpenMpRegions::plain_calls(), calls);
  EXPECT_EQ(level, 1);
  EXPECT_EQ(sum, 5050);
  {
    SerialOpenMpRegions::enter();
    one_thread_region(false, thread, team, level, sum);  // if(false): called directly
    EXPECT_EQ(SerialOpenMpRegions::plain_calls(), calls + 1);
    EXPECT_EQ(thread, 0);
    EXPECT_EQ(team, 1);
    EXPECT_EQ(level, 0) << "no team was set up";
    EXPECT_EQ(sum, 5050);
    one_thread_region(true, thread, team, level, sum);  // two threads asked for and given
    EXPECT_EQ(SerialOpenMpRegions::plain_calls(), calls + 1);
    EXPECT_EQ(team, 2);
    EXPECT_EQ(sum, 5050);
    omp_set_max_active_levels(0);  // as CHOLMOD's calls under OpenBLAS: every region serial
    one_thread_region(true, thread, team, level, sum);
    EXPECT_EQ(SerialOpenMpRegions::plain_calls(), calls + 2);
    EXPECT_EQ(team, 1);
    EXPECT_EQ(sum, 5050);
    omp_set_max_active_levels(levels);
    SerialOpenMpRegions::leave();
  }
  one_thread_region(false, thread, team, level, sum);  // the scope has ended
  EXPECT_EQ(SerialOpenMpRegions::plain_calls(), calls + 2);
  EXPECT_EQ(level, 1);
  omp_set_dynamic(dynamic);
}

namespace {
class TuningCli : public ScratchDirTest {
 protected:
  std::string footing() const {
    return std::string(GRADMPM_SOURCE_DIR) +
           "/examples/footing_tresca_2d.toml --set output.vtk_every=0 --set output.plot=false --set load_steps.count=6 "
           "--set 'constraints[3].displacement=[0.0,-0.03]'";
  }
  CliResult run(const std::string& folder, const std::string& env, const std::string& flags = "") const {
    return run_gradmpm("run " + footing() + flags + " --out " + (dir / folder).string(), env);
  }
};
}  // namespace

TEST_F(TuningCli, TheFirstLineSaysWhatIsOnAndEachSwitchTurnsItOff) {
  const std::string plain =
      "env -u GRADMPM_TUNING -u OMP_WAIT_POLICY -u GLIBC_TUNABLES -u MALLOC_TRIM_THRESHOLD_ -u MALLOC_MMAP_MAX_";
  const auto first_line = [&](const CliResult& r) { return r.out.substr(0, r.out.find('\n')); };
  CliResult r = run("on", plain);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(first_line(r).find("(OpenMP waiting passive), tuning: OpenMP waiting passive, freed memory kept, "
                               "CHOLMOD's serial regions as calls, BLAS threads set under CHOLMOD"),
            std::string::npos)
      << r.out;
  r = run("off", plain, " --no-tuning");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(first_line(r).find("(OpenMP waiting by default), tuning off (--no-tuning)"), std::string::npos) << r.out;
  r = run("zero", plain + " GRADMPM_TUNING=0");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(first_line(r).find("(OpenMP waiting by default), tuning off (GRADMPM_TUNING=0)"), std::string::npos)
      << r.out;
  r = run("blas", plain + " GRADMPM_TUNING=blas");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(first_line(r).find("(OpenMP waiting by default), tuning: BLAS threads set under CHOLMOD"),
            std::string::npos)
      << r.out;
  r = run("user", plain + " OMP_WAIT_POLICY=active MALLOC_TRIM_THRESHOLD_=131072");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(first_line(r).find("(OpenMP waiting active), tuning: OpenMP waiting as OMP_WAIT_POLICY says, malloc as "
                               "the user's settings say, CHOLMOD's"),
            std::string::npos)
      << r.out;
}

TEST_F(TuningCli, AnUnknownPartIsRefused) {
  const CliResult r = run("bad", "GRADMPM_TUNING=blas,turbo");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("GRADMPM_TUNING=blas,turbo: expected 1 (every part), 0 (none) or a comma-separated list of "
                       "wait, memory, regions and blas, not the part 'turbo'"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "bad" / "points_final.csv"));
}

TEST_F(TuningCli, TheAnswerDoesNotDependOnTheTuning) {
  const CliResult on = run("on", "env -u GRADMPM_TUNING"), off = run("off", "env -u GRADMPM_TUNING", " --no-tuning");
  ASSERT_EQ(on.code, 0) << on.err;
  ASSERT_EQ(off.code, 0) << off.err;
  const std::string a = slurp(dir / "on" / "points_final.csv");
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, slurp(dir / "off" / "points_final.csv"));
  EXPECT_EQ(slurp(dir / "on" / "reactions.csv"), slurp(dir / "off" / "reactions.csv"));
}
