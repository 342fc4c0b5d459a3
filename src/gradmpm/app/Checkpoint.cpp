#include "gradmpm/app/Checkpoint.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include <limits>
#include <numeric>
#include <optional>

#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/io/AtomicFiles.hpp"
#include "gradmpm/io/Hdf5Archive.hpp"
#include "gradmpm/mpm/RankPoints.hpp"

namespace gradmpm {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormat = "gradmpm checkpoint";
// 2: the points' layout and ids; a distributed run's point files. 3: the outputs' CRC-32.
// 4: the points' velocity, acceleration and pore pressure.
constexpr long long kFormatVersion = 4;
constexpr const char* kFile = "checkpoint.h5";
const std::string kProgram = std::string("gradmpm ") + GRADMPM_VERSION;

/// A distributed run's point file of rank r.
std::string point_file(long long r) { return fmt::format("points_{:04d}.h5", r); }

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
    // (a key not in a canonical text is not given or given at its default)
    const std::string sa = ia == va.end() ? "the default" : ia->second, sb = ib == vb.end() ? "the default" : ib->second;
    if (sa != sb) return fmt::format("{}: {} in the checkpoint, {} in this run", k, sa, sb);
  }
  return "?";
}

/// The CRC-32 (zlib's) of a file's bytes; nullopt when it cannot be read.
std::optional<unsigned long> crc32_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  uLong crc = crc32(0L, Z_NULL, 0);
  std::vector<char> buffer(1 << 20);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    crc = crc32(crc, reinterpret_cast<const Bytef*>(buffer.data()), static_cast<uInt>(in.gcount()));
  }
  if (in.bad()) return std::nullopt;
  return crc;
}

/// Names of the recorded outputs, one per line (output files are named by the program).
std::vector<std::string> recorded_names(const Archive& a) {
  std::vector<std::string> names;
  std::istringstream in(a.text("outputs_files/names"));
  for (std::string line; std::getline(in, line);) names.push_back(line);
  return names;
}

/// Throws InputError unless `outputs` holds every file `a` recorded, of its size and CRC-32.
void check_outputs(const Archive& a, const fs::path& outputs, const std::string& where) {
  const std::vector<std::string> names = recorded_names(a);
  const auto n = static_cast<long long>(names.size());
  const std::vector<long long>& sizes = a.integers("outputs_files/sizes", n);
  const std::vector<long long>& crcs = a.integers("outputs_files/crc32", n);
  for (long long k = 0; k < n; ++k) {
    const fs::path file = outputs / names[k];
    std::error_code ec;
    const auto status = fs::status(file, ec);
    const std::string damaged = fmt::format("{}: its outputs/{}", where, names[k]);
    if (!fs::is_regular_file(status))
      throw InputError(damaged + " is missing (damaged checkpoint: the restart would publish incomplete outputs)");
    const auto size = static_cast<long long>(fs::file_size(file, ec));
    if (ec || size != sizes[k])
      throw InputError(fmt::format("{} has {} bytes, the checkpoint recorded {} (damaged checkpoint)", damaged,
                                   ec ? -1 : size, sizes[k]));
    const auto crc = crc32_of(file);
    if (!crc || static_cast<long long>(*crc) != crcs[k])
      throw InputError(damaged + " is not the file the checkpoint recorded: its CRC-32 differs (damaged checkpoint)");
  }
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
  std::string problem;
  if (ranks::rank() == 0) {  // (a distributed run: the folder is rank 0's, on a file system the ranks share)
    std::error_code ec;
    fs::create_directories(folder_, ec);
    if (ec) problem = fmt::format("{}: cannot create the checkpoint folder ({})", shown_, ec.message());
    // A temporary is a checkpoint a killed run did not finish: nobody else writes here, as
    // the run holds the lock on its output folder.
    for (const auto& e : fs::directory_iterator(folder_, ec))
      if (e.path().filename().string().starts_with(".step_")) fs::remove_all(e.path(), ec);
  }
  ranks::stop_if_any<OutputError>(problem);
  const std::string pid = std::to_string(::getpid());  // rank 0's names the temporaries
  const std::vector<char> told = ranks::broadcast(std::vector<char>(pid.begin(), pid.end()));
  tag_.assign(told.begin(), told.end());
}

