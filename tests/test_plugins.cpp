// Requirements on the plugins (core/Plugins.hpp), the parts loaded on first use:
//  P1 a process that uses neither PETSc, MPI nor HDF5 loads none of their libraries
//     (the start-up they cost: docs/performance.md);
//  P2 a run that needs a plugin it cannot load stops with exit 2, naming the file, what
//     needed it and the way out (GRADMPM_PLUGIN_DIR), and publishes no final outputs;
//  P3 with the plugins where they belong, the same runs succeed (PETSc's solver, a
//     checkpoint), loading them then.
#include <gtest/gtest.h>

#include "CliTestUtil.hpp"

using namespace gradmpm::test;

namespace {
class Plugins : public ScratchDirTest {
 protected:
  std::string column() const {
    return std::string(GRADMPM_SOURCE_DIR) + "/examples/column_1d.toml --set output.plot=false";
  }
};
}  // namespace

TEST_F(Plugins, ASerialRunLoadsNeitherPetscNorMpiNorHdf5) {
  // LD_DEBUG=files lists every shared object the dynamic loader opens, dlopen's included.
  const CliResult r = run_gradmpm("run " + column() + " --out " + (dir / "plain").string(), "LD_DEBUG=files");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* library : {"libpetsc", "libmpi", "libhdf5", "libgradmpm_petsc", "libgradmpm_hdf5"})
    EXPECT_EQ(r.err.find(library), std::string::npos) << library << " was loaded:\n" << r.err.substr(0, 4000);
  EXPECT_NE(r.err.find("libgradmpm.so"), std::string::npos) << "LD_DEBUG listed nothing?";
}

TEST_F(Plugins, ACheckpointLoadsHdf5AndWithoutItsPluginTheRunStopsSayingSo) {
  const std::string args = "run " + column() + " --set output.checkpoint_every=10 --out ";
  CliResult r = run_gradmpm(args + (dir / "with").string(), "LD_DEBUG=files");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("libgradmpm_hdf5.so"), std::string::npos);
  r = run_gradmpm(args + (dir / "without").string(), "GRADMPM_PLUGIN_DIR=" + (dir / "nowhere").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("a checkpoint (HDF5) needs the plugin " + (dir / "nowhere" / "libgradmpm_hdf5.so").string() +
                       ", which could not be loaded"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("GRADMPM_PLUGIN_DIR"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "without" / "points_final.csv"));
}

#ifdef GRADMPM_WITH_PETSC
TEST_F(Plugins, PetscsSolverLoadsItsPluginAndWithoutItTheRunStopsSayingSo) {
  const std::string args = "run " + column() + " --set linear_solver.type=petsc --out ";
  CliResult r = run_gradmpm(args + (dir / "with").string(), "LD_DEBUG=files");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("libgradmpm_petsc.so"), std::string::npos);
  EXPECT_NE(r.err.find("libpetsc"), std::string::npos);
  r = run_gradmpm(args + (dir / "without").string(), "GRADMPM_PLUGIN_DIR=" + (dir / "nowhere").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("linear_solver.type = \"petsc\" needs the plugin " +
                       (dir / "nowhere" / "libgradmpm_petsc.so").string() + ", which could not be loaded"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "without" / "points_final.csv"));
}
#endif
