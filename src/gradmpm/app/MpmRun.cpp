// Runs an MPM case: reads it (app/MpmCaseReader.cpp), solves it with the gradient step
// as a post-step stage of the driver, and writes the outputs, each file all or nothing:
//   points_NNNN.vtu, grid_NNNN.vtu, points.pvd, grid.pvd   every output.vtk_every steps
//     (on N MPI ranks points_NNNN.pvtu and one piece points_NNNN_R.vtu per rank)
//   newton_history.csv, tracked_points.csv, reactions.csv,
//   energy.csv (work, elastic energy, dissipation)          after every step
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
#include "gradmpm/core/Errors.hpp"
#include "gradmpm/core/LoadTimeEnvironment.hpp"
#include "gradmpm/core/Ranks.hpp"
#include "gradmpm/core/Timer.hpp"
#include "gradmpm/io/EmbeddedScripts.hpp"
#include "gradmpm/io/Python.hpp"
#include "gradmpm/io/StagedOutputs.hpp"
#include "gradmpm/io/Vtk.hpp"

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
void print_step(const StepInfo& info) {
  std::string res;
  for (double r : info.residuals) res += fmt::format(" {:.1e}", r);
  fmt::print("  step {:4d}  load {:.4f}  iterations {:2d}  cuts {}{}  residuals{}{}{}  ({:.2f} s)\n", info.step,
             info.load_factor, info.phases.iterations, info.cuts,
             info.staggers ? fmt::format("  staggers {}", info.staggers) : "", res,
             info.indefinite_solves
                 ? fmt::format("  [{} indefinite tangent(s), linear_solver.general]", info.indefinite_solves)
                 : "",
             info.backtracks ? fmt::format("  [{} halved correction(s): a point inverted]", info.backtracks) : "",
             info.seconds);
  if (info.migrated > 0) fmt::print("             {} point(s) moved to another rank\n", info.migrated);
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
  for (std::size_t k = 0; k < cf.array_size("rigid_boxes"); ++k) {
    const std::string key = fmt::format("rigid_boxes[{}].penalty", k);
    const double penalty = read_number(cf, fmt::format("rigid_boxes[{}]", k), mpm_section("rigid_boxes").key("penalty"));
    if (penalty > stiff)
      return fmt::format(
          "; {} = {:g} is the likely cause: a contact that stiff leaves round-off above the tolerance; try "
          "{:g} or less (the default is 100), or a larger nonlinear_solver.tolerance",
          key, penalty, stiff);
  }
  return "";
}

