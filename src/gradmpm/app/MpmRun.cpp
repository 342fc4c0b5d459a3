// Runs an MPM case: reads it (app/MpmCaseReader.cpp), solves it with the gradient step
// as a post-step stage of the driver, and writes the outputs, each file all or nothing:
//   points_NNNN.vtu, grid_NNNN.vtu, points.pvd, grid.pvd   every output.vtk_every steps
//     (on N MPI ranks points_NNNN.pvtu and one piece points_NNNN_R.vtu per rank)
//   newton_history.csv, tracked_points.csv, reactions.csv,
//   energy.csv (work, elastic energy, dissipation),
//   consolidation.csv (with [[point_sets]])                after every step
//   load_displacement.png                                  at the end, with named constraints
//   points_final.csv, points_gradient.csv                  at the end
//   column_check.csv, column.png                           with output.check = "column"
// and, with output.checkpoint_every, checkpoints beside the output folder (app/Checkpoint.hpp).
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cstdlib>
#include <optional>
#include <sstream>

#include "gradmpm/app/CaseKeys.hpp"
#include "gradmpm/app/Checkpoint.hpp"
#include "gradmpm/app/ColumnCheck.hpp"
#include "gradmpm/app/MemoryCheck.hpp"
#include "gradmpm/app/MpmCase.hpp"
#include "gradmpm/app/PointColumns.hpp"
#include "gradmpm/app/StrengthReduction.hpp"
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/PlatformHooks.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/core/Timer.hpp"
#include "gradmpm/io/EmbeddedScripts.hpp"
#include "gradmpm/io/Python.hpp"
#include "gradmpm/io/StagedOutputs.hpp"
#include "gradmpm/io/Vtk.hpp"
#include "gradmpm/mpm/InitialStress.hpp"

