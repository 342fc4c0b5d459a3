#pragma once
// Checkpoint and restart of MPM runs (issue 12, point 2).
//
// `[output] checkpoint_every = N` makes a run write, after every N-th converged load step,
// a checkpoint folder DIR.checkpoints/step_NNNNNN beside its output folder DIR:
//   checkpoint.h5   the whole state (io/Hdf5Archive.hpp): every point array with every
//                   state variable, the driver's load factor, next increment and counts,
//                   the post-step stages' state, the outputs accumulated so far (CSV
//                   rows, VTK series), the case text and the program version
//   outputs/        the run's output files as they were at that step (hard links, so no
//                   copy and no extra disk space for VTU files written once)
// A checkpoint folder is written under a temporary name and renamed into place when it
// is complete and flushed to disk: kill -9 at any moment leaves the earlier checkpoints
// whole (and a temporary that the next run removes). The last `checkpoint_keep` are kept.
//
// `gradmpm run CASE --restart DIR.checkpoints/step_NNNNNN` (or its checkpoint.h5) reads
// the same case, replaces the points and the driver's state by the checkpoint's, starts
// its output folder from the checkpoint's outputs and continues: the final outputs are
// the uninterrupted run's, bit for bit. A checkpoint of another case (compared as the
// TOML the program read, overrides included), another dimension or another program
// version is refused (exit 2) with the difference.
#include <filesystem>
#include <string>

#include "gradmpm/io/Archive.hpp"
#include "gradmpm/mpm/QuasiStatic.hpp"

namespace gradmpm {

/// Where the checkpoints of the run whose output folder is `out_dir` go: DIR.checkpoints.
std::filesystem::path checkpoint_folder_of(const std::filesystem::path& out_dir);

/// The checkpoint folder of a run and the writing of its checkpoints.
class CheckpointFolder {
 public:
  /// `folder`: where checkpoints go (DIR.checkpoints); `shown` names it in messages.
  /// Removes temporaries that a killed run left there.
  CheckpointFolder(std::filesystem::path folder, std::string shown, int every, int keep);
  bool due(const StepInfo& info) const { return every_ > 0 && !info.last && info.step % every_ == 0; }
  /// Writes the checkpoint of `step`: `a` and hard links to the files of `outputs`. Atomic;
  /// then removes the oldest beyond `keep`. Returns the folder's name as shown.
  std::string write(int step, const Archive& a, const std::filesystem::path& outputs) const;

 private:
  std::filesystem::path folder_;
  std::string shown_;
  int every_, keep_;
};

/// A checkpoint read for a restart.
struct Restart {
  Archive archive;
  std::filesystem::path outputs;  ///< its output files, to start the restarted run's folder from
};

/// Reads `path` (a step_NNNNNN folder or its checkpoint.h5) and checks that it belongs to
/// this program version, this dimension and this case (`case_text`, CaseFile::canonical_text);
/// throws InputError naming what differs.
Restart read_checkpoint(const std::filesystem::path& path, const std::string& case_text, int dim);

/// The header every checkpoint starts with: format, program version, case text, dimension.
void put_checkpoint_header(Archive& a, const std::string& case_text, int dim, int step);

/// The model's points (every array, every state variable) and the driver's state.
template <int dim>
void save_run_state(Archive& a, const Model<dim>& m, const DriverState& driver,
                    const std::vector<PostStepStage<dim>*>& stages);
/// Replaces the points' arrays by the checkpoint's; returns the driver's state.
template <int dim>
DriverState restore_run_state(const Archive& a, Model<dim>& m, const std::vector<PostStepStage<dim>*>& stages);

/// Hard-links (or copies, across file systems) every file of `from` into `to`.
void link_files(const std::filesystem::path& from, const std::filesystem::path& to);

}  // namespace gradmpm
