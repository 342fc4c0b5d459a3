#pragma once
// Checkpoint and restart of MPM runs, serial and distributed.
//
// `[output] checkpoint_every = N` makes a run write, after every N-th converged load step,
// a checkpoint folder DIR.checkpoints/step_NNNNNN beside its output folder DIR:
//   checkpoint.h5   the whole state (io/Hdf5Archive.hpp): the driver's load factor, next
//                   increment and counts, the ordering the next step's analysis takes
//                   (NewtonSettings::reuse_ordering: without it a restart would order
//                   afresh and differ in round-off), the outputs accumulated so far (CSV rows, VTK
//                   series), the case text and the program version, the points' layout
//                   (layout/: their number, the number of point files, each file's cells);
//                   and, of a serial run, the points: every array (points/), every state
//                   variable, the post-step stages' per-point arrays, the ids
//   points_RRRR.h5  a distributed run's points, one file per rank, written by that rank
//                   (the points it owns, as above): no rank ever holds every point
//   outputs/        the run's output files as they were at that step (hard links, so no
//                   copy and no extra disk space for VTU files written once); checkpoint.h5
//                   records each one's name, size and CRC-32, and a restart refuses a
//                   checkpoint whose outputs/ lacks a file or holds another one
// A checkpoint folder is written under a temporary name and renamed into place when it
// is complete and flushed to disk (in a distributed run: when every rank's file is):
// kill -9 at any moment leaves the earlier checkpoints whole (and a temporary that the
// next run removes). The last `checkpoint_keep` are kept. The last step is checkpointed
// too when `checkpoint_every` divides its number (a restart from it only publishes).
//
// `gradmpm run CASE --restart DIR.checkpoints/step_NNNNNN` (or its checkpoint.h5) reads
// the same case, replaces the points and the driver's state by the checkpoint's, starts
// its output folder from the checkpoint's outputs and continues: the final outputs are
// the uninterrupted run's, bit for bit (serially; on several ranks to PETSc's round-off).
// A restart may use another number of ranks than the run that wrote the checkpoint
// (serial included): each rank keeps the checkpoint's points that lie in its cells,
// reading only the files whose points' cells meet its own (checkpoint.h5 lists each
// file's range of cells): its own file alone when the ranks are as many. A checkpoint of
// another case (compared as the values the program read, overrides included, a key given
// at its default as one not given: app/CaseKeys.hpp mpm_canonical_text), another
// dimension or another program version is refused (exit 2) with the difference.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

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
  bool due(const StepInfo& info) const { return every_ > 0 && info.step % every_ == 0; }
  /// Writes the checkpoint of `step`: `a` (rank 0's; the outputs' sizes and CRC-32 are
  /// added to it), `points` (each rank's file in a distributed run; empty serially) and
  /// hard links to the files of `outputs`. Atomic; then removes the oldest beyond `keep`.
  /// Returns the folder's name as shown. A collective call in a distributed run: a rank
  /// that cannot write stops every rank with its message.
  std::string write(int step, Archive& a, const Archive& points, const std::filesystem::path& outputs) const;

 private:
  std::filesystem::path folder_;
  /// Puts the name, size and CRC-32 of every file in `outputs` into `a`.
  void record_outputs(Archive& a, const std::filesystem::path& outputs) const;
  std::string shown_;
  int every_, keep_;
  std::string tag_;  ///< of the temporaries' names: rank 0's process id
  /// The CRC-32 of output files already summed, by name, with the size, modification time
  /// and inode they had: a VTU file written once is read once, not at every checkpoint.
  struct Summed {
    long long size, mtime, inode;
    unsigned long crc;
  };
  mutable std::map<std::string, Summed> summed_;
};

/// A checkpoint read for a restart.
struct Restart {
  Archive archive;                ///< checkpoint.h5 (a distributed run's points are in their own files)
  std::filesystem::path folder;   ///< the step_NNNNNN folder
  std::filesystem::path outputs;  ///< its output files, to start the restarted run's folder from
  int threads = 0;                ///< the threads of the run that wrote it (0: not recorded)
};

/// Reads `path` (a step_NNNNNN folder or its checkpoint.h5) and checks that it belongs to
/// this program version, this dimension and this case (`case_text`, CaseFile::canonical_text)
/// and that its outputs/ holds the files it recorded, of their sizes and CRC-32; throws
/// InputError naming what differs.
Restart read_checkpoint(const std::filesystem::path& path, const std::string& case_text, int dim);

/// The header every checkpoint starts with: format, program version, case text, dimension,
/// step, and the run's threads (a restart with other threads is told it continues to
/// round-off, not bit for bit: docs/reliability.md).
void put_checkpoint_header(Archive& a, const std::string& case_text, int dim, int step, int threads);

/// The driver's state into `a` and the model's points (every array, every state variable,
/// the stages' per-point arrays, the points' ids) into `a` serially or into `points`, this
/// rank's file, in a distributed run (a collective call: `a` gets the number of points of
/// every rank).
template <int dim>
void save_run_state(Archive& a, Archive& points, const Model<dim>& m, const DriverState& driver,
                    const std::vector<PostStepStage<dim>*>& stages);
/// Replaces the points' arrays by the checkpoint's (a distributed run: the points in this
/// rank's cells, Model::rank_boxes, from whichever rank's file holds them); returns the
/// driver's state. A collective call in a distributed run.
template <int dim>
DriverState restore_run_state(const Restart& r, Model<dim>& m, const std::vector<PostStepStage<dim>*>& stages);

/// The per-point arrays of checkpoint files (every array whose name starts with one of
/// `prefixes`, "points/" and the stages' "NAME/", but points/count and points/state_stride;
/// points/id among them), the points kept from each file gathered and put in id order: how
/// a restart on any number of ranks takes its points.
class PointRows {
 public:
  explicit PointRows(std::vector<std::string> prefixes) : prefixes_(std::move(prefixes)) {}
  /// Appends the points of `file` whose `keep` is non-zero (one entry per point).
  void add(const Archive& file, const std::vector<char>& keep);
  /// The points added, in increasing id: points/count, points/id and every per-point array.
  /// `source`: the checkpoint's name, for messages.
  Archive take(const std::string& source) const;
  long long count() const { return static_cast<long long>(ids_.size()); }

 private:
  bool per_point(const std::string& name) const;
  std::vector<std::string> prefixes_;
  std::vector<long long> ids_;
  std::map<std::string, std::vector<double>> reals_;
  std::map<std::string, std::vector<long long>> integers_;
};

/// Hard-links (or copies, across file systems) every file of `from` into `to`.
void link_files(const std::filesystem::path& from, const std::filesystem::path& to);

}  // namespace gradmpm