void CheckpointFolder::record_outputs(Archive& a, const fs::path& outputs) const {
  std::string names;
  std::vector<long long> sizes, crcs;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(outputs))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    struct stat st {};
    if (::stat(file.c_str(), &st) != 0) throw OutputError(fmt::format("{}: cannot read its size", file.string()));
    const long long mtime = static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec;
    const std::string name = file.filename().string();
    auto it = summed_.find(name);
    if (it == summed_.end() || it->second.size != st.st_size || it->second.mtime != mtime ||
        it->second.inode != static_cast<long long>(st.st_ino)) {
      const auto crc = crc32_of(file);
      if (!crc) throw OutputError(fmt::format("{}: cannot read it to sum it", file.string()));
      it = summed_.insert_or_assign(name, Summed{st.st_size, mtime, static_cast<long long>(st.st_ino), *crc}).first;
    }
    names += name + "\n";
    sizes.push_back(it->second.size);
    crcs.push_back(static_cast<long long>(it->second.crc));
  }
  a.put_text("outputs_files/names", names);
  a.put("outputs_files/sizes", std::move(sizes));
  a.put("outputs_files/crc32", std::move(crcs));
}

std::string CheckpointFolder::write(int step, Archive& a, const Archive& points, const fs::path& outputs) const {
  const bool root = ranks::rank() == 0;
  const std::string name = fmt::format("step_{:06d}", step);
  const fs::path final_path = folder_ / name, tmp = folder_ / fmt::format(".{}.tmp-{}", name, tag_);
  const std::string shown = shown_ + "/" + name;
  std::string problem;
  if (root) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    fs::create_directories(tmp / "outputs", ec);
    if (ec) problem = fmt::format("{}: cannot create ({})", shown, ec.message());
  }
  ranks::stop_if_any<OutputError>(problem);
  if (ranks::distributed()) {  // each rank its points, flushed before rank 0 publishes the folder
    const std::string file = point_file(ranks::rank());
    try {
      write_hdf5_archive(tmp / file, points);
      fsync_path(tmp / file, shown);
    } catch (const UserError& e) {
      problem = fmt::format("rank {}: {}", ranks::rank(), e.what());
    }
    ranks::stop_if_any<OutputError>(problem);
  }
  if (root) try {
      link_files(outputs, tmp / "outputs");
      record_outputs(a, tmp / "outputs");  // what was linked: a restart checks it is there whole
      write_hdf5_archive(tmp / kFile, a);
      fsync_path(tmp / kFile, shown);
      fsync_path(tmp / "outputs", shown);
      fsync_path(tmp, shown);
      // Into place in one rename; an older checkpoint of the same step (an earlier run that
      // went further) is swapped out, so a complete one is there at every moment.
      move_into_place(tmp, final_path, folder_ / fmt::format(".{}.old-{}", name, tag_), shown + ": cannot publish");
      fsync_path(folder_, shown_);
      // Keep the last keep_ up to this step; later ones are an earlier run's, which this run rewrites.
      auto all = checkpoints_in(folder_);
      std::vector<fs::path> older;
      std::error_code ec;
      for (const auto& [s, p] : all) {
        if (s > step) fs::remove_all(p, ec);
        if (s < step) older.push_back(p);
      }
      if (keep_ > 0)
        for (std::size_t i = 0; i + keep_ - 1 < older.size(); ++i) fs::remove_all(older[i], ec);
    } catch (const UserError& e) {
      problem = with_path_shown(e.what(), tmp, shown);  // the step's name, not the hidden temporary's
      std::error_code ec;
      fs::remove_all(tmp, ec);  // what was written of it gives back the space it took
    }
  ranks::stop_if_any<OutputError>(problem);  // no rank goes on past a checkpoint that is not there
  return shown;
}

