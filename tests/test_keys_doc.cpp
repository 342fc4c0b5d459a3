// Requirements on the key declarations (io/Keys.hpp, app/CaseKeys.cpp):
//  R1 docs/case-files.md holds exactly the tables the declarations render: it is not
//     stale (fix: scripts/update-docs);
//  R2 a declared key gives its default when absent, and its range and message when the
//     value is outside it, the same text the docs show;
//  R3 every registered material's and linear solver's keys and names appear in the docs.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "gradmpm/app/CaseKeys.hpp"
#include "gradmpm/app/KeysDoc.hpp"
#include "gradmpm/basis/BasisKind.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/materials/MaterialRegistry.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

using namespace gradmpm;

namespace {
std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
const std::string kDoc = std::string(GRADMPM_SOURCE_DIR) + "/docs/case-files.md";
}  // namespace

TEST(KeysDoc, CaseFilesDocumentationIsGeneratedFromTheDeclarations) {
  const std::string doc = read(kDoc);
  ASSERT_FALSE(doc.empty()) << kDoc;
  for (const auto& kind : key_doc_kinds())
    EXPECT_NE(doc.find("<!-- keys " + kind + " -->"), std::string::npos) << "no generated region for " << kind;
  EXPECT_TRUE(with_generated_keys(doc) == doc) << "docs/case-files.md is stale: run scripts/update-docs";
}

TEST(KeysDoc, EveryMaterialAndSolverIsDocumented) {
  const std::string doc = read(kDoc);
  for (const auto& law : MaterialRegistry::instance().all())
    EXPECT_NE(doc.find("`model = \"" + law.model + "\"`"), std::string::npos) << law.model;
  for (const auto& s : LinearSolverRegistry::instance().all())
    EXPECT_NE(doc.find("`\"" + s.name + "\"`: " + s.doc), std::string::npos) << s.name;
}

TEST(Keys, DefaultsRangesAndMessagesComeFromTheDeclaration) {
  const SectionSpec& nl = mpm_section("nonlinear_solver");
  const KeySpec& its = nl.key("max_iterations");
  EXPECT_EQ(its.default_name(), "`25`");
  EXPECT_EQ(its.expected(), "an integer from 1 to 1000");
  CaseFile absent = CaseFile::parse("[nonlinear_solver]\n", "k.toml");
  EXPECT_EQ(read_integer(absent, "nonlinear_solver", its), 25);
  CaseFile bad = CaseFile::parse("[nonlinear_solver]\nmax_iterations = 0\n", "k.toml");
  try {
    read_integer(bad, "nonlinear_solver", its);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "k.toml: nonlinear_solver.max_iterations: expected an integer from 1 to 1000, got 0");
  }
  const KeySpec& tol = nl.key("tolerance");
  EXPECT_EQ(tol.expected(), "a number in (0, 1)");
  CaseFile edge = CaseFile::parse("[nonlinear_solver]\ntolerance = 1.0\n", "k.toml");
  EXPECT_THROW(read_number(edge, "nonlinear_solver", tol), InputError) << "the open bound is excluded";
  CaseFile ok = CaseFile::parse("[nonlinear_solver]\ntolerance = 1e-6\n", "k.toml");
  EXPECT_EQ(read_number(ok, "nonlinear_solver", tol), 1e-6);
  const KeySpec& basis = mpm_section("basis").key("type");
  CaseFile spline = CaseFile::parse("[basis]\ntype = \"spline\"\n", "k.toml");
  try {
    read_string(spline, "basis", basis);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find("expected \"mpm\", \"gimp\" or \"ugimp\" (uGIMP), or \"cpgimp\", got \"spline\""),
        std::string::npos)
        << e.what();
  }
  // The name the run's first line prints for uGIMP is a valid value too.
  CaseFile ugimp = CaseFile::parse("[basis]\ntype = \"ugimp\"\n", "k.toml");
  EXPECT_EQ(read_string(ugimp, "basis", basis), "ugimp");
  EXPECT_EQ(to_string(*parse_basis(read_string(ugimp, "basis", basis))), "ugimp");
}
