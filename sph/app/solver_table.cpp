#include "sph/app/solver_table.h"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "common/checked_file.h"
#include "common/exit_codes.h"
#include "common/image_writer.h"
#include "common/output_folder.h"
#include "common/picture_grid.h"
#include "common/progress.h"
#include "common/stopwatch.h"
#include "sph/app/scene_runner.h"
#include "sph/app/solver_comparison.h"
#include "sph/core/config.h"
#include "sph/core/simulation_error.h"
#include "sph/simulation/frame_loop.h"
#include "sph/simulation/simulation.h"

namespace sph {

namespace {

std::string format(const char* pattern, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, pattern, value);
  return buf;
}

std::string time_label(double t) {
  return "t = " + format("%g", t) + " s";
}

void check_request(const SolverTableRequest& r) {
  if (r.solvers.empty())
    throw common::InputError(
        "--solvers: expected at least one solver, comma-separated (e.g. dfsph,wcsph)");
  for (size_t i = 0; i < r.solvers.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (r.solvers[i] == r.solvers[j])
        throw common::InputError("--solvers: \"" + r.solvers[i] + "\" is named twice");
  if (r.frames.empty())
    throw common::InputError(
        "--frames: expected at least one frame count, comma-separated (e.g. 40,80,120)");
  for (size_t k = 0; k < r.frames.size(); ++k) {
    if (r.frames[k] < 1)
      throw common::InputError("--frames: expected frame counts >= 1, got " +
                               std::to_string(r.frames[k]));
    if (k > 0 && r.frames[k] <= r.frames[k - 1])
      throw common::InputError("--frames: expected increasing frame counts, got " +
                               std::to_string(r.frames[k]) + " after " +
                               std::to_string(r.frames[k - 1]));
  }
  if (r.cell_width < 16)
    throw common::InputError("views.png: expected cells at least 16 pixels wide, got " +
                             std::to_string(r.cell_width));
}

// The view of one moment: the active fluid over the boundary, oil where its fraction >= 0.5.
common::RgbImage render_view(const Simulation& sim, const common::FrameRenderer& renderer,
                             common::ViewAxis axis) {
  const FluidParticles& f = sim.fluid();
  std::vector<common::Point> points(f.active_count());
  std::vector<std::uint8_t> oil(f.active_count());
  for (Index i = 0; i < f.active_count(); ++i) {
    points[i] = f.position[i].cast<float>();
    oil[i] = is_oil(f.oil_fraction[i]);
  }
  return renderer.render(points, oil, axis);
}

// What a responder compares between solvers: the largest slick and how far its front got over
// the whole run (at the end of a long run the oil may have left the reach), with the first bank
// contacts and arrivals, from the same per-frame metrics a run's spill.json holds.
nlohmann::json spill_summary(const SpillMetrics& spill) {
  const nlohmann::json all = spill.to_json();
  double peak_area = 0, peak_area_t = 0, furthest = 0;
  for (const auto& frame : all.at("frames")) {
    const double area = frame.at("slick_area_m2").get<double>();
    if (area > peak_area) {
      peak_area = area;
      peak_area_t = frame.at("t").get<double>();
    }
    furthest = std::max(furthest, frame.at("front_distance_m").get<double>());
  }
  return {{"peak_slick_area_m2", peak_area},
          {"peak_slick_area_t_s", peak_area_t},
          {"furthest_front_m", furthest},
          {"first_left_bank_contact_s", all.at("first_left_bank_contact_s")},
          {"first_right_bank_contact_s", all.at("first_right_bank_contact_s")},
          {"arrival_s", all.at("arrival_s")}};
}

std::string failure_text(const nlohmann::json& failure) {
  const nlohmann::json& frame = failure.at("frame");
  return frame.is_null() ? std::string("failed while setting up")
                         : "failed in frame " + std::to_string(frame.get<int>()) +
                               " (at t = " + format("%g", failure.at("t_s").get<double>()) + " s)";
}

struct SolverRun {
  nlohmann::json row;
  std::vector<std::optional<common::RgbImage>> views;  // per moment; empty where not reached
};

SolverRun run_solver(const LoadedScene& scene, const SolverTableRequest& r, double frame_dt,
                     common::ViewAxis axis, const std::string& what) {
  const std::string& solver = scene.config.solver;
  SolverRun out;
  out.views.resize(r.frames.size());
  nlohmann::json wall = nlohmann::json::array();
  for (size_t k = 0; k < r.frames.size(); ++k) wall.push_back(nullptr);
  out.row = {{"solver", solver}};
  common::ProgressReporter progress(r.log ? *r.log : std::cerr, r.terminal, r.frames.back(), what);
  std::unique_ptr<Simulation> simulation;
  bool set_up = false;
  int done = 0;  // the last frame finished
  try {
    const auto setup_start = std::chrono::steady_clock::now();
    simulation = std::make_unique<Simulation>(scene.config);
    Simulation& sim = *simulation;
    const double setup_s = common::seconds_since(setup_start);
    const Aabb& d = sim.domain();
    std::vector<common::Point> boundary(sim.boundary().size());
    for (size_t i = 0; i < boundary.size(); ++i)
      boundary[i] = sim.boundary().position[i].cast<float>();
    const common::FrameRenderer renderer(boundary,
                                         common::Bounds{d.min.cast<float>(), d.max.cast<float>()},
                                         float(scene.config.particle_radius), r.cell_width);
    const std::unique_ptr<SpillMetrics> spill = river_spill_metrics(scene.config);
    if (spill) measure_spill(*spill, sim);
    set_up = true;

    FrameLoop loop;
    loop.last = r.frames.back();
    loop.frame_dt = frame_dt;
    loop.stop = r.stop;
    loop.interrupted_note = "nothing written";
    loop.progress = r.log ? &progress : nullptr;
    double simulated_s = 0;  // wall time of the simulation alone, pictures and metrics not counted
    size_t next = 0;
    FrameStats last;
    const FrameLoopTotals totals =
        run_frames(sim, loop, [&](int frame, const FrameStats& stats, double seconds) {
          simulated_s += seconds;
          last = stats;
          if (spill) measure_spill(*spill, sim);
          if (next < r.frames.size() && frame == r.frames[next]) {
            wall[next] = simulated_s;
            out.views[next] = render_view(sim, renderer, axis);
            ++next;
          }
          done = frame;
        });
    const nlohmann::json summary = run_summary(sim, simulated_s, totals.iterations_density,
                                               totals.iterations_divergence, r.threads);
    out.row["status"] = "ok";
    out.row["wall_s"] = wall;
    out.row["setup_s"] = setup_s;
    out.row["steps"] = summary.at("steps");
    out.row["particle_steps_per_s"] = summary.at("particle_steps_per_s");
    out.row["iterations_density"] = totals.iterations_density;
    out.row["iterations_divergence"] = totals.iterations_divergence;
    out.row["density_error_percent"] = 100 * last.density_error_avg;
    out.row["fluid_particles"] = summary.at("fluid_particles");
    if (spill) out.row["spill"] = spill_summary(*spill);
    out.row["summary"] = summary;
    if (r.log) progress.finish(std::to_string(sim.steps()) + " steps");
  } catch (const common::Interrupted&) {
    throw;
  } catch (const std::exception& e) {
    out.row["status"] = "failed";
    out.row["wall_s"] = wall;
    nlohmann::json failure = {{"reason", e.what()}};
    if (set_up) {
      failure["frame"] = done + 1;
      failure["t_s"] = simulation->time();  // the last step that was finished
    } else {
      failure["frame"] = nullptr;  // setting the scene up failed
    }
    out.row["failure"] = failure;
    if (r.log)
      *r.log << (r.terminal ? "\n" : "") << what << ": " << failure_text(out.row["failure"]) << ": "
             << e.what() << "\n";
  }
  return out;
}

std::string seconds_cell(const nlohmann::json& v) {
  if (v.is_null()) return "–";
  const double s = v.get<double>();
  return format(s < 10 ? "%.2f" : s < 100 ? "%.1f" : "%.0f", s);
}

std::string rate_cell(double rate) {
  if (rate >= 1e6) return format("%.2f M", rate / 1e6);
  if (rate >= 1e3) return format("%.1f k", rate / 1e3);
  return format("%.0f", rate);
}

std::string iterations_cell(double mean) {
  return mean > 0 ? format("%.1f", mean) : "–";
}

std::string optional_seconds(const nlohmann::json& v) {
  return v.is_null() ? "never" : format("%g", v.get<double>());
}

}  // namespace

namespace {

// The scene, its moments and the machine, above the table.
void markdown_header(std::ostream& md, const nlohmann::json& table) {
  const nlohmann::json& machine = table.at("machine");
  md << "# Solver comparison: " << table.at("scene").get<std::string>() << "\n\n";
  md << "- scene: `" << table.at("scene_file").get<std::string>() << "`";
  if (!table.at("overrides").empty()) {
    md << ", with";
    for (const auto& o : table.at("overrides")) md << " `--set " << o.get<std::string>() << "`";
  }
  md << "\n- frame_dt: " << format("%g", table.at("frame_dt").get<double>()) << " s; moments: ";
  for (size_t k = 0; k < table.at("frames").size(); ++k)
    md << (k ? ", " : "") << "frame " << table.at("frames")[k].get<int>() << " ("
       << time_label(table.at("times_s")[k].get<double>()) << ")";
  md << "\n- threads: " << table.at("threads").get<int>() << "\n";
  md << "- machine: " << machine.at("cpu").get<std::string>() << ", "
     << machine.at("hardware_threads").get<long>() << " hardware threads, "
     << machine.at("build_type").get<std::string>() << " build, "
     << machine.at("real").get<std::string>() << "\n\n";
}

void markdown_column_heads(std::ostream& md, const nlohmann::json& table, bool spill) {
  md << "| solver | status";
  for (const auto& t : table.at("times_s"))
    md << " | wall s to " << format("%g", t.get<double>()) << " s";
  md << " | particle-steps/s | density it./step | divergence it./step | density error % (end) | "
        "fluid particles";
  if (spill)
    md << " | peak slick area m² (at s) | furthest front m | left bank first oiled s | right "
          "bank first oiled s";
  md << " |\n|---|---";
  for (size_t k = 0; k < table.at("times_s").size(); ++k) md << "|---:";
  md << "|---:|---:|---:|---:|---:" << (spill ? "|---:|---:|---:|---:" : "") << "|\n";
}

void markdown_row(std::ostream& md, const nlohmann::json& row, bool spill) {
  const bool ok = row.at("status") == "ok";
  md << "| " << row.at("solver").get<std::string>() << " | "
     << (ok ? std::string("ok") : failure_text(row.at("failure")));
  for (const auto& w : row.at("wall_s")) md << " | " << seconds_cell(w);
  if (ok) {
    md << " | " << rate_cell(row.at("particle_steps_per_s").get<double>()) << " | "
       << iterations_cell(row.at("iterations_density").get<double>()) << " | "
       << iterations_cell(row.at("iterations_divergence").get<double>()) << " | "
       << format("%.3g", row.at("density_error_percent").get<double>()) << " | "
       << row.at("fluid_particles").get<long>();
  } else {
    md << " | – | – | – | – | –";
  }
  if (spill) {
    if (row.contains("spill")) {
      const nlohmann::json& s = row.at("spill");
      md << " | " << format("%.3f", s.at("peak_slick_area_m2").get<double>()) << " ("
         << format("%g", s.at("peak_slick_area_t_s").get<double>()) << ") | "
         << format("%.2f", s.at("furthest_front_m").get<double>()) << " | "
         << optional_seconds(s.at("first_left_bank_contact_s")) << " | "
         << optional_seconds(s.at("first_right_bank_contact_s"));
    } else {
      md << " | – | – | – | –";
    }
  }
  md << " |\n";
}

// What the columns mean, the failures, and what views.png shows.
void markdown_notes(std::ostream& md, const nlohmann::json& table, bool spill) {
  md << "\nWall time: the simulation's alone from t = 0 (setting the scene up, pictures and "
        "metrics not counted). Iterations: mean per solver step; – where the solver made none. "
        "Density error: the mean relative density error over the last frame's steps.";
  if (spill)
    md << " Spill metrics as in a run's spill.json (oil: oil fraction >= 0.5); first oiled: the "
          "first frame with oil at that bank (never: not by the end).";
  md << "\n";

  bool failures = false;
  for (const auto& row : table.at("rows"))
    if (row.at("status") != "ok") {
      if (!failures) md << "\nFailures:\n\n";
      failures = true;
      md << "- " << row.at("solver").get<std::string>() << ", " << failure_text(row.at("failure"))
         << ": " << row.at("failure").at("reason").get<std::string>() << "\n";
    }

  const nlohmann::json& views = table.at("views");
  md << "\n`" << views.at("file").get<std::string>() << "` (" << views.at("width").get<int>()
     << " x " << views.at("height").get<int>() << " px, " << views.at("view").get<std::string>()
     << " view, oil dark where its fraction >= 0.5): columns left to right ";
  for (size_t c = 0; c < views.at("columns").size(); ++c)
    md << (c ? ", " : "") << views.at("columns")[c].get<std::string>();
  md << "; rows top to bottom ";
  for (size_t k = 0; k < views.at("rows_t_s").size(); ++k)
    md << (k ? ", " : "") << time_label(views.at("rows_t_s")[k].get<double>());
  md << ". Grey cells: the solver had failed before that moment.\n";
}

}  // namespace

std::string solver_table_markdown(const nlohmann::json& table) {
  std::ostringstream md;
  markdown_header(md, table);
  bool spill = false;
  for (const auto& row : table.at("rows")) spill = spill || row.contains("spill");
  markdown_column_heads(md, table, spill);
  for (const auto& row : table.at("rows")) markdown_row(md, row, spill);
  markdown_notes(md, table, spill);
  return md.str();
}

namespace {

// Refuses moments beyond the scene's end, saying how to reach them.
void check_frames_fit(const SolverTableRequest& r, const SceneConfig& scene) {
  const double frame_dt = shortest_decimal(scene.output.frame_dt);
  const int scene_frames = frame_count(scene);
  if (r.frames.back() > scene_frames)
    throw common::InputError(
        "--frames " + std::to_string(r.frames.back()) + ": the scene ends at frame " +
        std::to_string(scene_frames) + " (end_time " + format("%g", double(scene.end_time)) +
        " s, frames every " + format("%g", frame_dt) +
        " s); raise it with --set /end_time=" + format("%g", double(r.frames.back()) * frame_dt));
}

// A picture of a solver that finished, to size the grid's cells; throws when every solver failed.
const common::RgbImage& finished_picture(const std::vector<SolverRun>& runs,
                                         const std::vector<std::string>& solvers) {
  const common::RgbImage* reference = nullptr;
  std::string failures;
  for (size_t s = 0; s < runs.size(); ++s) {
    if (runs[s].row.at("status") == "ok") {
      if (!reference) reference = &*runs[s].views.front();
    } else {
      failures += (failures.empty() ? "" : "; ") + solvers[s] + " " +
                  failure_text(runs[s].row.at("failure")) + ": " +
                  runs[s].row.at("failure").at("reason").get<std::string>();
    }
  }
  if (!reference) throw SimulationError("every solver failed, nothing written: " + failures);
  return *reference;
}

// table.json's "definitions": what each figure of a row means.
nlohmann::json row_definitions() {
  return {{"wall_s",
           "seconds of simulation from t = 0 to each moment (setup, pictures and metrics "
           "not counted); null where the solver had failed"},
          {"setup_s", "seconds to set the scene up (particles, boundary, terrain)"},
          {"particle_steps_per_s", "solver steps x active fluid particles at the end / wall time"},
          {"iterations_density", "mean constant-density (pressure) iterations per solver step"},
          {"iterations_divergence", "mean divergence-free iterations per solver step"},
          {"density_error_percent", "mean relative density error over the last frame's steps, %"},
          {"fluid_particles", "active fluid particles at the end"},
          {"spill",
           "river leaks: the largest slick area over the run and when, the furthest front, first "
           "bank contacts and arrivals (per frame in a run's spill.json)"},
          {"failure",
           "the frame being simulated when the run failed (null: while setting up), "
           "the simulated time it had reached and the error"}};
}

}  // namespace

nlohmann::json write_solver_table(const SolverTableRequest& r) {
  check_request(r);
  const std::vector<LoadedScene> scenes =
      load_scene_per_solver(r.scene_file, r.overrides, r.solvers, "--solvers");
  const SceneConfig& first = scenes.front().config;
  const double frame_dt = shortest_decimal(first.output.frame_dt);
  check_frames_fit(r, first);
  const common::ViewAxis axis =
      first.terrain_grid ? common::ViewAxis::kRiver : common::ViewAxis::kTop;

  common::OutputFolderPolicy policy;
  policy.markers = {"table.json", "table.md", "views.png"};
  policy.replace = r.force;
  policy.inputs = {r.scene_file};
  policy.log = r.log;
  common::OutputFolder output(r.out_dir.string(), policy);

  std::vector<SolverRun> runs;
  for (size_t s = 0; s < scenes.size(); ++s)
    runs.push_back(run_solver(scenes[s], r, frame_dt, axis,
                              "compare " + r.solvers[s] + " (" + std::to_string(s + 1) + "/" +
                                  std::to_string(scenes.size()) + ")"));
  const common::RgbImage& reference = finished_picture(runs, r.solvers);

  std::vector<std::string> row_labels;
  nlohmann::json times = nlohmann::json::array();
  for (int frame : r.frames) {
    times.push_back(double(frame) * frame_dt);
    row_labels.push_back(time_label(double(frame) * frame_dt));
  }
  common::PictureGrid grid(reference.width, reference.height, r.solvers, row_labels);
  for (size_t s = 0; s < runs.size(); ++s)
    for (size_t k = 0; k < r.frames.size(); ++k) {
      if (runs[s].views[k])
        grid.place(int(k), int(s), *runs[s].views[k]);
      else
        grid.leave_empty(int(k), int(s), "failed");
    }

  nlohmann::json rows = nlohmann::json::array();
  for (const auto& run : runs) rows.push_back(run.row);
  const nlohmann::json table = {{"command", "spill-sim compare"},
                                {"scene", first.name},
                                {"scene_file", r.scene_file},
                                {"overrides", r.overrides},
                                {"frame_dt", frame_dt},
                                {"frames", r.frames},
                                {"times_s", times},
                                {"threads", r.threads},
                                {"machine", machine_description(r.threads)},
                                {"solvers", r.solvers},
                                {"rows", rows},
                                {"views",
                                 {{"file", "views.png"},
                                  {"view", axis == common::ViewAxis::kRiver ? "river" : "top"},
                                  {"columns", r.solvers},
                                  {"rows_t_s", times},
                                  {"cell_width", grid.cell_width()},
                                  {"cell_height", grid.cell_height()},
                                  {"width", grid.image().width},
                                  {"height", grid.image().height}}},
                                {"definitions", row_definitions()}};

  const std::filesystem::path& staging = output.staging();
  common::write_file_atomically(staging / "table.json", table.dump(2) + "\n");
  common::write_file_atomically(staging / "table.md", solver_table_markdown(table));
  common::write_png((staging / "views.png").string(), grid.image());
  output.commit();
  return table;
}

}  // namespace sph
