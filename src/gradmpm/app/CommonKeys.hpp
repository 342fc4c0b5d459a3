#pragma once
// Readers of the sections shared by the bar and the MPM cases: [linear_solver] and
// [gradient] (keys declared in app/CaseKeys.cpp).
#include "gradmpm/gradient/MpmGradient.hpp"
#include "gradmpm/io/CaseFile.hpp"
#include "gradmpm/solver/linear/LinearSolverSettings.hpp"

namespace gradmpm {

/// Declares [linear_solver] and refuses the keys it replaced with a message naming the
/// new one. Call before CaseFile::reject_unknown().
void declare_linear_solver_section(CaseFile& cf);

/// Reads [linear_solver]; names must be registered solvers (general: a general one).
LinearSolverSettings read_linear_solver_settings(const CaseFile& cf);

/// Reads the optional [gradient] section of an MPM case (variant, length_scale, apply,
/// fields) and refuses combinations that make no sense.
GradientSettings read_gradient_settings(const CaseFile& cf);

}  // namespace gradmpm