void put_checkpoint_header(Archive& a, const std::string& case_text, int dim, int step, int threads) {
  a.put_text("format", kFormat);
  a.put_integer("format_version", kFormatVersion);
  a.put_text("program", kProgram);
  a.put_text("case", case_text);
  a.put_integer("dimension", dim);
  a.put_integer("step", step);
  a.put_integer("threads", threads);
}

Restart read_checkpoint(const fs::path& path, const std::string& case_text, int dim) {
  const fs::path file = fs::is_directory(path) ? path / kFile : path;
  if (!fs::exists(file))
    throw InputError(fmt::format("--restart {}: no such checkpoint (expected a step_NNNNNN folder or its {})",
                                 path.string(), kFile));
  Restart r{read_hdf5_archive(file), file.parent_path(), file.parent_path() / "outputs"};
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
  check_outputs(a, r.outputs, where);
  if (a.has("threads")) r.threads = static_cast<int>(a.integer("threads"));
  return r;
}

bool PointRows::per_point(const std::string& name) const {
  if (name == "points/count") return false;
  return std::any_of(prefixes_.begin(), prefixes_.end(), [&](const std::string& p) { return name.starts_with(p); });
}

void PointRows::add(const Archive& file, const std::vector<char>& keep) {
  const long long n = file.integer("points/count");
  if (static_cast<long long>(keep.size()) != n) throw std::logic_error("PointRows::add: one keep flag per point");
  const std::vector<long long>& ids = file.integers("points/id", n);
  auto append = [&](const std::string& name, const auto& from, auto& to) {
    if (n == 0) return;  // (the name is known: a rank may keep no point of any file)
    if (from.size() % static_cast<std::size_t>(n) != 0)
      throw InputError(fmt::format("{}: '{}' holds {} values, not the same number for each of its {} points",
                                   file.source(), name, from.size(), n));
    const std::size_t w = from.size() / static_cast<std::size_t>(n);
    for (long long k = 0; k < n; ++k)
      if (keep[k]) to.insert(to.end(), from.begin() + k * w, from.begin() + (k + 1) * w);
  };
  for (const auto& [name, v] : file.all_reals())
    if (per_point(name)) append(name, v, reals_[name]);
  for (const auto& [name, v] : file.all_integers())
    if (per_point(name) && name != "points/id") append(name, v, integers_[name]);
  for (long long k = 0; k < n; ++k)
    if (keep[k]) ids_.push_back(ids[k]);
}

Archive PointRows::take(const std::string& source) const {
  const std::size_t n = ids_.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return ids_[i] < ids_[j]; });
  Archive a(source);
  a.put_integer("points/count", static_cast<long long>(n));
  std::vector<long long> ids(n);
  for (std::size_t i = 0; i < n; ++i) ids[i] = ids_[order[i]];
  for (std::size_t i = 1; i < n; ++i)
    if (ids[i] == ids[i - 1]) throw InputError(fmt::format("{}: point {} is there twice (damaged)", source, ids[i]));
  a.put("points/id", std::move(ids));
  auto permuted = [&](const auto& v) {
    std::remove_cvref_t<decltype(v)> out(v.size());
    const std::size_t w = n ? v.size() / n : 0;
    for (std::size_t i = 0; i < n; ++i) std::copy_n(v.begin() + order[i] * w, w, out.begin() + i * w);
    return out;
  };
  for (const auto& [name, v] : reals_) a.put(name, permuted(v));
  for (const auto& [name, v] : integers_) a.put(name, permuted(v));
  return a;
}

namespace {

/// The model's points (this rank's), every per-point array, under points/ and the stages' names.
template <int dim>
void save_points(Archive& a, const Model<dim>& m, const std::vector<PostStepStage<dim>*>& stages) {
  const MaterialPoints<dim>& p = m.points;
  a.put_integer("points/count", p.size());
  std::vector<long long> ids(m.point_ids.begin(), m.point_ids.end());
  if (m.point_ids.empty()) {  // a serial run: every point, in id order
    ids.resize(p.size());
    std::iota(ids.begin(), ids.end(), 0LL);
  }
  a.put("points/id", std::move(ids));
  p.for_each_array([&](const char* name, const auto& v) { put_array(a, std::string("points/") + name, v); });
  a.put("points/state", p.state);
  for (const PostStepStage<dim>* s : stages) s->save(a);
}

}  // namespace

