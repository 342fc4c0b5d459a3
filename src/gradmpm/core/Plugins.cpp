#include "gradmpm/core/Plugins.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

std::string plugin_folder() {
  if (const char* dir = std::getenv("GRADMPM_PLUGIN_DIR"); dir && *dir) return dir;
  Dl_info self{};
  if (dladdr(reinterpret_cast<void*>(&plugin_folder), &self) == 0 || !self.dli_fname) return ".";
  return std::filesystem::path(self.dli_fname).parent_path().string();
}

void* plugin_symbol(const char* name, const char* symbol, const std::string& needed_by) {
  static std::mutex guard;
  static std::map<std::string, void*> opened;
  const std::lock_guard lock(guard);
  const std::string file = (std::filesystem::path(plugin_folder()) / fmt::format("libgradmpm_{}.so", name)).string();
  void*& handle = opened[file];
  if (!handle) {
    // RTLD_GLOBAL: Open MPI opens components of its own that look for libmpi's symbols.
    handle = dlopen(file.c_str(), RTLD_NOW | RTLD_GLOBAL);
    if (!handle) {
      const char* why = dlerror();
      opened.erase(file);
      throw UserError(fmt::format("{} needs the plugin {}, which could not be loaded ({}); rebuild gradmpm, or set "
                                  "GRADMPM_PLUGIN_DIR to the folder that holds it",
                                  needed_by, file, why ? why : "unknown reason"));
    }
  }
  dlerror();
  void* address = dlsym(handle, symbol);
  if (!address)
    throw UserError(fmt::format("{} needs {} from the plugin {}, which lacks it (a plugin of another build?)",
                                needed_by, symbol, file));
  return address;
}

}  // namespace gradmpm
