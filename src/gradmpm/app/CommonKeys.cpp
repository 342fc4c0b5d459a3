#include "gradmpm/app/CommonKeys.hpp"

#include <fmt/format.h>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

void declare_linear_solver_section(CaseFile& cf) {
  for (const char* old : {"solver.linear", "nonlinear_solver.linear_solver"})
    if (cf.has(old))
      throw InputError(fmt::format("{}: {}: this key is now [linear_solver] type (docs/case-files.md)", cf.name(), old));
  cf.declare_section("linear_solver", {"type", "general", "pcg_tolerance", "pcg_max_iterations"}, false);
}

LinearSolverSettings read_linear_solver_settings(const CaseFile& cf) {
  const auto& registry = LinearSolverRegistry::instance();
  LinearSolverSettings s;
  s.type = cf.string_or("linear_solver.type", s.type);
  cf.require(registry.find(s.type) != nullptr, "linear_solver.type", "one of " + registry.quoted_names());
  s.general = cf.string_or("linear_solver.general", s.general);
  const auto* general = registry.find(s.general);
  cf.require(general && general->general, "linear_solver.general",
             "a solver of general matrices, one of " + registry.quoted_names(true));
  s.pcg_tolerance = cf.number_or("linear_solver.pcg_tolerance", s.pcg_tolerance);
  cf.require(s.pcg_tolerance > 0.0 && s.pcg_tolerance < 1.0, "linear_solver.pcg_tolerance", "a number in (0, 1)");
  const long long its = cf.integer_or("linear_solver.pcg_max_iterations", s.pcg_max_iterations);
  cf.require(its >= 0 && its <= 100'000'000, "linear_solver.pcg_max_iterations",
             "an integer from 0 (scaled to the problem) to 100000000");
  s.pcg_max_iterations = static_cast<int>(its);
  return s;
}

GradientSettings read_gradient_settings(const CaseFile& cf) {
  GradientSettings g;
  const auto v = parse_gradient_variant(cf.string_or("gradient.variant", "none"));
  cf.require(v.has_value(), "gradient.variant", "one of \"u-RA\", \"e-RA\", \"s-RA\", \"none\"");
  g.variant = *v;
  if (g.variant == GradientVariant::None) {
    for (const char* k : {"gradient.length_scale", "gradient.apply", "gradient.fields"})
      cf.require(!cf.has(k), k, "no such key when gradient.variant = \"none\" (it would have no effect)");
    return g;
  }
  g.length_scale = cf.number("gradient.length_scale");
  cf.require(g.length_scale >= 0.0, "gradient.length_scale", "a length scale l >= 0");
  const std::string apply = cf.string_or("gradient.apply", "each_step");
  cf.require(apply == "each_step" || apply == "end", "gradient.apply", "\"each_step\" or \"end\"");
  g.apply = apply == "end" ? GradientApply::End : GradientApply::EachStep;
  const std::string fields = cf.string_or("gradient.fields", g.apply == GradientApply::End ? "grid" : "points");
  cf.require(fields == "points" || fields == "grid", "gradient.fields", "\"points\" or \"grid\"");
  g.fields = fields == "grid" ? GradientFields::Grid : GradientFields::Points;
  cf.require(!(g.apply == GradientApply::End && g.fields == GradientFields::Points), "gradient.fields",
             "\"grid\" when gradient.apply = \"end\" (a single smoothing at the end has nothing for the points "
             "to carry between steps)");
  return g;
}

}  // namespace gradmpm
