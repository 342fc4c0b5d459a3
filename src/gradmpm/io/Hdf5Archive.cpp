// io/Hdf5Archive.hpp's files, in the plugin libgradmpm_hdf5.so (core/Plugins.hpp).
#include "gradmpm/io/Hdf5Archive.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <sstream>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

namespace {

/// Closes an HDF5 handle at scope exit.
struct Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  Handle(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  ~Handle() {
    if (id >= 0) close(id);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id; }
};

/// Prepares the library once, before any other HDF5 call: our messages, not HDF5's stack;
/// and no HDF5 clean-up at exit. A file whose close failed (a full disk) stays in HDF5's
/// list of open files, and closing it again at exit crashed (H5F__close_cb from
/// H5F_term_package); every file is closed here, so the clean-up has nothing else to do.
void quiet_hdf5() {
  static const bool prepared = [] {
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)prepared;
}

void write_dataset(hid_t file, const std::string& name, hid_t file_type, hid_t mem_type, const void* data,
                   std::size_t n, const std::filesystem::path& path) {
  auto fail = [&] {
    throw OutputError(fmt::format("{}: cannot write dataset '{}' (disk full?)", path.string(), name));
  };
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl, 1);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  const hsize_t dims[1] = {static_cast<hsize_t>(n)};
  // Empty arrays: a contiguous empty dataset (a chunk cannot be empty); others chunked
  // with the Fletcher-32 checksum.
  if (n > 0) {
    const hsize_t chunk[1] = {std::min<hsize_t>(dims[0], 1u << 16)};
    if (H5Pset_chunk(dcpl, 1, chunk) < 0 || H5Pset_fletcher32(dcpl) < 0) fail();
  }
  Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose);
  Handle set(H5Dcreate2(file, name.c_str(), file_type, space, lcpl, dcpl, H5P_DEFAULT), H5Dclose);
  if (set < 0) fail();
  if (n > 0 && H5Dwrite(set, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) fail();
}

template <typename T>
std::vector<T> read_dataset(hid_t file, const std::string& name, H5T_class_t cls, hid_t mem_type,
                            const std::filesystem::path& path) {
  auto fail = [&](const std::string& why) {
    throw InputError(fmt::format("{}: dataset '{}': {}", path.string(), name, why));
  };
  Handle set(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (set < 0) fail("missing");
  Handle type(H5Dget_type(set), H5Tclose);
  if (H5Tget_class(type) != cls) fail("of the wrong type");
  Handle space(H5Dget_space(set), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (n < 0 || H5Sget_simple_extent_ndims(space) != 1) fail("not a one-dimensional array");
  std::vector<T> v(static_cast<std::size_t>(n));
  if (n > 0 && H5Dread(set, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
    fail("cannot be read (checksum mismatch: the file is damaged)");
  return v;
}

void write_archive(const std::filesystem::path& path, const Archive& a) {
  quiet_hdf5();
  std::string index;
  {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    H5Pset_libver_bounds(fapl, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);  // checksummed metadata
    Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose);
    if (file < 0) throw OutputError(fmt::format("{}: cannot create the checkpoint file", path.string()));
    for (const auto& [name, v] : a.all_reals()) {
      write_dataset(file, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data(), v.size(), path);
      index += "real " + name + "\n";
    }
    for (const auto& [name, v] : a.all_integers()) {
      write_dataset(file, name, H5T_STD_I64LE, H5T_NATIVE_LLONG, v.data(), v.size(), path);
      index += "integer " + name + "\n";
    }
    for (const auto& [name, t] : a.all_texts()) {
      write_dataset(file, name, H5T_STD_U8LE, H5T_NATIVE_UCHAR, t.data(), t.size(), path);
      index += "text " + name + "\n";
    }
    write_dataset(file, "index", H5T_STD_U8LE, H5T_NATIVE_UCHAR, index.data(), index.size(), path);
    if (H5Fflush(file, H5F_SCOPE_GLOBAL) < 0)
      throw OutputError(fmt::format("{}: cannot write the checkpoint file (disk full?)", path.string()));
    const herr_t closed = H5Fclose(file.id);
    file.id = -1;  // (closed or not, never closed twice)
    if (closed < 0) throw OutputError(fmt::format("{}: cannot close the checkpoint file (disk full?)", path.string()));
  }
}

Archive read_archive(const std::filesystem::path& path) {
  quiet_hdf5();
  // A FIFO or a device would block the open or never end: only regular files are read.
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw InputError(fmt::format("{}: not a regular file (a checkpoint is an HDF5 file)", path.string()));
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw InputError(
        fmt::format("{}: not a readable HDF5 checkpoint (missing, truncated or another kind of file)", path.string()));
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (file < 0) throw InputError(fmt::format("{}: cannot open the HDF5 checkpoint (damaged?)", path.string()));
  Archive a(path.string());
  const std::vector<unsigned char> raw =
      read_dataset<unsigned char>(file, "index", H5T_INTEGER, H5T_NATIVE_UCHAR, path);
  std::istringstream index(std::string(raw.begin(), raw.end()));
  std::string kind, name;
  while (index >> kind && std::getline(index >> std::ws, name)) {
    if (kind == "real") {
      a.put(name, read_dataset<double>(file, name, H5T_FLOAT, H5T_NATIVE_DOUBLE, path));
    } else if (kind == "integer") {
      a.put(name, read_dataset<long long>(file, name, H5T_INTEGER, H5T_NATIVE_LLONG, path));
    } else if (kind == "text") {
      const auto bytes = read_dataset<unsigned char>(file, name, H5T_INTEGER, H5T_NATIVE_UCHAR, path);
      a.put_text(name, std::string(bytes.begin(), bytes.end()));
    } else {
      throw InputError(fmt::format("{}: unknown array kind '{}' in the index (damaged?)", path.string(), kind));
    }
  }
  return a;
}

}  // namespace

}  // namespace gradmpm

/// The plugin's entry point (io/Hdf5Plugin.cpp reads it).
extern "C" const gradmpm::Hdf5ArchiveFiles* gradmpm_hdf5_archive_files() {
  static const gradmpm::Hdf5ArchiveFiles files{gradmpm::write_archive, gradmpm::read_archive};
  return &files;
}
