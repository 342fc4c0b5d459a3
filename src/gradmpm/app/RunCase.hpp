#pragma once
// `gradmpm run`: reads a case file, picks the problem it describes, solves it and
// writes its outputs. Errors propagate as exceptions (core/Errors.hpp) that the
// command line maps to exit codes.
#include <filesystem>
#include <string>
#include <vector>

namespace gradmpm {

struct RunOptions {
  std::filesystem::path out;           ///< empty: out/<case file stem>
  std::vector<std::string> overrides;  ///< "section.key=value"
  bool quiet = false;
  std::filesystem::path restart;  ///< an MPM checkpoint to continue from (app/Checkpoint.hpp)
};

void run_case(const std::filesystem::path& case_file, const RunOptions& options);

}  // namespace gradmpm
