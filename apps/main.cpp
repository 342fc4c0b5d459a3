// gradmpm: implicit material point method with gradient elasticity.
//
//   gradmpm run CASE.toml [--out DIR] [--set section.key=value ...] [--restart CHECKPOINT]
//   gradmpm keys [bar|bar-mpm|mpm]      the case-file keys as markdown tables
//
// Exit codes: 0 success, 1 numerical or plotting failure, 2 bad input (case file,
// key, value, command line, or an output path that cannot be written; or `run` started
// as several MPI ranks, which is not supported yet).
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <omp.h>
#include <unistd.h>

#include <cstdlib>
#include <exception>

#include "gradmpm/app/KeysDoc.hpp"
#include "gradmpm/app/MpiLaunch.hpp"
#include "gradmpm/app/RunCase.hpp"
#include "gradmpm/core/Errors.hpp"

namespace {
// GNU OpenMP's idle threads spin while they wait for work: on a machine shared with other
// processes that made runs 10-25x slower than one thread (issue 12). libgomp reads
// OMP_WAIT_POLICY when it is loaded, before main, so the first start sets it to passive and
// executes itself again. A user's own OMP_WAIT_POLICY is kept.
void prefer_passive_openmp(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GRADMPM_KEEP_OPENMP")) return;
  ::setenv("OMP_WAIT_POLICY", "passive", 1);
  ::setenv("GRADMPM_KEEP_OPENMP", "1", 1);  // never twice, whatever exec does
  ::execv("/proc/self/exe", argv);          // returns only when it fails: run on as we are
}
}  // namespace

int main(int argc, char** argv) {
  prefer_passive_openmp(argv);
  CLI::App app{
      "gradmpm: implicit quasi-static Material Point Method with Ru-Aifantis gradient elasticity.\n"
      "Each analysis is described by a TOML case file (see examples/ and docs/case-files.md)."};
  app.set_version_flag("--version", std::string("gradmpm ") + GRADMPM_VERSION);
  app.require_subcommand(1);

  gradmpm::RunOptions options;
  std::string case_file;
  CLI::App* run =
      app.add_subcommand("run",
                         "Run the analysis a case file describes and write its outputs (CSV, plots) to DIR.\n"
                         "Exit codes: 0 success, 1 numerical or plotting failure, 2 bad input or unwritable output.");
  run->add_option("case", case_file, "TOML case file, e.g. examples/bar_bimaterial.toml")->required();
  run->add_option("-o,--out", options.out, "output directory (created if needed; default out/<case name>)");
  run->add_option("-s,--set", options.overrides,
                  "override a case-file key, e.g. --set bar.elements=160 --set gradient.variant=e-RA\n"
                  "(repeatable; the value is read as TOML, or as a plain string)")
      ->type_name("KEY=VALUE");
  run->add_flag("-q,--quiet", options.quiet, "print nothing on success");
  run->add_option("--restart", options.restart,
                  "continue from a checkpoint (DIR.checkpoints/step_NNNNNN, written with output.checkpoint_every) of "
                  "the same case and --set options; the final outputs are the uninterrupted run's")
      ->type_name("CHECKPOINT");
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

  if (run->parsed()) {
    // Not distributed yet (issue 14): every rank would run the whole case into the same
    // folder. One message (rank 0's), the same exit code on every rank.
    if (const gradmpm::MpiLaunch mpi = gradmpm::mpi_launch_from_environment(); mpi.size > 1) {
      if (mpi.rank == 0)
        fmt::print(stderr,
                   "gradmpm: error: started as {} MPI ranks, but gradmpm does not run distributed yet: run it "
                   "without mpirun (one process uses every core, --threads N)\n",
                   mpi.size);
      return 2;
    }
  }

  try {
    if (run->parsed() && threads > 0) omp_set_num_threads(threads);
    if (run->parsed()) gradmpm::run_case(case_file, options);
    if (keys->parsed() && update_doc.empty()) fmt::print("{}", gradmpm::keys_markdown(keys_kind));
    if (keys->parsed() && !update_doc.empty()) gradmpm::update_generated_keys(update_doc);
    return 0;
  } catch (const gradmpm::UserError& e) {  // bad input or an unwritable output path
    fmt::print(stderr, "gradmpm: error: {}\n", e.what());
    return 2;
  } catch (const gradmpm::SolverError& e) {
    fmt::print(stderr, "gradmpm: solver failure: {}\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "gradmpm: failure: {}\n", e.what());
    return 1;
  }
}
