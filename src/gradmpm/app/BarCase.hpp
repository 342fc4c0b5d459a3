#pragma once
// The bar case file: [bar], [gradient], [output], [linear_solver] (docs/case-files.md),
// and the files it writes: bar.csv, bar_points.csv, bar.png.
#include <filesystem>

#include "gradmpm/app/BarMpm.hpp"
#include "gradmpm/app/BarProblem.hpp"
#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/io/StagedOutputs.hpp"

namespace gradmpm {

struct BarOutputOptions {
  bool plot = true;
};

/// Reads and validates every key; throws InputError naming file and key. With an [mpm]
/// section (the bar solved by the MPM), `mpm` receives its settings and [gradient] also
/// takes apply and fields; without one, `mpm` must be null.
BarConfig read_bar_config(CaseFile& cf, BarOutputOptions& output, BarMpmConfig* mpm = nullptr);

/// Largest relative error of the gradient strain against its closed form
/// (nodes for u-RA/e-RA, points for s-RA/none where the field is discontinuous).
double bar_strain_error(const BarConfig& c, const BarResult& r);

/// Stages bar.csv, bar_points.csv and (if asked) bar.png in `out` and commits them:
/// all appear, or none.
void write_bar_outputs(const BarConfig& c, const BarResult& r, StagedOutputs& out, const BarOutputOptions& options);

}  // namespace gradmpm
