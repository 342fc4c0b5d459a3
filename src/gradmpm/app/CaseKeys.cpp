#include "gradmpm/app/CaseKeys.hpp"

#include <stdexcept>

#include "gradmpm/app/BarCase.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/app/StrengthReduction.hpp"
#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/materials/MaterialRegistry.hpp"
#include "gradmpm/solver/linear/LinearSolver.hpp"

namespace gradmpm {

// The key tables are laid out by hand: one key per line or two reads as a table;
// clang-format would give every field its own line.
// clang-format off

namespace {
using K = KeyType;

KeySpec variant_key(bool required) {
  KeySpec k{.name = "variant", .type = K::String, .choices = {"u-RA", "e-RA", "s-RA", "none"},
            .doc = "which field the Ru-Aifantis step smooths (docs/gradient-study.md)"};
  if (!required) k.default_value = std::string("none");
  return k;
}
KeySpec length_scale_key(const char* default_text) {
  return {.name = "length_scale", .type = K::Number, .default_text = default_text, .min = 0.0,
          .allowed = "a length scale l >= 0", .doc = "l, the internal length"};
}
}  // namespace

const SectionSpec& linear_solver_section() {
  static const SectionSpec s = [] {
    const auto& r = LinearSolverRegistry::instance();
    std::string types, generals;
    for (const auto& info : r.all()) types += (types.empty() ? "" : "; ") + ("`\"" + info.name + "\"`: " + info.doc);
    return SectionSpec{
        "linear_solver", SectionKind::Section, false, "the sparse linear solver of every system the case solves",
        {{.name = "type", .type = K::String, .default_value = LinearSolverSettings{}.type,
          .allowed = "one of " + r.quoted_names(),
          .doc = "solver of the symmetric systems (the tangent when every material's is symmetric, the Helmholtz "
                 "systems): " + types},
         {.name = "general", .type = K::String, .default_value = LinearSolverSettings{}.general,
          .default_text = "`type` when it solves general matrices, else \"umfpack\"",
          .allowed = "a solver of general matrices, one of " + r.quoted_names(true),
          .doc = "solver of non-symmetric tangents and of a symmetric tangent that `type` finds not positive definite"},
         {.name = "pcg_tolerance", .type = K::Number, .default_value = LinearSolverSettings{}.pcg_tolerance, .min = 0.0, .max = 1.0, .min_open = true,
          .max_open = true, .doc = "relative residual at which \"pcg\" stops"},
         {.name = "pcg_max_iterations", .type = K::Integer, .default_value = static_cast<long long>(LinearSolverSettings{}.pcg_max_iterations), .min = 0.0, .max = 1e8,
          .allowed = "an integer from 0 (scaled to the problem) to 100000000",
          .doc = "iteration limit of \"pcg\"; 0: max(200, 20 sqrt(n)); not converging is a solver failure"},
         {.name = "options", .type = K::String, .default_value = LinearSolverSettings{}.options,
          .allowed = "no options for a solver that takes none; for \"petsc\", options PETSc uses",
          .doc = "options passed to solvers that take them: \"petsc\" gives them to PETSc's options database for its "
                 "KSP and PC, e.g. \"-ksp_type cg -pc_type hypre\" (docs/performance.md)"}}};
  }();
  return s;
}

const SectionSpec& gradient_section() {
  static const SectionSpec s{
      "gradient", SectionKind::Section, false, "the Ru-Aifantis gradient step",
      {variant_key(false), length_scale_key("required unless `none`"),
       {.name = "apply", .type = K::String, .default_value = std::string("each_step"), .choices = {"each_step", "end"},
        .allowed = "\"each_step\" or \"end\"", .doc = "smooth after every load step, or once after the last"},
       {.name = "fields", .type = K::String, .default_text = "`\"points\"` (`\"grid\"` with `apply = \"end\"`)",
        .choices = {"points", "grid"}, .allowed = "\"points\" or \"grid\"",
        .doc = "`points`: step increments smoothed and carried by the points; `grid`: the total field smoothed from "
               "the points when needed; `end` + `points` is refused"}}};
  return s;
}

const SectionSpec& regularisation_section() {
  static const SectionSpec s{
      "regularisation", SectionKind::Section, false, "implicit-gradient regularisation of softening plasticity (docs/shear-bands.md)",
      {{.name = "type", .type = K::String, .default_value = std::string("none"), .choices = {"none", "implicit-gradient"},
        .doc = "`implicit-gradient`: every softening material's strength follows kappa_hat = (1 - m) kappa + m kappa_bar, kappa_bar - l^2 laplacian kappa_bar = kappa"},
       {.name = "length_scale", .type = K::Number, .default_text = "required unless `none`", .min = 0.0, .min_open = true,
        .allowed = "a length scale l > 0", .doc = "l, the internal length of the nonlocal plastic strain"},
       {.name = "nonlocal_weight", .type = K::Number, .default_value = 2.0, .min = 1.0, .max = 1e6,
        .allowed = "a weight m from 1 to 1e6",
        .doc = "m; m > 1 (over-nonlocal) regularises fully, m = 1 does not; (1 - m) kappa + m kappa_bar carries m times "
               "the round-off of kappa, and the answer departs beyond about 1e7 (docs/shear-bands.md)"},
       {.name = "history", .type = K::String, .default_value = std::string("points"), .choices = {"points", "grid"},
        .doc = "`points`: kappa_bar of the last step starts the next step's iteration; `grid`: recomputed from kappa_n on the new step's grid"},
       {.name = "coupling", .type = K::String, .default_value = std::string("staggered"), .choices = {"staggered", "monolithic"},
        .doc = "`monolithic`: displacements and kappa_bar by one Newton iteration with the coupled tangent (one rank; quasi-static load steps: no [arc_length], [time] or pore pressure); "
               "`staggered`: Newton with kappa_bar frozen, then kappa_bar, repeated"},
       {.name = "max_iterations", .type = K::Integer, .default_value = static_cast<long long>(Regularisation{}.max_iterations), .min = 1.0, .max = 10000.0,
        .doc = "staggered iterations (Newton, then kappa_bar) per load step before it is cut"},
       {.name = "tolerance", .type = K::Number, .default_value = Regularisation{}.tolerance, .min = 0.0, .max = 1.0, .min_open = true,
        .max_open = true, .doc = "the staggered iteration stops when kappa_bar changes by less than this times its largest value (and Newton is in balance with it)"}}};
  return s;
}

const SectionSpec& bar_mpm_gradient_section() {
  static const SectionSpec s = [] {
    SectionSpec g = gradient_section();
    g.required = true;
    return g;
  }();
  return s;
}

const SectionSpec& bar_gradient_section() {
  static const SectionSpec s{"gradient", SectionKind::Section, true, "the Ru-Aifantis gradient step",
                             {variant_key(true), length_scale_key("required unless `none` (then 0)")}};
  return s;
}

const SectionSpec& bar_section() {
  static const SectionSpec s{
      "bar", SectionKind::Section, true, "the bi-material bar of the paper (Figure 2)",
      {{.name = "length", .type = K::Number, .min = 0.0, .min_open = true, .allowed = "a length > 0", .doc = "bar length L"},
       {.name = "elements", .type = K::Integer, .min = 1.0, .max = 5e6,
        .doc = "cells of the background grid (linear elements)"},
       {.name = "split", .type = K::Number, .min = 0.0, .max = 1.0, .min_open = true, .max_open = true,
        .allowed = "a fraction of the length strictly between 0 and 1",
        .doc = "fraction of the length where the material changes (a = split L)"},
       {.name = "young", .type = K::Other, .type_text = "[number, number]", .allowed = "two Young's moduli > 0 ([left, right])",
        .doc = "Young's moduli [left, right]"},
       {.name = "end_displacement", .type = K::Number, .allowed = "a finite number",
        .doc = "delta, prescribed at x = L (x = 0 is fixed)"},
       {.name = "points_per_element", .type = K::Integer, .default_value = static_cast<long long>(BarConfig{}.points_per_element), .min = 1.0, .max = 4.0,
        .allowed = "an integer from 1 to 4 (Gauss points per element)", .doc = "Gauss points (material points) per element"}}};
  return s;
}

const SectionSpec& bar_output_section() {
  static const SectionSpec s{"output", SectionKind::Section, false, "outputs",
                             {{.name = "plot", .type = K::Boolean, .default_value = BarOutputOptions{}.plot,
                               .doc = "write bar.png with Python 3 + matplotlib ($GRADMPM_PYTHON, else /usr/bin/python3, else python3)"}}};
  return s;
}

const SectionSpec& bar_mpm_section() {
  static const SectionSpec s{
      "mpm", SectionKind::Section, true, "the bar solved by the implicit MPM",
      {{.name = "load_steps", .type = K::Integer, .min = 1.0, .max = 1e6, .doc = "load steps"},
       {.name = "basis", .type = K::String, .default_value = std::string("mpm"), .choices = {"mpm", "gimp", "cpgimp"},
        .allowed = "\"mpm\", \"gimp\" or \"cpgimp\"",
        .doc = "`mpm` (points at Gauss positions), `gimp` or `cpgimp` (points at sub-cell centres)"}}};
  return s;
}

namespace {
/// [arc_length] (mpm_sections).
SectionSpec arc_length_section() {
  const std::string dimvec = "[dim numbers]";
  return SectionSpec{"arc_length", SectionKind::Section, false, "arc-length control instead of load steps: the load factor is found with the displacements, so the path past a limit point and a snap-back are followed (no [load_steps]; docs/mpm.md)",
         {{.name = "max_steps", .type = K::Integer, .min = 1.0, .max = 1e6, .doc = "the run stops after this many steps"},
          {.name = "method", .type = K::String, .default_value = std::string("cylindrical"), .choices = {"cylindrical", "relative-displacement", "displacement"},
           .doc = "`cylindrical`: |du| over every dof is the arc (Crisfield 1981); `relative-displacement`: the displacement of node `to` less that of node `from` (component `component`) grows by the arc each step (indirect displacement control, de Borst 1987): follows a snap-back whose displacements retrace their way (a softening zone between unloading parts); `displacement`: the displacement of node `at` grows by the arc each step (displacement control of a load-driven case: past its limit load)"},
          {.name = "at", .type = K::Other, .type_text = dimvec, .default_text = "none",
           .doc = "displacement: the point whose nearest grid node's displacement is controlled (inside the body)"},
          {.name = "from", .type = K::Other, .type_text = dimvec, .default_text = "none",
           .doc = "relative-displacement: the point whose nearest grid node is `from` (inside the body)"},
          {.name = "to", .type = K::Other, .type_text = dimvec, .default_text = "none", .doc = "relative-displacement: see `from`"},
          {.name = "component", .type = K::String, .default_value = std::string("x"), .choices = {"x", "y", "z"},
           .doc = "relative-displacement: the component controlled"},
          {.name = "initial_increment", .type = K::Number, .default_value = ArcLengthSettings{}.initial_increment, .min = 0.0, .max = 1.0, .min_open = true,
           .doc = "the first step's load factor (load-controlled): its displacement's length is the first arc"},
          {.name = "max_load_factor", .type = K::Number, .default_value = ArcLengthSettings{}.max_load_factor, .min = 0.0, .max = 1e6, .min_open = true,
           .doc = "the run stops once the load factor reaches this (and where it has fallen back to 0)"},
          {.name = "target_iterations", .type = K::Integer, .default_value = static_cast<long long>(ArcLengthSettings{}.target_iterations), .min = 1.0, .max = 100.0,
           .doc = "the arc grows or shrinks by sqrt(target / Newton iterations of the last step), by 2 at most"}}};
}

/// [time] (mpm_sections).
/// [analysis] (mpm_sections).
SectionSpec analysis_section() {
  const StrengthReductionSettings d;
  return SectionSpec{"analysis", SectionKind::Section, false, "what the case computes: its load steps once, or the factor of safety by strength reduction (docs/strength-reduction.md)",
         {{.name = "type", .type = K::String, .default_value = std::string("load-steps"), .choices = {"load-steps", "strength-reduction"},
           .doc = "`load-steps`: the case's load steps, once (the other keys unread); `strength-reduction`: the case again per trial factor F with c / F and tan(phi) / F (sigma_y / F), bisected to the largest F that reaches equilibrium"},
          {.name = "first_factor", .type = K::Number, .default_value = d.first_factor, .min = 0.0, .max = 1e3, .min_open = true,
           .allowed = "a factor > 0 (at most 1000)", .doc = "strength reduction: the first trial factor; doubled while trials stand, halved while they fail, then bisected"},
          {.name = "min_factor", .type = K::Number, .default_value = d.min_factor, .min = 0.0, .max = 1e3, .min_open = true,
           .allowed = "a factor > 0 (at most 1000)", .doc = "strength reduction: the search stops when a trial at this factor fails"},
          {.name = "max_factor", .type = K::Number, .default_value = d.max_factor, .min = 0.0, .max = 1e3, .min_open = true,
           .allowed = "a factor > 0 (at most 1000)", .doc = "strength reduction: the search stops when a trial at this factor stands"},
          {.name = "failure_displacement", .type = K::Number, .default_text = "required with strength-reduction", .min = 0.0, .max = 1e12, .min_open = true,
           .allowed = "a length > 0", .doc = "strength reduction: a trial fails where a point has moved farther than this (MPM follows a slope that slides on to a new rest), or where Newton fails after every cut"},
          {.name = "tolerance", .type = K::Number, .default_value = d.tolerance, .min = 0.0, .max = 1.0, .min_open = true, .max_open = true,
           .allowed = "a number between 0 and 1", .doc = "strength reduction: the bisection stops when the factors that stood and failed are this close"}}};
}

SectionSpec time_section() {
  return SectionSpec{"time", SectionKind::Section, false, "implicit dynamics: the points' inertia, time steps from t = 0 to end_time (no [load_steps]; docs/dynamics.md)",
         {{.name = "dt", .type = K::Number, .min = 0.0, .max = 1e12, .min_open = true, .allowed = "a time step > 0",
           .doc = "the nominal time step (halved where Newton fails, grown back after)"},
          {.name = "end_time", .type = K::Number, .min = 0.0, .max = 1e15, .min_open = true, .allowed = "a time > 0",
           .doc = "the run ends at this time"},
          {.name = "scheme", .type = K::String, .default_value = std::string("newmark"), .choices = {"newmark", "generalised-alpha"},
           .doc = "`newmark` (beta, gamma; the trapezoidal rule by default: no numerical damping) or `generalised-alpha` (Chung & Hulbert 1993, rho_inf)"},
          {.name = "beta", .type = K::Number, .default_value = TimeSettings{}.beta, .min = 0.0, .max = 0.5, .min_open = true,
           .doc = "Newmark's beta (unconditionally stable for 2 beta >= gamma >= 1/2)"},
          {.name = "gamma", .type = K::Number, .default_value = TimeSettings{}.gamma, .min = 0.5, .max = 1.0,
           .doc = "Newmark's gamma (above 1/2: damps, first-order accurate)"},
          {.name = "rho_inf", .type = K::Number, .default_value = TimeSettings{}.rho_inf, .min = 0.0, .max = 1.0,
           .doc = "generalised-alpha's spectral radius at dt -> infinity: 1 keeps every mode, 0 damps the highest at once"},
          {.name = "ramp_time", .type = K::Number, .default_value = 0.0, .min = 0.0, .max = 1e15,
           .doc = "the loads (and prescribed displacements) reach their totals linearly at this time; 0: loads in full from t = 0 (then no displacement but 0 may be prescribed)"},
          {.name = "mass", .type = K::String, .default_value = std::string("lumped"), .choices = {"lumped", "consistent"},
           .doc = "`lumped` (m_i = sum_p N_ip m_p) or `consistent` (M_ij = sum_p N_ip N_jp m_p; one rank; singular where a cell has fewer points than nodes)"},
          {.name = "damping", .type = K::Number, .default_value = 0.0, .min = 0.0, .max = 1e12,
           .doc = "Rayleigh's mass-proportional damping alpha (1/s): the force alpha M v"},
          {.name = "pic_fraction", .type = K::Number, .default_value = 0.0, .min = 0.0, .max = 1.0,
           .doc = "theta of the points' velocity update (1 - theta) v_Newmark + theta sum_i N_ip v_i: 0 keeps the velocity the grid cannot see (it never moves anything), above 0 lets it decay (a dissipation)"},
          {.name = "stop_at_rest", .type = K::Number, .default_value = 0.0, .min = 0.0, .max = 1.0, .max_open = true,
           .doc = "stop once the kinetic energy has fallen to this fraction of its peak and the inertia and damping forces to its square root of the forces in balance (at rest, not at an oscillation's turning point); 0: run to end_time"},
          {.name = "inertia", .type = K::Boolean, .default_value = true,
           .doc = "false: time steps without inertia, for consolidation ([pore_pressure] drainage = \"coupled\": the time is the pore water's flow; docs/pore-pressure.md)"}}};
}

/// [[ties]] (mpm_sections).
SectionSpec point_sets_section() {
  const std::string dimvec = "[dim numbers]";
  return SectionSpec{"point_sets", SectionKind::Array, false, "named sets of material points, those in a box at the start: a run with pore pressure reports each set's mean excess pore pressure and degree of consolidation in consolidation.csv (docs/pore-pressure.md)",
         {{.name = "name", .type = K::String, .doc = "the set's name in consolidation.csv"},
          {.name = "min", .type = K::Other, .type_text = dimvec, .doc = "the box of the points (with `max`), at the start"},
          {.name = "max", .type = K::Other, .type_text = dimvec, .doc = "see `min`"}}};
}

SectionSpec ties_section() {
  const std::string dimvec = "[dim numbers]";
  return SectionSpec{"ties", SectionKind::Array, false, "grid nodes whose displacement components move together: a rigid frictionless plate under a load (penalty; one rank)",
         {{.name = "face", .type = K::String, .default_text = "none", .allowed = "a grid face \"x-\", \"x+\", \"y-\", ...",
           .doc = "node set: a grid face"},
          {.name = "min", .type = K::Other, .type_text = dimvec, .default_text = "none",
           .doc = "node set: the nodes inside the box min..max (inclusive), instead of `face`"},
          {.name = "max", .type = K::Other, .type_text = dimvec, .default_text = "none", .doc = "see `min`"},
          {.name = "components", .type = K::Other, .type_text = "[strings]",
           .doc = "the components tied, e.g. [\"y\"]: every node of the set (that a point reaches) moves as its neighbours in the set do"},
          {.name = "penalty", .type = K::Number, .default_value = 1e4, .min = 0.0, .max = 1e10, .min_open = true,
           .allowed = "a number > 0 (at most 1e10)",
           .doc = "alpha: the tie's stiffness alpha E h^(dim-2) between neighbouring nodes (E the stiffest material's); the nodes differ by about 1 / alpha of the strain's displacement"}}};
}

/// [[point_loads]] (mpm_sections).
SectionSpec point_loads_section() {
  const std::string dimvec = "[dim numbers]";
  return SectionSpec{"point_loads", SectionKind::Array, false, "forces on material points",
         {{.name = "min", .type = K::Other, .type_text = dimvec, .doc = "the box of points loaded (with `max`)"},
          {.name = "max", .type = K::Other, .type_text = dimvec, .doc = "see `min`"},
          {.name = "force", .type = K::Other, .type_text = dimvec, .doc = "force on every point in the box at load factor 1"}}};
}

/// [[rigid_boxes]] (mpm_sections).
SectionSpec rigid_boxes_section() {
  const std::string dimvec = "[dim numbers]";
  return SectionSpec{"rigid_boxes", SectionKind::Array, false, "rigid boxes pushing the points by penalty contact, frictionless or rough (a footing that follows the material, a shaft)",
         {{.name = "name", .type = K::String, .default_text = "none",
           .doc = "its contact force and displacement go to reactions.csv every step"},
          {.name = "min", .type = K::Other, .type_text = dimvec, .doc = "the box at load factor 0 (with `max`); no point's domain may overlap it then"},
          {.name = "max", .type = K::Other, .type_text = dimvec, .doc = "see `min`"},
          {.name = "displacement", .type = K::Other, .type_text = dimvec, .default_text = "zero",
           .doc = "the box's displacement at load factor 1"},
          {.name = "penalty", .type = K::Number, .default_value = 100.0, .min = 0.0, .max = 1e8, .min_open = true,
           .allowed = "a number > 0 (at most 1e8)",
           .doc = "alpha: contact stiffness k = alpha E / h per unit area (E the stiffest material's, h the smallest cell size); the penetration is q h / (alpha E); above 1e3 round-off in the contact may keep Newton above its tolerance (the failure message then names this key)"},
          {.name = "friction", .type = K::Number, .default_value = 0.0, .min = 0.0, .max = 10.0,
           .allowed = "a number from 0 to 10",
           .doc = "mu: Coulomb friction, the shear the box carries is at most adhesion + mu times the pressure (a stiff stick below it, sliding at it; a non-symmetric tangent)"},
          {.name = "adhesion", .type = K::Number, .default_value = 0.0, .min = 0.0, .max = 1e12,
           .allowed = "a stress >= 0",
           .doc = "a: the shear strength of the interface at no pressure (undrained clay's alpha s_u, with friction = 0: a Tresca interface)"}}};
}

/// [[rigid_bodies]] (mpm_sections): [[rigid_boxes]]' keys, with a shape for min and max.
SectionSpec rigid_bodies_section() {
  SectionSpec sec{"rigid_bodies", SectionKind::Array, false, "rigid bodies of other shapes than boxes, pushing the points as [[rigid_boxes]] do (a cone, a wedge, an inclined plate; 2D and r-z)",
         {{.name = "shape", .type = K::String, .choices = {"polygon"},
           .doc = "\"polygon\": a convex polygon given by `vertices`"},
          {.name = "vertices", .type = K::Other, .type_text = "[[x, y], ...]",
           .doc = "the convex polygon at load factor 0, >= 3 vertices in either order; no point's domain may overlap it then"}}};
  for (const KeySpec& key : rigid_boxes_section().keys)
    if (key.name != "min" && key.name != "max") sec.keys.push_back(key);
  for (KeySpec& key : sec.keys)
    if (key.name == "displacement") key.doc = "the body's displacement at load factor 1 (it translates, without turning)";
  return sec;
}

/// [nonlinear_solver] (mpm_sections).
SectionSpec nonlinear_solver_section() {
  return SectionSpec{"nonlinear_solver", SectionKind::Section, false, "Newton-Raphson",
         {{.name = "tolerance", .type = K::Number, .default_value = NewtonSettings{}.tolerance, .min = 0.0, .max = 1.0, .min_open = true,
           .max_open = true, .doc = "on |r_free| / max(|f_ext|, |f_int|)"},
          {.name = "max_iterations", .type = K::Integer, .default_value = static_cast<long long>(NewtonSettings{}.max_iterations), .min = 1.0, .max = 1000.0,
           .doc = "Newton iterations per step before a cut"},
          {.name = "max_cuts", .type = K::Integer, .default_value = static_cast<long long>(NewtonSettings{}.max_cuts), .min = 0.0, .max = 30.0,
           .doc = "halvings of a failing increment before the run stops"},
          {.name = "line_search", .type = K::String, .default_value = std::string("auto"), .choices = {"auto", "on", "off"},
           .doc = "halve a Newton correction that does not lower the residual (up to 6 times); auto: on where a rigid body has friction or adhesion (partial slip), off elsewhere"}}};
}

/// [[pressure_constraints]] (mpm_sections).
SectionSpec pressure_constraints_section() {
  const std::string dimvec = "[dim numbers]";
  return SectionSpec{"pressure_constraints", SectionKind::Array, false, "grid nodes whose pore pressure is held (drained faces; [pore_pressure])",
         {{.name = "face", .type = K::String, .default_text = "none", .allowed = "a grid face \"x-\", \"x+\", \"y-\", ...",
           .doc = "node set: a grid face"},
          {.name = "min", .type = K::Other, .type_text = dimvec, .default_text = "none",
           .doc = "node set: the nodes inside the box min..max (inclusive), instead of `face`"},
          {.name = "max", .type = K::Other, .type_text = dimvec, .default_text = "none", .doc = "see `min`"},
          {.name = "pressure", .type = K::Number, .default_value = 0.0, .doc = "the pore pressure held (0: a drained face)"}}};
}

/// [pore_pressure] (mpm_sections).
SectionSpec pore_pressure_section() {
  return SectionSpec{"pore_pressure", SectionKind::Section, false, "pore water of a saturated soil: the pore pressure p solved with the displacements (u-p), undrained or with Darcy flow (docs/pore-pressure.md)",
         {{.name = "drainage", .type = K::String, .default_value = std::string("coupled"), .choices = {"drained", "undrained", "coupled"},
           .doc = "`drained`: no pore pressure (the laws' stress is the total stress); `undrained`: p without flow (k = 0), in load steps; `coupled`: consolidation, Darcy flow over time steps ([time] with inertia = false)"},
          {.name = "stabilisation", .type = K::Number, .default_value = PoreSettings{}.stabilisation, .min = 0.0, .max = 1e3,
           .allowed = "a number from 0 (off) to 1000",
           .doc = "tau of the polynomial pressure projection tau / (2 G) (q - Pi q)(dp - Pi dp) (Dohrmann & Bochev 2004; White & Borja 2008), Pi the mean over the points sharing a stencil: the equal-order pressure's stabilisation where flow is slow (undrained loading, the first steps)"},
          {.name = "water_table", .type = K::Number, .default_text = "none",
           .doc = "the water table's elevation (its coordinate against gravity, which must be along one axis): below it the hydrostatic p = rho_w |g| depth is where [initial_stress] starts p (required there) and what p_excess (excess_pore_pressure) in the outputs is measured from"}}};
}

/// [initial_stress] (mpm_sections).
SectionSpec initial_stress_section() {
  return SectionSpec{"initial_stress", SectionKind::Section, false, "geostatic initial stresses (the K0 procedure): the points start at rest under their weight, gravity acts in full from the first step (docs/pore-pressure.md)",
         {{.name = "k0", .type = K::Number, .min = 0.0, .max = 10.0, .min_open = true, .allowed = "a ratio in (0, 10]",
           .doc = "K0 = sigma'_h / sigma'_v (e.g. 1 - sin phi', Jaky; nu / (1 - nu) for an elastic body under its weight); with pore pressure, p starts hydrostatic below [pore_pressure] water_table"}}};
}

/// The pore fluid's keys of every [materials.NAME] section (read with [pore_pressure]).
std::vector<KeySpec> pore_fluid_keys() {
  return {{.name = "permeability", .type = K::Number, .default_text = "none", .min = 0.0, .allowed = "a hydraulic conductivity >= 0",
           .doc = "[pore_pressure] coupled: the hydraulic conductivity k (m/s) of Darcy's q = -k grad h, h = p / gamma_w + z; c_v = k E_oed / gamma_w"},
          {.name = "permeability_law", .type = K::String, .default_value = std::string("constant"), .choices = {"constant", "kozeny-carman"},
           .doc = "[pore_pressure] coupled: `constant`, or `kozeny-carman`: k = permeability (n^3 / (1 - n)^2) / (n_0^3 / (1 - n_0)^2) at the current porosity n"},
          {.name = "porosity", .type = K::Number, .default_text = "none", .min = 0.0, .max = 1.0, .min_open = true, .max_open = true,
           .allowed = "a porosity in (0, 1)",
           .doc = "[pore_pressure]: the porosity n_0 at the start (the fluid's storage n / K_f; n follows the volume)"},
          {.name = "fluid_bulk_modulus", .type = K::Number, .default_value = PoreFluid{}.bulk_modulus, .min = 0.0, .min_open = true,
           .allowed = "a bulk modulus > 0", .doc = "[pore_pressure]: K_f of the pore fluid (water: 2.2e9 Pa)"},
          {.name = "fluid_density", .type = K::Number, .default_value = PoreFluid{}.density, .min = 0.0, .min_open = true,
           .allowed = "a density > 0",
           .doc = "[pore_pressure]: rho_w; gamma_w = rho_w |g| ([loads] gravity; 9.80665 where there is none); the fluid's weight drives the flow"}};
}
}  // namespace

const std::vector<SectionSpec>& mpm_sections() {
  static const std::vector<SectionSpec> s = [] {
    std::vector<KeySpec> material_keys = {
        {.name = "model", .type = K::String, .allowed = MaterialRegistry::instance().quoted_names(),
         .doc = "the constitutive law; its keys are listed below"}};
    for (const auto& law : MaterialRegistry::instance().all())
      for (const auto& k : law.keys) {
        bool seen = false;
        for (const auto& m : material_keys) seen = seen || m.name == k.name;
        if (!seen) material_keys.push_back(k);
      }
    for (const auto& k : pore_fluid_keys()) material_keys.push_back(k);
    const std::string dimvec = "[dim numbers]";
    return std::vector<SectionSpec>{
        {"grid", SectionKind::Section, true, "the background grid",
         {{.name = "origin", .type = K::Other, .type_text = dimvec, .doc = "lower corner of the background grid"},
          {.name = "cell_size", .type = K::Other, .type_text = "number or " + dimvec, .allowed = "cell sizes > 0",
           .doc = "cell size, one for all directions or one per direction"},
          {.name = "cells", .type = K::Other, .type_text = "[dim integers]", .allowed = "cell counts from 1 to 10000000",
           .doc = "cells per direction; their number is the dimension (1, 2 = plane strain, 3)"}}},
        {"basis", SectionKind::Section, false, "the shape functions",
         {{.name = "type", .type = K::String, .default_value = std::string("mpm"),
           .choices = {"mpm", "gimp", "ugimp", "cpgimp"},
           .allowed = "\"mpm\", \"gimp\" or \"ugimp\" (uGIMP), or \"cpgimp\"",
           .doc = "`mpm` (linear), `gimp` = `ugimp` (uGIMP, the name the run's first line prints), `cpgimp`"}}},
        {"materials", SectionKind::TableOfSections, true, "one section per material, named by the bodies", material_keys},
        {"bodies", SectionKind::Array, true, "bodies of material points",
         {{.name = "material", .type = K::String, .allowed = "the name of a [materials.NAME] section",
           .doc = "the material of the body's points"},
          {.name = "min", .type = K::Other, .type_text = dimvec, .default_text = "required (or `polygon`, `mesh`, `stl`)",
           .doc = "the body's box (with `max`), inside the grid"},
          {.name = "max", .type = K::Other, .type_text = dimvec, .default_text = "required (or `polygon`, `mesh`, `stl`)",
           .doc = "the body's box (with `min`)"},
          {.name = "polygon", .type = K::Other, .type_text = "[[x, y], ...]", .default_text = "none",
           .doc = "2D only: a polygon (>= 3 vertices) instead of a box"},
          {.name = "holes", .type = K::Other, .type_text = "[[[x, y], ...], ...]", .default_text = "none",
           .doc = "with `polygon`: polygons cut out of it (each inside it, apart from the others): a tunnel, a culvert, a pile's bore"},
          {.name = "mesh", .type = K::String, .default_text = "none",
           .doc = "a gmsh mesh (MSH 4.1 ASCII; its path relative to the case file) instead of a box: its linear "
                  "elements of the case's dimension make the body (docs/geometry.md)"},
          {.name = "stl", .type = K::String, .default_text = "none",
           .doc = "3D: a closed, consistently oriented STL surface (ASCII or binary; its path relative to the case file) bounding the body instead of a box (docs/geometry.md)"},
          {.name = "physical", .type = K::String, .default_text = "every element",
           .doc = "with `mesh`: the name of the physical group whose elements make the body"},
          {.name = "placement", .type = K::String, .default_value = std::string("grid"), .choices = {"grid", "elements"},
           .doc = "with `mesh`: `grid`, points at the sub-cell centres inside the elements (`points_per_cell`); "
                  "`elements`, points at the elements' quadrature points, their volumes adding up to the mesh's (one rank)"},
          {.name = "points_per_cell", .type = K::Integer, .default_value = 2LL, .min = 1.0, .max = 8.0,
           .allowed = "an integer from 1 to 8 (points per cell and direction)",
           .doc = "points per cell and direction, at sub-cell centres (volume = sub-cell volume), kept where they fall "
                  "inside the body"},
          {.name = "velocity", .type = K::Other, .type_text = dimvec, .default_text = "zero",
           .doc = "a dynamic case's initial velocity of the body's points (an impact, a thrown block; [time])"}}},
        {"mpm", SectionKind::Section, false, "options of the MPM itself",
         {{.name = "fbar", .type = K::Boolean, .default_value = false,
           .doc = "F-bar against volumetric locking (Coombs et al. 2018): the points of a cell share its volume change; finite-strain laws only; non-symmetric tangent"},
          {.name = "axisymmetric", .type = K::Boolean, .default_value = false,
           .doc = "2D only: axisymmetric about the y axis (r-z: x is the radius, > 0 at every point); the hoop strain u_r / r; volumes, masses, point loads and reactions per radian (docs/axisymmetry.md)"},
          {.name = "ghost_penalty", .type = K::Number, .default_value = 0.0, .min = 0.0, .max = 1e3,
           .allowed = "a number from 0 to 1000",
           .doc = "ghost stabilisation of cells empty of points (Burman 2010, Coombs 2023): alpha in the penalty alpha E h on the jumps of the step's displacement gradient across their faces; 0 = off; 1e-3 for perfectly plastic F-bar runs (docs/plasticity.md)"}}},
        {"loads", SectionKind::Section, false, "body forces",
         {{.name = "gravity", .type = K::Other, .type_text = dimvec, .default_text = "zero",
           .doc = "acceleration at load factor 1; body force m_p g"}}},
        {"constraints", SectionKind::Array, false, "grid-node constraints",
         {{.name = "name", .type = K::String, .default_text = "none",
           .doc = "names the node set: its reaction and mean displacement (over the nodes the step solved for) go to reactions.csv every step (blocks of one name form one set)"},
          {.name = "face", .type = K::String, .default_text = "none", .allowed = "a grid face \"x-\", \"x+\", \"y-\", ...",
           .doc = "node set: a grid face"},
          {.name = "min", .type = K::Other, .type_text = dimvec, .default_text = "none",
           .doc = "node set: the nodes inside the box min..max (inclusive), instead of `face`"},
          {.name = "max", .type = K::Other, .type_text = dimvec, .default_text = "none", .doc = "see `min`"},
          {.name = "fix", .type = K::Other, .type_text = "[strings]",
           .doc = "components held, e.g. [\"x\", \"y\"] (fixed) or [\"x\"] (roller)"},
          {.name = "displacement", .type = K::Other, .type_text = dimvec, .default_text = "zero",
           .doc = "total prescribed displacement of the held components at load factor 1"},
          {.name = "gradient_boundary", .type = K::Boolean, .default_value = true,
           .doc = "false: a support that only removes rigid motion (a pinned node), not a boundary of the body; the "
                  "gradient step keeps its natural condition there (u-RA holds no value, e-RA/s-RA no odd component)"}}},
        rigid_boxes_section(),
        rigid_bodies_section(),
        point_loads_section(),
        point_sets_section(),
        ties_section(),
        pressure_constraints_section(),
        pore_pressure_section(),
        initial_stress_section(),
        {"load_steps", SectionKind::Section, false, "the load stepping of a quasi-static analysis (required without [time] or [arc_length])",
         {{.name = "count", .type = K::Integer, .min = 1.0, .max = 1e6, .doc = "nominal number of load steps"}}},
        analysis_section(),
        arc_length_section(),
        time_section(),
        nonlinear_solver_section(),
        linear_solver_section(),
        {"output", SectionKind::Section, false, "outputs",
         {{.name = "vtk_every", .type = K::Integer, .default_value = static_cast<long long>(MpmOutputSettings{}.vtk_every), .min = 0.0, .max = 1e9,
           .allowed = "an integer from 0 (no VTK output) to 1000000000", .doc = "VTK every n steps (and the last); 0: none"},
          {.name = "track", .type = K::Other, .type_text = "[integers]", .default_text = "none",
           .doc = "point ids written to tracked_points.csv every step"},
          {.name = "check", .type = K::String, .default_value = MpmOutputSettings{}.check, .choices = {"", "column"},
           .allowed = "\"column\" (or no key)",
           .doc = "`column`: compare with the column closed form (one Hencky material, nu = 0, one box body, gravity "
                  "along the last axis)"},
          {.name = "plot", .type = K::Boolean, .default_value = MpmOutputSettings{}.plot, .doc = "write the figures: column.png (check = \"column\"), load_displacement.png (named constraints)"},
          {.name = "checkpoint_every", .type = K::Integer, .default_value = static_cast<long long>(MpmOutputSettings{}.checkpoint_every), .min = 0.0, .max = 1e9,
           .allowed = "an integer from 0 (no checkpoints) to 1000000000",
           .doc = "a checkpoint every n steps in DIR.checkpoints/step_NNNNNN (restart with --restart); 0: none"},
          {.name = "checkpoint_keep", .type = K::Integer, .default_value = static_cast<long long>(MpmOutputSettings{}.checkpoint_keep), .min = 0.0, .max = 1e9,
           .allowed = "an integer from 0 (keep all) to 1000000000", .doc = "how many of the latest checkpoints are kept; 0: all"}}},
        gradient_section(),
        regularisation_section(),
    };
  }();
  return s;
}

const SectionSpec& mpm_section(const std::string& name) {
  for (const auto& s : mpm_sections())
    if (s.name == name) return s;
  throw std::logic_error("no MPM section " + name);
}

// clang-format on

namespace {
const KeySpec* find_key(const std::vector<KeySpec>& keys, const std::string& name) {
  for (const KeySpec& k : keys)
    if (k.name == name) return &k;
  return nullptr;
}
}  // namespace

const KeySpec* mpm_key_spec(const CaseFile& cf, const std::string& key) {
  const auto dot = key.find('.');
  if (dot == std::string::npos) return nullptr;
  const std::string head = key.substr(0, dot), rest = key.substr(dot + 1);
  const std::string section = head.substr(0, head.find('['));  // "bodies[2]" -> "bodies"
  for (const SectionSpec& s : mpm_sections()) {
    if (s.name != section) continue;
    if (s.kind != SectionKind::TableOfSections) return find_key(s.keys, rest);
    // [materials.NAME]: the keys of the law that `model` names (names hold no '.').
    const auto name_end = rest.find('.');
    if (name_end == std::string::npos) return nullptr;
    const std::string prefix = head + "." + rest.substr(0, name_end);
    const std::string model = cf.has(prefix + ".model") ? cf.string(prefix + ".model") : "";
    const MaterialInfo* law = MaterialRegistry::instance().find(model);
    return law ? find_key(law->keys, rest.substr(name_end + 1)) : nullptr;
  }
  return nullptr;
}

std::string mpm_canonical_text(const CaseFile& cf) {
  return cf.canonical_text([&](const std::string& key) { return mpm_key_spec(cf, key); });
}

}  // namespace gradmpm
