#pragma once
// The column verification of an MPM case (output.check = "column"): the final state
// against the closed form of a Hencky column under self-weight (analytic/Column.hpp).
#include <filesystem>
#include <string>

#include "gradmpm/mpm/Model.hpp"

namespace gradmpm {

/// Compares the final state with the column closed form; writes column_check.csv and
/// (if asked) column.png in `dir`, all or nothing; returns a one-line summary.
template <int dim>
std::string column_check(const Model<dim>& m, const std::filesystem::path& dir, bool plot);

}  // namespace gradmpm