template <int dim>
void save_run_state(Archive& a, Archive& points, const Model<dim>& m, const DriverState& driver,
                    const std::vector<PostStepStage<dim>*>& stages) {
  a.put_real("driver/load_factor", driver.load_factor);
  a.put_real("driver/next_increment", driver.next_increment);
  a.put_real("driver/time", driver.time);
  a.put_real("driver/peak_kinetic_energy", driver.peak_kinetic_energy);
  a.put("driver/arc_previous", driver.arc_previous);
  a.put_real("driver/arc_nominal", driver.arc_nominal);
  a.put_real("driver/peak_load_factor", driver.peak_load_factor);
  a.put("driver/summary",
        std::vector<long long>{driver.summary.steps, driver.summary.total_iterations, driver.summary.cuts});
  const CarriedOrdering& o = driver.ordering;
  a.put("driver/ordering", std::vector<long long>(o.nodes.begin(), o.nodes.end()));
  a.put_real("driver/ordering_fill", o.fill);
  a.put_real("driver/ordering_entries", o.entries);
  double total = m.points.size();
  ranks::sum(&total, 1);  // (serially the identity)
  a.put_integer("layout/points", static_cast<long long>(total));
  a.put_integer("layout/state_stride", m.points.state_stride);
  if (!ranks::distributed()) {
    a.put_integer("layout/files", 0);  // the points are in this file
    save_points(a, m, stages);
    return;
  }
  a.put_integer("layout/files", ranks::size());
  // The cells each file's points lie in, as the box of their cells (the lowest and the
  // highest cell index in each direction; an empty file's lowest above its highest): a
  // restart reads only the files that may hold points in its cells.
  std::vector<int> box(2 * dim);
  for (int d = 0; d < dim; ++d) box[d] = std::numeric_limits<int>::max(), box[dim + d] = -1;
  for (const int key : cell_corner_keys(m.grid, m.points.position)) {
    const auto c = m.grid.node_ijk(key);
    for (int d = 0; d < dim; ++d) box[d] = std::min(box[d], c[d]), box[dim + d] = std::max(box[dim + d], c[d]);
  }
  const std::vector<int> boxes = ranks::all_gather(box);
  a.put("layout/file_cells", std::vector<long long>(boxes.begin(), boxes.end()));
  save_points(points, m, stages);
}

