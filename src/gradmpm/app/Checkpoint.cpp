#include "gradmpm/app/Checkpoint.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/io/AtomicFiles.hpp"
#include "gradmpm/io/Hdf5Archive.hpp"

namespace gradmpm {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormat = "gradmpm checkpoint";
constexpr long long kFormatVersion = 1;
constexpr const char* kFile = "checkpoint.h5";
const std::string kProgram = std::string("gradmpm ") + GRADMPM_VERSION;

/// Step numbers of the complete checkpoint folders in `folder`.
std::vector<std::pair<int, fs::path>> checkpoints_in(const fs::path& folder) {
  static const std::regex name(R"(step_([0-9]{6,}))");
  std::vector<std::pair<int, fs::path>> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    std::smatch m;
    const std::string n = e.path().filename().string();
    if (e.is_directory() && std::regex_match(n, m, name)) found.emplace_back(std::stoi(m[1]), e.path());
  }
  std::sort(found.begin(), found.end());
  return found;
}

/// The first key whose value differs between two canonical case texts.
std::string first_difference(const std::string& a, const std::string& b) {
  auto values = [](const std::string& text) {
    std::map<std::string, std::string> v;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      const auto eq = line.find(" = ");
      v[line.substr(0, eq)] = eq == std::string::npos ? "" : line.substr(eq + 3);
    }
    return v;
  };
  const auto va = values(a), vb = values(b);
  std::set<std::string> keys;
  for (const auto& [k, v] : va) keys.insert(k);
  for (const auto& [k, v] : vb) keys.insert(k);
  for (const auto& k : keys) {
    const auto ia = va.find(k), ib = vb.find(k);
    const std::string sa = ia == va.end() ? "not set" : ia->second, sb = ib == vb.end() ? "not set" : ib->second;
    if (sa != sb) return fmt::format("{}: checkpoint {}, this run {}", k, sa, sb);
  }
  return "?";
}

/// One per-point array in an archive: doubles as they are, integers as 64-bit, fixed-size
/// Eigen objects flattened (Archive::put_objects).
void put_array(Archive& a, const std::string& name, const std::vector<double>& v) { a.put(name, v); }
void put_array(Archive& a, const std::string& name, const std::vector<int>& v) {
  a.put(name, std::vector<long long>(v.begin(), v.end()));
}
template <typename T>
void put_array(Archive& a, const std::string& name, const std::vector<T>& v) {
  a.put_objects(name, v);
}
void get_array(const Archive& a, const std::string& name, long long n, std::vector<double>& v) { v = a.reals(name, n); }
void get_array(const Archive& a, const std::string& name, long long n, std::vector<int>& v) {
  const auto& x = a.integers(name, n);
  v.assign(x.begin(), x.end());
}
template <typename T>
void get_array(const Archive& a, const std::string& name, long long n, std::vector<T>& v) {
  a.get_objects(name, n, v);
}

}  // namespace

fs::path checkpoint_folder_of(const fs::path& out_dir) { return fs::path(out_dir.string() + ".checkpoints"); }

void link_files(const fs::path& from, const fs::path& to) {
  for (const auto& e : fs::directory_iterator(from)) {
    if (!e.is_regular_file() || e.path().filename().string().starts_with(".")) continue;
    const fs::path target = to / e.path().filename();
    std::error_code ec;
    fs::remove(target, ec);
    ec = link_or_copy(e.path(), target);
    if (ec)
      throw OutputError(fmt::format("{}: cannot link or copy {} ({})", to.string(), e.path().string(), ec.message()));
  }
}

CheckpointFolder::CheckpointFolder(fs::path folder, std::string shown, int every, int keep)
    : folder_(std::move(folder)), shown_(std::move(shown)), every_(every), keep_(keep) {
  if (every_ <= 0) return;
  std::error_code ec;
  fs::create_directories(folder_, ec);
  if (ec) throw OutputError(fmt::format("{}: cannot create the checkpoint folder ({})", shown_, ec.message()));
  // A temporary is a checkpoint a killed run did not finish: nobody else writes here, as
  // the run holds the lock on its output folder.
  for (const auto& e : fs::directory_iterator(folder_, ec))
    if (e.path().filename().string().starts_with(".step_")) fs::remove_all(e.path(), ec);
}

std::string CheckpointFolder::write(int step, const Archive& a, const fs::path& outputs) const {
  const std::string name = fmt::format("step_{:06d}", step);
  const fs::path final_path = folder_ / name, tmp = folder_ / fmt::format(".{}.tmp-{}", name, ::getpid());
  const std::string shown = shown_ + "/" + name;
  std::error_code ec;
  fs::remove_all(tmp, ec);
  fs::create_directories(tmp / "outputs", ec);
  if (ec) throw OutputError(fmt::format("{}: cannot create ({})", shown, ec.message()));
  write_hdf5_archive(tmp / kFile, a);
  link_files(outputs, tmp / "outputs");
  fsync_path(tmp / kFile, shown);
  fsync_path(tmp / "outputs", shown);
  fsync_path(tmp, shown);
  // Into place in one rename; an older checkpoint of the same step (an earlier run that
  // went further) is swapped out, so a complete one is there at every moment.
  move_into_place(tmp, final_path, folder_ / fmt::format(".{}.old-{}", name, ::getpid()), shown + ": cannot publish");
  fsync_path(folder_, shown_);
  // Keep the last keep_ up to this step; later ones are an earlier run's, which this run rewrites.
  auto all = checkpoints_in(folder_);
  std::vector<fs::path> older;
  for (const auto& [s, p] : all) {
    if (s > step) fs::remove_all(p, ec);
    if (s < step) older.push_back(p);
  }
  if (keep_ > 0)
    for (std::size_t i = 0; i + keep_ - 1 < older.size(); ++i) fs::remove_all(older[i], ec);
  return shown;
}