namespace gradmpm {

namespace fs = std::filesystem;

namespace {

void write_now(const fs::path& dir, const std::string& name, const std::string& content) {
  StagedOutputs out(dir);
  out.write_text(name, content);
  out.commit();
}

/// The point columns of points_final.csv and tracked_points.csv (state variables appended).
const std::vector<std::string> kFinalColumns = {"id", "original_position", "position", "stress", "volume", "mass"};
const std::vector<std::string> kTrackedColumns = {"id", "position", "stress"};

/// tracked_points.csv's columns: kTrackedColumns, the state variables, and p with pore
/// pressure (and p_excess with a water table).
template <int dim>
std::vector<std::string> tracked_columns(const PointColumns<dim>& table, const Model<dim>& m) {
  std::vector<std::string> columns = table.with_state(kTrackedColumns);
  if (m.pore.active()) columns.push_back("pore_pressure");
  if (m.pore.water_table) columns.push_back("excess_pore_pressure");
  return columns;
}
const std::vector<std::string> kGradientColumns = {
    "id", "position", "displacement", "gradient_displacement", "elastic_strain", "gradient_strain", "gradient_stress"};

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

/// A VTK series (points.pvd, grid.pvd) in a checkpoint.
using Series = std::vector<std::pair<double, std::string>>;
void put_series(Archive& a, const std::string& name, const Series& s) {
  std::vector<double> load;
  std::string files;
  for (const auto& [l, f] : s) {
    load.push_back(l);
    files += f + "\n";
  }
  a.put(name + "_load", load);
  a.put_text(name + "_files", files);
}
Series get_series(const Archive& a, const std::string& name) {
  std::istringstream files(a.text(name + "_files"));
  Series s;
  std::string f;
  for (double l : a.reals(name + "_load")) {
    if (!std::getline(files, f)) throw InputError(fmt::format("{}: '{}' is damaged", a.source(), name));
    s.emplace_back(l, f);
  }
  return s;
}

/// A distributed run's pieces of one step: each rank writes STEM_NNNN_R.vtu for each
/// (STEM, its piece's text) of `mine` (its points, its cells of the grid) into `folder`;
/// returns, for each stem, every rank's piece names once every rank has written its own.
/// A rank that cannot write its pieces stops every rank.
std::vector<std::vector<std::string>> write_vtu_pieces(const fs::path& folder, int step,
                                                       const std::vector<std::pair<std::string, std::string>>& mine) {
  const int size = ranks::size(), rank = ranks::rank();
  std::vector<std::vector<std::string>> pieces(mine.size());
  for (std::size_t k = 0; k < mine.size(); ++k)
    for (int r = 0; r < size; ++r) pieces[k].push_back(fmt::format("{}_{:04d}_{}.vtu", mine[k].first, step, r));
  std::string problem;
  try {
    StagedOutputs out(folder);
    for (std::size_t k = 0; k < mine.size(); ++k) out.write_text(pieces[k][rank], mine[k].second);
    out.commit();
  } catch (const OutputError& e) {
    problem = fmt::format("rank {}: {}", rank, e.what());
  }
  ranks::stop_if_any<OutputError>(problem);  // every rank, the first rank's message
  return pieces;
}

/// A CSV table of the points, arranged by id over the ranks (arrange_by_id), as `name` in
/// the output folder `dir`. A distributed run writes it into rank 0's staged file in
/// `shared` (its output folder, as every rank names it): rank 0 the header, then each rank
/// its rows at the offset of the ranks before it (ranks::write_in_rank_order); rank 0
/// publishes it when every rank has written. A collective call.
void write_in_id_order(const fs::path& dir, const fs::path& shared, const std::string& name, const CsvTable& table) {
  if (!ranks::distributed()) return write_now(dir, name, table.str());
  const bool root = ranks::rank() == 0;
  std::optional<StagedOutputs> out;
  std::string problem, staged;
  if (root) try {
      out.emplace(shared);
      staged = out->stage(name).string();
    } catch (const OutputError& e) {
      problem = e.what();
    }
  ranks::stop_if_any<OutputError>(problem);
  const std::vector<char> told = ranks::broadcast(std::vector<char>(staged.begin(), staged.end()));
  problem = ranks::write_in_rank_order(std::string(told.begin(), told.end()),
                                       root ? table.header() + table.rows() : table.rows());
  if (!problem.empty()) problem = fmt::format("rank {}: {}", ranks::rank(), problem);
  ranks::stop_if_any<OutputError>(problem);
  if (root) try {
      out->commit();
    } catch (const OutputError& e) {
      problem = e.what();
    }
  ranks::stop_if_any<OutputError>(problem);
}

template <int dim>
void print_step(const StepInfo& info, bool inertial) {
  std::string res;
  for (double r : info.residuals) res += fmt::format(" {:.1e}", r);
  std::string where = info.time_increment > 0.0 ? fmt::format("t {:.6g}  dt {:.3g}", info.time, info.time_increment)
                                                : fmt::format("load {:.4f}", info.load_factor);
  if (inertial) where += fmt::format("  kinetic {:.4g}", info.kinetic_energy);
  fmt::print("  step {:4d}  {}  iterations {:2d}  cuts {}{}  residuals{}{}{}{}  ({:.2f} s)\n", info.step, where,
             info.phases.iterations, info.cuts,
             info.staggers ? fmt::format("  staggers {}", info.staggers) : "", res,
             info.indefinite_solves
                 ? fmt::format("  [{} indefinite tangent(s), linear_solver.general]", info.indefinite_solves)
                 : "",
             info.backtracks ? fmt::format("  [{} halved correction(s): a point inverted]", info.backtracks) : "",
             info.line_searches ? fmt::format("  [{} line-search halving(s)]", info.line_searches) : "", info.seconds);
  if (info.migrated > 0) fmt::print("             {} point(s) moved to another rank\n", info.migrated);
  if (info.at_rest) fmt::print("             at rest: the kinetic energy has fallen to [time] stop_at_rest of its peak\n");
  for (const std::string& why : info.cut_reasons) fmt::print("             cut: {}\n", why);
  std::fflush(stdout);
}

/// A stalled Newton with a stiff rigid box: the likely cause, said in the failure message.
/// Its contact stiffness is penalty x E / h, and the round-off of a penetration of h /
/// (penalty E) per unit pressure sets a floor under the residual: the platen block stalls
/// at 1e-7 with penalty 1e4, where 1e-9 is asked, and converges with 3e3 or less.
std::string penalty_hint(const CaseFile& cf, const std::string& failure) {
  if (failure.find("no convergence") == std::string::npos) return "";
  constexpr double stiff = 1e3;
  for (const std::string section : {"rigid_boxes", "rigid_bodies"})
    for (std::size_t k = 0; k < cf.array_size(section); ++k) {
      const std::string block = fmt::format("{}[{}]", section, k), key = block + ".penalty";
      const double penalty = read_number(cf, block, mpm_section(section).key("penalty"));
      if (penalty > stiff)
        return fmt::format(
            "; {} = {:g} is the likely cause: a contact that stiff leaves round-off above the tolerance; try "
            "{:g} or less (the default is 100), or a larger nonlinear_solver.tolerance",
            key, penalty, stiff);
    }
  return "";
}

/// The case as read, or a strength-reduction trial's: its strengths divided by `factor`.
template <int dim>
MpmCase<dim> with_strength_factor(MpmCase<dim> c, const CaseFile& cf, const std::optional<StrengthTrial>& trial) {
  if (trial) reduce_strengths(cf, c.model.materials, trial->factor);
  return c;
}

/// One MPM run, in the phases `run` reads as: the case read and its header printed, the
/// start (fresh, or a checkpoint's state and outputs), the load steps with their outputs
/// after each (observe), then the final files. A distributed run: rank 0 writes the
/// outputs; the others only their VTU pieces (no CSV files, checkpoints or plots of their
/// own: at 1000 ranks, 999 plots).
template <int dim>
class MpmRun {
 public:
  MpmRun(CaseFile& cf, const fs::path& dir, const MpmRunOptions& options)
      : cf_(cf),
        dir_(dir),
        shown_(options.shown.empty() ? dir : options.shown),
        options_(options),
        quiet_(options.quiet),
        writes_(ranks::rank() == 0),
        case_text_(mpm_canonical_text(cf)),  // a default spelt out is no other case
        // A distributed run's rank makes only its own points (a restart replaces them by
        // the checkpoint's points in its cells).
        c_(with_strength_factor(read_mpm_case<dim>(cf, ranks::distributed()), cf, options.strength_trial)),
        m_(c_.model),
        output_(c_.output),
        dynamic_(m_.time.dynamic()),
        probe_(dir),  // fails now, before solving, if the directory is unusable
        gradient_step_(m_, c_.gradient),
        restart_(options.restart.empty() ? std::nullopt
                                         : std::optional<Restart>(read_checkpoint(options.restart, case_text_, dim))),
        checkpoints_(options.checkpoints.empty() ? checkpoint_folder_of(dir) : options.checkpoints,
                     checkpoint_folder_of(shown_).string(), output_.checkpoint_every, output_.checkpoint_keep),
        tracked_table_(m_, nullptr),  // no gradient fields: one table serves every step
        tracked_columns_(tracked_columns(tracked_table_, m_)),
        block_u_(m_.node_sets.size(), Vec<dim>::Zero()) {
    if (gradient_step_.enabled()) stages_.push_back(&gradient_step_);
    if (dynamic_) {  // a time column after the step's in every CSV file, kinetic energy in energy.csv
      history_ = "step,time,load_factor,iteration,residual\n";
      reactions_ = "step,time,load,name,rx,ry,rz,ux,uy,uz\n";
      energy_ = "step,time,load_factor,work,elastic_energy,dissipation,kinetic_energy\n";
    }
    tracked_ = std::string(dynamic_ ? "step,time,load_factor," : "step,load_factor,") +
               join(tracked_table_.csv_header(tracked_columns_)) + "\n";
    reports_ = !m_.node_sets.empty();
    for (const auto& b : m_.rigid_boxes) reports_ = reports_ || !b.name.empty();
    consolidation_ = std::string(dynamic_ ? "step,time,load_factor," : "step,load_factor,") +
                     "name,points,mean_excess_pore_pressure,degree_of_consolidation\n";
  }

