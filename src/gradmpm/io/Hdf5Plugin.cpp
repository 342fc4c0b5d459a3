// io/Hdf5Archive.hpp's functions, from the plugin libgradmpm_hdf5.so (core/Plugins.hpp).
#include "gradmpm/core/Plugins.hpp"
#include "gradmpm/io/Hdf5Archive.hpp"

namespace gradmpm {

namespace {
const Hdf5ArchiveFiles& plugin() {
  static const Hdf5ArchiveFiles& files = *plugin_function<const Hdf5ArchiveFiles* (*)()>(
      "hdf5", "gradmpm_hdf5_archive_files", "a checkpoint (HDF5)")();
  return files;
}
}  // namespace

void write_hdf5_archive(const std::filesystem::path& file, const Archive& a) { plugin().write(file, a); }

Archive read_hdf5_archive(const std::filesystem::path& file) { return plugin().read(file); }

}  // namespace gradmpm
