#include "farfield/reach_flow.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>

#include "common/config_error.h"
#include "common/json_file.h"
#include "reach/raster.h"

namespace farfield {

namespace fs = std::filesystem;

ReachFlow::ReachFlow(const ReachFlowRequest& q) : dry_depth_(q.dry_depth) {
  const auto refuse = [&](const std::string& key, const std::string& message) {
    return common::ConfigError(q.config_file, q.pointer + key, message);
  };
  const fs::path dir(q.run_dir);
  if (!fs::is_regular_file(dir / "reach.json") || !fs::is_regular_file(dir / "bed.tif"))
    throw refuse("/reach_run", q.run_dir + " is not a reach run folder (no reach.json or bed.tif)");
  const nlohmann::json summary = common::load_json_file((dir / "reach.json").string(), "reach run");
  const nlohmann::json& frames = summary.at("frames");
  if (frames.empty()) throw refuse("/reach_run", q.run_dir + "/reach.json lists no output");
  steady_ = summary.contains("steady") && summary["steady"].value("reached", false);

  const nlohmann::json terrain = summary.at("config").at("terrain");
  if (q.manning >= 0) {
    manning_ = q.manning;
  } else if (!terrain.value("manning_file", std::string()).empty()) {
    throw refuse("/manning", "the reach run " + q.run_dir +
                                 " took Manning's n from a raster: give one value for the drift");
  } else {
    manning_ = terrain.value("manning", 0.035);
  }

  // The output times from the start time on.
  double start = frames.back().at("t_s").get<double>();
  if (q.start_time >= 0) {
    std::string times;
    bool found = false;
    // The output nearest the time asked, within half a second (frames may be closer than that).
    for (const auto& f : frames) {
      const double t = f.at("t_s").get<double>();
      times += (times.empty() ? "" : ", ") + std::to_string(std::lround(t));
      if (std::abs(t - q.start_time) <= 0.5 &&
          (!found || std::abs(t - q.start_time) < std::abs(start - q.start_time))) {
        start = t;
        found = true;
      }
    }
    if (!found)
      throw refuse("/start_time", "the reach run has no output at " + std::to_string(q.start_time) +
                                      " s (its outputs: " + times + " s)");
  }
  const reach::Raster bed = reach::read_raster((dir / "bed.tif").string());
  grid_ = bed.grid;
  crs_wkt_ = bed.crs_wkt;
  bed_ = bed.values;
  for (const auto& f : frames) {
    const double t = f.at("t_s").get<double>();
    if (t < start - 0.5) continue;
    // Velocities are nodata where dry: a frame of a dry start has none at all.
    const auto raster = [&](const char* what) {
      const reach::Raster r = reach::read_raster(
          (dir / f.at("files").at(what).get<std::string>()).string(), {{}, 1, true});
      if (r.grid.nx != grid_.nx || r.grid.ny != grid_.ny)
        throw refuse("/reach_run", q.run_dir + ": the " + what + " raster at " +
                                       std::to_string(std::lround(t)) +
                                       " s is not on bed.tif's grid");
      return r.values;
    };
    Frame frame;
    frame.t = t - start;
    frame.depth = raster("depth");
    const reach::Field vx = raster("velocity_x"), vy = raster("velocity_y");
    frame.qx.resize(grid_.cells());
    frame.qy.resize(grid_.cells());
    for (size_t c = 0; c < grid_.cells(); ++c) {
      const double h = frame.depth[c];
      const bool closed = !std::isfinite(h) || !std::isfinite(bed_[c]);
      if (closed) frame.depth[c] = std::numeric_limits<double>::quiet_NaN();
      frame.qx[c] = closed ? frame.depth[c] : std::isfinite(vx[c]) ? h * vx[c] : 0.0;
      frame.qy[c] = closed ? frame.depth[c] : std::isfinite(vy[c]) ? h * vy[c] : 0.0;
    }
    frames_.push_back(std::move(frame));
  }
  known_until_ = steady_ ? std::numeric_limits<double>::infinity() : frames_.back().t;
}

// Bilinear weights found once for the three fields; a cell that is closed (NaN) gives no weight.
void ReachFlow::sample_frame(const Frame& f, double x, double y, double& h, double& qx,
                             double& qy) const {
  const reach::Grid& g = grid_;
  const double fx = (x - g.x0) / g.dx - 0.5, fy = (y - g.y0) / g.dy - 0.5;
  const int i0 = int(std::floor(fx)), j0 = int(std::floor(fy));
  const double tx = fx - i0, ty = fy - j0;
  double sh = 0, sx = 0, sy = 0, weight = 0;
  for (int dj = 0; dj < 2; ++dj)
    for (int di = 0; di < 2; ++di) {
      const int i = std::clamp(i0 + di, 0, g.nx - 1), j = std::clamp(j0 + dj, 0, g.ny - 1);
      const size_t c = g.at(i, j);
      const double w = (di ? tx : 1 - tx) * (dj ? ty : 1 - ty);
      if (!(w > 0) || !std::isfinite(f.depth[c])) continue;
      sh += w * f.depth[c];
      sx += w * f.qx[c];
      sy += w * f.qy[c];
      weight += w;
    }
  if (weight > 0) {
    h = sh / weight;
    qx = sx / weight;
    qy = sy / weight;
  } else {
    h = qx = qy = std::numeric_limits<double>::quiet_NaN();
  }
}

FlowSample ReachFlow::sample(double x, double y, double t) const {
  FlowSample s;
  const reach::Grid& g = grid_;
  if (x < g.x0 || y < g.y0 || x > g.x0 + g.nx * g.dx || y > g.y0 + g.ny * g.dy) return s;
  double h, qx, qy;
  size_t k = 0;
  while (k + 1 < frames_.size() && frames_[k + 1].t <= t) ++k;
  sample_frame(frames_[k], x, y, h, qx, qy);
  if (k + 1 < frames_.size() && t > frames_[k].t) {
    double h1, qx1, qy1;
    sample_frame(frames_[k + 1], x, y, h1, qx1, qy1);
    const double a = (t - frames_[k].t) / (frames_[k + 1].t - frames_[k].t);
    h = (1 - a) * h + a * h1;
    qx = (1 - a) * qx + a * qx1;
    qy = (1 - a) * qy + a * qy1;
  }
  if (!(h >= dry_depth_)) {
    s.where = FlowWhere::bank;
    s.depth = std::isfinite(h) ? h : 0.0;
    return s;
  }
  s.where = FlowWhere::water;
  s.depth = h;
  s.u = qx / h;
  s.v = qy / h;
  s.manning = manning_;
  return s;
}

reach::WaterState ReachFlow::water_at(double t) const {
  size_t k = 0;
  while (k + 1 < frames_.size() && frames_[k + 1].t <= t) ++k;
  return {frames_[k].depth, frames_[k].qx, frames_[k].qy};
}

}  // namespace farfield
