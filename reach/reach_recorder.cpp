#include "reach/reach_recorder.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/axis_ticks.h"
#include "common/image_writer.h"
#include "reach/reach_map.h"

namespace reach {

namespace {

// The depth below which a cell does not count in the steady-state residual (m).
constexpr double kResidualDepth = 0.01;

// The pictures' depth and arrow scales: a 1-2-5 value at or above the figure, 1 when it is 0.
double scale_step(double v) {
  return v > 0 ? common::round_up_to_125(v) : 1.0;
}

}  // namespace

ReachRecorder::ReachRecorder(const ReachModel& model, const ReachConfig& config,
                             std::filesystem::path dir, std::ostream& log)
    : model_(model),
      solver_(*model.solver),
      config_(config),
      dir_(std::move(dir)),
      log_(log),
      volume0_(model.solver->volume()),
      window_depth_(model.solver->state().h),
      window_start_(model.solver->time()),
      residual_(std::nan("")) {
  const size_t cells = solver_.grid().cells();
  for (size_t c = 0; c < cells; ++c) open_cells_ += !solver_.closed(c);
  max_depth_.assign(cells, std::nan(""));
  max_level_.assign(cells, std::nan(""));
  std::filesystem::create_directories(dir_ / "rasters");
  std::filesystem::create_directories(dir_ / "png");
}

Raster ReachRecorder::raster_of(const Field& values) const {
  Raster r;
  r.grid = solver_.grid();
  r.crs_wkt = model_.terrain.crs_wkt;
  r.values = values;
  return r;
}

// Steady also needs what leaves to match what enters, to 1 % of the inflow (a filling
// floodplain can hold the depth's rate low for a while).
bool ReachRecorder::balanced() const {
  double in = 0, net = 0;
  for (double q : solver_.section_discharge()) {
    in += std::max(q, 0.0);
    net += q;
  }
  return in == 0 || std::abs(net) <= 0.01 * in;
}

void ReachRecorder::after_step() {
  const WaterState& w = solver_.state();
  const size_t cells = solver_.grid().cells();
  for (size_t c = 0; c < cells; ++c) {
    if (solver_.closed(c)) continue;
    max_depth_[c] = std::isnan(max_depth_[c]) ? w.h[c] : std::max(max_depth_[c], w.h[c]);
    if (w.h[c] > config_.dry_depth)
      max_level_[c] = std::isnan(max_level_[c])
                          ? w.h[c] + solver_.bed()[c]
                          : std::max(max_level_[c], w.h[c] + solver_.bed()[c]);
  }
  // The steady-state residual: how fast the depths drift, from the state one window ago
  // (oscillations within the window, a film wetting and drying at the edge, do not count).
  if (solver_.time() - window_start_ < config_.steady_window) return;
  double sum = 0;
  long deep = 0;
  const double span = solver_.time() - window_start_;
  for (size_t c = 0; c < cells; ++c)
    if (w.h[c] > kResidualDepth) {
      const double rate = (w.h[c] - window_depth_[c]) / span;
      sum += rate * rate;
      ++deep;
    }
  residual_ = deep > 0 ? std::sqrt(sum / double(deep)) : 0.0;
  window_depth_ = w.h;
  window_start_ = solver_.time();
  steady_ = config_.steady_tolerance > 0 && residual_ < config_.steady_tolerance && balanced();
}

void ReachRecorder::write_frame() {
  const Grid& g = solver_.grid();
  const size_t cells = g.cells();
  const double nan = std::nan(""), dry = config_.dry_depth;
  const WaterState& w = solver_.state();
  Field depth(cells, nan), level(cells, nan), vx(cells, nan), vy(cells, nan);
  double wetted = 0, fastest = 0, deepest = 0;
  std::vector<double> speeds;  // of cells deeper than 10 cm, for the arrows' scale
  long against_edge = 0;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const size_t c = g.at(i, j);
      if (solver_.closed(c)) continue;
      depth[c] = w.h[c];
      if (w.h[c] <= dry) continue;
      level[c] = w.h[c] + solver_.bed()[c];
      vx[c] = w.hu[c] / w.h[c];
      vy[c] = w.hv[c] / w.h[c];
      wetted += g.cell_area();
      fastest = std::max(fastest, std::hypot(vx[c], vy[c]));
      if (w.h[c] > 0.1) speeds.push_back(std::hypot(vx[c], vy[c]));
      deepest = std::max(deepest, w.h[c]);
      const bool edge = i == 0 || j == 0 || i == g.nx - 1 || j == g.ny - 1;
      if (edge && !model_.section_cells[c] && w.h[c] > 0.05) ++against_edge;
    }
  const std::string t = frame_stamp(solver_.time(), last_frame_time_, config_.output_every);
  last_frame_time_ = solver_.time();
  nlohmann::json files = nlohmann::json::object();
  for (const auto& [what, values] : {std::pair<const char*, const Field*>{"depth", &depth},
                                     {"level", &level},
                                     {"velocity_x", &vx},
                                     {"velocity_y", &vy}}) {
    const std::string name = "rasters/" + std::string(what) + "_" + t + ".tif";
    write_geotiff((dir_ / name).string(), raster_of(*values));
    files[what] = name;
  }
  depth_scale_ = std::max(depth_scale_, scale_step(deepest));
  // The arrows' scale: the 95th percentile of the speed where the water is deeper than 10 cm
  // (a thin wetting front runs fast and would shrink every other arrow).
  if (!speeds.empty()) {
    const size_t k = speeds.size() * 95 / 100;
    std::nth_element(speeds.begin(), speeds.begin() + long(k), speeds.end());
    speed_scale_ = std::max(speed_scale_, scale_step(speeds[k]));
  }
  files["map"] = "png/map_" + t + ".png";
  common::write_png(
      (dir_ / files["map"].get<std::string>()).string(),
      draw_reach_map(g, solver_.bed(), w, solver_.time(), depth_scale_, speed_scale_, dry));
  nlohmann::json sections = nlohmann::json::object();
  const auto names = solver_.section_names();
  for (size_t k = 0; k < names.size(); ++k) sections[names[k]] = solver_.section_discharge()[k];
  const double balance =
      solver_.volume() - (volume0_ + solver_.boundary_volume_in() + solver_.clamped_volume());
  frames_.push_back({{"t_s", solver_.time()},
                     {"volume_m3", solver_.volume()},
                     {"wetted_area_m2", wetted},
                     {"max_depth_m", deepest},
                     {"max_speed_m_s", fastest},
                     {"section_discharge_m3_s", sections},
                     {"volume_balance_error_m3", balance},
                     {"residual_m_s",
                      std::isnan(residual_) ? nlohmann::json(nullptr) : nlohmann::json(residual_)},
                     {"wet_cells_against_the_grid_edge", against_edge},
                     {"files", files}});
  if (against_edge > 0 && warnings_.empty()) {
    warnings_.push_back(std::to_string(against_edge) +
                        " wet cells (deeper than 5 cm) against the grid's edge outside the "
                        "sections at t = " +
                        std::to_string(solver_.time()) +
                        " s: walls hold the water there, so the flow may overtop the banks "
                        "beyond the terrain; widen the window or lower the discharge");
    log_ << "warning: " << warnings_.back() << "\n";
  }
}

