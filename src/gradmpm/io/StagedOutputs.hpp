#pragma once
// All-or-nothing output: files are written under temporary names in the output
// directory and renamed onto their final names only when every one of them was
// written completely. If anything fails (or the run stops early) the temporaries
// are removed and files from earlier runs stay as they were.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace gradmpm {

class StagedOutputs {
 public:
  /// Creates `dir` if needed and checks that it can be written; throws OutputError.
  explicit StagedOutputs(std::filesystem::path dir);
  ~StagedOutputs();
  StagedOutputs(const StagedOutputs&) = delete;
  StagedOutputs& operator=(const StagedOutputs&) = delete;

  const std::filesystem::path& dir() const { return dir_; }
  /// Temporary path standing in for `filename` until commit().
  std::filesystem::path stage(const std::string& filename);
  /// Stages `filename` with `content` and returns the temporary path (readable until
  /// commit()); throws OutputError on a failed or short write.
  std::filesystem::path write_text(const std::string& filename, std::string_view content);
  /// Renames every staged file onto its final name.
  void commit();
  /// Final paths of the committed files.
  std::vector<std::filesystem::path> committed() const;

 private:
  std::filesystem::path dir_;
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged_;  // temp, final
  bool committed_ = false;
};

}  // namespace gradmpm
