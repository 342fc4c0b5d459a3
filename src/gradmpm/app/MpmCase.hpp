#pragma once
// MPM case files ([grid], [basis], [materials.NAME], [[bodies]], [loads], [[constraints]],
// [[point_loads]], [load_steps], [nonlinear_solver], [linear_solver], [output],
// [gradient]; keys declared in app/CaseKeys.cpp, docs/case-files.md): reading returns
// one value, MpmCase; run_mpm_case solves it and writes VTK, CSV and the progress.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "gradmpm/gradient/MpmGradient.hpp"
#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/mpm/QuasiStatic.hpp"

namespace gradmpm {

struct MpmOutputSettings {
  int vtk_every = 1;             ///< write VTK every n steps (and the last); 0: never
  std::vector<long long> track;  ///< point ids written to tracked_points.csv each step
  std::string check;             ///< "" or "column": compare with the column closed form
  bool plot = true;              ///< with check = "column": column.png
  int checkpoint_every = 0;      ///< a checkpoint every n steps (app/Checkpoint.hpp); 0: none
  int checkpoint_keep = 2;       ///< how many checkpoints are kept (the latest); 0: all
};

/// How far a run got, updated after every converged step (a failing strength-reduction
/// trial's last converged state).
struct MpmRunProgress {
  double load_factor = 0.0;
  int steps = 0, iterations = 0, cuts = 0;  ///< over the converged steps
  double max_displacement = 0.0;            ///< the largest |x_p - X_p| of the points
};

/// A trial of a strength-reduction analysis (app/StrengthReduction.hpp): the case with
/// its materials' strengths divided by `factor`, run once; it stops (SolverError) where a
/// point has moved farther than `failure_displacement`.
struct StrengthTrial {
  double factor = 1.0;
  double failure_displacement = 0.0;
};

/// How run_mpm_case runs a case besides what the case file says.
struct MpmRunOptions {
  bool quiet = false;
  std::filesystem::path shown;        ///< the folder named in messages (default: the output folder)
  std::filesystem::path checkpoints;  ///< where checkpoints go (default: <output folder>.checkpoints)
  std::filesystem::path restart;      ///< a checkpoint to continue from (empty: start at load factor 0)
  /// A distributed run: the folder every rank writes its piece of the points' VTU files
  /// into (rank 0's output folder); empty in a serial run.
  std::filesystem::path pieces;
  std::optional<StrengthTrial> strength_trial;  ///< a trial of a strength-reduction analysis
  MpmRunProgress* progress = nullptr;           ///< where the run says how far it got (optional)
};

/// Everything a case file describes.
template <int dim>
struct MpmCase {
  Model<dim> model;
  NewtonSettings newton;
  GradientSettings gradient;
  MpmOutputSettings output;
  double memory_estimate = 0.0;  ///< bytes one process is estimated to need at its peak (app/MemoryCheck.hpp)
};

/// Spatial dimension of an MPM case (the length of grid.cells).
int mpm_case_dimension(const CaseFile& cf);

/// Reads and validates every key and builds the model (points with their initial
/// material state); throws InputError naming the key. rank_points_only (a distributed
/// run, every rank calling): each rank makes only the points in its cells of the run's
/// cut (Model::rank_boxes, Model::point_ids: mpm/RankPoints.hpp), never every point; the
/// checks of the input are made over every rank's points, so every rank meets the same error.
template <int dim>
MpmCase<dim> read_mpm_case(CaseFile& cf, bool rank_points_only = false);

/// Reads, runs and writes the outputs of an MPM case in `out_dir`.
void run_mpm_case(CaseFile& cf, const std::filesystem::path& out_dir, const MpmRunOptions& options);
/// The same, messages naming `shown` (the folder the outputs are published to; default out_dir).
inline void run_mpm_case(CaseFile& cf, const std::filesystem::path& out_dir, bool quiet,
                         const std::filesystem::path& shown = {}) {
  run_mpm_case(cf, out_dir, MpmRunOptions{.quiet = quiet, .shown = shown});
}

}  // namespace gradmpm