  void run() {
    print_header();
    const DriverState start = restart_ ? restore() : DriverState{};
    // A distributed run: from here on each rank holds the points in its cells (and the
    // gradient step their fields), the outputs gather what they need.
    own_rank_points(m_, stages_);
    if (!restart_) record(0, dynamic_ ? m_.time.load_factor(0.0) : 0.0, 0.0, nullptr);
    const auto t0 = Clock::now();
    try {
      const RunSummary summary = run_quasi_static<dim>(
          m_, c_.newton, stages_, [&](const Model<dim>&, const StepInfo& info) { observe(info); }, start);
      finish(summary, seconds_since(t0));
    } catch (const SolverError& e) {
      if (!quiet_) fmt::print("  stopped; the files of the converged steps go to {}\n", shown_.string());
      const std::string hint = penalty_hint(cf_, e.what());
      if (hint.empty()) throw;
      throw SolverError(std::string(e.what()) + hint);
    }
  }

 private:
  /// The run's first line: what runs, on what, with which process settings.
  void print_header() {
    double points_in_all = m_.points.size();
    std::string partition;  // a distributed run's boxes of cells, and the points they hold
    if (!m_.rank_boxes.empty()) {
      ranks::sum(&points_in_all, 1);  // each rank made its own
      const std::vector<int> held = ranks::all_gather({m_.points.size()});
      std::string across;
      for (int d = 0; d < dim; ++d) across += (d ? " x " : "") + std::to_string(m_.rank_boxes.cut(d).size() - 1);
      partition = fmt::format("; the grid cut into {} boxes of cells, {} to {} points per rank", across,
                              *std::min_element(held.begin(), held.end()), *std::max_element(held.begin(), held.end()));
      if (!cf_.has("linear_solver.type"))  // (the default on several ranks: CommonKeys.cpp)
        partition += fmt::format("; linear solver \"petsc\" (the default on {} ranks: {})", ranks::size(),
                                 c_.newton.linear_solver.options.empty()
                                     ? "CG with GAMG for a symmetric tangent, MUMPS's LU for a general one"
                                     : "its options from linear_solver.options");
    }
    if (quiet_) return;
    const char* tuning = platform_hooks().summary;
    const char* wait = std::getenv("OMP_WAIT_POLICY");
    const TimeSettings& t = m_.time;
    const std::string steps =
        t.inertial() ? fmt::format("dynamic ({}, {} mass, dt {:g} to t = {:g})",
                                   t.scheme == TimeSettings::Scheme::Newmark ? "Newmark" : fmt::format("generalised-alpha, rho_inf {:g}", t.rho_inf),
                                   t.consistent_mass ? "consistent" : "lumped", t.dt, t.end_time)
        : t.dynamic() ? fmt::format("time steps without inertia (dt {:g} to t = {:g})", t.dt, t.end_time)
                      : fmt::format("{} load step(s)", c_.newton.load_steps);
    fmt::print("gradmpm: {}D implicit MPM, {} points, {} grid nodes, basis {}, {}, {}{} thread(s) (OpenMP {}){}{}\n",
               dim, static_cast<long long>(points_in_all), m_.grid.num_nodes(), to_string(m_.basis), steps,
               ranks::distributed() ? fmt::format("{} MPI ranks of ", ranks::size()) : std::string(),
               omp_get_max_threads(), wait ? fmt::format("waiting {}", wait) : std::string("waiting by default"),
               tuning ? fmt::format(", {}", tuning) : std::string(), partition);
  }

