#include "gradmpm/app/RunCase.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <optional>

#include "gradmpm/app/BarCase.hpp"
#include "gradmpm/app/Checkpoint.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/io/RunFolder.hpp"
#include "gradmpm/io/StagedOutputs.hpp"

namespace gradmpm {

namespace {
void run_bar(CaseFile& cf, const std::filesystem::path& out_dir, bool quiet) {
  BarOutputOptions output;
  BarMpmConfig mpm;
  const bool as_mpm = cf.has_section("mpm");
  const BarConfig config = read_bar_config(cf, output, as_mpm ? &mpm : nullptr);
  StagedOutputs out(out_dir);  // fails now, before solving, if the directory is unusable

  double gradient_s = 0, classical_s = 0;
  const BarResult r = as_mpm ? solve_bar_mpm(mpm, &gradient_s, &classical_s) : solve_bar(config);
  const double err = bar_strain_error(config, r);
  write_bar_outputs(config, r, out, output);

  if (quiet) return;
  if (as_mpm)
    fmt::print(
        "gradmpm: bi-material bar as MPM, {} elements, {} points, {} load steps, basis {}, variant {} with l = {:g}\n",
        config.elements, r.points.size(), mpm.load_steps, to_string(mpm.basis), to_string(config.variant),
        config.length_scale);
  else
    fmt::print("gradmpm: bi-material bar, {} elements, {} points, {} dofs, variant {} with l = {:g}\n", config.elements,
               r.points.size(), r.dofs, to_string(config.variant), config.length_scale);
  fmt::print("  classical stress at x = 0: {:.10g}; gradient strain vs closed form: max relative error {:.3e}\n",
             r.stress_classical[0], err);
  if (as_mpm)
    fmt::print("  time: classical MPM {:.3g} s, gradient step {:.3g} s ({:.1f} %)\n", classical_s, gradient_s,
               100.0 * gradient_s / std::max(classical_s, 1e-12));
  else
    fmt::print("  time: assembly {:.3g} s, classical solve {:.3g} s, gradient step {:.3g} s, recovery {:.3g} s\n",
               r.timings.assembly_s, r.timings.classical_solve_s, r.timings.gradient_s, r.timings.recovery_s);
}
/// A distributed run (core/Ranks.hpp): every rank solves, rank 0 alone prints and writes
/// the output folder but for the other ranks' pieces of the points' VTU files and their
/// points' files of a checkpoint (the others write nothing else; they are given a scratch
/// folder of their own, removed at the end).
/// Whether rank 0 could open the folder is told to every rank before any solving.
void run_on_ranks(CaseFile& cf, const std::filesystem::path& out_dir, const RunOptions& options) {
  namespace fs = std::filesystem;
  std::optional<RunFolder> folder;
  std::string problem;
  if (ranks::rank() == 0) try {
      folder.emplace(out_dir);
    } catch (const OutputError& e) {
      problem = e.what();
    }
  const std::vector<char> told = ranks::broadcast(std::vector<char>(problem.begin(), problem.end()));
  if (!told.empty()) throw UserError(std::string(told.begin(), told.end()));  // every rank, one message
  // Rank 0's output folder, where every rank writes its piece of the points' VTU files (a
  // file system the ranks share, as on a cluster).
  const std::string staging = folder ? folder->staging().string() : std::string();
  const std::vector<char> shared = ranks::broadcast(std::vector<char>(staging.begin(), staging.end()));
  // And its checkpoint folder, where every rank writes its points' file of a checkpoint.
  const std::string beside = folder ? checkpoint_folder_of(folder->dir()).string() : std::string();
  const std::vector<char> checkpoints = ranks::broadcast(std::vector<char>(beside.begin(), beside.end()));
  fs::path scratch;
  if (!folder) {
    scratch = fs::temp_directory_path() / fmt::format("gradmpm-rank{}-{}", ranks::rank(), ::getpid());
    fs::create_directories(scratch);
  }
  struct Remove {
    fs::path dir;
    ~Remove() {
      std::error_code ignored;
      if (!dir.empty()) fs::remove_all(dir, ignored);
    }
  } remove{scratch};
  const fs::path dir = folder ? folder->staging() : scratch;
  const MpmRunOptions run{.quiet = options.quiet || !folder,
                          .shown = out_dir,
                          .checkpoints = std::string(checkpoints.begin(), checkpoints.end()),
                          .restart = options.restart,
                          .pieces = std::string(shared.begin(), shared.end())};
  try {
    run_mpm_case(cf, dir, run);
  } catch (const SolverError&) {
    if (folder) folder->publish();
    throw;
  }
  if (!folder) return;
  folder->publish();
  if (!options.quiet) fmt::print("  wrote {}: {}\n", out_dir.string(), folder->summary());
}
}  // namespace

void run_case(const std::filesystem::path& case_file, const RunOptions& options) {
  CaseFile cf = CaseFile::load(case_file, options.overrides);
  const std::filesystem::path out_dir =
      options.out.empty() ? std::filesystem::path("out") / case_file.stem() : options.out;
  const bool bar = cf.has_section("bar"), mpm = cf.has_section("grid");
  if (bar && mpm)
    throw InputError(
        fmt::format("{}: both [bar] and [grid]: a case is either the 1D bar or an MPM analysis", cf.name()));
  if (!bar && !mpm)
    throw InputError(fmt::format(
        "{}: no problem section found; expected [bar] (1D bar) or [grid] (MPM) (see examples/)", cf.name()));
  if (bar && !options.restart.empty())
    throw InputError(fmt::format("--restart {}: {} is a 1D bar case, which has no checkpoints (MPM cases only)",
                                 options.restart.string(), cf.name()));
  if (ranks::distributed()) {
    if (bar) throw InputError(fmt::format("{}: the 1D bar runs on one process: start it without mpirun", cf.name()));
    return run_on_ranks(cf, out_dir, options);
  }
  // The run writes into a staging folder and publishes it whole (io/RunFolder.hpp): a
  // numerical failure publishes its converged steps; anything else leaves out_dir as it was.
  RunFolder folder(out_dir);
  try {
    if (bar)
      run_bar(cf, folder.staging(), options.quiet);
    else
      run_mpm_case(cf, folder.staging(),
                   MpmRunOptions{.quiet = options.quiet,
                                 .shown = out_dir,
                                 .checkpoints = checkpoint_folder_of(folder.dir()),
                                 .restart = options.restart});
  } catch (const SolverError&) {
    folder.publish();
    throw;
  } catch (const OutputError& e) {  // (a full disk): name DIR, not the hidden staging folder
    throw OutputError(folder.shown_as(e.what(), out_dir));
  }
  folder.publish();
  if (!options.quiet) fmt::print("  wrote {}: {}\n", out_dir.string(), folder.summary());
}

}  // namespace gradmpm
