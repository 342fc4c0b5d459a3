// Requirements on messages: every bad input gets one line, exit 2, and a
// true statement of what is wrong.
//  R1 values and keys are printed on one line: arrays with NaN, line breaks in strings and
//     keys escaped (\n);
//  R2 --set with a line break is refused (TOML would read the first line and drop the rest);
//  R3 an index too large for any array is exit 2, not "failure: stol";
//  R4 a material name with a dot is refused by name, not with a false missing key;
//  R5 a folder given as the case file is named as such;
//  R6 a number beyond the key's range is refused, never wrapped (output.vtk_every = 2^32 + 1);
//  R7 overlapping bodies are refused (their points would count mass and stiffness twice);
//  R8 the closing line lists the files the run wrote: no VTK files with vtk_every = 0,
//     points_gradient.csv when the gradient step writes it.
#include <gtest/gtest.h>

#include "CliTestUtil.hpp"

using namespace gradmpm::test;

namespace {
class Messages : public ScratchDirTest {
 protected:
  std::string example(const char* name) const { return std::string(GRADMPM_SOURCE_DIR) + "/examples/" + name; }
  void expect_refused(const std::string& args, const std::string& message) {
    const CliResult r = run_gradmpm("run " + args + " --out " + (dir / "o").string());
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
  }
  fs::path write(const char* name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return dir / name;
  }
};
const std::string kOneBody =
    "[grid]\norigin = [0.0]\ncell_size = 1.0\ncells = [4]\n[materials.a]\nmodel = \"hencky\"\nyoung = 1.0\n"
    "[[bodies]]\nmaterial = \"a\"\nmin = [0.0]\nmax = [2.0]\n[load_steps]\ncount = 1\n";
}  // namespace

TEST_F(Messages, ValuesAndKeysArePrintedOnOneLine) {
  expect_refused(example("column_2d.toml") + " --set 'grid.origin=[nan, 0.0]'",
                 "grid.origin (from --set): expected an array of 2 numbers, got [ nan, 0.0 ]");
  const fs::path f = write("nl.toml", "[bar]\nlength = 1.0\n\"ele\\nments\" = 3\n[gradient]\nvariant = \"none\"\n");
  expect_refused(f.string(), "bar.ele\\nments: unknown key");
  const fs::path g = write("str.toml", kOneBody + "[basis]\ntype = \"gi\\nmp\"\n");
  expect_refused(g.string(), "got \"gi\\nmp\"");
}

TEST_F(Messages, SetWithALineBreakIsRefused) {
  expect_refused(example("bar_bimaterial.toml") + " --set 'bar.elements=80\nsplit = 0.9'",  // a real line break
                 "--set 'bar.elements=80\\nsplit = 0.9': expected one line section.key=value (it holds a line break)");
}

TEST_F(Messages, HugeIndicesNamesWithDotsFoldersAndWrapsAreInputErrors) {
  expect_refused(example("column_2d.toml") + " --set 'bodies[99999999999999999999].material=soil'",
                 "bodies has no entry [99999999999999999999]");
  const fs::path dot = write("dot.toml",
                             "[grid]\norigin = [0.0]\ncell_size = 1.0\ncells = [4]\n[materials.\"so.il\"]\n"
                             "model = \"hencky\"\nyoung = 1.0\n[[bodies]]\nmaterial = \"so.il\"\n"
                             "min = [0.0]\nmax = [2.0]\n[load_steps]\ncount = 1\n");
  expect_refused(dot.string(), "[materials.\"so.il\"]: expected a material name without dots");
  expect_refused(dir.string(), ": is a folder, not a case file");
  expect_refused(example("column_2d.toml") + " --set output.vtk_every=4294967297",
                 "output.vtk_every (from --set): expected an integer from 0 (no VTK output) to 1000000000, got "
                 "4294967297");
}

TEST_F(Messages, OverlappingBodiesAreRefused) {
  const fs::path f = write("overlap.toml", kOneBody + "[[bodies]]\nmaterial = \"a\"\nmin = [1.0]\nmax = [3.0]\n");
  expect_refused(f.string(), "bodies[1].min: expected a body that does not overlap bodies[0]");
  // Touching bodies are fine.
  const fs::path t = write("touch.toml", kOneBody + "[[bodies]]\nmaterial = \"a\"\nmin = [2.0]\nmax = [3.0]\n");
  const CliResult r = run_gradmpm("run " + t.string() + " --out " + (dir / "o").string());
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST_F(Messages, TheClosingLineListsTheFilesWritten) {
  CliResult r = run_gradmpm("run " + example("column_2d.toml") + " --out " + (dir / "o").string() +
                            " --set output.vtk_every=0 --set output.plot=false");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("wrote " + (dir / "o").string() +
                       ": column_check.csv, energy.csv, newton_history.csv, points_final.csv\n"),
            std::string::npos)
      << r.out;
  r = run_gradmpm("run " + example("column_2d.toml") + " --out " + (dir / "g").string() +
                  " --set gradient.variant=e-RA --set gradient.length_scale=0.5 --set output.vtk_every=0 --set "
                  "output.plot=false");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("points_gradient.csv"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find(".pvd"), std::string::npos) << r.out;
}
