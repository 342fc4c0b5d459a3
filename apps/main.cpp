// gradmpm: implicit material point method with gradient elasticity.
//
//   gradmpm run CASE.toml [--out DIR] [--set section.key=value ...] [--restart CHECKPOINT]
//   gradmpm keys [bar|bar-mpm|mpm]      the case-file keys as markdown tables
//
// Exit codes: 0 success, 1 numerical or plotting failure, 2 bad input (case file,
// key, value, command line, or an output path that cannot be written).
//
//   mpirun -n N gradmpm run CASE.toml ...   the same run on N MPI ranks (docs/parallel.md)
//   --no-tuning (or GRADMPM_TUNING=0)       the runtimes untuned (tuning/ProcessTuning.hpp)
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <optional>

#include "gradmpm/app/KeysDoc.hpp"
#include "gradmpm/app/MpiLaunch.hpp"
#include "gradmpm/app/RunCase.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Ranks.hpp"

int main(int argc, char** argv) {
  // The process tuning was decided before main (tuning/ProcessTuning.hpp).
  CLI::App app{
      "gradmpm: implicit quasi-static Material Point Method with Ru-Aifantis gradient elasticity.\n"
      "Each analysis is described by a TOML case file (see examples/ and docs/case-files.md)."};
  app.set_version_flag("--version", std::string("gradmpm ") + GRADMPM_VERSION);
  app.require_subcommand(1);
  app.fallthrough();  // --no-tuning after the subcommand too
  bool no_tuning = false;  // acted on before main (tuning/ProcessTuning.hpp); taken here so it parses
  app.add_flag("--no-tuning", no_tuning,
               "leave the runtimes as their defaults and the environment say: no passive OpenMP waiting, freed "
               "memory returned, no serial regions as calls, no BLAS threads set (as GRADMPM_TUNING=0; docs/performance.md)");

  // An empty path is a mistake (a shell variable that was not set), never "the default".
  const CLI::Validator non_empty(
      [](const std::string& v) { return v.empty() ? std::string("expected a path, got an empty one") : std::string(); },
      "PATH");
  gradmpm::RunOptions options;
  std::string case_file;
  CLI::App* run =
      app.add_subcommand("run",
                         "Run the analysis a case file describes and write its outputs (CSV, plots) to DIR.\n"
                         "Exit codes: 0 success, 1 numerical or plotting failure, 2 bad input or unwritable output.");
  run->add_option("case", case_file, "TOML case file, e.g. examples/bar_bimaterial.toml")->required();
  run->add_option("-o,--out", options.out, "output directory (created if needed; default out/<case name>)")
      ->check(non_empty);
  run->add_option("-s,--set", options.overrides,
                  "override a case-file key, e.g. --set bar.elements=160 --set gradient.variant=e-RA\n"
                  "(repeatable; the value is read as TOML, or as a plain string)")
      ->type_name("KEY=VALUE");
  run->add_flag("-q,--quiet", options.quiet, "print nothing on success");
  run->add_option("--restart", options.restart,
                  "continue from a checkpoint (DIR.checkpoints/step_NNNNNN, written with output.checkpoint_every) of "
                  "the same case and --set options; the final outputs are the uninterrupted run's")
      ->type_name("CHECKPOINT")
      ->check(non_empty);
  int threads = 0;
  run->add_option("-j,--threads", threads,
                  "OpenMP threads of the point loops and the solvers (default: OMP_NUM_THREADS, else every core)")
      ->check(CLI::Range(1, 1024));

  std::string keys_kind = "mpm";
  CLI::App* keys = app.add_subcommand(
      "keys",
      "Print the case-file keys of KIND (bar, bar-mpm or mpm) as markdown tables: type, default, allowed values, "
      "meaning. docs/case-files.md holds the same tables (scripts/update-docs).");
  keys->add_option("kind", keys_kind, "bar, bar-mpm or mpm (default)");
  std::string update_doc;
  keys->add_option("--update", update_doc,
                   "instead of printing, rewrite the tables between <!-- keys KIND --> and <!-- /keys --> in FILE "
                   "(docs/case-files.md)")
      ->type_name("FILE");

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --help-all, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "gradmpm: error: {}\nRun 'gradmpm --help' for usage.\n", e.what());
    return 2;
  }

  // Several MPI ranks (mpirun -n N): MPI runs for the life of main (docs/parallel.md).
  const gradmpm::MpiLaunch mpi = gradmpm::mpi_launch_from_environment();
#ifndef GRADMPM_WITH_PETSC
  if (run->parsed() && mpi.size > 1) {
    if (mpi.rank == 0)
      fmt::print(stderr, "gradmpm: error: started as {} MPI ranks, but this build has no MPI (built without PETSc)\n",
                 mpi.size);
    return 2;
  }
#endif
  std::optional<gradmpm::ranks::Session> session;
  if (run->parsed() && mpi.size > 1) {
    session.emplace(&argc, &argv);
    // The ranks of one machine share its cores: each gets its share of OpenMP threads.
    if (threads == 0 && !std::getenv("OMP_NUM_THREADS")) {
      const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
      const int on_this_machine = local ? std::max(1, std::atoi(local)) : mpi.size;
      threads = std::max(1, omp_get_num_procs() / on_this_machine);
    }
  }
  // One message (rank 0's) for an error every rank meets (the same input, the same
  // numbers); an error only one rank can meet (its own files) stops every rank.
  const bool speaks = gradmpm::ranks::rank() == 0;
  auto fail = [&](bool everywhere, int code, const char* kind, const char* what) {
    if (speaks || !everywhere) fmt::print(stderr, "gradmpm: {}: {}\n", kind, what);
    if (!everywhere) gradmpm::ranks::abort(code);
    return code;
  };

  try {
    if (run->parsed() && threads > 0) omp_set_num_threads(threads);
    if (run->parsed()) gradmpm::run_case(case_file, options);
    if (keys->parsed() && update_doc.empty()) fmt::print("{}", gradmpm::keys_markdown(keys_kind));
    if (keys->parsed() && !update_doc.empty()) gradmpm::update_generated_keys(update_doc);
    return 0;
  } catch (const gradmpm::OutputError& e) {  // an unwritable output path (rank 0's files)
    return fail(!gradmpm::ranks::distributed(), 2, "error", e.what());
  } catch (const gradmpm::UserError& e) {  // bad input
    return fail(true, 2, "error", e.what());
  } catch (const gradmpm::SolverError& e) {
    return fail(true, 1, "solver failure", e.what());
  } catch (const std::exception& e) {
    return fail(!gradmpm::ranks::distributed(), 1, "failure", e.what());
  }
}