  /// The checkpoint's points, driver state and outputs so far; returns where the driver starts.
  DriverState restore() {
    const Archive& a = restart_->archive;
    const DriverState start = restore_run_state<dim>(*restart_, m_, stages_);
    history_ = a.text("outputs/newton_history");
    tracked_ = a.text("outputs/tracked_points");
    reactions_ = a.text("outputs/reactions");
    energy_ = a.text("outputs/energy");
    if (!m_.point_sets.empty()) {
      consolidation_ = a.text("outputs/consolidation");
      peak_excess_ = a.reals("outputs/consolidation_peak", static_cast<long long>(m_.point_sets.size()));
    }
    a.get_objects("outputs/block_displacement", static_cast<long long>(block_u_.size()), block_u_);
    pvd_points_ = get_series(a, "outputs/points_pvd");
    pvd_grid_ = get_series(a, "outputs/grid_pvd");
    if (writes_) link_files(restart_->outputs, dir_);
    if (quiet_) return start;
    fmt::print("  restarting from {}: step {}, load factor {:.6g}\n", options_.restart.string(), start.summary.steps,
               start.load_factor);
    // OpenBLAS splits a factorisation's products by its threads: other threads, other
    // last bits (docs/reliability.md, tests/test_threads.cpp R2b).
    if (restart_->threads > 0 && restart_->threads != omp_get_max_threads())
      fmt::print(
          "  note: the checkpoint was written with {} thread(s), this run has {}: the answer follows the "
          "uninterrupted run's to round-off, not bit for bit (the BLAS sums in another order)\n",
          restart_->threads, omp_get_max_threads());
    return start;
  }

