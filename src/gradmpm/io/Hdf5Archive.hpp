#pragma once
// An Archive (io/Archive.hpp) as an HDF5 file (Debian's libhdf5): one dataset per array,
// at the archive's name ("points/position" is dataset position in group points), doubles
// as IEEE 64-bit, integers as 64-bit, texts as bytes, so `h5dump` and h5py read a
// checkpoint as it is. Every dataset carries HDF5's Fletcher-32 checksum and the file
// uses the latest format (checksummed metadata): a damaged or truncated file is refused
// on reading, never read as wrong numbers. The dataset "index" lists the arrays.
// HDF5 itself is in the plugin libgradmpm_hdf5.so (io/Hdf5Archive.cpp), loaded the first
// time a checkpoint is written or read (core/Plugins.hpp).
#include <filesystem>

#include "gradmpm/io/Archive.hpp"

namespace gradmpm {

/// Writes `a` to `file` (replacing it) and closes it; throws OutputError. Flushing it to
/// disk (fsync) is the caller's (app/Checkpoint.cpp does, before it publishes).
void write_hdf5_archive(const std::filesystem::path& file, const Archive& a);

/// Reads every array of `file`; throws InputError (not HDF5, damaged, checksum mismatch).
Archive read_hdf5_archive(const std::filesystem::path& file);

/// The plugin's two functions (its entry point gradmpm_hdf5_archive_files returns them).
struct Hdf5ArchiveFiles {
  void (*write)(const std::filesystem::path& file, const Archive& a);
  Archive (*read)(const std::filesystem::path& file);
};

}  // namespace gradmpm
