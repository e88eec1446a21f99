#include "reach/reach_run.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>

#include "common/axis_ticks.h"
#include "common/checked_file.h"
#include "common/memory_limit.h"
#include "common/output_folder.h"
#include "common/progress.h"
#include "reach/channel_carving.h"
#include "reach/reach_checks.h"
#include "reach/reach_map.h"
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

// The depth below which a cell does not count in the steady-state residual (m).
constexpr double kResidualDepth = 0.01;

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// "t0000600s", or with `decimals` places ("t0000000.25s").
std::string stamp_with(double t, int decimals) {
  char text[48];
  std::snprintf(text, sizeof text, "t%0*.*fs", decimals > 0 ? 8 + decimals : 7, decimals, t);
  return text;
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
  // A raster that cannot be used is named with the key that gave it.
  const auto keyed = [&](const char* pointer, auto read) {
    try {
      return read();
    } catch (const RasterError& e) {
      throw ConfigError(file, pointer, e.what());
    }
  };
  const Raster header = keyed("/terrain/file", [&] { return raster_header(c.terrain.file); });
  // Sized first, then only the window read, coarsened strip by strip: a 20,000 x 20,000 raster
  // was read whole (7 GB) before the window and coarsening applied.
  check_terrain_size(header, c.terrain, common::physical_memory_bytes(), file);
  Raster r = keyed("/terrain/file", [&] {
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
  Field manning;
  Raster n_raster;
  if (!c.terrain.manning_file.empty()) {
    const Raster n_header =
        keyed("/terrain/manning_file", [&] { return raster_header(c.terrain.manning_file); });
    if (n_header.grid.nx != header.grid.nx || n_header.grid.ny != header.grid.ny)
      throw ConfigError(file, "/terrain/manning_file",
                        c.terrain.manning_file + " is " + std::to_string(n_header.grid.nx) + " x " +
                            std::to_string(n_header.grid.ny) + " cells, the terrain " +
                            std::to_string(header.grid.nx) + " x " +
                            std::to_string(header.grid.ny));
    n_raster = keyed("/terrain/manning_file", [&] {
      return read_raster(c.terrain.manning_file, {c.terrain.window, c.terrain.coarsen});
    });
  }
  check_elevations(r, c.terrain.file, file);
  if (c.terrain.channel) m.carved_cells = carve_channel(r.grid, r.values, *c.terrain.channel);
  if (!n_raster.values.empty()) {
    manning = n_raster.values;
    for (size_t k = 0; k < manning.size(); ++k) {
      if (std::isnan(manning[k])) manning[k] = c.terrain.manning;
      if (!(manning[k] >= 0 && manning[k] <= kMaxManning))
        throw ConfigError(file, "/terrain/manning_file",
                          c.terrain.manning_file + " has a Manning's n of " + number(manning[k]) +
                              " at (" + number(r.grid.x(int(k) % r.grid.nx)) + ", " +
                              number(r.grid.y(int(k) / r.grid.nx)) + "), beyond 0 to " +
                              number(kMaxManning));
    }
  } else {
    manning = {c.terrain.manning};
  }
  SolverSettings settings;
  settings.cfl = c.cfl;
  settings.dry_depth = c.dry_depth;
  try {
    m.solver = std::make_unique<ShallowWaterSolver>(r.grid, r.values, manning, settings);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(file, "/terrain", e.what());
  }
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
  if (c.initial_level) {
    m.solver->fill_to_level(*c.initial_level);
    consider_wave(std::sqrt(9.81 * std::max(0.0, *c.initial_level - lowest_bed)), "/initial_level");
  }
  m.terrain = std::move(r);
  return m;
}

nlohmann::json run_reach(const ReachRunOptions& o) {
  const ReachConfig config = load_reach_config(o.config_file, o.overrides);
  ReachModel model = build_reach(config, o.config_file);
  const double least_steps = check_run_length(config, model, o.config_file);
  ShallowWaterSolver& solver = *model.solver;
  const Grid& g = solver.grid();
  std::ostream& log = *o.log;

  common::OutputFolderPolicy policy;
  policy.markers = {"reach.json"};
  policy.replace = o.force;
  policy.inputs = {o.config_file, config.terrain.file};
  policy.log = o.log;
  common::OutputFolder out(o.out_dir, policy);
  const fs::path dir = out.staging();
  fs::create_directories(dir / "rasters");
  fs::create_directories(dir / "png");

  const size_t cells = g.cells();
  const double nan = std::nan("");
  const double dry = config.dry_depth;
  long open_cells = 0;
  for (size_t c = 0; c < cells; ++c) open_cells += !solver.closed(c);
  Field max_depth(cells, nan), max_level(cells, nan);
  const auto track_maxima = [&] {
    const WaterState& w = solver.state();
    for (size_t c = 0; c < cells; ++c) {
      if (solver.closed(c)) continue;
      max_depth[c] = std::isnan(max_depth[c]) ? w.h[c] : std::max(max_depth[c], w.h[c]);
      if (w.h[c] > dry)
        max_level[c] = std::isnan(max_level[c]) ? w.h[c] + solver.bed()[c]
                                                : std::max(max_level[c], w.h[c] + solver.bed()[c]);
    }
  };
  const auto raster_of = [&](const Field& values) {
    Raster r;
    r.grid = g;
    r.crs_wkt = model.terrain.crs_wkt;
    r.values = values;
    return r;
  };

  // The pictures' depth and arrow scales: a 1-2-5 value at or above the figure, 1 when it is 0.
  const auto scale_step = [](double v) { return v > 0 ? common::round_up_to_125(v) : 1.0; };
  const std::vector<char> closed = closed_cells(model.terrain);

  // Sections' cells, so that water against a wall of the grid's edge can be told apart.
  std::vector<char> in_section(cells, 0);
  const auto mark = [&](const SectionConfig& sc) {
    const Section s = section_of(sc, g, closed, o.config_file, "");
    for (int k = s.first; k <= s.last; ++k) {
      switch (s.side) {
        case Side::kWest:
          in_section[g.at(0, k)] = 1;
          break;
        case Side::kEast:
          in_section[g.at(g.nx - 1, k)] = 1;
          break;
        case Side::kSouth:
          in_section[g.at(k, 0)] = 1;
          break;
        case Side::kNorth:
          in_section[g.at(k, g.ny - 1)] = 1;
          break;
      }
    }
  };
  for (const auto& b : config.inflows)
    if (b.section) mark(*b.section);
  for (const auto& b : config.outflows) mark(b.section);

  nlohmann::json frames = nlohmann::json::array();
  std::vector<std::string> warnings;
  double depth_scale = 0, speed_scale = 0, residual = nan;
  const double volume0 = solver.volume();
  long steps = 0;
  double last_frame_time = -1;  // no frame yet

  const auto write_frame = [&] {
    const WaterState& w = solver.state();
    Field depth(cells, nan), level(cells, nan), vx(cells, nan), vy(cells, nan);
    double wetted = 0, fastest = 0, deepest = 0;
    std::vector<double> speeds;  // of cells deeper than 10 cm, for the arrows' scale
    long against_edge = 0;
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const size_t c = g.at(i, j);
        if (solver.closed(c)) continue;
        depth[c] = w.h[c];
        if (w.h[c] <= dry) continue;
        level[c] = w.h[c] + solver.bed()[c];
        vx[c] = w.hu[c] / w.h[c];
        vy[c] = w.hv[c] / w.h[c];
        wetted += g.cell_area();
        fastest = std::max(fastest, std::hypot(vx[c], vy[c]));
        if (w.h[c] > 0.1) speeds.push_back(std::hypot(vx[c], vy[c]));
        deepest = std::max(deepest, w.h[c]);
        const bool edge = i == 0 || j == 0 || i == g.nx - 1 || j == g.ny - 1;
        if (edge && !in_section[c] && w.h[c] > 0.05) ++against_edge;
      }
    const std::string t = frame_stamp(solver.time(), last_frame_time, config.output_every);
    last_frame_time = solver.time();
    nlohmann::json files = nlohmann::json::object();
    for (const auto& [what, values] : {std::pair<const char*, const Field*>{"depth", &depth},
                                       {"level", &level},
                                       {"velocity_x", &vx},
                                       {"velocity_y", &vy}}) {
      const std::string name = "rasters/" + std::string(what) + "_" + t + ".tif";
      write_geotiff((dir / name).string(), raster_of(*values));
      files[what] = name;
    }
    depth_scale = std::max(depth_scale, scale_step(deepest));
    // The arrows' scale: the 95th percentile of the speed where the water is deeper than 10 cm
    // (a thin wetting front runs fast and would shrink every other arrow).
    if (!speeds.empty()) {
      const size_t k = speeds.size() * 95 / 100;
      std::nth_element(speeds.begin(), speeds.begin() + long(k), speeds.end());
      speed_scale = std::max(speed_scale, scale_step(speeds[k]));
    }
    files["map"] = "png/map_" + t + ".png";
    common::write_png(
        (dir / files["map"].get<std::string>()).string(),
        draw_reach_map(g, solver.bed(), w, solver.time(), depth_scale, speed_scale, dry));
    nlohmann::json sections = nlohmann::json::object();
    const auto names = solver.section_names();
    for (size_t k = 0; k < names.size(); ++k) sections[names[k]] = solver.section_discharge()[k];
    const double balance =
        solver.volume() - (volume0 + solver.boundary_volume_in() + solver.clamped_volume());
    frames.push_back({{"t_s", solver.time()},
                      {"volume_m3", solver.volume()},
                      {"wetted_area_m2", wetted},
                      {"max_depth_m", deepest},
                      {"max_speed_m_s", fastest},
                      {"section_discharge_m3_s", sections},
                      {"volume_balance_error_m3", balance},
                      {"residual_m_s",
                       std::isnan(residual) ? nlohmann::json(nullptr) : nlohmann::json(residual)},
                      {"wet_cells_against_the_grid_edge", against_edge},
                      {"files", files}});
    if (against_edge > 0 && warnings.empty()) {
      warnings.push_back(std::to_string(against_edge) +
                         " wet cells (deeper than 5 cm) against the grid's edge outside the "
                         "sections at t = " +
                         std::to_string(solver.time()) +
                         " s: walls hold the water there, so the flow may overtop the banks "
                         "beyond the terrain; widen the window or lower the discharge");
      log << "warning: " << warnings.back() << "\n";
    }
  };

  omp_set_num_threads(o.threads);
  const auto start = std::chrono::steady_clock::now();
  // Progress in thousandths of the simulated time (a run shorter than a second still moves).
  constexpr long kProgressUnits = 1000;
  common::ProgressReporter progress(log, o.terminal, kProgressUnits, "reach " + config.name);
  log << "reach " << config.name << ": at least " << number(least_steps) << " steps to "
      << number(config.end_time) << " s\n";
  track_maxima();
  write_frame();
  bool steady = false;
  Field window_depth = solver.state().h;  // the depths at the start of the residual's window
  double window_start = solver.time();
  // Steady also needs what leaves to match what enters, to 1 % of the inflow (a filling
  // floodplain can hold the depth's rate low for a while).
  const auto balanced = [&] {
    double in = 0, net = 0;
    for (double q : solver.section_discharge()) {
      in += std::max(q, 0.0);
      net += q;
    }
    return in == 0 || std::abs(net) <= 0.01 * in;
  };
  double next_output = config.output_every;
  while (solver.time() < config.end_time && !steady) {
    const double target = std::min(next_output, config.end_time);
    while (solver.time() < target) {
      double dt = std::min({solver.stable_dt(), config.max_dt, target - solver.time()});
      if (!(dt > 0) || !std::isfinite(dt))
        throw std::runtime_error("the reach's time step fell to " + std::to_string(dt) +
                                 " s at t = " + std::to_string(solver.time()) + " s");
      if (target - solver.time() - dt < 1e-9 * target) dt = target - solver.time();
      solver.step(dt);
      if (++steps > config.max_steps)
        throw ConfigError(o.config_file, "/max_steps",
                          "the run passed " + number(config.max_steps) +
                              " steps at t = " + number(solver.time()) + " of " +
                              number(config.end_time) + " s (its step had fallen to " + number(dt) +
                              " s): check the inflows and the terrain, or raise /max_steps");
      if (target - solver.time() < 1e-9 * target) solver.set_time(target);
      track_maxima();
      if (o.stop && o.stop->load()) throw common::Interrupted("interrupted; nothing written");
      if (steps % 50 == 0 || dt < 1e-3 * config.output_every) {
        char detail[128];
        std::snprintf(detail, sizeof detail, "t=%.6gs of %.6gs dt=%.3gs residual=%.2e m/s",
                      solver.time(), config.end_time, dt, residual);
        progress.update(long(kProgressUnits * solver.time() / config.end_time), detail);
      }
      // The steady-state residual: how fast the depths drift, from the state one window ago
      // (oscillations within the window, a film wetting and drying at the edge, do not count).
      if (solver.time() - window_start >= config.steady_window) {
        double sum = 0;
        long deep = 0;
        const double span = solver.time() - window_start;
        for (size_t c = 0; c < cells; ++c)
          if (solver.state().h[c] > kResidualDepth) {
            const double rate = (solver.state().h[c] - window_depth[c]) / span;
            sum += rate * rate;
            ++deep;
          }
        residual = deep > 0 ? std::sqrt(sum / double(deep)) : 0.0;
        window_depth = solver.state().h;
        window_start = solver.time();
        if (config.steady_tolerance > 0 && residual < config.steady_tolerance && balanced()) {
          steady = true;
          break;
        }
      }
    }
    write_frame();
    next_output += config.output_every;
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress.finish("done");

  // The bed the flow ran on (coarsened, carved; NaN where closed), which a near field inside the
  // reach takes as its terrain (reach/near_field_window.h).
  Field bed = solver.bed();
  for (size_t c = 0; c < cells; ++c)
    if (solver.closed(c)) bed[c] = nan;
  write_geotiff((dir / "bed.tif").string(), raster_of(bed));
  write_geotiff((dir / "max_depth.tif").string(), raster_of(max_depth));
  write_geotiff((dir / "max_level.tif").string(), raster_of(max_level));
  common::write_png((dir / "map.png").string(),
                    draw_reach_map(g, solver.bed(), solver.state(), solver.time(), depth_scale,
                                   speed_scale, dry));
  const double balance =
      solver.volume() - (volume0 + solver.boundary_volume_in() + solver.clamped_volume());
  nlohmann::json summary = {
      {"name", config.name},
      {"description", config.description},
      {"config", common::JsonWriter::write_struct(config)},
      {"grid",
       {{"nx", g.nx},
        {"ny", g.ny},
        {"dx_m", g.dx},
        {"dy_m", g.dy},
        {"x0", g.x0},
        {"y0", g.y0},
        {"open_cells", open_cells},
        {"carved_cells", model.carved_cells},
        {"crs_wkt", model.terrain.crs_wkt}}},
      {"end_time_s", solver.time()},
      {"steady",
       {{"tolerance_m_s", config.steady_tolerance},
        {"reached", steady},
        {"residual_m_s", residual}}},
      {"volume_balance",
       {{"initial_m3", volume0},
        {"final_m3", solver.volume()},
        {"net_inflow_m3", solver.boundary_volume_in()},
        {"clamped_m3", solver.clamped_volume()},
        {"error_m3", balance}}},
      {"frames", frames},
      {"warnings", warnings},
      {"steps", steps},
      {"threads", o.threads},
      {"wall_s", wall},
      {"cell_updates_per_s", wall > 0 ? double(steps) * double(open_cells) / wall : 0.0},
      {"definitions",
       {{"section_discharge_m3_s",
         "discharge through each section over the last step, positive "
         "into the reach"},
        {"residual_m_s",
         "RMS over the cells deeper than 1 cm of the depth's rate of change over "
         "the last step"},
        {"volume_balance_error_m3",
         "volume now - (initial volume + net inflow through the sections + round-off clamps)"},
        {"cell_updates_per_s", "steps x open cells / wall time (each step has two stages)"},
        {"rasters",
         "rasters/depth, level (water surface, NaN where dry), velocity_x, velocity_y "
         "(m/s, east and north) at each output time; max_depth.tif and max_level.tif "
         "over the whole run; bed.tif, the bed the flow ran on (coarsened, carved); all "
         "GeoTIFF in the terrain's CRS"}}}};
  common::write_file_atomically(dir / "reach.json", summary.dump(2) + "\n");
  // A Ctrl-C while the last files were written keeps its promise too.
  if (o.stop && o.stop->load()) throw common::Interrupted("interrupted; nothing written");
  out.commit();
  return summary;
}

}  // namespace reach
