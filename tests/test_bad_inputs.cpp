// Requirement: every input of the bad-input corpus
// (tests/bad_inputs/corpus.txt: malformed files, impossible values, sizes beyond the
// machine, a failing solve) ends with its documented exit code and a one-line message
// holding the documented fragment (command-line errors add one line pointing to --help); a refused input (exit 2)
// leaves no output folder.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "CliTestUtil.hpp"

using namespace gradmpm::test;

namespace {
struct BadInput {
  int code;
  std::string args, fragment;
};

std::vector<BadInput> corpus() {
  const std::string folder = std::string(GRADMPM_SOURCE_DIR) + "/tests/bad_inputs";
  std::ifstream in(folder + "/corpus.txt");
  std::vector<BadInput> cases;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    BadInput c;
    std::string code;
    std::getline(fields, code, '\t');
    std::getline(fields, c.args, '\t');
    std::getline(fields, c.fragment);
    c.code = std::stoi(code);
    for (auto [token, path] :
         {std::pair<std::string, std::string>{"@EX", std::string(GRADMPM_SOURCE_DIR) + "/examples"}, {"@BAD", folder}})
      for (std::size_t at; (at = c.args.find(token)) != std::string::npos;) c.args.replace(at, token.size(), path);
    cases.push_back(c);
  }
  return cases;
}

class BadInputs : public ScratchDirTest {};
}  // namespace

TEST_F(BadInputs, EachEndsWithItsExitCodeAndOneLine) {
  const auto cases = corpus();
  ASSERT_GE(cases.size(), 25u) << "the corpus was not read";
  int k = 0;
  for (const auto& c : cases) {
    const fs::path out = dir / ("o" + std::to_string(k++));
    const CliResult r = run_gradmpm("run " + c.args + " --out " + out.string());
    EXPECT_EQ(r.code, c.code) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.fragment), std::string::npos) << c.args << "\nstderr: " << r.err;
    // One line (a command-line error adds the pointer to --help).
    const bool usage = r.err.find("Run 'gradmpm --help' for usage.") != std::string::npos;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), usage ? 2 : 1) << c.args << "\n" << r.err;
    if (c.code == 2) EXPECT_FALSE(fs::exists(out)) << c.args << ": an output folder was created";
  }
}
