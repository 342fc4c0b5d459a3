#pragma once
// The factor of safety by strength reduction ([analysis] type = "strength-reduction";
// docs/strength-reduction.md). The case runs as written, from its start to load factor 1,
// once per trial factor F, with every material's strength divided by F (c / F and
// tan(phi) / F, sigma_y / F: Material::strength_reduced). A trial that reaches load
// factor 1 stands. One fails where Newton fails after every cut of its step (no
// equilibrium at that strength: Griffiths & Lane 1999's criterion of non-convergence), or
// where a point has moved farther than failure_displacement: the finite-strain MPM
// follows a slope past failure, as it slides, and may find it a new rest. The first
// factor is tried, then doubled (or halved) until one trial stands and one fails, then
// the two are bisected until they are `tolerance` apart. The factor of safety is the
// largest factor that stood.
//
// Each trial writes the case's usual outputs into OUT/trials/NN_F<factor>/; OUT gets
// strength_reduction.csv (one row per trial) and mechanism.png (2D: the points coloured
// by eps_p at the largest factor that stood).
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/materials/Material.hpp"

namespace gradmpm {

struct StrengthReductionSettings {
  double first_factor = 1.0;  ///< the first trial
  double min_factor = 0.1;    ///< below it the search gives up (the body fails under its loads)
  double max_factor = 10.0;   ///< above it the search gives up (the body stands)
  double tolerance = 0.01;    ///< the bisection stops when the factors that stood and failed are this close
  /// A trial fails where a point moves farther (required: a large-deformation MPM follows
  /// a slope that slides to a new rest, so equilibrium alone does not mark failure).
  double failure_displacement = 0.0;
};

/// [analysis]: the strength-reduction settings when type = "strength-reduction" (the
/// keys checked, and the case's other sections against it), none for a plain analysis.
std::optional<StrengthReductionSettings> read_strength_reduction(const CaseFile& cf);

/// The case's materials (in [materials.NAME] order) with their strengths divided by
/// `factor`. A law with a strength that cannot be reduced (Modified Cam-Clay) is refused,
/// naming its section; elastic laws stay as they are.
void reduce_strengths(const CaseFile& cf, std::vector<std::shared_ptr<const Material>>& materials, double factor);

/// Runs the trials (each a run_mpm_case of the case with options.strength_factor set)
/// and writes strength_reduction.csv and mechanism.png into out_dir.
void run_strength_reduction(CaseFile& cf, const std::filesystem::path& out_dir, const MpmRunOptions& options,
                            const StrengthReductionSettings& settings);

}  // namespace gradmpm