void put_checkpoint_header(Archive& a, const std::string& case_text, int dim, int step) {
  a.put_text("format", kFormat);
  a.put_integer("format_version", kFormatVersion);
  a.put_text("program", kProgram);
  a.put_text("case", case_text);
  a.put_integer("dimension", dim);
  a.put_integer("step", step);
}

Restart read_checkpoint(const fs::path& path, const std::string& case_text, int dim) {
  const fs::path file = fs::is_directory(path) ? path / kFile : path;
  if (!fs::exists(file))
    throw InputError(fmt::format("--restart {}: no such checkpoint (expected a step_NNNNNN folder or its {})",
                                 path.string(), kFile));
  Restart r{read_hdf5_archive(file), file.parent_path() / "outputs"};
  const Archive& a = r.archive;
  const std::string where = "--restart " + path.string();
  if (!a.has("format") || a.text("format") != kFormat)
    throw InputError(fmt::format("{}: not a gradmpm checkpoint", where));
  if (a.integer("format_version") != kFormatVersion || a.text("program") != kProgram)
    throw InputError(
        fmt::format("{}: written by {} (checkpoint format {}); this is {} (format {}): a restart must "
                    "use the program that wrote the checkpoint",
                    where, a.text("program"), a.integer("format_version"), kProgram, kFormatVersion));
  if (a.integer("dimension") != dim)
    throw InputError(fmt::format("{}: a {}D checkpoint; this case is {}D", where, a.integer("dimension"), dim));
  if (a.text("case") != case_text)
    throw InputError(
        fmt::format("{}: written for another case ({}); restart with the case file and --set options "
                    "of the run that wrote it",
                    where, first_difference(a.text("case"), case_text)));
  if (!fs::is_directory(r.outputs))
    throw InputError(fmt::format("{}: its outputs folder {} is missing", where, r.outputs.string()));
  return r;
}

template <int dim>
void save_run_state(Archive& a, const Model<dim>& m, const DriverState& driver,
                    const std::vector<PostStepStage<dim>*>& stages) {
  a.put_real("driver/load_factor", driver.load_factor);
  a.put_real("driver/next_increment", driver.next_increment);
  a.put("driver/summary",
        std::vector<long long>{driver.summary.steps, driver.summary.total_iterations, driver.summary.cuts});
  const MaterialPoints<dim>& p = m.points;
  a.put_integer("points/count", p.size());
  p.for_each_array([&](const char* name, const auto& v) { put_array(a, std::string("points/") + name, v); });
  a.put_integer("points/state_stride", p.state_stride);
  a.put("points/state", p.state);
  for (const PostStepStage<dim>* s : stages) s->save(a);
}

template <int dim>
DriverState restore_run_state(const Archive& a, Model<dim>& m, const std::vector<PostStepStage<dim>*>& stages) {
  MaterialPoints<dim>& p = m.points;
  const long long n = a.integer("points/count");
  if (n != p.size()) throw InputError(fmt::format("{}: {} points; this case makes {}", a.source(), n, p.size()));
  if (a.integer("points/state_stride") != m.state_stride())
    throw InputError(fmt::format("{}: {} state values per point; this case's materials have {}", a.source(),
                                 a.integer("points/state_stride"), m.state_stride()));
  p.for_each_array([&](const char* name, auto& v) { get_array(a, std::string("points/") + name, n, v); });
  p.state_stride = m.state_stride();
  p.state = a.reals("points/state", n * p.state_stride);
  for (PostStepStage<dim>* s : stages) s->restore(a);
  DriverState d;
  d.load_factor = a.real("driver/load_factor");
  d.next_increment = a.real("driver/next_increment");
  const auto& s = a.integers("driver/summary", 3);
  d.summary = RunSummary{static_cast<int>(s[0]), static_cast<int>(s[1]), static_cast<int>(s[2])};
  return d;
}

#define GRADMPM_CHECKPOINT(dim)                                                      \
  template void save_run_state<dim>(Archive&, const Model<dim>&, const DriverState&, \
                                    const std::vector<PostStepStage<dim>*>&);        \
  template DriverState restore_run_state<dim>(const Archive&, Model<dim>&, const std::vector<PostStepStage<dim>*>&);
GRADMPM_CHECKPOINT(1)
GRADMPM_CHECKPOINT(2)
GRADMPM_CHECKPOINT(3)
#undef GRADMPM_CHECKPOINT

}  // namespace gradmpm