  /// Everything the outputs accumulate from step to step, for a checkpoint.
  void save_outputs(Archive& a) const {
    a.put_text("outputs/newton_history", history_);
    a.put_text("outputs/tracked_points", tracked_);
    a.put_text("outputs/reactions", reactions_);
    a.put_text("outputs/energy", energy_);
    if (!m_.point_sets.empty()) {
      a.put_text("outputs/consolidation", consolidation_);
      a.put("outputs/consolidation_peak", peak_excess_);
    }
    a.put_objects("outputs/block_displacement", block_u_);
    put_series(a, "outputs/points_pvd", pvd_points_);
    put_series(a, "outputs/grid_pvd", pvd_grid_);
  }

  /// The rows of one step (0: the start) in every output that has one.
  void record(int step, double lambda, double time, const StepInfo* info) {
    if (info) react(*info);
    track(step, lambda, time);
    balance(step, lambda, time);
    consolidate(step, lambda, time);
    if (output_.vtk_every > 0 && (step % output_.vtk_every == 0 || (info && info->last)))
      write_vtk(step, dynamic_ ? time : lambda, info);
  }

  /// The first columns of a step's rows: step and load factor, a dynamic run's time between.
  std::string lead(int step, double lambda, double time) const {
    return dynamic_ ? fmt::format("{},{},{}", step, time, lambda) : fmt::format("{},{}", step, lambda);
  }

  /// After each converged load step: its outputs, published whole, and its checkpoint.
  void observe(const StepInfo& info) {
    for (std::size_t k = 0; k < info.residuals.size(); ++k)
      fmt::format_to(std::back_inserter(history_), "{},{},{}\n", lead(info.step, info.load_factor, info.time), k,
                     info.residuals[k]);
    classical_seconds_ += info.seconds;
    const double moved = options_.progress || options_.strength_trial ? largest_displacement() : 0.0;
    if (options_.progress) report_progress(info, moved);
    record(info.step, info.load_factor, info.time, &info);
    if (writes_) {
      StagedOutputs out(dir_);
      out.write_text("newton_history.csv", history_);
      if (!output_.track.empty()) out.write_text("tracked_points.csv", tracked_);
      if (reports_) out.write_text("reactions.csv", reactions_);
      out.write_text("energy.csv", energy_);
      if (!m_.point_sets.empty()) out.write_text("consolidation.csv", consolidation_);
      out.commit();
      if (!quiet_) print_step<dim>(info, m_.time.inertial());
    }
    if (checkpoints_.due(info)) checkpoint(info);
    if (options_.strength_trial && moved > options_.strength_trial->failure_displacement)
      throw SolverError(fmt::format("load step {} (load factor {:.6g}): a point has moved {:.4g}, beyond "
                                    "analysis.failure_displacement = {:g}",
                                    info.step, info.load_factor, moved, options_.strength_trial->failure_displacement));
  }

  double largest_displacement() const {
    double largest = 0.0;
    for (int p = 0; p < m_.points.size(); ++p)
      largest = std::max(largest, (m_.points.position[p] - m_.points.original_position[p]).norm());
    return largest;
  }

  void report_progress(const StepInfo& info, double moved) {
    MpmRunProgress& p = *options_.progress;
    p.load_factor = info.load_factor;
    p.steps = info.step;
    p.iterations += info.phases.iterations;
    p.cuts += info.cuts;
    p.max_displacement = moved;
  }

  /// A distributed run's ranks write their points each (no rank holds every point), rank
  /// 0 the rest; every rank goes on once the checkpoint is in place.
  void checkpoint(const StepInfo& info) {
    Archive a, points;
    put_checkpoint_header(a, case_text_, dim, info.step, omp_get_max_threads());
    save_run_state<dim>(a, points, m_, info.after, stages_);
    save_outputs(a);
    const auto t_write = Clock::now();
    const std::string where = checkpoints_.write(info.step, a, points, dir_);
    if (!quiet_) fmt::print("  checkpoint {} ({:.2f} s)\n", where, seconds_since(t_write));
  }

