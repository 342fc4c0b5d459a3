#pragma once
// One run's output folder, published whole: a run writes every file into a fresh staging
// folder beside `--out DIR` (.DIR.staging-<pid>) and, when it ends (converged, or stopped
// by a numerical failure with its converged steps), swaps that folder with DIR in one
// atomic rename (renameat2 RENAME_EXCHANGE). So DIR holds, at every moment, either the
// previous run's complete results or this run's, never a mix, also when the process is
// killed (kill -9 leaves only a stale staging folder, which the next run removes).
//
// Files in DIR that gradmpm did not write (listed in no earlier run's manifest,
// .gradmpm-run, and not named like its outputs) are kept: they are hard-linked into the
// staging folder before the swap, so no moment loses them. DIR may not hold folders of its
// own (that is not an output folder: `--out .` is refused).
//
// One run at a time per DIR: the run holds an exclusive lock on .DIR.lock beside it for
// its whole life (released by the kernel however the process ends); a second run on the
// same DIR is refused with exit 2.
#include <filesystem>
#include <string>
#include <vector>

namespace gradmpm {

class RunFolder {
 public:
  /// Locks DIR, removes stale staging folders, checks DIR, creates the staging folder;
  /// throws OutputError (exit 2) when DIR is busy or unusable.
  explicit RunFolder(std::filesystem::path dir);
  ~RunFolder();  ///< without publish(): removes the staging folder (DIR stays as it was)
  RunFolder(const RunFolder&) = delete;
  RunFolder& operator=(const RunFolder&) = delete;

  const std::filesystem::path& dir() const { return dir_; }
  /// Where the run writes its files until publish().
  const std::filesystem::path& staging() const { return staging_; }
  /// `message` with the staging folder's path written as `shown` (DIR as the user gave it).
  std::string shown_as(std::string message, const std::filesystem::path& shown) const;
  /// Writes the manifest, keeps DIR's foreign files, and swaps the staging folder in.
  void publish();
  /// The files of the published run (its manifest), sorted.
  const std::vector<std::string>& files() const { return files_; }
  /// "points_final.csv, reactions.csv, points.pvd + 5 points_NNNN.vtu, ...": the files, the
  /// numbered VTU files counted.
  std::string summary() const;

 private:
  std::filesystem::path dir_, staging_;
  std::vector<std::string> files_;
  int lock_fd_ = -1;
  bool published_ = false;
};

/// Whether `name` is one of the files a gradmpm run writes (points_0012.vtu, reactions.csv,
/// a staged temporary, ...): such files in DIR belong to an earlier run, not to the user.
bool is_gradmpm_output_name(const std::string& name);

}  // namespace gradmpm
