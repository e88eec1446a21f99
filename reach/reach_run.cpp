#include "reach/reach_run.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "common/checked_file.h"
#include "common/memory_limit.h"
#include "common/number_text.h"
#include "common/output_folder.h"
#include "common/progress.h"
#include "reach/channel_carving.h"
#include "reach/reach_checks.h"
#include "reach/reach_recorder.h"
#include "reach/series.h"

namespace reach {

namespace fs = std::filesystem;

namespace {

Side side_of(const std::string& name) {
  if (name == "west") return Side::kWest;
  if (name == "east") return Side::kEast;
  if (name == "south") return Side::kSouth;
  return Side::kNorth;
}

// The cells whose centres lie in the section's stretch of the side.
Section section_of(const SectionConfig& c, const Grid& g, const std::vector<char>& closed_of,
                   const std::string& file, const std::string& pointer) {
  Section s;
  s.side = side_of(c.side);
  const bool along_y = s.side == Side::kWest || s.side == Side::kEast;
  const double origin = along_y ? g.y0 : g.x0, step = along_y ? g.dy : g.dx;
  const int count = along_y ? g.ny : g.nx;
  s.first = std::max(0, int(std::ceil((c.from - origin) / step - 0.5)));
  s.last = std::min(count - 1, int(std::floor((c.to - origin) / step - 0.5)));
  if (s.last < s.first || c.from < origin - 0.5 * step || c.to > origin + (count + 0.5) * step)
    throw ConfigError(file, pointer,
                      "section '" + c.name + "' (" + c.side + " side, " + std::to_string(c.from) +
                          " to " + std::to_string(c.to) + ") is not within the raster's " +
                          (along_y ? "y" : "x") + " range " + std::to_string(origin) + " to " +
                          std::to_string(origin + count * step));
  int open = 0;
  for (int k = s.first; k <= s.last; ++k) {
    int i = 0, j = 0;
    switch (s.side) {
      case Side::kWest:
        i = 0, j = k;
        break;
      case Side::kEast:
        i = g.nx - 1, j = k;
        break;
      case Side::kSouth:
        i = k, j = 0;
        break;
      case Side::kNorth:
        i = k, j = g.ny - 1;
        break;
    }
    open += !closed_of[g.at(i, j)];
  }
  if (open == 0)
    throw ConfigError(file, pointer,
                      "section '" + c.name + "' holds no cell with terrain (all nodata)");
  return s;
}

// The raster's cells as the solver's closedness (NaN bed).
std::vector<char> closed_cells(const Raster& r) {
  std::vector<char> closed(r.grid.cells());
  for (size_t c = 0; c < closed.size(); ++c) closed[c] = std::isnan(r.values[c]);
  return closed;
}

// "t0000600s", or with `decimals` places ("t0000000.25s").
std::string stamp_with(double t, int decimals) {
  char text[48];
  std::snprintf(text, sizeof text, "t%0*.*fs", decimals > 0 ? 8 + decimals : 7, decimals, t);
  return text;
}

// Calls `read`, naming `pointer` for a raster that cannot be used.
template <class Read>
auto keyed(const std::string& file, const char* pointer, Read read) {
  try {
    return read();
  } catch (const RasterError& e) {
    throw ConfigError(file, pointer, e.what());
  }
}

// The terrain of the config: sized first, then only the window read, coarsened strip by strip
// (a 20,000 x 20,000 raster was read whole, 7 GB, before the window and coarsening applied); its
// CRS projected and in metres, its elevations Earth's.
Raster read_terrain(const ReachConfig& c, const std::string& file) {
  const Raster header = keyed(file, "/terrain/file", [&] { return raster_header(c.terrain.file); });
  check_terrain_size(header, c.terrain, common::physical_memory_bytes(), file);
  Raster r = keyed(file, "/terrain/file", [&] {
    return read_raster(c.terrain.file, {c.terrain.window, c.terrain.coarsen});
  });
  if (!c.terrain.crs.empty()) {
    try {
      r.crs_wkt = crs_wkt_of(c.terrain.crs);
    } catch (const RasterError& e) {
      throw ConfigError(file, "/terrain/crs", e.what());
    }
  }
  if (r.crs_wkt.empty())
    throw ConfigError(file, "/terrain/crs",
                      c.terrain.file +
                          " has no coordinate reference system: give the one it is in here (e.g. "
                          "\"EPSG:2193\"), so that the outputs are georeferenced");
  if (crs_is_geographic(r.crs_wkt))
    throw ConfigError(file, "/terrain/file",
                      c.terrain.file +
                          " is in a geographic CRS (degrees); a grid in metres needs a projected "
                          "one: warp it first (gdalwarp -t_srs EPSG:...)");
  check_metres(r.crs_wkt, file, c.terrain.crs.empty() ? "/terrain/file" : "/terrain/crs",
               c.terrain.crs.empty() ? c.terrain.file : c.terrain.crs);
  check_elevations(r, c.terrain.file, file);
  return r;
}

// Manning's n per cell (a raster on the terrain's grid, its nodata the constant) or the constant.
Field read_manning(const ReachConfig& c, const Grid& grid, const std::string& file) {
  Field manning;
  Raster n_raster;
  if (!c.terrain.manning_file.empty()) {
    const Raster header =
        keyed(file, "/terrain/file", [&] { return raster_header(c.terrain.file); });
    const Raster n_header =
        keyed(file, "/terrain/manning_file", [&] { return raster_header(c.terrain.manning_file); });
    if (n_header.grid.nx != header.grid.nx || n_header.grid.ny != header.grid.ny)
      throw ConfigError(file, "/terrain/manning_file",
                        c.terrain.manning_file + " is " + std::to_string(n_header.grid.nx) + " x " +
                            std::to_string(n_header.grid.ny) + " cells, the terrain " +
                            std::to_string(header.grid.nx) + " x " +
                            std::to_string(header.grid.ny));
    n_raster = keyed(file, "/terrain/manning_file", [&] {
      return read_raster(c.terrain.manning_file, {c.terrain.window, c.terrain.coarsen});
    });
  }
  if (!n_raster.values.empty()) {
    manning = n_raster.values;
    for (size_t k = 0; k < manning.size(); ++k) {
      if (std::isnan(manning[k])) manning[k] = c.terrain.manning;
      if (!(manning[k] >= 0 && manning[k] <= kMaxManning))
        throw ConfigError(file, "/terrain/manning_file",
                          c.terrain.manning_file + " has a Manning's n of " +
                              common::number_text(manning[k]) + " at (" +
                              common::number_text(grid.x(int(k) % grid.nx)) + ", " +
                              common::number_text(grid.y(int(k) / grid.nx)) + "), beyond 0 to " +
                              common::number_text(kMaxManning));
    }
  } else {
    manning = {c.terrain.manning};
  }
  return manning;
}

// The inflows and outflows placed on the grid's edge (or over an area) and the initial water,
// checked (sections apart, series covering the run, discharges a river can carry), with the
// fastest wave they promise.
void place_boundaries(const ReachConfig& c, const Raster& r, ReachModel& m,
                      const std::string& file) {
  const auto closed = closed_cells(r);
  std::vector<std::pair<Section, std::string>> placed;  // every section and its key
  double lowest_bed = std::numeric_limits<double>::infinity();
  for (double z : r.values)
    if (!std::isnan(z)) lowest_bed = std::min(lowest_bed, z);
  const auto consider_wave = [&](double speed, const std::string& key) {
    if (speed > m.wave_speed) m.wave_speed = speed, m.wave_speed_key = key;
  };
  for (size_t k = 0; k < c.inflows.size(); ++k) {
    const std::string p = "/inflows/" + std::to_string(k);
    InflowBoundary b;
    const InflowConfig& in = c.inflows[k];
    if (in.section) {
      b.name = in.section->name;
      b.section = section_of(*in.section, r.grid, closed, file, p + "/section");
      placed.emplace_back(b.section, p + "/section");
    } else {
      b.name = in.name;
      const auto& a = in.area;
      for (int j = 0; j < r.grid.ny; ++j)
        for (int i = 0; i < r.grid.nx; ++i)
          if (r.grid.x(i) >= a[0] && r.grid.x(i) <= a[2] && r.grid.y(j) >= a[1] &&
              r.grid.y(j) <= a[3] && !closed[r.grid.at(i, j)])
            b.area.push_back(r.grid.at(i, j));
      if (b.area.empty())
        throw ConfigError(file, p + "/area", "no open cell of the terrain lies inside the area");
    }
    b.discharge = load_series(c.inflows[k].discharge, file, p + "/discharge");
    for (const auto& [t, q] : b.discharge.points())
      if (q < 0)
        throw ConfigError(file, p + "/discharge",
                          "expected a discharge >= 0, got " + std::to_string(q) +
                              " at t = " + std::to_string(t) + " s");
    check_covers(in.discharge, b.discharge, c.end_time, file, p + "/discharge");
    // The width the peak enters over: the section's, or across the area's cells.
    const bool along_y = b.section.side == Side::kWest || b.section.side == Side::kEast;
    const double width =
        in.section ? (b.section.last - b.section.first + 1) * (along_y ? r.grid.dy : r.grid.dx)
                   : std::sqrt(double(b.area.size()) * r.grid.cell_area());
    check_carried(b.discharge.peak(), width, file, p + "/discharge");
    consider_wave(critical_wave_speed(b.discharge.peak() / width), p + "/discharge");
    m.solver->add_inflow(b);
  }
  for (size_t k = 0; k < c.outflows.size(); ++k) {
    const std::string p = "/outflows/" + std::to_string(k);
    const OutflowConfig& o = c.outflows[k];
    OutflowBoundary b;
    b.name = o.section.name;
    b.section = section_of(o.section, r.grid, closed, file, p + "/section");
    placed.emplace_back(b.section, p + "/section");
    b.kind = o.kind == "stage"  ? OutflowKind::kStage
             : o.kind == "free" ? OutflowKind::kFree
                                : OutflowKind::kNormalDepth;
    b.slope = o.slope;
    if (o.stage) {
      b.stage = load_series(*o.stage, file, p + "/stage");
      check_covers(*o.stage, b.stage, c.end_time, file, p + "/stage");
      consider_wave(std::sqrt(9.81 * std::max(0.0, b.stage.peak() - lowest_bed)), p + "/stage");
    }
    m.solver->add_outflow(b);
  }
  check_sections_apart(placed, file);
  m.section_cells.assign(r.grid.cells(), 0);
  for (const auto& [s, key] : placed)
    for (int k = s.first; k <= s.last; ++k) {
      const int i = s.side == Side::kWest ? 0 : s.side == Side::kEast ? r.grid.nx - 1 : k;
      const int j = s.side == Side::kSouth ? 0 : s.side == Side::kNorth ? r.grid.ny - 1 : k;
      m.section_cells[r.grid.at(i, j)] = 1;
    }
  if (c.initial_level) {
    m.solver->fill_to_level(*c.initial_level);
    consider_wave(std::sqrt(9.81 * std::max(0.0, *c.initial_level - lowest_bed)), "/initial_level");
  }
}

}  // namespace

std::string frame_stamp(double t, double previous, double interval) {
  int decimals = 0;
  while (decimals < 9 && interval * std::pow(10.0, decimals) < 1 - 1e-9) ++decimals;
  while (decimals < 12 && stamp_with(t, decimals) == stamp_with(previous, decimals)) ++decimals;
  return stamp_with(t, decimals);
}

ReachModel build_reach(const ReachConfig& c, const std::string& file) {
  ReachModel m;
  Raster r = read_terrain(c, file);
  if (c.terrain.channel) m.carved_cells = carve_channel(r.grid, r.values, *c.terrain.channel);
  const Field manning = read_manning(c, r.grid, file);
  SolverSettings settings;
  settings.cfl = c.cfl;
  settings.dry_depth = c.dry_depth;
  try {
    m.solver = std::make_unique<ShallowWaterSolver>(r.grid, r.values, manning, settings);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(file, "/terrain", e.what());
  }
  place_boundaries(c, r, m, file);
  m.terrain = std::move(r);
  return m;
}

nlohmann::json run_reach(const ReachRunOptions& o) {
  const ReachConfig config = load_reach_config(o.config_file, o.overrides);
  ReachModel model = build_reach(config, o.config_file);
  const double least_steps = check_run_length(config, model, o.config_file);
  ShallowWaterSolver& solver = *model.solver;
  std::ostream& log = *o.log;

  common::OutputFolderPolicy policy;
  policy.markers = {"reach.json"};
  policy.replace = o.force;
  policy.inputs = {o.config_file, config.terrain.file};
  policy.log = o.log;
  common::OutputFolder out(o.out_dir, policy);
  const fs::path dir = out.staging();
  ReachRecorder recorder(model, config, dir, log);

  omp_set_num_threads(o.threads);
  const auto start = std::chrono::steady_clock::now();
  // Progress in thousandths of the simulated time (a run shorter than a second still moves).
  constexpr long kProgressUnits = 1000;
  common::ProgressReporter progress(log, o.terminal, kProgressUnits, "reach " + config.name);
  log << "reach " << config.name << ": at least " << common::number_text(least_steps)
      << " steps to " << common::number_text(config.end_time) << " s\n";
  recorder.after_step();
  recorder.write_frame();
  long steps = 0;
  double next_output = config.output_every;
  while (solver.time() < config.end_time && !recorder.steady()) {
    const double target = std::min(next_output, config.end_time);
    while (solver.time() < target && !recorder.steady()) {
      double dt = std::min({solver.stable_dt(), config.max_dt, target - solver.time()});
      if (!(dt > 0) || !std::isfinite(dt))
        throw std::runtime_error("the reach's time step fell to " + std::to_string(dt) +
                                 " s at t = " + std::to_string(solver.time()) + " s");
      if (target - solver.time() - dt < 1e-9 * target) dt = target - solver.time();
      solver.step(dt);
      if (++steps > config.max_steps)
        throw ConfigError(o.config_file, "/max_steps",
                          "the run passed " + common::number_text(config.max_steps) +
                              " steps at t = " + common::number_text(solver.time()) + " of " +
                              common::number_text(config.end_time) + " s (its step had fallen to " +
                              common::number_text(dt) +
                              " s): check the inflows and the terrain, or raise /max_steps");
      if (target - solver.time() < 1e-9 * target) solver.set_time(target);
      recorder.after_step();
      if (o.stop && o.stop->load()) throw common::Interrupted("interrupted; nothing written");
      if (steps % 50 == 0 || dt < 1e-3 * config.output_every) {
        char detail[128];
        std::snprintf(detail, sizeof detail, "t=%.6gs of %.6gs dt=%.3gs residual=%.2e m/s",
                      solver.time(), config.end_time, dt, recorder.residual());
        progress.update(long(kProgressUnits * solver.time() / config.end_time), detail);
      }
    }
    recorder.write_frame();
    next_output += config.output_every;
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress.finish("done");
  const nlohmann::json summary = recorder.finish(steps, o.threads, wall);
  common::write_file_atomically(dir / "reach.json", summary.dump(2) + "\n");
  // A Ctrl-C while the last files were written keeps its promise too.
  if (o.stop && o.stop->load()) throw common::Interrupted("interrupted; nothing written");
  out.commit();
  return summary;
}

}  // namespace reach