  /// `at`: the PVD series' value of the step (the load factor, a dynamic run's time).
  void write_vtk(int step, double at, const StepInfo* info) {
    const PointColumns<dim> table(m_, gradient_step_.fields());
    std::vector<std::string> names = vtu_point_columns(table);
    if (dynamic_) names.push_back("velocity");
    if (m_.pore.active()) names.push_back("pore_pressure");
    if (m_.pore.water_table) names.push_back("excess_pore_pressure");
    const std::vector<VtkField> grid_fields = grid_vtk_fields(m_, info);  // (collective)
    // A distributed run: each rank its piece of each (its points, its cells of the grid),
    // and rank 0 the .pvtu files naming them.
    const bool in_pieces = ranks::distributed();
    const std::string pf = fmt::format("points_{:04d}.{}", step, in_pieces ? "pvtu" : "vtu");
    const std::string gf = fmt::format("grid_{:04d}.{}", step, in_pieces ? "pvtu" : "vtu");
    const auto pieces = in_pieces ? write_vtu_pieces(options_.pieces, step,
                                                     {{"points", table.vtu(names)}, {"grid", grid_vtu(m_, grid_fields)}})
                                  : std::vector<std::vector<std::string>>{};
    if (!writes_) return;  // rank 0 writes the rest
    StagedOutputs out(dir_);
    out.write_text(pf, in_pieces ? pvtu(table.vtk_layout(names), pieces[0]) : table.vtu(names));
    out.write_text(gf, in_pieces ? pvtu(grid_fields, pieces[1]) : grid_vtu(m_, grid_fields));
    pvd_points_.emplace_back(at, pf);
    pvd_grid_.emplace_back(at, gf);
    out.write_text("points.pvd", pvd(pvd_points_));
    out.write_text("grid.pvd", pvd(pvd_grid_));
    out.commit();
  }

  void reaction_row(const StepInfo& info, const std::string& name, const Vec<dim>& r, const Vec<dim>& u) {
    double rv[3] = {0, 0, 0}, uv[3] = {0, 0, 0};
    for (int d = 0; d < dim; ++d) {
      rv[d] = r[d];
      uv[d] = u[d];
    }
    fmt::format_to(std::back_inserter(reactions_), "{},{},{},{},{},{},{},{}\n", lead(info.step, info.load_factor, info.time),
                   name, rv[0], rv[1], rv[2], uv[0], uv[1], uv[2]);
  }

  /// Named constraint blocks: reaction (the sum over the nodes) and mean displacement (the
  /// nodes' increments summed over the steps); named rigid boxes: the force each exerts on
  /// the body, and its displacement.
  void react(const StepInfo& info) {
    if (!reports_) return;
    if (!m_.node_sets.empty()) react_node_sets(info);
    const Vector F = m_.rigid_boxes.empty() ? Vector() : info.rigid_forces();
    for (std::size_t b = 0; b < m_.rigid_boxes.size(); ++b)
      if (!m_.rigid_boxes[b].name.empty())
        reaction_row(info, m_.rigid_boxes[b].name, F.template segment<dim>(b * dim),
                     info.load_factor * m_.rigid_boxes[b].total);
  }

  /// Per set: the reactions and increments summed over its active nodes, and their count.
  /// A distributed run's ranks sum the nodes they own (the fields are right there), then
  /// the sums are added over the ranks: nothing is gathered whole.
  void react_node_sets(const StepInfo& info) {
    const Vector &R = info.grid_reaction(), &du = info.grid_displacement();
    const bool split = !m_.rank_boxes.empty();
    // A distributed run's fields are at the nodes listed (the active ones it knows).
    const std::vector<int> listed = split ? info.grid_nodes() : std::vector<int>{};
    const std::vector<bool> solved = split ? std::vector<bool>{} : info.grid_active();
    constexpr int per_set = 2 * dim + 1;  // r, sum of du, active nodes
    std::vector<double> sums(m_.node_sets.size() * per_set, 0.0);
    for (std::size_t b = 0; b < m_.node_sets.size(); ++b) {
      double* s = &sums[b * per_set];
      for (int n : m_.node_sets[b].nodes) {
        int at = n;  // where n's values are
        if (split) {
          if (m_.rank_boxes.owner(n) != ranks::rank()) continue;
          at = listed_position(listed, n);
          if (at < 0) continue;
        } else if (!solved[n]) {
          continue;
        }
        s[2 * dim] += 1.0;  // the mean displacement is over the nodes the step solved for
        for (int d = 0; d < dim; ++d) {
          s[d] += R[at * dim + d];
          s[dim + d] += du[at * dim + d];
        }
      }
    }
    if (split) ranks::sum(sums.data(), sums.size());
    for (std::size_t b = 0; b < m_.node_sets.size(); ++b) {
      const double* s = &sums[b * per_set];
      Vec<dim> r, mean;
      for (int d = 0; d < dim; ++d) {
        r[d] = s[d];
        mean[d] = s[dim + d];
      }
      if (s[2 * dim] > 0.0) block_u_[b] += mean / s[2 * dim];
      reaction_row(info, m_.node_sets[b].name, r, block_u_[b]);
    }
  }