template <int dim>
void run(CaseFile& cf, const fs::path& dir, const MpmRunOptions& options) {
  const bool quiet = options.quiet;
  // A distributed run: rank 0 writes the outputs; the others only their VTU pieces (no
  // CSV files, checkpoints or plots of their own: at 1000 ranks, 999 plots).
  const bool writes = ranks::rank() == 0;
  const fs::path shown = options.shown.empty() ? dir : options.shown;
  const std::string case_text = mpm_canonical_text(cf);  // a default spelt out is no other case
  // A distributed run's rank makes only its own points (a restart replaces them by the
  // checkpoint's points in its cells).
  MpmCase<dim> c = read_mpm_case<dim>(cf, ranks::distributed());
  Model<dim>& m = c.model;
  const MpmOutputSettings& output = c.output;
  StagedOutputs probe(dir);  // fails now, before solving, if the directory is unusable
  GradientStep<dim> gradient_step(m, c.gradient);
  std::vector<PostStepStage<dim>*> stages;
  if (gradient_step.enabled()) stages.push_back(&gradient_step);
  double classical_seconds = 0.0;
  std::optional<Restart> restart;
  if (!options.restart.empty()) restart = read_checkpoint(options.restart, case_text, dim);
  const CheckpointFolder checkpoints(options.checkpoints.empty() ? checkpoint_folder_of(dir) : options.checkpoints,
                                     checkpoint_folder_of(shown).string(), output.checkpoint_every,
                                     output.checkpoint_keep);

  std::vector<std::pair<double, std::string>> pvd_points, pvd_grid;
  std::string history = "step,load_factor,iteration,residual\n";
  // The tracked columns hold no gradient fields: one table serves every step (its columns
  // read the points when written).
  const PointColumns<dim> tracked_table(m, nullptr);
  const std::vector<std::string> tracked_columns = tracked_table.with_state(kTrackedColumns);
  std::string tracked = "step,load_factor," + join(tracked_table.csv_header(tracked_columns)) + "\n";
  auto write_vtk = [&](int step, double lambda, const StepInfo* info) {
    const PointColumns<dim> table(m, gradient_step.fields());
    const std::vector<std::string> names = vtu_point_columns(table);
    const std::vector<VtkField> grid_fields = grid_vtk_fields(m, info);  // (collective)
    // A distributed run: each rank its piece of each (its points, its cells of the grid),
    // and rank 0 the .pvtu files naming them.
    const bool in_pieces = ranks::distributed();
    const std::string pf = fmt::format("points_{:04d}.{}", step, in_pieces ? "pvtu" : "vtu");
    const std::string gf = fmt::format("grid_{:04d}.{}", step, in_pieces ? "pvtu" : "vtu");
    const auto pieces = in_pieces ? write_vtu_pieces(options.pieces, step,
                                                     {{"points", table.vtu(names)}, {"grid", grid_vtu(m, grid_fields)}})
                                  : std::vector<std::vector<std::string>>{};
    if (!writes) return;  // rank 0 writes the rest
    StagedOutputs out(dir);
    out.write_text(pf, in_pieces ? pvtu(table.vtk_layout(names), pieces[0]) : table.vtu(names));
    out.write_text(gf, in_pieces ? pvtu(grid_fields, pieces[1]) : grid_vtu(m, grid_fields));
    pvd_points.emplace_back(lambda, pf);
    pvd_grid.emplace_back(lambda, gf);
    out.write_text("points.pvd", pvd(pvd_points));
    out.write_text("grid.pvd", pvd(pvd_grid));
    out.commit();
  };
  // Named constraint blocks: reaction (sum over the nodes) and mean displacement (the
  // nodes' increments summed over the steps); named rigid boxes: contact force and displacement.
  std::string reactions = "step,load,name,rx,ry,rz,ux,uy,uz\n";
  std::vector<Vec<dim>> block_u(m.node_sets.size(), Vec<dim>::Zero());
  bool reports = !m.node_sets.empty();
  for (const auto& b : m.rigid_boxes) reports = reports || !b.name.empty();
  auto react = [&](const StepInfo& info) {
    if (!reports) return;
    auto row = [&](const std::string& name, const Vec<dim>& r, const Vec<dim>& u) {
      double rv[3] = {0, 0, 0}, uv[3] = {0, 0, 0};
      for (int d = 0; d < dim; ++d) {
        rv[d] = r[d];
        uv[d] = u[d];
      }
      fmt::format_to(std::back_inserter(reactions), "{},{},{},{},{},{},{},{},{}\n", info.step, info.load_factor, name,
                     rv[0], rv[1], rv[2], uv[0], uv[1], uv[2]);
    };
    if (!m.node_sets.empty()) {
      // Per set: the reactions and increments summed over its active nodes, and their
      // count. A distributed run's ranks sum the nodes they own (the fields are right
      // there), then the sums are added over the ranks: nothing is gathered whole.
      const Vector &R = info.grid_reaction(), &du = info.grid_displacement();
      const bool split = !m.rank_boxes.empty();
      // A distributed run's fields are at the nodes listed (the active ones it knows).
      const std::vector<int> listed = split ? info.grid_nodes() : std::vector<int>{};
      const std::vector<bool> solved = split ? std::vector<bool>{} : info.grid_active();
      constexpr int per_set = 2 * dim + 1;  // r, sum of du, active nodes
      std::vector<double> sums(m.node_sets.size() * per_set, 0.0);
      for (std::size_t b = 0; b < m.node_sets.size(); ++b) {
        double* s = &sums[b * per_set];
        for (int n : m.node_sets[b].nodes) {
          int at = n;  // where n's values are
          if (split) {
            if (m.rank_boxes.owner(n) != ranks::rank()) continue;
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
      for (std::size_t b = 0; b < m.node_sets.size(); ++b) {
        const double* s = &sums[b * per_set];
        Vec<dim> r, mean;
        for (int d = 0; d < dim; ++d) {
          r[d] = s[d];
          mean[d] = s[dim + d];
        }
        if (s[2 * dim] > 0.0) block_u[b] += mean / s[2 * dim];
        row(m.node_sets[b].name, r, block_u[b]);
      }
    }
    // Rigid boxes: the force each exerts on the body, and its displacement.
    const Vector F = m.rigid_boxes.empty() ? Vector() : info.rigid_forces();
    for (std::size_t b = 0; b < m.rigid_boxes.size(); ++b)
      if (!m.rigid_boxes[b].name.empty())
        row(m.rigid_boxes[b].name, F.template segment<dim>(b * dim), info.load_factor * m.rigid_boxes[b].total);
  };
  // The energy balance: the work of the points' stresses (= the external work, reactions
  // included, at equilibrium), the elastic energy they store, and what they dissipated.
  std::string energy = "step,load_factor,work,elastic_energy,dissipation\n";
  auto balance = [&](int step, double lambda) {
    double sums[2] = {0.0, 0.0};  // work, stored
    for (int p = 0; p < m.points.size(); ++p) {
      sums[0] += m.points.work[p];
      sums[1] += m.elastic_energy(p);
    }
    ranks::sum(sums, 2);  // a distributed run: each rank's points
    fmt::format_to(std::back_inserter(energy), "{},{},{},{},{}\n", step, lambda, sums[0], sums[1], sums[0] - sums[1]);
  };
  auto track = [&](int step, double lambda) {
    if (!ranks::distributed()) {
      tracked_table.append_rows(tracked, {double(step), lambda}, output.track, tracked_columns);
      return;
    }
    // Each rank the rows of the tracked points it owns, "k row" (k: the place in the
    // list); rank 0 puts them in the list's order.
    std::string mine;
    for (std::size_t k = 0; k < output.track.size(); ++k) {
      const auto at = std::lower_bound(m.point_ids.begin(), m.point_ids.end(), output.track[k]);
      if (at == m.point_ids.end() || *at != output.track[k]) continue;
      mine += fmt::format("{} ", k);
      tracked_table.append_rows(mine, {double(step), lambda}, {at - m.point_ids.begin()}, tracked_columns);
    }
    const std::vector<std::string> from_ranks = ranks::gather_on_root(mine);
    if (!writes) return;
    std::vector<std::string> rows(output.track.size());
    for (const std::string& text : from_ranks) {
      std::istringstream in(text);
      std::size_t k = 0;
      std::string row;
      while (in >> k && std::getline(in >> std::ws, row)) rows.at(k) = row + "\n";
    }
    for (const std::string& row : rows) tracked += row;
  };
  double points_in_all = m.points.size();
  std::string partition;  // a distributed run's boxes of cells, and the points they hold
  if (!m.rank_boxes.empty()) {
    ranks::sum(&points_in_all, 1);  // each rank made its own
    const std::vector<int> held = ranks::all_gather({m.points.size()});
    std::string across;
    for (int d = 0; d < dim; ++d) across += (d ? " x " : "") + std::to_string(m.rank_boxes.cut(d).size() - 1);
    partition = fmt::format("; the grid cut into {} boxes of cells, {} to {} points per rank", across,
                            *std::min_element(held.begin(), held.end()), *std::max_element(held.begin(), held.end()));
    if (!cf.has("linear_solver.type"))  // (the default on several ranks: CommonKeys.cpp)
      partition += fmt::format("; linear solver \"petsc\" (the default on {} ranks: {})", ranks::size(),
                               c.newton.linear_solver.options.empty()
                                   ? "CG with GAMG for a symmetric tangent, MUMPS's LU for a general one"
                                   : "its options from linear_solver.options");
  }

  const std::string hugetlb = malloc_hugetlb();
  if (!quiet)
    fmt::print(
        "gradmpm: {}D implicit MPM, {} points, {} grid nodes, basis {}, {} load step(s), {}{} thread(s) (OpenMP {}), "
        "{}, {}{}\n",
        dim, static_cast<long long>(points_in_all), m.grid.num_nodes(), to_string(m.basis), c.newton.load_steps,
        ranks::distributed() ? fmt::format("{} MPI ranks of ", ranks::size()) : std::string(), omp_get_max_threads(),
        std::getenv("OMP_WAIT_POLICY") ? fmt::format("waiting {}", std::getenv("OMP_WAIT_POLICY"))
                                       : std::string("waiting by default"),
        hugetlb.empty() || hugetlb == "0" ? std::string("no huge pages")
                                          : fmt::format("huge pages (glibc.malloc.hugetlb={})", hugetlb),
        malloc_keeps_freed_memory() ? "freed memory kept (glibc.malloc.mmap_max=0)" : "freed memory returned",
        partition);
  // Everything the outputs accumulate from step to step, for a checkpoint.
  auto save_outputs = [&](Archive& a) {
    a.put_text("outputs/newton_history", history);
    a.put_text("outputs/tracked_points", tracked);
    a.put_text("outputs/reactions", reactions);
    a.put_text("outputs/energy", energy);
    a.put_objects("outputs/block_displacement", block_u);
    put_series(a, "outputs/points_pvd", pvd_points);
    put_series(a, "outputs/grid_pvd", pvd_grid);
  };
  DriverState start;
  if (restart) {
    const Archive& a = restart->archive;
    start = restore_run_state<dim>(*restart, m, stages);
    history = a.text("outputs/newton_history");
    tracked = a.text("outputs/tracked_points");
    reactions = a.text("outputs/reactions");
    energy = a.text("outputs/energy");
    a.get_objects("outputs/block_displacement", static_cast<long long>(block_u.size()), block_u);
    pvd_points = get_series(a, "outputs/points_pvd");
    pvd_grid = get_series(a, "outputs/grid_pvd");
    if (writes) link_files(restart->outputs, dir);
    if (!quiet) {
      fmt::print("  restarting from {}: step {}, load factor {:.6g}\n", options.restart.string(), start.summary.steps,
                 start.load_factor);
      // OpenBLAS splits a factorisation's products by its threads: other threads, other
      // last bits (docs/reliability.md, tests/test_threads.cpp R2b).
      if (restart->threads > 0 && restart->threads != omp_get_max_threads())
        fmt::print(
            "  note: the checkpoint was written with {} thread(s), this run has {}: the answer follows the "
            "uninterrupted run's to round-off, not bit for bit (the BLAS sums in another order)\n",
            restart->threads, omp_get_max_threads());
    }
  }
  // A distributed run: from here on each rank holds the points in its cells (and the
  // gradient step their fields), the outputs gather what they need.
  own_rank_points(m, stages);
  if (!restart) {
    if (output.vtk_every > 0) write_vtk(0, 0.0, nullptr);
    track(0, 0.0);
    balance(0, 0.0);
  }

  const auto t0 = Clock::now();
  try {
    const RunSummary summary = run_quasi_static<dim>(
        m, c.newton, stages,
        [&](const Model<dim>&, const StepInfo& info) {
          for (std::size_t k = 0; k < info.residuals.size(); ++k)
            fmt::format_to(std::back_inserter(history), "{},{},{},{}\n", info.step, info.load_factor, k,
                           info.residuals[k]);
          track(info.step, info.load_factor);
          react(info);
          balance(info.step, info.load_factor);
          classical_seconds += info.seconds;
          if (output.vtk_every > 0 && (info.step % output.vtk_every == 0 || info.last))
            write_vtk(info.step, info.load_factor, &info);
          if (writes) {
            StagedOutputs out(dir);
            out.write_text("newton_history.csv", history);
            if (!output.track.empty()) out.write_text("tracked_points.csv", tracked);
            if (reports) out.write_text("reactions.csv", reactions);
            out.write_text("energy.csv", energy);
            out.commit();
            if (!quiet) print_step<dim>(info);
          }
          if (checkpoints.due(info)) {
            // A distributed run's ranks write their points each (no rank holds every
            // point), rank 0 the rest; every rank goes on once the checkpoint is in place.
            Archive a, points;
            put_checkpoint_header(a, case_text, dim, info.step, omp_get_max_threads());
            save_run_state<dim>(a, points, m, info.after, stages);
            save_outputs(a);
            const auto t_write = Clock::now();
            const std::string where = checkpoints.write(info.step, a, points, dir);
            if (!quiet) fmt::print("  checkpoint {} ({:.2f} s)\n", where, seconds_since(t_write));
          }
        },
        start);
    {
      // The final files in id order. A distributed run's ranks take even runs of ids
      // (arrange_by_id) and each writes its rows at their place: no rank holds every point.
      arrange_by_id(m, stages);
      const PointColumns<dim> table(m, gradient_step.fields());
      std::vector<std::string> final_columns = table.with_state(kFinalColumns);
      final_columns.push_back("dissipation");  // last: the columns before it keep their places
      write_in_id_order(dir, options.pieces, "points_final.csv", table.csv(final_columns));
      if (gradient_step.fields())
        write_in_id_order(dir, options.pieces, "points_gradient.csv", table.csv(kGradientColumns));
    }
    if (output.check == "column") collect_on_root(m, stages);  // the check reads every point (on rank 0)
    if (!writes) return;
    if (gradient_step.enabled() && !quiet)
      fmt::print(
          "  gradient step ({}, l = {:g}, apply = {}, fields = {}): {:.3f} s = {:.1f} % of the classical solve\n",
          to_string(c.gradient.variant), c.gradient.length_scale,
          c.gradient.apply == GradientApply::End ? "end" : "each_step",
          c.gradient.fields == GradientFields::Grid ? "grid" : "points", gradient_step.seconds(),
          100.0 * gradient_step.seconds() / std::max(classical_seconds, 1e-12));
    if (!quiet)
      fmt::print("  done: {} steps, {} Newton iterations, {} cut(s), {:.2f} s; {}peak memory {:.0f} MiB (estimated {:.0f} MiB)\n",
                 summary.steps, summary.total_iterations, summary.cuts, seconds_since(t0),
                 ranks::distributed() ? "rank 0's " : "", peak_resident_memory() / 1048576.0, c.memory_estimate / 1048576.0);
    if (reports && output.plot) {
      StagedOutputs out(dir);
      const auto csv = out.write_text("reactions.csv", reactions);
      const auto png = out.stage("load_displacement.png");
      run_python_script(embedded::plot_load_displacement_py,
                        {csv.string(), png.string(), fmt::format("{}D MPM, {} load steps", dim, summary.steps)});
      out.commit();
    }
    if (output.check == "column") {
      const std::string line = column_check(m, dir, output.plot);
      if (!quiet) fmt::print("  {}\n", line);
    }
  } catch (const SolverError& e) {
    if (!quiet) fmt::print("  stopped; the files of the converged steps go to {}\n", shown.string());
    const std::string hint = penalty_hint(cf, e.what());
    if (hint.empty()) throw;
    throw SolverError(std::string(e.what()) + hint);
  }
}

}  // namespace

void run_mpm_case(CaseFile& cf, const fs::path& out_dir, const MpmRunOptions& options) {
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
