#pragma once
// Shared by the tests that run the real gradmpm binary: a scratch folder per test and
// a runner that captures the exit code, stdout and stderr.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace gradmpm::test {

namespace fs = std::filesystem;

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A CSV file's columns by header name (a cell that is not a number reads as NaN).
inline std::map<std::string, std::vector<double>> csv_columns(const fs::path& file) {
  std::istringstream in(slurp(file));
  std::string line, cell;
  std::getline(in, line);
  std::vector<std::string> names;
  for (std::istringstream h(line); std::getline(h, cell, ',');) names.push_back(cell);
  std::map<std::string, std::vector<double>> t;
  while (std::getline(in, line)) {
    std::istringstream r(line);
    for (const auto& n : names) {
      std::getline(r, cell, ',');
      char* end = nullptr;
      const double v = std::strtod(cell.c_str(), &end);
      t[n].push_back(end != cell.c_str() ? v : std::nan(""));
    }
  }
  return t;
}

struct CliResult {
  int code;
  std::string out, err;
};

/// A fresh folder under /tmp for each test, removed afterwards.
class ScratchDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/gradmpm-test-XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    dir = tmpl;
  }
  void TearDown() override { fs::remove_all(dir); }

  /// Runs `env gradmpm args`, stdout and stderr kept in the scratch folder.
  CliResult run_gradmpm(const std::string& args, const std::string& env = "") const {
    const std::string cmd =
        env + " " + GRADMPM_EXE + " " + args + " >" + (dir / "stdout").string() + " 2>" + (dir / "stderr").string();
    const int status = std::system(cmd.c_str());
    return {WEXITSTATUS(status), slurp(dir / "stdout"), slurp(dir / "stderr")};
  }

  fs::path dir;
};

}  // namespace gradmpm::test