  /// The energy balance: the work of the points' stresses (= the external work, reactions
  /// included, at equilibrium), the elastic energy they store, and what they dissipated.
  void balance(int step, double lambda, double time) {
    double sums[3] = {0.0, 0.0, 0.0};  // work, stored, kinetic
    for (int p = 0; p < m_.points.size(); ++p) {
      sums[0] += m_.points.work[p];
      sums[1] += m_.elastic_energy(p);
      sums[2] += 0.5 * m_.points.mass[p] * m_.points.velocity[p].squaredNorm();
    }
    ranks::sum(sums, 3);  // a distributed run: each rank's points
    fmt::format_to(std::back_inserter(energy_), "{},{},{},{}{}\n", lead(step, lambda, time), sums[0], sums[1],
                   sums[0] - sums[1], dynamic_ ? fmt::format(",{}", sums[2]) : std::string());
  }

  /// Each point set's mean excess pore pressure (weighted by the points' volumes) and its
  /// degree of consolidation U = 1 - mean / peak, peak the mean of largest size so far: the
  /// share of the excess pressure the set has lost since its peak (Terzaghi's average
  /// degree of consolidation where the load comes at once).
  void consolidate(int step, double lambda, double time) {
    if (m_.point_sets.empty()) return;
    peak_excess_.resize(m_.point_sets.size(), 0.0);
    for (std::size_t s = 0; s < m_.point_sets.size(); ++s) {
      double weighted = 0.0, volume = 0.0;
      for (const int p : m_.point_sets[s].points) {
        weighted += m_.points.volume[p] * (m_.points.pore_pressure[p] - hydrostatic_pressure(m_, p));
        volume += m_.points.volume[p];
      }
      const double mean = weighted / volume;
      if (std::abs(mean) > std::abs(peak_excess_[s])) peak_excess_[s] = mean;
      const double degree = peak_excess_[s] != 0.0 ? 1.0 - mean / peak_excess_[s] : 0.0;
      fmt::format_to(std::back_inserter(consolidation_), "{},{},{},{},{}\n", lead(step, lambda, time),
                     m_.point_sets[s].name, m_.point_sets[s].points.size(), mean, degree);
    }
  }

  void track(int step, double lambda, double time) {
    const std::vector<double> first =
        dynamic_ ? std::vector<double>{double(step), time, lambda} : std::vector<double>{double(step), lambda};
    if (!ranks::distributed()) {
      tracked_table_.append_rows(tracked_, first, output_.track, tracked_columns_);
      return;
    }
    // Each rank the rows of the tracked points it owns, "k row" (k: the place in the
    // list); rank 0 puts them in the list's order.
    std::string mine;
    for (std::size_t k = 0; k < output_.track.size(); ++k) {
      const auto at = std::lower_bound(m_.point_ids.begin(), m_.point_ids.end(), output_.track[k]);
      if (at == m_.point_ids.end() || *at != output_.track[k]) continue;
      mine += fmt::format("{} ", k);
      tracked_table_.append_rows(mine, first, {at - m_.point_ids.begin()}, tracked_columns_);
    }
    const std::vector<std::string> from_ranks = ranks::gather_on_root(mine);
    if (!writes_) return;
    std::vector<std::string> rows(output_.track.size());
    for (const std::string& text : from_ranks) {
      std::istringstream in(text);
      std::size_t k = 0;
      std::string row;
      while (in >> k && std::getline(in >> std::ws, row)) rows.at(k) = row + "\n";
    }
    for (const std::string& row : rows) tracked_ += row;
  }

