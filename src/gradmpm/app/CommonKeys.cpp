#include "gradmpm/app/CommonKeys.hpp"

#include <fmt/format.h>

#include "gradmpm/app/CaseKeys.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

void declare_linear_solver_section(CaseFile& cf) {
  for (const char* old : {"solver.linear", "nonlinear_solver.linear_solver"})
    if (cf.has(old))
      throw InputError(
          fmt::format("{}: {}: this key is now [linear_solver] type (docs/case-files.md)", cf.name(), old));
  cf.declare(linear_solver_section());
}

LinearSolverSettings read_linear_solver_settings(const CaseFile& cf) {
  const auto& registry = LinearSolverRegistry::instance();
  const SectionSpec& sec = linear_solver_section();
  LinearSolverSettings s;
  // On several MPI ranks PETSc distributes the solves (docs/parallel.md): the default there,
  // and the only choice.
  KeySpec type_key = sec.key("type");
  if (ranks::distributed()) type_key.default_value = std::string("petsc");
  s.type = read_string(cf, sec.name, type_key);
  const LinearSolverInfo* type = registry.find(s.type);
  cf.require(type != nullptr, "linear_solver.type", sec.key("type").expected());
  cf.require(!ranks::distributed() || s.type == "petsc", "linear_solver.type",
             fmt::format("\"petsc\" on {} MPI ranks (with options = \"-ksp_type preonly -pc_type lu "
                         "-pc_factor_mat_solver_type mumps\" for a direct solve)",
                         ranks::size()));
  // A solver of general matrices solves the case's non-symmetric ones too, unless the
  // case names another ("petsc" then serves every system).
  KeySpec general_key = sec.key("general");
  if (type->general) general_key.default_value = s.type;
  s.general = read_string(cf, sec.name, general_key);
  const auto* general = registry.find(s.general);
  cf.require(general && general->general, "linear_solver.general", sec.key("general").expected());
  s.pcg_tolerance = read_number(cf, sec.name, sec.key("pcg_tolerance"));
  s.pcg_max_iterations = static_cast<int>(read_integer(cf, sec.name, sec.key("pcg_max_iterations")));
  s.options = read_string(cf, sec.name, sec.key("options"));
  cf.require(s.options.empty() || type->takes_options, "linear_solver.options",
             fmt::format("no options: \"{}\" takes none", s.type));
  if (!s.options.empty() && type->check_options)
    if (const std::string expected = type->check_options(s); !expected.empty())
      cf.require(false, "linear_solver.options", expected);
  return s;
}

GradientSettings read_gradient_settings(const CaseFile& cf) {
  const SectionSpec& sec = gradient_section();
  GradientSettings g;
  g.variant = *parse_gradient_variant(read_string(cf, sec.name, sec.key("variant")));
  if (g.variant == GradientVariant::None) {
    for (const char* k : {"length_scale", "apply", "fields"})
      cf.require(!cf.has(sec.name + "." + k), sec.name + "." + k,
                 "no such key when gradient.variant = \"none\" (it would have no effect)");
    return g;
  }
  g.length_scale = read_number(cf, sec.name, sec.key("length_scale"));
  g.apply = read_string(cf, sec.name, sec.key("apply")) == "end" ? GradientApply::End : GradientApply::EachStep;
  KeySpec fields = sec.key("fields");
  fields.default_value = std::string(g.apply == GradientApply::End ? "grid" : "points");
  g.fields = read_string(cf, sec.name, fields) == "grid" ? GradientFields::Grid : GradientFields::Points;
  cf.require(!(g.apply == GradientApply::End && g.fields == GradientFields::Points), "gradient.fields",
             "\"grid\" when gradient.apply = \"end\" (a single smoothing at the end has nothing for the points "
             "to carry between steps)");
  return g;
}

}  // namespace gradmpm
