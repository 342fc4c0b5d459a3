#include "gradmpm/io/StagedOutputs.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include "gradmpm/core/Errors.hpp"

namespace gradmpm {

namespace fs = std::filesystem;

StagedOutputs::StagedOutputs(fs::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_))
    throw OutputError(fmt::format("{}: cannot create output directory ({})", dir_.string(),
                                  ec ? ec.message() : "a file of that name exists"));
  if (::access(dir_.c_str(), W_OK | X_OK) != 0)
    throw OutputError(fmt::format("{}: output directory is not writable ({})", dir_.string(), std::strerror(errno)));
}

StagedOutputs::~StagedOutputs() {
  if (committed_) return;
  std::error_code ec;
  for (const auto& [tmp, final] : staged_) fs::remove(tmp, ec);
}

fs::path StagedOutputs::stage(const std::string& filename) {
  const fs::path tmp = dir_ / fmt::format(".{}.tmp-{}", filename, ::getpid());
  staged_.emplace_back(tmp, dir_ / filename);
  return tmp;
}

fs::path StagedOutputs::write_text(const std::string& filename, std::string_view content) {
  const fs::path tmp = stage(filename);
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (out) out.write(content.data(), static_cast<std::streamsize>(content.size()));
  if (out) out.close();
  if (!out) throw OutputError(fmt::format("{}: cannot write ({})", (dir_ / filename).string(), std::strerror(errno)));
  return tmp;
}

void StagedOutputs::commit() {
  for (const auto& [tmp, final] : staged_) {
    std::error_code ec;
    fs::rename(tmp, final, ec);
    if (ec) throw OutputError(fmt::format("{}: cannot write ({})", final.string(), ec.message()));
  }
  committed_ = true;
}

std::vector<fs::path> StagedOutputs::committed() const {
  std::vector<fs::path> out;
  if (committed_)
    for (const auto& [tmp, final] : staged_) out.push_back(final);
  return out;
}

}  // namespace gradmpm
