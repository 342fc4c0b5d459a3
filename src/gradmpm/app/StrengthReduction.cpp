#include "gradmpm/app/StrengthReduction.hpp"

#include <fmt/format.h>

#include <cmath>

#include "gradmpm/app/CaseKeys.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/core/Timer.hpp"
#include "gradmpm/io/EmbeddedScripts.hpp"
#include "gradmpm/io/Python.hpp"
#include "gradmpm/io/StagedOutputs.hpp"

namespace gradmpm {

namespace fs = std::filesystem;

std::optional<StrengthReductionSettings> read_strength_reduction(const CaseFile& cf) {
  const SectionSpec& a = mpm_section("analysis");
  const std::string type = read_string(cf, a.name, a.key("type"));
  // (With "load-steps" the other keys are left unread: --set analysis.type=load-steps runs
  // a strength-reduction case once, as written.)
  if (type != "strength-reduction") return std::nullopt;
  StrengthReductionSettings s;
  s.first_factor = read_number(cf, a.name, a.key("first_factor"));
  s.min_factor = read_number(cf, a.name, a.key("min_factor"));
  s.max_factor = read_number(cf, a.name, a.key("max_factor"));
  s.tolerance = read_number(cf, a.name, a.key("tolerance"));
  cf.require(cf.has("analysis.failure_displacement"), "analysis.failure_displacement",
             "a length > 0 with analysis.type = \"strength-reduction\" (a trial fails where a point moves farther: "
             "docs/strength-reduction.md)");
  s.failure_displacement = read_number(cf, a.name, a.key("failure_displacement"));
  cf.require(s.min_factor < s.first_factor, "analysis.min_factor",
             fmt::format("a factor below analysis.first_factor = {:g}", s.first_factor));
  cf.require(s.first_factor < s.max_factor, "analysis.max_factor",
             fmt::format("a factor above analysis.first_factor = {:g}", s.first_factor));
  // Each trial runs the case's load steps from its start to load factor 1.
  const std::string why = "no such section with analysis.type = \"strength-reduction\" (each trial runs [load_steps])";
  cf.require(!cf.has_section("time"), "time", why);
  cf.require(!cf.has_section("arc_length"), "arc_length", why);
  cf.require(!ranks::distributed(), "analysis.type",
             "\"load-steps\" in a run on more than one rank (the strength-reduction trials run on one)");
  cf.require(!cf.has("output.checkpoint_every") || cf.integer("output.checkpoint_every") == 0,
             "output.checkpoint_every", "0 with analysis.type = \"strength-reduction\" (its trials start afresh)");
  return s;
}

void reduce_strengths(const CaseFile& cf, std::vector<std::shared_ptr<const Material>>& materials, double factor) {
  const std::vector<std::string> names = cf.subsections("materials");
  bool any = false;
  for (std::size_t i = 0; i < materials.size(); ++i) {
    std::shared_ptr<const Material> reduced = materials[i]->strength_reduced(factor);
    const std::string key = "materials." + (i < names.size() ? names[i] : std::to_string(i)) + ".model";
    cf.require(reduced != nullptr || !materials[i]->has_strength(), key,
               fmt::format("a law whose strength a strength-reduction analysis can divide (mohr-coulomb, "
                           "drucker-prager, von-mises; \"{}\" has none)",
                           materials[i]->model()));
    if (!reduced) continue;
    materials[i] = std::move(reduced);
    any = true;
  }
  cf.require(any, "analysis.type",
             "\"load-steps\" here: no material has a strength to reduce (mohr-coulomb, drucker-prager, von-mises)");
}

namespace {

struct Trial {
  double factor = 0.0;
  bool stands = false;
  MpmRunProgress progress;
  double seconds = 0.0;
  std::string folder;  ///< relative to the output folder
  std::string failure;
};

/// Runs the case once with its strengths divided by `factor` into out_dir/trials/NN_F...
Trial run_trial(CaseFile& cf, const fs::path& out_dir, const fs::path& shown, int number, double factor,
                double failure_displacement) {
  Trial t;
  t.factor = factor;
  t.folder = fmt::format("trials/{:02d}_F{:.4f}", number, factor);
  const fs::path dir = out_dir / t.folder;
  fs::create_directories(dir);
  MpmRunOptions trial{.quiet = true, .shown = shown / t.folder};
  trial.strength_trial = StrengthTrial{factor, failure_displacement};
  trial.progress = &t.progress;
  const auto t0 = Clock::now();
  try {
    run_mpm_case(cf, dir, trial);
    t.stands = true;
  } catch (const SolverError& e) {
    t.failure = e.what();
  }
  t.seconds = seconds_since(t0);
  return t;
}

std::string csv_row(int number, const Trial& t) {
  return fmt::format("{},{},{},{},{},{},{},{},{},{}\n", number, t.factor, t.stands ? 1 : 0, t.progress.load_factor,
                     t.progress.steps, t.progress.iterations, t.progress.cuts, t.progress.max_displacement, t.seconds,
                     t.folder);
}

/// The next factor to try: doubled (halved) until a trial has stood and one has failed,
/// then halfway; none when the search is done or out of its range.
std::optional<double> next_factor(const StrengthReductionSettings& s, const std::optional<double>& stood,
                                  const std::optional<double>& failed) {
  if (stood && failed) {
    if (*failed - *stood <= s.tolerance * (1.0 + 1e-12)) return std::nullopt;
    return 0.5 * (*stood + *failed);
  }
  if (stood) return *stood >= s.max_factor ? std::nullopt : std::optional<double>(std::min(2.0 * *stood, s.max_factor));
  return *failed <= s.min_factor ? std::nullopt : std::optional<double>(std::max(0.5 * *failed, s.min_factor));
}

}  // namespace

void run_strength_reduction(CaseFile& cf, const fs::path& out_dir, const MpmRunOptions& options,
                            const StrengthReductionSettings& s) {
  if (!options.restart.empty())
    throw InputError(fmt::format("--restart {}: {} is a strength-reduction analysis, whose trials start afresh "
                                 "(it writes no checkpoints)",
                                 options.restart.string(), cf.name()));
  const fs::path shown = options.shown.empty() ? out_dir : options.shown;
  std::string csv = "trial,factor,stands,load_factor,steps,newton_iterations,cuts,max_displacement,seconds,folder\n";
  std::optional<double> stood, failed;
  std::optional<Trial> best;  ///< the trial of the largest factor that stood
  std::optional<double> factor = s.first_factor;
  for (int number = 1; factor; ++number) {
    const Trial t = run_trial(cf, out_dir, shown, number, *factor, s.failure_displacement);
    csv += csv_row(number, t);
    {  // after every trial, whole: a long search stopped keeps the rows so far
      StagedOutputs out(out_dir);
      out.write_text("strength_reduction.csv", csv);
      out.commit();
    }
    if (!options.quiet && number == 1)  // (after the first trial: a case it refuses prints its error alone)
      fmt::print("gradmpm: strength reduction: c / F and tan(phi) / F (sigma_y / F), the case's load steps per trial; "
                 "F from {:g}, to within {:g}\n",
                 s.first_factor, s.tolerance);
    if (!options.quiet)
      fmt::print("  trial {:2d}  F {:.4f}  {}  load factor {:.4f}  steps {}  iterations {}  cuts {}  max |u| {:.3g}  "
                 "({:.2f} s)\n",
                 number, t.factor, t.stands ? "stands" : "fails ", t.progress.load_factor, t.progress.steps,
                 t.progress.iterations, t.progress.cuts, t.progress.max_displacement, t.seconds);
    if (t.stands) {
      stood = t.factor;
      best = t;
    } else {
      failed = t.factor;
    }
    factor = next_factor(s, stood, failed);
  }
  const bool plot = best && failed && mpm_case_dimension(cf) == 2 &&
                    read_boolean(cf, "output", mpm_section("output").key("plot"));
  if (plot) {
    StagedOutputs out(out_dir);
    const fs::path png = out.stage("mechanism.png");
    run_python_script(embedded::plot_points_py,
                      {(out_dir / best->folder / "points_final.csv").string(), png.string(), "eps_p",
                       fmt::format("eps_p at F = {:.4f}, the largest factor that stood (F = {:.4f} failed)",
                                   best->factor, *failed)});
    out.commit();
  }
  if (options.quiet) return;
  if (stood && failed)
    fmt::print("  factor of safety {:.4f} (it stands at F = {:.4f} and fails at F = {:.4f})\n", *stood, *stood,
               *failed);
  else if (stood)
    fmt::print("  factor of safety above analysis.max_factor = {:g}: every trial stood\n", s.max_factor);
  else
    fmt::print("  factor of safety below analysis.min_factor = {:g}: every trial failed (the trials' folders say "
               "where each stopped)\n",
               s.min_factor);
  fmt::print("  the trials' outputs are in {}\n", (shown / "trials").string());
}

}  // namespace gradmpm
