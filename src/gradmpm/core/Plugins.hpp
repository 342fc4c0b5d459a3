#pragma once
// Parts of gradmpm that need large libraries load them when a run first uses them, from
// a plugin beside libgradmpm, instead of every process linking them:
//   libgradmpm_petsc.so  PETSc and MPI (linear_solver.type = "petsc", runs on several MPI
//                        ranks): with Open MPI and PETSc's own dependencies, about 50 libraries
//   libgradmpm_hdf5.so   HDF5 checkpoints: with libcurl and its TLS stack, about 20
// Loading them took 60 ms of every start, when most runs use neither (docs/performance.md).
// A plugin is opened once and stays for the life of the process.
#include <string>

namespace gradmpm {

/// The folder the plugins are read from: GRADMPM_PLUGIN_DIR when set, else the folder of
/// libgradmpm itself (the build's lib/ folder, or where it is installed).
std::string plugin_folder();

/// The address of `symbol` in plugin `name` (libgradmpm_NAME.so in plugin_folder()).
/// Throws UserError naming the file, what went wrong and `needed_by` (what asked for it)
/// when the plugin cannot be opened or lacks the symbol.
void* plugin_symbol(const char* name, const char* symbol, const std::string& needed_by);

/// plugin_symbol() as a function of type F.
template <class F>
F plugin_function(const char* name, const char* symbol, const std::string& needed_by) {
  return reinterpret_cast<F>(plugin_symbol(name, symbol, needed_by));
}

}  // namespace gradmpm