template <int dim>
DriverState restore_run_state(const Restart& r, Model<dim>& m, const std::vector<PostStepStage<dim>*>& stages) {
  const Archive& a = r.archive;
  MaterialPoints<dim>& p = m.points;
  const bool split = ranks::distributed();  // each rank keeps the points in its cells
  if (split && m.rank_boxes.empty())
    throw std::logic_error("a distributed restart needs the ranks' cells (read_mpm_case with rank_points_only)");
  double made = p.size();
  ranks::sum(&made, 1);
  const long long total = a.integer("layout/points");
  if (total != static_cast<long long>(made))
    throw InputError(fmt::format("{}: {} points; this case makes {}", a.source(), total, made));
  if (a.integer("layout/state_stride") != m.state_stride())
    throw InputError(fmt::format("{}: {} state values per point; this case's materials have {}", a.source(),
                                 a.integer("layout/state_stride"), m.state_stride()));
  std::vector<std::string> prefixes{"points/"};
  for (const PostStepStage<dim>* s : stages) prefixes.push_back(s->name() + "/");
  PointRows rows(prefixes);
  std::string problem;
  try {
    // The points of a file this rank keeps: those in its cells (all of them serially).
    auto keep_of = [&](const Archive& file) {
      const long long n = file.integer("points/count");
      std::vector<Vec<dim>> x;
      file.get_objects("points/position", n, x);
      std::vector<char> keep(n, 1);
      if (split) {
        const std::vector<int> rank = owners(m.grid, m.rank_boxes, x);
        for (long long k = 0; k < n; ++k) keep[k] = rank[k] == ranks::rank();
      }
      return keep;
    };
    const long long files = a.integer("layout/files");
    if (files == 0) {
      rows.add(a, keep_of(a));
    } else {
      // Only the files whose points' cells meet this rank's box: restarted on as many
      // ranks (the same case, so the same boxes) its own file alone; on other numbers of
      // ranks the few whose boxes overlap its box.
      auto meets = [&](long long f) {
        if (!split) return true;
        const RankBoxes::Box mine = m.rank_boxes.box(ranks::rank());
        if (!a.has("layout/file_cells")) return true;  // (an earlier version's checkpoint: every file)
        const std::vector<long long>& cells = a.integers("layout/file_cells", 2 * dim * files);
        for (int d = 0; d < dim; ++d)  // (an empty file: its lowest above its highest)
          if (cells[2 * dim * f + d] >= mine.hi[d] || cells[2 * dim * f + dim + d] < mine.lo[d]) return false;
        return true;
      };
      for (long long f = 0; f < files; ++f) {
        if (!meets(f)) continue;
        const fs::path file = r.folder / point_file(f);
        if (!fs::exists(file))
          throw InputError(fmt::format("{}: {} is missing (the checkpoint has {} point files)", r.folder.string(),
                                       point_file(f), files));
        const Archive piece = read_hdf5_archive(file);
        rows.add(piece, keep_of(piece));
      }
    }
  } catch (const UserError& e) {
    problem = e.what();
  }
  ranks::stop_if_any<InputError>(problem);  // a file only some ranks read stops them all
  double kept = static_cast<double>(rows.count());
  ranks::sum(&kept, 1);
  if (static_cast<long long>(kept) != total)
    throw InputError(
        fmt::format("{}: its point files hold {} of its {} points (damaged)", r.folder.string(), kept, total));
  Archive mine;
  try {
    mine = rows.take(a.source());
  } catch (const UserError& e) {
    problem = e.what();
  }
  ranks::stop_if_any<InputError>(problem);
  const long long n = mine.integer("points/count");
  p.for_each_array([&](const char* name, auto& v) { get_array(mine, std::string("points/") + name, n, v); });
  p.state_stride = m.state_stride();
  p.state = mine.reals("points/state", n * p.state_stride);
  const std::vector<long long>& ids = mine.integers("points/id", n);
  if (split)
    m.point_ids.assign(ids.begin(), ids.end());
  else
    m.point_ids.clear();
  for (PostStepStage<dim>* s : stages) s->restore(mine);
  DriverState d;
  d.load_factor = a.real("driver/load_factor");
  d.next_increment = a.real("driver/next_increment");
  d.time = a.real("driver/time");
  d.peak_kinetic_energy = a.real("driver/peak_kinetic_energy");
  d.arc_previous = a.reals("driver/arc_previous");
  d.arc_nominal = a.real("driver/arc_nominal");
  d.peak_load_factor = a.real("driver/peak_load_factor");
  const auto& s = a.integers("driver/summary", 3);
  d.summary = RunSummary{static_cast<int>(s[0]), static_cast<int>(s[1]), static_cast<int>(s[2])};
  for (const long long node : a.integers("driver/ordering")) {
    if (node < 0 || node >= m.grid.num_nodes())
      throw InputError(fmt::format("{}: driver/ordering names node {}, not one of the grid's {} (damaged)",
                                   r.folder.string(), node, m.grid.num_nodes()));
    d.ordering.nodes.push_back(static_cast<int>(node));
  }
  d.ordering.fill = a.real("driver/ordering_fill");
  d.ordering.entries = a.real("driver/ordering_entries");
  return d;
}

#define GRADMPM_CHECKPOINT(dim)                                                                \
  template void save_run_state<dim>(Archive&, Archive&, const Model<dim>&, const DriverState&, \
                                    const std::vector<PostStepStage<dim>*>&);                  \
  template DriverState restore_run_state<dim>(const Restart&, Model<dim>&, const std::vector<PostStepStage<dim>*>&);
GRADMPM_CHECKPOINT(1)
GRADMPM_CHECKPOINT(2)
GRADMPM_CHECKPOINT(3)
#undef GRADMPM_CHECKPOINT

}  // namespace gradmpm