  /// The final files in id order. A distributed run's ranks take even runs of ids
  /// (arrange_by_id) and each writes its rows at their place: no rank holds every point.
  void write_final_points() {
    arrange_by_id(m_, stages_);
    const PointColumns<dim> table(m_, gradient_step_.fields());
    std::vector<std::string> final_columns = table.with_state(kFinalColumns);
    final_columns.push_back("dissipation");  // last: the columns before it keep their places
    if (dynamic_) final_columns.push_back("velocity");
    if (m_.pore.active()) final_columns.push_back("pore_pressure");
    if (m_.pore.water_table) final_columns.push_back("excess_pore_pressure");
    write_in_id_order(dir_, options_.pieces, "points_final.csv", table.csv(final_columns));
    if (gradient_step_.fields())
      write_in_id_order(dir_, options_.pieces, "points_gradient.csv", table.csv(kGradientColumns));
  }

  /// After the last step: the final files, the summary lines, the plot and the column check.
  void finish(const RunSummary& summary, double seconds) {
    write_final_points();
    if (output_.check == "column") collect_on_root(m_, stages_);  // the check reads every point (on rank 0)
    if (!writes_) return;
    if (gradient_step_.enabled() && !quiet_)
      fmt::print(
          "  gradient step ({}, l = {:g}, apply = {}, fields = {}): {:.3f} s = {:.1f} % of the classical solve\n",
          to_string(c_.gradient.variant), c_.gradient.length_scale,
          c_.gradient.apply == GradientApply::End ? "end" : "each_step",
          c_.gradient.fields == GradientFields::Grid ? "grid" : "points", gradient_step_.seconds(),
          100.0 * gradient_step_.seconds() / std::max(classical_seconds_, 1e-12));
    if (!quiet_)
      fmt::print(
          "  done: {} steps, {} Newton iterations, {} cut(s), {:.2f} s; {}peak memory {:.0f} MiB (estimated {:.0f} "
          "MiB)\n",
          summary.steps, summary.total_iterations, summary.cuts, seconds, ranks::distributed() ? "rank 0's " : "",
          peak_resident_memory() / 1048576.0, c_.memory_estimate / 1048576.0);
    if (reports_ && output_.plot) {
      StagedOutputs out(dir_);
      const auto csv = out.write_text("reactions.csv", reactions_);
      const auto png = out.stage("load_displacement.png");
      run_python_script(embedded::plot_load_displacement_py,
                        {csv.string(), png.string(), fmt::format("{}D MPM, {} load steps", dim, summary.steps)});
      out.commit();
    }
    if (output_.check == "column") {
      const std::string line = column_check(m_, dir_, output_.plot);
      if (!quiet_) fmt::print("  {}\n", line);
    }
  }

  CaseFile& cf_;
  const fs::path dir_, shown_;
  const MpmRunOptions& options_;
  const bool quiet_, writes_;
  const std::string case_text_;
  MpmCase<dim> c_;
  Model<dim>& m_;
  const MpmOutputSettings& output_;
  const bool dynamic_;  ///< [time]: a time column in the outputs
  StagedOutputs probe_;
  GradientStep<dim> gradient_step_;
  std::vector<PostStepStage<dim>*> stages_;
  std::optional<Restart> restart_;
  const CheckpointFolder checkpoints_;
  const PointColumns<dim> tracked_table_;
  const std::vector<std::string> tracked_columns_;
  double classical_seconds_ = 0.0;
  Series pvd_points_, pvd_grid_;
  std::string history_ = "step,load_factor,iteration,residual\n";
  std::string tracked_;
  std::string reactions_ = "step,load,name,rx,ry,rz,ux,uy,uz\n";
  std::string energy_ = "step,load_factor,work,elastic_energy,dissipation\n";
  std::string consolidation_;        ///< consolidation.csv ([[point_sets]])
  std::vector<double> peak_excess_;  ///< per point set: its mean excess pore pressure of largest size so far
  std::vector<Vec<dim>> block_u_;
  bool reports_ = false;
};

template <int dim>
void run(CaseFile& cf, const fs::path& dir, const MpmRunOptions& options) {
  MpmRun<dim>(cf, dir, options).run();
}

}  // namespace

void run_mpm_case(CaseFile& cf, const fs::path& out_dir, const MpmRunOptions& options) {
  if (!options.strength_trial)
    if (const auto reduction = read_strength_reduction(cf)) return run_strength_reduction(cf, out_dir, options, *reduction);
  switch (mpm_case_dimension(cf)) {
    case 1:
      return run<1>(cf, out_dir, options);
    case 2:
      return run<2>(cf, out_dir, options);
    default:
      return run<3>(cf, out_dir, options);
  }
}

}  // namespace gradmpm