nlohmann::json ReachRecorder::finish(long steps, int threads, double wall_s) {
  const Grid& g = solver_.grid();
  const double nan = std::nan("");
  // The bed the flow ran on (coarsened, carved; NaN where closed), which a near field inside the
  // reach takes as its terrain (reach/near_field_window.h).
  Field bed = solver_.bed();
  for (size_t c = 0; c < g.cells(); ++c)
    if (solver_.closed(c)) bed[c] = nan;
  write_geotiff((dir_ / "bed.tif").string(), raster_of(bed));
  write_geotiff((dir_ / "max_depth.tif").string(), raster_of(max_depth_));
  write_geotiff((dir_ / "max_level.tif").string(), raster_of(max_level_));
  common::write_png((dir_ / "map.png").string(),
                    draw_reach_map(g, solver_.bed(), solver_.state(), solver_.time(), depth_scale_,
                                   speed_scale_, config_.dry_depth));
  const double balance =
      solver_.volume() - (volume0_ + solver_.boundary_volume_in() + solver_.clamped_volume());
  return {{"name", config_.name},
          {"description", config_.description},
          {"config", common::JsonWriter::write_struct(config_)},
          {"grid",
           {{"nx", g.nx},
            {"ny", g.ny},
            {"dx_m", g.dx},
            {"dy_m", g.dy},
            {"x0", g.x0},
            {"y0", g.y0},
            {"open_cells", open_cells_},
            {"carved_cells", model_.carved_cells},
            {"crs_wkt", model_.terrain.crs_wkt}}},
          {"end_time_s", solver_.time()},
          {"steady",
           {{"tolerance_m_s", config_.steady_tolerance},
            {"reached", steady_},
            {"residual_m_s", residual_}}},
          {"volume_balance",
           {{"initial_m3", volume0_},
            {"final_m3", solver_.volume()},
            {"net_inflow_m3", solver_.boundary_volume_in()},
            {"clamped_m3", solver_.clamped_volume()},
            {"error_m3", balance}}},
          {"frames", frames_},
          {"warnings", warnings_},
          {"steps", steps},
          {"threads", threads},
          {"wall_s", wall_s},
          {"cell_updates_per_s", wall_s > 0 ? double(steps) * double(open_cells_) / wall_s : 0.0},
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
}

}  // namespace reach
