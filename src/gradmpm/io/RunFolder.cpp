#include "gradmpm/io/RunFolder.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/io/AtomicFiles.hpp"

namespace gradmpm {

namespace fs = std::filesystem;

namespace {
constexpr const char* kManifest = ".gradmpm-run";

std::string sibling(const fs::path& dir, const std::string& what) {
  return (dir.parent_path() / fmt::format(".{}{}", dir.filename().string(), what)).string();
}

/// The files an earlier run listed in DIR's manifest.
std::set<std::string> manifest_of(const fs::path& dir) {
  std::set<std::string> names;
  std::ifstream in(dir / kManifest);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line))
    if (!line.empty()) names.insert(line);
  return names;
}
}  // namespace

bool is_gradmpm_output_name(const std::string& name) {
  static const std::regex outputs(
      R"((points|grid)_[0-9]+\.vtu|(points|grid)\.pvd|(points_final|points_gradient|newton_history|tracked_points|reactions|column_check|bar|bar_points)\.csv|(column|load_displacement|bar)\.png|\..+\.tmp-[0-9]+|\.gradmpm-run)");
  return std::regex_match(name, outputs);
}

namespace {
/// DIR with the links of its last component followed (a chain of them too): `--out link`
/// with link -> /scratch/run writes, locks and publishes in /scratch/run, as `--out
/// /scratch/run` does, and never replaces the link by a folder. A dangling link's target
/// is made like any absent DIR.
fs::path without_final_links(fs::path dir, const std::string& shown) {
  for (int hops = 0; fs::is_symlink(dir); ++hops) {
    if (hops == 40) throw OutputError(fmt::format("{}: too many levels of symbolic links", shown));
    std::error_code ec;
    const fs::path target = fs::read_symlink(dir, ec);
    if (ec) throw OutputError(fmt::format("{}: cannot read the link ({})", shown, ec.message()));
    dir = (target.is_absolute() ? target : dir.parent_path() / target).lexically_normal();
    if (dir.filename().empty()) dir = dir.parent_path();
  }
  return dir;
}
}  // namespace

RunFolder::RunFolder(fs::path dir) {
  const std::string shown = dir.string();
  dir_ = fs::absolute(dir).lexically_normal();
  if (dir_.filename().empty()) dir_ = dir_.parent_path();  // "out/" -> "out"
  dir_ = without_final_links(dir_, shown);
  if (dir_ == dir_.root_path()) throw OutputError(fmt::format("{}: not an output folder", shown));
  std::error_code ec;
  fs::create_directories(dir_.parent_path(), ec);
  if (ec) throw OutputError(fmt::format("{}: cannot create output directory ({})", shown, ec.message()));
  // One run at a time: an exclusive lock on .DIR.lock, released however the process ends.
  const std::string lock = sibling(dir_, ".lock");
  lock_fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) throw OutputError(fmt::format("{}: cannot create {} ({})", shown, lock, std::strerror(errno)));
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    char pid[32] = {};
    const ssize_t n = ::pread(lock_fd_, pid, sizeof pid - 1, 0);
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw OutputError(
        fmt::format("{}: another gradmpm run{} is writing this folder; wait for it or choose another --out", shown,
                    n > 0 ? fmt::format(" (pid {})", std::string(pid, n)) : ""));
  }
  const std::string me = std::to_string(::getpid());
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, me.data(), me.size(), 0) < 0) {
    // the pid is only for the message of a second run
  }
  // Stale staging folders of runs that were killed (the lock says none is alive).
  const std::string stale = fmt::format(".{}.staging-", dir_.filename().string());
  for (const auto& e : fs::directory_iterator(dir_.parent_path(), ec))
    if (e.path().filename().string().rfind(stale, 0) == 0) fs::remove_all(e.path(), ec);
  // DIR: absent, or a folder of files (gradmpm's and the user's), never of folders.
  if (fs::exists(dir_)) {
    if (!fs::is_directory(dir_)) throw OutputError(fmt::format("{}: exists and is not a folder", shown));
    for (const auto& e : fs::directory_iterator(dir_, ec))
      if (e.is_directory() && !e.is_symlink())
        throw OutputError(fmt::format(
            "{}: holds the folder {}, which gradmpm did not write; an output folder holds files only (choose another "
            "--out)",
            shown, e.path().filename().string()));
    if (::access(dir_.c_str(), W_OK | X_OK) != 0)
      throw OutputError(fmt::format("{}: output directory is not writable ({})", shown, std::strerror(errno)));
  }
  staging_ = sibling(dir_, ".staging-" + me);
  if (!fs::create_directory(staging_, ec) || ec)
    throw OutputError(fmt::format("{}: cannot create the staging folder {} ({})", shown, staging_.string(),
                                  ec ? ec.message() : "it exists"));
}

RunFolder::~RunFolder() {
  std::error_code ec;
  if (!published_ && !staging_.empty()) fs::remove_all(staging_, ec);
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

void RunFolder::publish() {
  // The manifest: which files this run wrote (the next run replaces exactly these).
  std::ostringstream manifest;
  manifest << "gradmpm run output (pid " << ::getpid() << ")\n";
  files_.clear();
  for (const auto& e : fs::directory_iterator(staging_))
    if (e.is_regular_file()) files_.push_back(e.path().filename().string());
  std::sort(files_.begin(), files_.end());
  for (const auto& f : files_) manifest << f << "\n";
  {
    std::ofstream out(staging_ / kManifest, std::ios::trunc);
    out << manifest.str();
    if (!out)
      throw OutputError(fmt::format("{}: cannot write ({})", (staging_ / kManifest).string(), std::strerror(errno)));
  }
  // Keep the user's files: hard links (or copies) in the staging folder, so that no moment
  // loses them (the originals stay in DIR until the swap).
  std::error_code ec;
  if (fs::exists(dir_)) {
    const std::set<std::string> earlier = manifest_of(dir_);
    for (const auto& e : fs::directory_iterator(dir_, ec)) {
      const std::string name = e.path().filename().string();
      if (earlier.count(name) || is_gradmpm_output_name(name) || fs::exists(staging_ / name)) continue;
      (void)link_or_copy(e.path(), staging_ / name);
    }
  }
  // The swap: one atomic rename.
  move_into_place(staging_, dir_, sibling(dir_, ".staging-" + std::to_string(::getpid()) + "-old"),
                  dir_.string() + ": cannot publish the run");
  published_ = true;
}

std::string RunFolder::shown_as(std::string message, const fs::path& shown) const {
  return with_path_shown(std::move(message), staging_, shown.string());
}

std::string RunFolder::summary() const {
  static const std::regex numbered(R"((points|grid)_[0-9]+\.vtu)");
  std::string s;
  int points = 0, grid = 0;
  for (const auto& f : files_) {
    if (std::regex_match(f, numbered)) {
      ++(f[0] == 'p' ? points : grid);
      continue;
    }
    s += (s.empty() ? "" : ", ") + f;
  }
  if (points) s += fmt::format(", {} points_NNNN.vtu", points);
  if (grid) s += fmt::format(", {} grid_NNNN.vtu", grid);
  return s;
}

}  // namespace gradmpm
