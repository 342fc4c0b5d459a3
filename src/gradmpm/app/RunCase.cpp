#include "gradmpm/app/RunCase.hpp"

#include <fmt/format.h>

#include "gradmpm/app/BarCase.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/io/StagedOutputs.hpp"

namespace gradmpm {

namespace {
void run_bar(CaseFile& cf, const std::filesystem::path& out_dir, bool quiet) {
  BarOutputOptions output;
  const BarConfig config = read_bar_config(cf, output);
  StagedOutputs out(out_dir);  // fails now, before solving, if the directory is unusable

  const BarResult r = solve_bar(config);
  const double err = bar_strain_error(config, r);
  write_bar_outputs(config, r, out, output);

  if (quiet) return;
  fmt::print("gradmpm: bi-material bar, {} elements, {} points, {} dofs, variant {} with l = {:g}\n",
             config.elements, r.points.size(), r.dofs, to_string(config.variant), config.length_scale);
  fmt::print("  classical stress {:.10g}; gradient strain vs closed form: max relative error {:.3e}\n",
             r.stress_classical[0], err);
  fmt::print("  time: assembly {:.3g} s, classical solve {:.3g} s, gradient step {:.3g} s, recovery {:.3g} s\n",
             r.timings.assembly_s, r.timings.classical_solve_s, r.timings.gradient_s, r.timings.recovery_s);
  for (const auto& f : out.committed()) fmt::print("  wrote {}\n", f.string());
}
}  // namespace

void run_case(const std::filesystem::path& case_file, const RunOptions& options) {
  CaseFile cf = CaseFile::load(case_file, options.overrides);
  const std::filesystem::path out_dir =
      options.out.empty() ? std::filesystem::path("out") / case_file.stem() : options.out;
  if (cf.has_section("bar")) return run_bar(cf, out_dir, options.quiet);
  throw InputError(fmt::format("{}: no problem section found; expected [bar] (see examples/)", cf.name()));
}

}  // namespace gradmpm
