#pragma once
// MPM case files ([grid], [basis], [materials.NAME], [[bodies]], [loads], [[constraints]],
// [[point_loads]], [load_steps], [nonlinear_solver], [output]; docs/case-files.md) and
// the run that writes VTK, CSV and the terminal progress.
#include <filesystem>

#include "gradmpm/gradient/MpmGradient.hpp"
#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/mpm/QuasiStatic.hpp"

namespace gradmpm {

struct MpmOutputOptions {
  int vtk_every = 1;               ///< write VTK every n steps (and the last); 0: never
  std::vector<long long> track;    ///< point ids written to tracked_points.csv each step
  std::string check;               ///< "" or "column": compare with the column closed form
  bool plot = true;                ///< with check = "column": column.png
};

/// Spatial dimension of an MPM case (the length of grid.cells).
int mpm_case_dimension(const CaseFile& cf);

/// Reads and validates every key and builds the model; throws InputError naming the key.
template <int dim>
Model<dim> read_mpm_case(CaseFile& cf, NewtonSettings& newton, MpmOutputOptions& output,
                         GradientSettings* gradient = nullptr);

/// Reads, runs and writes the outputs of an MPM case in `out_dir`.
void run_mpm_case(CaseFile& cf, const std::filesystem::path& out_dir, bool quiet);

}  // namespace gradmpm
