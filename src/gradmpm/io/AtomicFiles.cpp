#include "gradmpm/io/AtomicFiles.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <stdio.h>  // renameat2 (glibc >= 2.28)
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

namespace fs = std::filesystem;

void fsync_path(const fs::path& p, const std::string& shown) {
  const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
  const bool ok = fd >= 0 && ::fsync(fd) == 0;
  if (fd >= 0) ::close(fd);
  if (!ok) throw OutputError(fmt::format("{}: cannot flush to disk", shown));
}

std::error_code link_or_copy(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::create_hard_link(from, to, ec);
  if (ec) {
    ec.clear();
    fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
  }
  return ec;
}

void move_into_place(const fs::path& fresh, const fs::path& target, const fs::path& aside, const std::string& failure) {
  std::error_code ec;
  if (!fs::exists(target)) {
    fs::rename(fresh, target, ec);
    if (ec) throw OutputError(fmt::format("{} ({})", failure, ec.message()));
    return;
  }
  if (::renameat2(AT_FDCWD, fresh.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
    fs::remove_all(fresh, ec);  // what was at target
    return;
  }
  if (errno != EINVAL && errno != ENOSYS) throw OutputError(fmt::format("{} ({})", failure, std::strerror(errno)));
  fs::rename(target, aside, ec);
  if (!ec) fs::rename(fresh, target, ec);
  if (ec) throw OutputError(fmt::format("{} ({})", failure, ec.message()));
  fs::remove_all(aside, ec);
}

std::string with_path_shown(std::string message, const std::filesystem::path& hidden, const std::string& shown) {
  const std::string h = hidden.string();
  if (h.empty()) return message;
  for (std::size_t at = 0; (at = message.find(h, at)) != std::string::npos; at += shown.size())
    message.replace(at, h.size(), shown);
  return message;
}

}  // namespace gradmpm
