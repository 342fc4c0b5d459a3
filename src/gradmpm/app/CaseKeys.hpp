#pragma once
// Every section and key of the case files, declared once (io/Keys.hpp): the readers
// take defaults, ranges and messages from here, CaseFile takes the valid keys, and
// `gradmpm keys` renders docs/case-files.md's tables. Defaults that code building a
// model without a case file also needs live in the settings structs (NewtonSettings,
// LinearSolverSettings, MpmOutputSettings, ...) and are taken from there.
#include <string>
#include <vector>

#include "gradmpm/io/Keys.hpp"

namespace gradmpm {

/// [linear_solver], shared by the bar and the MPM cases.
const SectionSpec& linear_solver_section();
/// [gradient] of MPM cases and of the bar as MPM (variant defaults to "none").
const SectionSpec& gradient_section();
/// [regularisation] of MPM cases (implicit-gradient plasticity).
const SectionSpec& regularisation_section();
/// [gradient] of the bar as MPM: gradient_section(), required.
const SectionSpec& bar_mpm_gradient_section();
/// [gradient] of the FEM bar: variant and length_scale, variant required.
const SectionSpec& bar_gradient_section();

/// The bar: [bar], [output]; and [mpm] for the bar as MPM.
const SectionSpec& bar_section();
const SectionSpec& bar_output_section();
const SectionSpec& bar_mpm_section();

/// MPM cases, in the order the docs list them. [materials.NAME] holds `model` plus the
/// keys of the law it names (MaterialRegistry).
const std::vector<SectionSpec>& mpm_sections();
const SectionSpec& mpm_section(const std::string& name);

/// The declaration of a key of an MPM case ("load_steps.count", "bodies[2].min",
/// "materials.soil.density": the law the section's `model` names), or nullptr.
const KeySpec* mpm_key_spec(const CaseFile& cf, const std::string& key);
/// CaseFile::canonical_text of an MPM case: keys given at their default dropped.
std::string mpm_canonical_text(const CaseFile& cf);

}  // namespace gradmpm
